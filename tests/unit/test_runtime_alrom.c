/* The runtime's adaptive linear ROM (runtime/alrom.c) against the precompute's simulator
 * (precompute/grassmann, rk_alrom) on the same scene and decoder: with every vertex stored and a
 * lumped mass the two are the same method, so a double build takes the same steps (this file
 * compiled with -DROMRT_DOUBLE, test_runtime_alrom_double) and a float build stays close. With only
 * the surface and the cubature's vertices stored, the runtime's basis lives on those: its error
 * against the precompute's is measured and bounded. Also: pushing, reset, a corrupted chunk. */
#include "testlib.h"
#include "pipeline/pipeline.h"
#include "pipeline/method_adaptive_linear.h"
#include "formats/rombin_read.h"
#include "runtime/romrt.h"
#include "runtime/romrt_impl.h" /* the step's own rows (m->al.rows), for romrt_basis_rows */

#include <stdint.h>

#ifdef ROMRT_DOUBLE
#define ASSET_REAL "float64"
#define PARITY_TOL 1e-6
#else
#define ASSET_REAL "float32"
#define PARITY_TOL 1e-3
#endif

/* A bar clamped at x = 0 whose far end is driven down and sideways (a bend, under
 * gravity), the quadratic decoder of bar_size modes (6), a history of 8 steps; cubature on or off. */
static int bar_size = 6;
static const char *bar_with(const char *show, int cubature, const char *decoder);
static const char *bar(const char *show, int cubature)
{
    return bar_with(show, cubature, "\"decoder\": \"quadratic\"");
}

static const char *bar_with(const char *show, int cubature, const char *decoder)
{
    static char json[2048];
    snprintf(json, sizeof json,
             "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1, 0.2, 0.2], \"cells\": [10, 2, 2]}},"
             " \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000},"
             " \"fixed\": [{\"box\": [[-1, -1, -1], [0.01, 2, 2]]}],"
             " \"moving\": [{\"box\": [[0.99, -1, -1], [2, 2, 2]], \"translate\": {\"velocity\": [0, -0.5, 0.3]}}]}],"
             " \"gravity\": [0, -9.81, 0], \"lumped_mass\": true, \"newton\": {\"tolerance\": 1e-9},"
             " \"time\": {\"step\": 0.01, \"duration\": 0.3, \"integrator\": \"backward_euler\"},"
             " \"rom\": {\"method\": \"adaptive_linear\", \"size\": %d, %s, \"history\": 8,"
             "  %s \"asset\": {\"show\": \"%s\", \"precision\": \"%s\","
             "   \"groups\": [{\"name\": \"middle\", \"box\": [[0.45, -1, -1], [0.55, 2, 2]]}]}}}",
             bar_size, decoder, cubature ? "\"cubature\": {\"tolerance\": 0.01}," : "", show, ASSET_REAL);
    return json;
}

typedef struct {
    rk_scene scene;
    rk_scene_sim sim;
    rk_baked baked;
    void *arena;
    romrt_model *m;
    const uint32_t *vmap;
    rk_alrom s;
    rk_decoder dec;
    int *cub_element;
    double *cub_weight;
    int stage;
} fixture;

static void fixture_close(fixture *f)
{
    if (f->stage >= 4) rk_alrom_free(&f->s);
    if (f->stage >= 3) rk_decoder_free(&f->dec);
    if (f->stage >= 2) rk_scene_sim_free(&f->sim);
    if (f->stage >= 1) rk_scene_free(&f->scene);
    rk_baked_free(&f->baked);
    free(f->arena);
    free(f->cub_element);
    free(f->cub_weight);
    memset(f, 0, sizeof *f);
}

/* The scene's asset opened by the runtime and the precompute's simulator on the same decoder and
 * cubature (both deterministic: the bake computes them the same way). */
static int fixture_open(fixture *f, const char *json, rk_error *err)
{
    memset(f, 0, sizeof *f);
    if (rk_scene_parse(json, "test.json", &f->scene, err)) return -1;
    f->stage = 1;
    const rk_rom_entry *e = &f->scene.entries[0];
    rk_bake_request req = {0};
    if (rk_scene_bake(&f->scene, e, &req, &f->baked, err) || rk_scene_build(&f->scene, &f->sim, err)) return -1;
    f->stage = 2;
    rombin_file file;
    rombin_chunk c;
    rombin_error re;
    if (rombin_open(&file, f->baked.data, f->baked.bytes, NULL, &re) || !rombin_find(&file, ROMBIN_VMAP, &c))
        return rk_fail(err, "the asset has no VMAP");
    f->vmap = (const uint32_t *)(const void *)c.data;
    size_t need;
    romrt_error rerr;
    if (romrt_arena_size(f->baked.data, f->baked.bytes, &need, &rerr)) return rk_fail(err, "arena size: %s", rerr.message);
    f->arena = aligned_alloc(16, (need + 15) / 16 * 16);
    if (romrt_open(f->baked.data, f->baked.bytes, f->arena, need, &f->m, &rerr))
        return rk_fail(err, "open: %s", rerr.message);
    double *D = NULL;
    int T = 0, ncub = 0;
    if (e->cubature && rk_scene_training_frames(&f->sim, &D, &T, err)) return -1;
    rk_moving_fit fit;
    int rc = rk_scene_alrom_decoder(&f->scene, &f->sim, e, NULL, 0, &f->dec, err) ||
             rk_scene_alrom_cubature(&f->sim, e, &f->dec, D, T, &f->cub_element, &f->cub_weight, &ncub, &fit, err);
    free(D);
    if (rc) return -1;
    f->stage = 3;
    rk_alrom_options o = rk_adaptive_linear_of(e)->opt;
    if (ncub) {
        o.ncub = ncub;
        o.cub_element = f->cub_element;
        o.cub_weight = f->cub_weight;
    } else { /* every element at weight 1: the runtime's quadrature when there is no cubature */
        o.ncub = f->sim.mesh.nt;
        f->cub_element = malloc(sizeof(int) * o.ncub);
        f->cub_weight = malloc(sizeof(double) * o.ncub);
        for (int t = 0; t < o.ncub; t++) f->cub_element[t] = t, f->cub_weight[t] = 1;
        o.cub_element = f->cub_element;
        o.cub_weight = f->cub_weight;
    }
    if (rk_alrom_init(&f->s, &f->sim.fem, &f->sim.options, &f->dec, &o, err)) return -1;
    f->stage = 4;
    return 0;
}

/* Both for `steps` (and full order beside them when fom is given): the largest difference of the
 * shown positions over the largest displacement, runtime against precompute; with fom, each one's
 * largest difference from full order likewise into err_rt and err_pc. */
static double run_both(fixture *f, int steps, rk_fom *fom, double *err_rt, double *err_pc, rk_error *err, int *failed)
{
    int n = romrt_shown_count(f->m);
    romrt_real *xyz = malloc(sizeof(romrt_real) * 3 * n);
    double worst = 0, scale = 0, wr = 0, wp = 0;
    romrt_error rerr;
    *failed = 0;
    for (int k = 0; k < steps; k++) {
        if (rk_alrom_step(&f->s, err) || (fom && rk_fom_step(fom, err))) {
            *failed = 1;
            break;
        }
        if (romrt_step(f->m, &rerr) != ROMRT_OK) {
            snprintf(err->msg, sizeof err->msg, "runtime step %d: %s", k, rerr.message);
            *failed = 1;
            break;
        }
        romrt_positions(f->m, xyz, 3 * (size_t)n, 3, NULL);
        for (int i = 0; i < 3 * n; i++) {
            int dof = 3 * (int)f->vmap[i / 3] + i % 3;
            worst = fmax(worst, fabs((double)xyz[i] - f->s.fom.x[dof]));
            scale = fmax(scale, fabs(f->s.fom.x[dof] - f->sim.mesh.X[dof]));
            if (fom) {
                wr = fmax(wr, fabs((double)xyz[i] - fom->x[dof]));
                wp = fmax(wp, fabs(f->s.fom.x[dof] - fom->x[dof]));
            }
        }
    }
    if (fom) *err_rt = wr / scale, *err_pc = wp / scale;
    free(xyz);
    return worst / scale;
}

/* The step's own rows at the used vertices that are shown (m->al.rows) against romrt_basis_rows,
 * the K-space basis formed apart: their largest difference and the largest row entry; returns the
 * vertices compared, -1 when romrt_basis_rows fails. */
static int used_rows_against_basis(const romrt_model *m, double *diff, double *big)
{
    int r = m->r, checked = 0;
    romrt_real *rows = malloc(sizeof(romrt_real) * 3 * (size_t)m->shown * (size_t)r);
    *diff = *big = 0;
    if (!rows || romrt_basis_rows(m, rows, 3 * (size_t)m->shown * (size_t)r, NULL) != ROMRT_OK) {
        free(rows);
        return -1;
    }
    for (int k = 0; k < m->al.ns_on; k++) {
        int v = (int)m->al.sv[k];
        if (v >= m->shown) continue;
        for (int i = 3 * v * r; i < 3 * (v + 1) * r; i++) {
            *diff = fmax(*diff, fabs((double)rows[i] - (double)m->al.rows[i]));
            *big = fmax(*big, fabs((double)m->al.rows[i]));
        }
        checked++;
    }
    free(rows);
    return checked;
}

/* The history is blended from the second step. The paper's step (ridge and budget 0) amplified a
 * perturbation about 2.5 times a step on this bend (the history basis' smallest direction barely
 * above the rank floor: a difference of rounding, 1e-11 after the decoder's steps, was 1e-9 after
 * the first blended one); the default step grows one by at most 1.02 (test_runtime_alrom_growth).
 * A long run is still compared by its error against full order. */
TEST(every_vertex_stored_takes_the_precompute_steps)
{
    for (int cub = 0; cub < 2; cub++) {
        rk_error err = {{0}};
        fixture f;
        int failed;
        CHECK_OK(fixture_open(&f, bar("all", cub), &err));
        double rel = run_both(&f, 10, NULL, NULL, NULL, &err, &failed);
        CHECK(!failed, "%s", err.msg);
        printf("# every vertex stored, %s: relative difference %.3g over 10 steps (tol %g); the precompute's basis "
               "blended the history in %ld of them\n",
               cub ? "cubature" : "every element", rel, PARITY_TOL, f.s.stats.history_used);
        CHECK(f.s.stats.history_used >= 3, "the history was blended in only %ld steps", f.s.stats.history_used);
        CHECK(rel <= PARITY_TOL, "relative difference %.3g above %g", rel, PARITY_TOL);
        /* romrt_basis_rows forms every shown row from the K-space basis; at the vertices the step
         * reads it must give the rows the step formed itself */
        double diff, big;
        int checked = used_rows_against_basis(f.m, &diff, &big);
        CHECK(checked >= 0, "basis rows");
        CHECK(checked > 0 && diff <= 1e-5 * big, "basis rows at %d used vertices %g off the step's (largest %g)",
              checked, diff, big);
        fixture_close(&f);
    }
}

/* The step forms its rows at the used vertices as z^T Z (alrom_basis.c, row_times: 8 columns at a
 * time in registers, then the rest one by one), z a row's ring entries and Jacobian row. At r = 10
 * both paths run; the rows must be the K-space basis B C_s at those vertices (romrt_basis_rows,
 * rt_alrom_row: another formation) to round-off, in double to 1e-12 of the largest. */
TEST(step_rows_are_the_k_space_basis)
{
    rk_error err = {{0}};
    fixture f;
    int failed;
    bar_size = 10;
    CHECK_OK(fixture_open(&f, bar("all", 1), &err));
    bar_size = 6;
    double rel = run_both(&f, 10, NULL, NULL, NULL, &err, &failed);
    CHECK(!failed, "%s", err.msg);
    CHECK(f.s.stats.history_used >= 3, "the history was blended in only %ld steps", f.s.stats.history_used);
    CHECK(rel <= PARITY_TOL, "r = 10: relative difference %.3g from the precompute above %g", rel, PARITY_TOL);
    double diff, big;
#ifdef ROMRT_DOUBLE
    double tol = 1e-12;
#else
    double tol = 1e-5;
#endif
    CHECK(f.m->r == 10, "r = %d", f.m->r);
    int checked = used_rows_against_basis(f.m, &diff, &big);
    CHECK(checked >= 0, "basis rows");
    printf("# r = 10: the step's rows at %d used vertices %.3g from B C_s (largest %.3g); %.3g from the precompute\n",
           checked, diff, big, rel);
    CHECK(checked > 0 && diff <= tol * big, "rows %g off B C_s (tol %g of %g)", diff, tol, big);
    fixture_close(&f);
}

/* A CROM decoder (small networks, a short training on the scene's own run): its weights in the
 * asset, every vertex stored for its encoder, the same steps as the precompute's simulator. */
TEST(crom_decoder_takes_the_precompute_steps)
{
    rk_error err = {{0}};
    fixture f;
    int failed;
    CHECK_OK(fixture_open(&f, bar_with("surface", 0, "\"decoder\": \"crom\", \"crom\": {\"encoder_width\": 16, "
                                       "\"encoder_layers\": 1, \"decoder_width\": 16, \"decoder_layers\": 2, \"epochs\": 30}"),
                          &err));
    CHECK(romrt_shown_count(f.m) < (size_t)f.sim.mesh.nv, "the surface is shown, every vertex stored");
    double rel = run_both(&f, 10, NULL, NULL, NULL, &err, &failed);
    CHECK(!failed, "%s", err.msg);
    printf("# CROM decoder: relative difference %.3g over 10 steps (tol %g), history blended in %ld\n", rel, PARITY_TOL,
           f.s.stats.history_used);
    CHECK(rel <= PARITY_TOL, "relative difference %.3g above %g", rel, PARITY_TOL);
    /* a CROM basis has no K-space to carry a kept Newton matrix in (runtime/alrom_keep.c) */
    CHECK(romrt_set_hessian_reuse(f.m, 10, NULL) == ROMRT_E_UNSUPPORTED, "a CROM model keeps no Newton matrix");
    fixture_close(&f);
}

/* An app's sphere collider under the middle of the bar its driven end bends down: the adaptive
 * step's rows change every step, and the barrier and its step filter act through them; no shown
 * vertex may enter the sphere. */
TEST(a_collider_holds_the_adaptive_bar)
{
    rk_error err = {{0}};
    fixture f;
    romrt_error rerr;
    CHECK_OK(fixture_open(&f, bar("surface", 0), &err));
    CHECK(romrt_takes_colliders(f.m), "the asset keeps its collision vertices");
    const double centre[3] = {0.5, -0.22, 0}, radius = 0.1;
    romrt_collider c = {ROMRT_COLLIDER_SPHERE, {0.5, -0.22, 0}, {1, 0, 0, 0, 1, 0, 0, 0, 1}, 0.1, 0, {0, 0, 0}};
    CHECK(romrt_set_collider(f.m, 0, &c, &rerr) == ROMRT_OK, "a sphere under the bar: %s", rerr.message);
    int n = romrt_shown_count(f.m), ok = 1, k;
    romrt_real *xyz = malloc(sizeof(romrt_real) * 3 * n);
    double nearest = 1;
    for (k = 0; k < 30 && ok; k++) {
        ok = romrt_step(f.m, &rerr) == ROMRT_OK;
        romrt_positions(f.m, xyz, 3 * (size_t)n, 3, NULL);
        for (int i = 0; i < n; i++) {
            double d2 = 0;
            for (int a = 0; a < 3; a++) d2 += ((double)xyz[3 * i + a] - centre[a]) * ((double)xyz[3 * i + a] - centre[a]);
            nearest = fmin(nearest, sqrt(d2) - radius);
        }
    }
    CHECK(ok, "step %d: %s", k, rerr.message);
    printf("# a sphere collider under the adaptive bar: nearest shown vertex %.3g m outside it\n", nearest);
    CHECK(nearest > 0, "a shown vertex entered the sphere (%g m)", nearest);
    CHECK(nearest < 0.01, "the bar never came near the sphere (%g m): the test shows nothing", nearest);
    free(xyz);
    fixture_close(&f);
}

TEST(surface_and_cubature_vertices_as_accurate)
{
    rk_error err = {{0}};
    fixture f;
    rk_fom fom;
    int failed;
    double err_rt = 0, err_pc = 0;
    CHECK_OK(fixture_open(&f, bar("surface", 1), &err));
    CHECK_OK(rk_fom_init(&fom, &f.sim.fem, &f.sim.options, &err));
    double rel = run_both(&f, 30, &fom, &err_rt, &err_pc, &err, &failed);
    CHECK(!failed, "%s", err.msg);
    printf("# surface and cubature vertices stored (%d of %d), 30 steps: largest error against full order %.3g "
           "(the precompute's, every vertex: %.3g); %.3g apart\n",
           (int)romrt_shown_count(f.m), f.sim.mesh.nv, err_rt, err_pc, rel);
    CHECK(err_rt < 2 * err_pc + 0.02, "the runtime's error %.3g against the precompute's %.3g", err_rt, err_pc);
    rk_fom_free(&fom);
    fixture_close(&f);
}

/* Positions of the shown vertices after `steps` steps, with a push on the middle group. */
static void stepped(romrt_model *m, int steps, const romrt_real *push, romrt_real *xyz)
{
    romrt_error rerr;
    size_t g;
    if (push && (romrt_find_group(m, "middle", &g, &rerr) || romrt_add_force(m, g, push, &rerr)))
        CHECK(0, "push: %s", rerr.message);
    for (int k = 0; k < steps; k++) romrt_step(m, &rerr);
    romrt_positions(m, xyz, 3 * (size_t)(romrt_shown_count(m)), 3, NULL);
}

TEST(push_reset_and_refusals)
{
    rk_error err = {{0}};
    fixture f;
    CHECK_OK(fixture_open(&f, bar("surface", 0), &err));
    int n = romrt_shown_count(f.m);
    romrt_real *a = malloc(sizeof(romrt_real) * 3 * n), *b = malloc(sizeof(romrt_real) * 3 * n);
    const romrt_real push[3] = {0, 0, 50};
    stepped(f.m, 10, NULL, a);
    romrt_reset(f.m, NULL);
    stepped(f.m, 10, NULL, b);
    double same = 0, moved = 0, side = 0;
    for (int i = 0; i < 3 * n; i++) same = fmax(same, fabs((double)a[i] - b[i]));
    CHECK(same == 0, "after romrt_reset the same steps land %g m apart", same);
    romrt_reset(f.m, NULL);
    stepped(f.m, 10, push, b);
    for (int i = 0; i < 3 * n; i++) moved = fmax(moved, fabs((double)a[i] - b[i]));
    for (int i = 2; i < 3 * n; i += 3) side = fmax(side, (double)b[i] - a[i]);
    CHECK(moved > 1e-3 && side > 1e-3, "a 50 N push along z moved the bar %g m (%g along z)", moved, side);
    /* the state saved after 10 steps and restored gives the same next 5 steps (to round-off: the
     * clock restarts from t0 = 10 h, so the prescribed targets' times round differently; a float
     * state keeps the double displacements to about 48 bits) */
    int ns = romrt_state_size(f.m);
    romrt_real *state = malloc(sizeof(romrt_real) * ns), *again = malloc(sizeof(romrt_real) * 3 * n);
    romrt_reset(f.m, NULL);
    stepped(f.m, 10, NULL, a);
    CHECK(romrt_get_state(f.m, state, ns, NULL) == ROMRT_OK, "get_state");
    stepped(f.m, 5, NULL, b);
    stepped(f.m, 7, NULL, again); /* elsewhere */
    CHECK(romrt_set_state(f.m, state, ns, NULL) == ROMRT_OK, "set_state");
    stepped(f.m, 5, NULL, again);
    double back = 0, size = 0;
    for (int i = 0; i < 3 * n; i++) {
        back = fmax(back, fabs((double)b[i] - again[i]));
        size = fmax(size, fabs((double)b[i]));
    }
    printf("# state restored after 10 steps: 5 more steps land %.3g m from the first time\n", back);
    CHECK(back < (sizeof(romrt_real) == 8 ? 1e-12 : 1e-6) * size, "restored state drifts by %g m", back);
    state[3] = (romrt_real)1e6; /* the ring's count past m */
    CHECK(romrt_set_state(f.m, state, ns, NULL) == ROMRT_E_ARGUMENT, "a ring count past m is refused");
    free(state);
    free(again);
    const romrt_real huge[3] = {0, 0, (romrt_real)(sizeof(romrt_real) == 4 ? 3e38 : 1e308)};
    romrt_add_vertex_force(f.m, 0, huge, NULL);
    CHECK(romrt_add_vertex_force(f.m, 0, huge, NULL) == ROMRT_E_ARGUMENT, "a force whose sum overflows is refused");
    /* a corrupted history length: refused at open, naming the chunk */
    rombin_file file;
    rombin_chunk c;
    rombin_error re;
    CHECK(!rombin_open(&file, f.baked.data, f.baked.bytes, NULL, &re) && rombin_find(&file, ROMBIN_ALRH, &c), "ALRH");
    uint32_t *head = (uint32_t *)(void *)(f.baked.data + (c.data - f.baked.data));
    head[ROMBIN_ALRH_PAIRS] += 1;
    size_t need;
    romrt_error rerr;
    romrt_status st = romrt_arena_size(f.baked.data, f.baked.bytes, &need, &rerr);
    CHECK(st != ROMRT_OK, "a damaged ALRH is refused");
    free(a);
    free(b);
    fixture_close(&f);
}

/* The Newton matrix kept across steps in the moving basis (runtime/alrom_keep.c: carried into each
 * new basis by the M-orthogonal projection, the inertia exact), under the default a fixed basis
 * gets (up to 10 steps): the same steps to the solve's tolerance (1e-9 here; the gradient is the
 * new basis' own at every iteration) as a fresh matrix at every iteration, with far fewer
 * factorizations. In double one matrix serves the 10 steps (a carry that got the coordinates
 * wrong would be rebuilt at once, at least once a step); in float the floor's rule (step.c) ends
 * each step on a fresh matrix, and the carried one serves the next step's first iterations. Over
 * 10 steps, as the parity test above: the blended steps' growth (up to 1.02 a step) and the
 * history's rank decisions let two runs that differ by round-off part further in longer ones. */
static void steps_counted(romrt_model *m, int steps, long *iterations, long *factorizations, romrt_real *xyz)
{
    romrt_step_info info;
    info.size = sizeof info;
    romrt_error rerr;
    *iterations = *factorizations = 0;
    for (int k = 0; k < steps; k++) {
        CHECK(romrt_step(m, &rerr) == ROMRT_OK, "step %d: %s", k, rerr.message);
        romrt_last_step(m, &info, NULL);
        *iterations += (long)info.newton_iterations;
        *factorizations += (long)info.factorizations;
    }
    romrt_positions(m, xyz, 3 * (size_t)(romrt_shown_count(m)), 3, NULL);
}

TEST(kept_newton_matrix_meets_the_same_tolerance)
{
    rk_error err = {{0}};
    fixture f;
    romrt_step_info info;
    info.size = sizeof info;
    CHECK_OK(fixture_open(&f, bar("all", 1), &err));
    int n = romrt_shown_count(f.m);
    romrt_real *a = malloc(sizeof(romrt_real) * 3 * n), *b = malloc(sizeof(romrt_real) * 3 * n);
    long it_fresh, fact_fresh, it_kept, fact_kept;
    romrt_last_step(f.m, &info, NULL);
    CHECK(info.hessian_reuse == 10, "the adaptive model's default reuse is %zu steps, not 10", info.hessian_reuse);
    CHECK(romrt_set_hessian_reuse(f.m, 1, NULL) == ROMRT_OK, "reuse 1");
    steps_counted(f.m, 10, &it_fresh, &fact_fresh, a);
    romrt_reset(f.m, NULL);
    CHECK(romrt_set_hessian_reuse(f.m, 10, NULL) == ROMRT_OK, "reuse 10");
    steps_counted(f.m, 10, &it_kept, &fact_kept, b);
    double apart = 0, size = 0;
    for (int i = 0; i < 3 * n; i++) {
        apart = fmax(apart, fabs((double)a[i] - b[i]));
        size = fmax(size, fabs((double)a[i]));
    }
    printf("# kept Newton matrix, 10 steps: %ld iterations, %ld factorizations (fresh: %ld, %ld); %.3g m apart "
           "(largest coordinate %.3g)\n", it_kept, fact_kept, it_fresh, fact_fresh, apart, size);
#ifdef ROMRT_DOUBLE
    CHECK(fact_kept <= 5, "the kept matrix was rebuilt %ld times in 10 steps", fact_kept);
#endif
    CHECK(fact_kept * 2 <= fact_fresh, "the kept matrix served little: %ld factorizations against %ld", fact_kept,
          fact_fresh);
    CHECK(apart <= PARITY_TOL * size, "the kept matrix's steps land %g m from the fresh ones", apart);
    free(a);
    free(b);
    fixture_close(&f);
}

int main(void)
{
    RUN(every_vertex_stored_takes_the_precompute_steps);
    RUN(step_rows_are_the_k_space_basis);
    RUN(crom_decoder_takes_the_precompute_steps);
    RUN(a_collider_holds_the_adaptive_bar);
    RUN(surface_and_cubature_vertices_as_accurate);
    RUN(push_reset_and_refusals);
    RUN(kept_newton_matrix_meets_the_same_tolerance);
    return test_finish();
}
