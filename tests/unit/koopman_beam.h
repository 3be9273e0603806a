/* Shared by the neural DMD tests (test_koopman_neural.c, test_koopman_shape.c): a procedural
 * cantilever box beam built from scene JSON, its full-order run as a Koopman trajectory, and the
 * rollout error of an operator against that run. */
#ifndef RK_TEST_KOOPMAN_BEAM_H
#define RK_TEST_KOOPMAN_BEAM_H

#include "testlib.h"
#include "asset/asset.h"
#include "formats/rombin_write.h"
#include "koopman/koopman.h"
#include "pipeline/method_koopman.h"
#include "runtime/romrt.h"
#include "util/util.h"

/* A cantilever 1 x thick x 0.2 m (the box spans [0, 1] x [0, thick] x [0, 0.2]), clamped at x = 0,
 * sagging from rest under gravity along -y; `run` is its full-order run (when duration > 0). */
typedef struct {
    rk_scene scene;
    rk_scene_sim sim;
    rk_koopman_run run;
    int ready, ran;
} beam;

/* The scene alone (no full-order run): the mesh, masses and forcing of a beam of that thickness. */
static inline int beam_build(beam *b, double thick, int cx, int cy, int cz, double duration, rk_error *err)
{
    char json[1024];
    snprintf(json, sizeof json,
             "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1, %.17g, 0.2], \"cells\": [%d, %d, %d]}},"
             " \"material\": {\"model\": \"neohookean\", \"young\": 5e6, \"poisson\": 0.35, \"density\": 1000},"
             " \"fixed\": [{\"box\": [[-1, -1, -1], [0.001, 1, 1]]}]}],"
             " \"gravity\": [0, -9.81, 0], \"damping\": {\"mass\": 0.5, \"stiffness\": 0.002},"
             " \"time\": {\"step\": 0.01, \"duration\": %.17g}}",
             thick, cx, cy, cz, duration);
    memset(b, 0, sizeof *b);
    if (rk_scene_parse(json, "beam.json", &b->scene, err)) return -1;
    if (rk_scene_build(&b->scene, &b->sim, err)) {
        rk_scene_free(&b->scene);
        return -1;
    }
    b->ready = 1;
    return 0;
}

static inline void beam_close(beam *b)
{
    if (!b->ready) return;
    if (b->ran) rk_koopman_run_free(&b->run);
    rk_scene_sim_free(&b->sim);
    rk_scene_free(&b->scene);
    b->ready = b->ran = 0;
}

/* The beam and its full-order run over `duration` seconds. */
static inline int beam_open_thick(beam *b, double thick, int cx, int cy, int cz, double duration, rk_error *err)
{
    if (beam_build(b, thick, cx, cy, cz, duration, err)) return -1;
    if (rk_koopman_scene_run(&b->sim, NULL, &b->run, err)) {
        beam_close(b);
        return -1;
    }
    b->ran = 1;
    return 0;
}

/* The 0.2 m thick beam of test_koopman_neural. */
static inline int beam_open(beam *b, int cx, int cy, int cz, double duration, rk_error *err)
{
    return beam_open_thick(b, 0.2, cx, cy, cz, duration, err);
}

/* The vertex at rest position (x, y, z), or -1. */
static inline int beam_vertex(const beam *b, double x, double y, double z)
{
    for (int p = 0; p < b->sim.mesh.nv; p++) {
        const double *X = b->sim.mesh.X + 3 * p;
        if (fabs(X[0] - x) < 1e-9 && fabs(X[1] - y) < 1e-9 && fabs(X[2] - z) < 1e-9) return p;
    }
    return -1;
}

/* The beam as a training mesh of the neural DMD, shape code gamma (or NULL). */
static inline rk_koopman_neural_mesh beam_mesh(const beam *b, const double *gamma)
{
    rk_koopman_neural_mesh m = {b->sim.mesh.X, b->sim.mesh.nv, &b->run.t, 1, gamma};
    return m;
}

/* The rollout of k from the run's start against the run (rk_koopman_rollout_error). */
static inline int rollout_error(const rk_koopman *k, const rk_koopman_run *run, double *pct, double *peak,
                                rk_error *err)
{
    return rk_koopman_rollout_error(k, &run->t, pct, peak, err);
}

/* The operator k on beam u's mesh baked by the existing Koopman bake (rk_asset_bake_koopman) and
 * stepped by the runtime (float) from the run's start under its gravity, against the precompute's
 * double rollout of the same operator (rk_koopman_forced, one step at a time): the largest
 * |x - X - u| over every value and frame in *worst, the largest |u| in *peak. */
static inline int runtime_against_rollout(const rk_koopman *k, const beam *u, double *worst, double *peak,
                                          rk_error *err)
{
    int nv = u->sim.mesh.nv, n = 3 * nv, T = u->run.t.frames, rc;
    rk_koopman_geometry g = {.nv = nv, .X = u->sim.mesh.X, .vertex_mass = u->sim.fem.vertex_mass,
                             .accel = u->run.accel, .u0 = u->run.u + n, .u_prev = u->run.u, .trajectories = 2};
    rk_asset_options ao;
    rk_asset_default_options(&ao);
    rk_baked baked;
    size_t need = 0;
    rc = rk_bake_koopman(k, &g, &ao, NULL, &baked, err);
    const unsigned char *asset = baked.data;
    size_t bytes = baked.bytes;
    romrt_error re = {0};
    romrt_model *rm = NULL;
    void *arena = NULL;
    romrt_status st = ROMRT_E_ARGUMENT;
    if (!rc && romrt_arena_size(asset, bytes, &need, &re) == ROMRT_OK) arena = aligned_alloc(16, (need + 15) / 16 * 16);
    if (arena) st = romrt_open(asset, bytes, arena, need, &rm, &re);
    double *z = calloc((size_t)k->r, sizeof(double)), *ud = calloc((size_t)n, sizeof(double));
    romrt_real *x = calloc((size_t)n, sizeof(romrt_real));
    *worst = *peak = 0;
    rk_koopman_lift(k, u->run.u + n, u->run.u, z);
    for (int t = 2; st == ROMRT_OK && t < T; t++) {
        st = romrt_step(rm, &re);
        if (st == ROMRT_OK) st = romrt_positions(rm, x, 3 * (size_t)nv, 3, NULL);
        rk_koopman_forced(k, 1, u->run.accel, z, err);
        rk_koopman_positions(k, z, ud);
        for (int i = 0; st == ROMRT_OK && i < n; i++) {
            *worst = fmax(*worst, fabs((double)x[i] - u->sim.mesh.X[i] - ud[i]));
            *peak = fmax(*peak, fabs(ud[i]));
        }
    }
    free(z);
    free(ud);
    free(x);
    free(arena);
    rk_baked_free(&baked);
    if (rc) return rk_error_prefix(err, "bake");
    if (st != ROMRT_OK) return rk_fail(err, "runtime: status %d (%s)", (int)st, re.message);
    return 0;
}

#endif
