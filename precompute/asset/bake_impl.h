/* Private to precompute/asset: what the reduced-model and the Koopman bakes share. */
#ifndef RK_ASSET_BAKE_IMPL_H
#define RK_ASSET_BAKE_IMPL_H

#include "asset/asset.h"

typedef struct {
    int nv, count, shown;
    int *stored;         /* nv: stored index of a source vertex, or -1 */
    int *source;         /* count: source vertex of a stored one */
    unsigned char *need; /* nv: 1 shown, 2 needed otherwise */
    int *tris, nf;       /* boundary triangles (source numbers) */
    int *group_first, *group_count, *group_verts, group_total;
} rk_bake_state;

/* s->tris / s->nf (the boundary triangles, source numbers, owned by s) are set by the caller first. */
int rk_bake_select(int nv, const double *X, const int *extra, int nextra, const rk_asset_options *o, rk_bake_state *s,
                   rk_error *err);
void rk_bake_state_free(rk_bake_state *s);
int rk_bake_add_u32s(rombin_writer *w, const char *id, int critical, const int *v, size_t n, rk_error *err);
/* VERT (the stored vertices' rest positions, from X over all source vertices) and VMAP. */
int rk_bake_add_vertices(const double *X, const rk_bake_state *s, rombin_writer *w, rk_error *err);
/* A Koopman operator's own chunks over the stored vertices s (bake_koopman.c): KHED, KPRM, KEIG,
 * KACC, KINI, KOUT, KIMP. */
int rk_bake_koopman_chunks(const rk_koopman *k, const rk_koopman_geometry *g, const rk_asset_options *o,
                           const rk_bake_state *s, rombin_writer *w, rk_error *err);
/* A prescribed group's motion as ROMBIN_PIN_PARAMS values (PINS, AMOT): kind, axis, center, rate,
 * velocity, 0. */
void rk_bake_motion_params(const rk_prescribed *p, double *out);
/* An adaptive linear ROM's chunks over the stored vertices s (bake_alrom.c): ALRH, ALRP, QDRV, and
 * VMSS and VLOD with each unstored vertex's mass and load moved to its nearest stored vertex along
 * the mesh's edges, AMOV and AMOT. */
int rk_bake_alrom_chunks(const rk_asset_rom *R, const rk_bake_state *s, rombin_writer *w, rk_error *err);
/* Several objects (bake_objects.c): COBJ, the object of each of the ncv collision vertices;
 * nothing for one object. */
int rk_bake_objects(const rk_rom_model *m, int ncv, rombin_writer *w, rk_error *err);
/* The scene's obstacles other than planes (bake_obstacles.c): OBHD, OBJS, OBMO, OBVX, OBED, OBTR,
 * OBVN, OBVB, OBIT, and the collision surface CEDG, CTRI; OBHD, CEDG and CTRI alone for several
 * objects or self-contact without such obstacles; nothing without any of them. */
int rk_bake_obstacles(const rk_rom_model *m, const rk_fem *fem, const rk_asset_options *o, rombin_writer *w,
                      rk_error *err);
/* GRPS, GVTX, GNAM, and SURF unless nothing is shown (renumbers s's groups and triangles). */
int rk_bake_add_groups_and_surface(const rk_asset_options *o, rk_bake_state *s, rombin_writer *w, rk_error *err);

#endif
