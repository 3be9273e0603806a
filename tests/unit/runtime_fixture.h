/* Shared by the runtime tests: a scene's reduced model (precompute/rom) and its baked asset in
 * memory, opened by the runtime built in this test's precision. */
#ifndef RK_TEST_RUNTIME_FIXTURE_H
#define RK_TEST_RUNTIME_FIXTURE_H

#include <stdint.h>

#include "testlib.h"
#include "pipeline/method_fixed.h"
#include "formats/rombin_read.h"
#include "runtime/romrt.h"
#include "rom/rom.h"

typedef struct {
    rk_scene scene;
    rk_scene_sim sim;
    rk_scene_rom R;
    unsigned char *asset;
    size_t bytes;
    void *arena;
    romrt_model *m;
    const uint32_t *vmap;     /* stored vertex -> source vertex (the asset's VMAP) */
    double *v0;               /* r: the baked initial velocity (VEL0), or NULL: at rest */
    int stage;
} rt_fixture;

static inline void rt_fixture_close(rt_fixture *f)
{
    if (f->stage >= 3) rk_scene_rom_free(&f->R);
    if (f->stage >= 2) rk_scene_sim_free(&f->sim);
    if (f->stage >= 1) rk_scene_free(&f->scene);
    free(f->asset);
    free(f->arena);
    free(f->v0);
    memset(f, 0, sizeof *f);
}

/* Builds the scene's first rom entry (training on its full-order run where its basis or cubature
 * needs one, as the bake does), bakes it with real type `real_type` and opens it with the runtime.
 * 0 on success; err or rerr says why not. */
static inline int rt_fixture_open(rt_fixture *f, const char *json, int real_type, rk_error *err, romrt_error *rerr)
{
    memset(f, 0, sizeof *f);
    double *D = NULL;
    int T = 0;
    if (rk_scene_parse(json, "test.json", &f->scene, err)) return -1;
    f->stage = 1;
    const rk_rom_entry *entry = &f->scene.entries[0];
    if (rk_scene_build(&f->scene, &f->sim, err)) return -1;
    f->stage = 2;
    if (!f->sim.cloud_points && (entry->cubature || rk_basis_needs_frames(&entry->basis)) && /* a cloud has no full order */
        rk_scene_training_frames(&f->sim, &D, &T, err))
        return -1;
    int rc = rk_scene_rom_build(&f->scene, &f->sim, entry, D, T, &f->R, err);
    free(D);
    if (rc) return -1;
    f->stage = 3;
    rombin_writer w;
    rombin_writer_init(&w, real_type, 0);
    rk_asset_rom source = rk_scene_asset_rom(&f->sim, &f->R);
    double moved_by; /* what the basis misses of the initial velocities: romkit build reports it */
    if (rk_scene_rom_velocity0(&f->sim, &f->R, &f->v0, &moved_by, err)) return -1;
    source.velocity0 = f->v0;
    rc = rk_asset_bake(&source, NULL, NULL, &entry->asset, NULL, &w, NULL, err) || rombin_serialize(&w, &f->asset, &f->bytes, err);
    rombin_writer_free(&w);
    if (rc) return -1;
    rombin_file file;
    rombin_chunk c;
    rombin_error e;
    if (rombin_open(&file, f->asset, f->bytes, NULL, &e) || !rombin_find(&file, ROMBIN_VMAP, &c))
        return rk_fail(err, "baked asset has no VMAP: %s", e.message);
    f->vmap = (const uint32_t *)(const void *)c.data;
    size_t need;
    if (romrt_arena_size(f->asset, f->bytes, &need, rerr) != ROMRT_OK) return rk_fail(err, "arena size: %s", rerr->message);
    f->arena = aligned_alloc(16, (need + 15) / 16 * 16);
    if (!f->arena || romrt_open(f->asset, f->bytes, f->arena, need, &f->m, rerr) != ROMRT_OK)
        return rk_fail(err, "open: %s", rerr->message);
    return 0;
}

/* The precompute's positions of the shown vertices, X + U q, in the asset's order. */
static inline void rt_fixture_reference(const rt_fixture *f, const double *q, double *xyz)
{
    int n = romrt_shown_count(f->m), ndof = 3 * f->sim.mesh.nv, r = f->R.basis.r;
    for (int i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) {
            int k = 3 * (int)f->vmap[i] + a;
            double s = f->sim.mesh.X[k];
            for (int j = 0; j < r; j++) s += f->R.basis.U[(size_t)ndof * j + k] * q[j];
            xyz[3 * i + a] = s;
        }
}

/* X + U q at every mesh vertex for the runtime's q, read in double (r may pass the header's
 * default ROMRT_MAX_R, which the library is built above): what the contact stage's exact test
 * measures. */
static inline void rt_fixture_positions(const rt_fixture *f, double *x)
{
    int r = f->R.basis.r;
    romrt_real *q = calloc((size_t)r, sizeof(romrt_real));
    double *qd = calloc((size_t)r, sizeof(double));
    romrt_reduced_coordinates(f->m, q, r, NULL);
    for (int j = 0; j < r; j++) qd[j] = (double)q[j];
    rk_rom_positions(f->R.basis.U, 3 * f->sim.mesh.nv, r, f->sim.mesh.X, qd, x);
    free(q), free(qd);
}

/* An opened asset's surface for the exact crossing tests: its shown positions (x, in double) and
 * triangles (rt_surface_read after each step). */
typedef struct {
    int n, nt, *tris;
    romrt_real *xyz;
    double *x;
} rt_surface;

static inline void rt_surface_init(rt_surface *b, const romrt_model *m)
{
    b->n = (int)romrt_shown_count(m), b->nt = (int)romrt_triangle_count(m);
    b->tris = calloc((size_t)3 * b->nt + 3, sizeof(int));
    b->xyz = calloc((size_t)3 * b->n, sizeof(romrt_real));
    b->x = calloc((size_t)3 * b->n, sizeof(double));
    romrt_triangles(m, b->tris, 3 * (size_t)b->nt, NULL);
}

static inline void rt_surface_read(rt_surface *b, const romrt_model *m)
{
    romrt_positions(m, b->xyz, 3 * (size_t)b->n, 3, NULL);
    for (int i = 0; i < 3 * b->n; i++) b->x[i] = (double)b->xyz[i];
}

static inline void rt_surface_free(rt_surface *b) { free(b->tris), free(b->xyz), free(b->x); }

#endif
