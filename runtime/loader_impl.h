/* Private to the runtime: reading a model's chunks once, in romrt_open. The sizing pass runs with
 * arena NULL and only counts the bytes of converted arrays; the placing pass writes them. */
#ifndef ROMRT_LOADER_H
#define ROMRT_LOADER_H

#include "runtime/romrt_impl.h"

typedef struct {
    rombin_file file;
    unsigned char *arena;
    size_t used, cap;
    int scanned;              /* every real already checked finite (by the sizing pass) */
    romrt_error *err;
} rt_loader;

static inline size_t rt_align16(size_t n) { return (n + 15) / 16 * 16; }

/* Value i of a real chunk, whatever the file's real type. */
double rt_real_at(const rt_loader *L, const rombin_chunk *c, uint64_t i);
/* The chunk `id` of `count` elements of `type` (count 0: any whole number of them; *found says
 * whether it is there; required chunks fail when absent). */
romrt_status rt_chunk(rt_loader *L, const char *id, int type, uint64_t count, int required, rombin_chunk *c,
                      int *found);
/* A real array of `count` values, finite, in place or converted into the arena. */
romrt_status rt_reals(rt_loader *L, const char *id, uint64_t count, int required, const romrt_real **out);
/* `count` reals of zeroed scratch in the arena (*out NULL in the sizing pass). */
void rt_scratch(rt_loader *L, size_t count, romrt_real **out);
/* The same for doubles, in either build. */
void rt_scratch_wide(rt_loader *L, size_t count, double **out);
/* `count` zeroed u32s (or int32s) of scratch in the arena (*out NULL in the sizing pass). */
void rt_scratch_u32(rt_loader *L, size_t count, uint32_t **out);
romrt_status rt_u32s(rt_loader *L, const char *id, uint64_t count, int required, const uint32_t **out);
/* Entries [lo, hi) of each of n records of `stride` u32s are below limit. */
romrt_status rt_indices_below(rt_loader *L, const char *id, const uint32_t *a, uint64_t n, uint64_t stride,
                              uint64_t lo, uint64_t hi, uint32_t limit);
/* A prescribed motion's ROMBIN_PIN_PARAMS values p (PINS, AMOT): kind 0, 1 or 2, the reserved last
 * value 0, a twist's axis non-zero; refused naming `what` and i ("pin ", g). */
romrt_status rt_check_motion(rt_loader *L, const char *id, const char *what, uint64_t i, const romrt_real *p);
/* A model's header chunk `id` of `count` u32s: fields from first_reserved on are 0, r (at r_at)
 * is 1..ROMRT_MAX_R, stored vertices (at vertices_at) 1..ROMRT_MAX_VERTICES, shown (at shown_at)
 * at most those. */
romrt_status rt_head(rt_loader *L, const char *id, uint64_t count, int first_reserved, int r_at, int vertices_at,
                     int shown_at, const uint32_t **head);
/* GRPS, GVTX, GNAM and SURF (m->ngroups set), then their indices against m->nv and m->shown. */
romrt_status rt_load_groups_and_surface(rt_loader *L, romrt_model *m);
romrt_status rt_check_groups_and_surface(rt_loader *L, const romrt_model *m);

/* SKIN against ROWS: the rows must be linear blend skinning over the stored rest positions. */
romrt_status rt_skin_check(rt_loader *L, const romrt_model *m);
/* An adaptive linear ROM's chunks (alrom.c; ALRH and the rest, when there): its arrays and scratch
 * after the reduced model's, then their contents. */
romrt_status rt_alrom_arrays(rt_loader *L, romrt_model *m);
romrt_status rt_alrom_contents(rt_loader *L, romrt_model *m);
/* Several objects' chunk (objects_load.c; COBJ, when there; 1.5's CRAD refused): the array, then
 * its indices and the collision surface it needs (OBHD). */
romrt_status rt_objects_arrays(rt_loader *L, romrt_model *m);
romrt_status rt_objects_contents(rt_loader *L, romrt_model *m);
/* The obstacles' chunks (contact_load.c; OBHD and the rest, when there): their arrays and
 * scratch, then their indices, the BVH's shape and boxes, and the start apart from them. */
romrt_status rt_obstacles_arrays(rt_loader *L, romrt_model *m);
romrt_status rt_obstacles_contents(rt_loader *L, romrt_model *m);
/* A Koopman asset's chunks (koopman.c), as sizes / arrays / contents in open.c. */
romrt_status rt_koopman_sizes(rt_loader *L, romrt_model *m);
romrt_status rt_koopman_arrays(rt_loader *L, romrt_model *m);
romrt_status rt_koopman_contents(rt_loader *L, romrt_model *m);

#endif
