/* The adaptive linear ROM's basis cadence (issue 33; runtime/alrom.c, ALRH's cadence K): the
 * basis is formed every K steps and held between. Asserted on test_runtime_alrom_growth's bar:
 *   - cadence 1 bakes the asset the scene without it does, byte for byte (today's step);
 *   - K = 3's first step (a refresh) is K = 1's, bit for bit;
 *   - its basis rows are the same after steps 1, 2 and 3 (held) and change at step 4 (refreshed),
 *     while K = 1's change at step 2: the held basis is reused, and only between refreshes;
 *   - a state set (romrt_set_state) forms the basis afresh at the next step;
 *   - the encoder's iteration cap reaches the asset and the run (1 iteration moves the steps);
 *   - the precompute's simulator (precompute/grassmann/alrom.c) takes the same cadence: K = 3's
 *     first step is K = 1's, it forms (and blends) its basis on a third of the steps only, and its
 *     run parts from K = 1's. */
#include "testlib.h"
#include "pipeline/pipeline.h"
#include "pipeline/method_adaptive_linear.h"
#include "runtime/romrt.h"

#include <stdint.h>

#ifdef ROMRT_DOUBLE
#define ASSET_REAL "float64"
#else
#define ASSET_REAL "float32"
#endif

static const char *bar(const char *extra)
{
    static char json[2048];
    snprintf(json, sizeof json,
             "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1, 0.2, 0.2], \"cells\": [10, 2, 2]}},"
             " \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000},"
             " \"fixed\": [{\"box\": [[-1, -1, -1], [0.01, 2, 2]]}],"
             " \"moving\": [{\"box\": [[0.99, -1, -1], [2, 2, 2]], \"translate\": {\"velocity\": [0, -0.5, 0.3]}}]}],"
             " \"gravity\": [0, -9.81, 0], \"lumped_mass\": true, \"newton\": {\"tolerance\": 1e-10},"
             " \"time\": {\"step\": 0.01, \"duration\": 0.3, \"integrator\": \"backward_euler\"},"
             " \"rom\": {\"method\": \"adaptive_linear\", \"size\": 6, \"decoder\": \"quadratic_pod\", \"history\": 8 %s,"
             "  \"asset\": {\"show\": \"all\", \"precision\": \"%s\"}}}",
             extra, ASSET_REAL);
    return json;
}

static int bake(const char *extra, rk_baked *out, rk_error *err)
{
    rk_scene scene;
    rk_bake_request req = {0};
    memset(out, 0, sizeof *out);
    if (rk_scene_parse(bar(extra), "cadence.json", &scene, err)) return -1;
    int rc = rk_scene_bake(&scene, &scene.entries[0], &req, out, err);
    rk_scene_free(&scene);
    return rc;
}

typedef struct {
    rk_baked baked;
    void *arena;
    romrt_model *m;
    size_t nshown, r, nrows;
} run;

static int run_open(run *x, const char *extra, rk_error *err)
{
    romrt_error rerr;
    size_t need;
    memset(x, 0, sizeof *x);
    if (bake(extra, &x->baked, err)) return -1;
    if (romrt_arena_size(x->baked.data, x->baked.bytes, &need, &rerr)) return rk_fail(err, "runtime: %s", rerr.message);
    x->arena = aligned_alloc(16, (need + 15) / 16 * 16);
    if (romrt_open(x->baked.data, x->baked.bytes, x->arena, need, &x->m, &rerr))
        return rk_fail(err, "runtime: %s", rerr.message);
    x->nshown = romrt_shown_count(x->m);
    x->r = romrt_reduced_size(x->m);
    x->nrows = 3 * x->nshown * x->r;
    return 0;
}

static void run_close(run *x)
{
    free(x->arena);
    rk_baked_free(&x->baked);
}

/* One step, then the shown positions and the basis rows it used. */
static int step(run *x, romrt_real *pos, romrt_real *rows, rk_error *err)
{
    romrt_error rerr;
    if (romrt_step(x->m, &rerr) || romrt_positions(x->m, pos, 3 * x->nshown, 3, &rerr) ||
        romrt_basis_rows(x->m, rows, x->nrows, &rerr))
        return rk_fail(err, "runtime: %s", rerr.message);
    return 0;
}

static int same(const romrt_real *a, const romrt_real *b, size_t n) { return !memcmp(a, b, sizeof(romrt_real) * n); }

TEST(cadence_one_is_todays_asset)
{
    rk_error err = {{0}};
    rk_baked a, b;
    CHECK_OK(bake("", &a, &err));
    CHECK_OK(bake(", \"cadence\": 1, \"encoder_iterations\": 20", &b, &err));
    CHECK(a.bytes == b.bytes && !memcmp(a.data, b.data, a.bytes), "cadence 1 changed the asset (%zu vs %zu bytes)",
          a.bytes, b.bytes);
    rk_baked_free(&a);
    rk_baked_free(&b);
}

TEST(a_held_basis_is_reused_between_refreshes)
{
    rk_error err = {{0}};
    run one, three;
    CHECK_OK(run_open(&one, "", &err));
    CHECK_OK(run_open(&three, ", \"cadence\": 3", &err));
    size_t np = 3 * one.nshown, nr = one.nrows;
    romrt_real *buf = malloc(sizeof(romrt_real) * (2 * np + 6 * nr)), *p1 = buf, *p3 = p1 + np, *r1[2], *r3[4];
    r1[0] = p3 + np, r1[1] = r1[0] + nr;
    r3[0] = r1[1] + nr, r3[1] = r3[0] + nr, r3[2] = r3[1] + nr, r3[3] = r3[2] + nr;
    for (int t = 0; t < 4; t++) { /* a few steps in, so that the history blends: steps 5..8 */
        CHECK_OK(step(&one, p1, r1[0], &err));
        CHECK_OK(step(&three, p3, r3[0], &err));
    }
    CHECK(!same(p1, p3, np), "K = 3 stepped as K = 1 over 4 steps: the cadence did nothing");
    /* both from K = 1's state: the set state is refreshed at the next step in either */
    romrt_error rerr;
    size_t ns = romrt_state_size(one.m);
    romrt_real *s = malloc(sizeof(romrt_real) * ns);
    CHECK(!romrt_get_state(one.m, s, ns, &rerr) && !romrt_set_state(one.m, s, ns, &rerr) && /* (its Newton matrix
                                                                                               * fresh too) */
              !romrt_set_state(three.m, s, ns, &rerr),
          "state: %s", rerr.message);
    CHECK_OK(step(&one, p1, r1[0], &err));
    CHECK_OK(step(&three, p3, r3[0], &err));
    CHECK(same(p1, p3, np), "a refreshed step of K = 3 is not K = 1's from the same state");
    CHECK(same(r1[0], r3[0], nr), "a refreshed basis of K = 3 is not K = 1's from the same state");
    CHECK_OK(step(&one, p1, r1[1], &err));
    for (int t = 1; t < 4; t++) CHECK_OK(step(&three, p3, r3[t], &err));
    CHECK(!same(r1[0], r1[1], nr), "K = 1's basis did not move in a step: the test shows nothing");
    CHECK(same(r3[0], r3[1], nr) && same(r3[0], r3[2], nr), "K = 3's basis moved in a held step");
    CHECK(!same(r3[0], r3[3], nr), "K = 3's basis was not refreshed after 3 steps");
    for (size_t i = 0; i < np; i++) CHECK(isfinite((double)p3[i]), "position %zu is not finite", i);
    free(s);
    free(buf);
    run_close(&one);
    run_close(&three);
}

TEST(the_encoder_cap_reaches_the_run)
{
    rk_error err = {{0}};
    run full, capped;
    CHECK_OK(run_open(&full, "", &err));
    CHECK_OK(run_open(&capped, ", \"encoder_iterations\": 1", &err));
    size_t np = 3 * full.nshown, nr = full.nrows;
    romrt_real *buf = malloc(sizeof(romrt_real) * (2 * np + 2 * nr));
    int differ = 0;
    for (int t = 0; t < 10; t++) {
        CHECK_OK(step(&full, buf, buf + 2 * np, &err));
        CHECK_OK(step(&capped, buf + np, buf + 2 * np + nr, &err));
        differ |= !same(buf, buf + np, np);
    }
    CHECK(differ, "one encoder iteration stepped as twenty over 10 steps: the cap did not reach the encoder");
    free(buf);
    run_close(&full);
    run_close(&capped);
}

/* The precompute's simulator on the bar with the entry's options and cadence K: positions after
 * step 1 and after `steps` into x1 and xt, and the steps whose basis blended the history. */
#define BAR_NV (11 * 3 * 3) /* the bar's 10 x 2 x 2 cells' vertices */

static int precompute_run(int cadence, int steps, double *x1, double *xt, long *blended, rk_error *err)
{
    rk_scene scene;
    rk_scene_sim sim;
    rk_decoder dec = {0};
    rk_alrom A = {0};
    int rc = -1, stage = 0;
    if (rk_scene_parse(bar(""), "cadence.json", &scene, err)) return -1;
    stage = 1;
    if (rk_scene_build(&scene, &sim, err)) goto out;
    stage = 2;
    if (sim.mesh.nv != BAR_NV) {
        rk_fail(err, "the bar has %d vertices, the test's buffers %d", sim.mesh.nv, BAR_NV);
        goto out;
    }
    rk_alrom_options o = rk_adaptive_linear_of(&scene.entries[0])->opt;
    o.cadence = cadence;
    if (rk_scene_alrom_decoder(&scene, &sim, &scene.entries[0], NULL, 0, &dec, err) ||
        rk_alrom_init(&A, &sim.fem, &sim.options, &dec, &o, err))
        goto out;
    for (int t = 0; t < steps; t++) {
        if (rk_alrom_step(&A, err)) goto out;
        if (t == 0) memcpy(x1, A.fom.x, sizeof(double) * 3 * (size_t)sim.mesh.nv);
    }
    memcpy(xt, A.fom.x, sizeof(double) * 3 * (size_t)sim.mesh.nv);
    *blended = A.stats.history_used;
    rc = 0;
out:
    rk_alrom_free(&A);
    rk_decoder_free(&dec);
    if (stage >= 2) rk_scene_sim_free(&sim);
    rk_scene_free(&scene);
    return rc;
}

TEST(the_precompute_simulator_takes_the_cadence)
{
    rk_error err = {{0}};
    static double a1[3 * BAR_NV], at[3 * BAR_NV], b1[3 * BAR_NV], bt[3 * BAR_NV];
    long blended_one, blended_three;
    CHECK_OK(precompute_run(1, 9, a1, at, &blended_one, &err));
    CHECK_OK(precompute_run(3, 9, b1, bt, &blended_three, &err));
    printf("# precompute, 9 steps: history blended in %ld (K = 1), %ld (K = 3)\n", blended_one, blended_three);
    CHECK(!memcmp(a1, b1, sizeof a1), "K = 3's first step is not K = 1's");
    CHECK(memcmp(at, bt, sizeof at), "K = 3 stepped as K = 1 over 9 steps");
    CHECK(blended_one >= 7, "K = 1 blended only %ld of 9 steps: the test shows nothing", blended_one);
    CHECK(blended_three >= 1 && blended_three <= 3, "K = 3 blended %ld of 9 steps (3 refreshes)", blended_three);
}

int main(void)
{
    RUN(cadence_one_is_todays_asset);
    RUN(a_held_basis_is_reused_between_refreshes);
    RUN(the_encoder_cap_reaches_the_run);
    RUN(the_precompute_simulator_takes_the_cadence);
    return test_finish();
}
