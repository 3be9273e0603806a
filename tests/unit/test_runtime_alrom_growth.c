/* The adaptive linear ROM's free run does not amplify its errors (issue 33). At every step of a
 * driven bend the state (u, v) is perturbed, stepped once beside the run, and the perturbation's
 * energy norm |dv|_M^2 + |du|_K^2 (M the mass, K the rest stiffness) after the step is divided by
 * that before: the step's growth factor, the largest over a short power iteration
 * (precompute/grassmann/growth.c). It must be at most 1 + TOL at every step, the blended ones
 * included: in the precompute's simulator (double) and in the runtime (this file's float build,
 * and test_runtime_alrom_growth_double). The paper's step (Eq. 13: ridge and budget 0) multiplies
 * a perturbation by far more on the same bend; asserted, so the test sees the difference.
 *
 * TOL: the budget (the scene's default, 0.01) bounds what the history adds to first order
 * (history_ridge in precompute/grassmann/alrom.c; measured 1.25 budget on the armadillo), and a
 * fixed basis (PCA's) already departs from the linear theory's 1 by the elasticity's nonlinearity
 * (the norm's K is the rest stiffness; 1.0014 on the armadillo's bend): 1 + 2 budget covers both. */
#include "testlib.h"
#include "pipeline/pipeline.h"
#include "pipeline/method_adaptive_linear.h"
#include "formats/rombin_read.h"
#include "runtime/romrt.h"

#include <stdint.h>

#ifdef ROMRT_DOUBLE
#define ASSET_REAL "float64"
#define EPS 1e-6
#else
#define ASSET_REAL "float32"
/* well above float's round-off in the solve (at 1e-3 it reads 1.022, at 1e-4 2.75), and still a
 * linearisation: the double build at 1e-6 reads the same growth to 1e-4 */
#define EPS 1e-2
#endif
#define BUDGET 0.01 /* the default (rk_alrom_default_options) */
#define TOL (2 * BUDGET)
#define STATE_HEAD 3 /* the clock's pair and have_prev (runtime/access.c) */

/* A bar clamped at x = 0 whose far end is driven down and sideways under gravity, the quadratic
 * decoder of 6 modes, a history of 8 steps (test_runtime_alrom.c's bend); `extra`: more keys. */
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

typedef struct {
    rk_scene scene;
    rk_scene_sim sim;
    rk_sparse M, K;
    int stage;
} scene_fixture;

static int scene_open(scene_fixture *f, const char *json, rk_error *err)
{
    memset(f, 0, sizeof *f);
    if (rk_scene_parse(json, "growth.json", &f->scene, err)) return -1;
    f->stage = 1;
    if (rk_scene_build(&f->scene, &f->sim, err)) return -1;
    f->stage = 2;
    if (rk_sparse_alloc_pattern(&f->sim.fem, &f->M, err) || rk_sparse_alloc_pattern(&f->sim.fem, &f->K, err)) return -1;
    rk_fem_add_mass(&f->sim.fem, f->sim.options.lumped_mass, 1.0, &f->M);
    rk_fem_add_rest_stiffness(&f->sim.fem, 1.0, &f->K);
    return 0;
}

static void scene_close(scene_fixture *f)
{
    rk_sparse_free(&f->M);
    rk_sparse_free(&f->K);
    if (f->stage >= 2) rk_scene_sim_free(&f->sim);
    if (f->stage >= 1) rk_scene_free(&f->scene);
}

/* The precompute's simulator: the largest growth over the run's steps, and over its blended ones. */
static int precompute_growth(const char *extra, double *worst, long *blended, rk_error *err)
{
    scene_fixture f;
    rk_decoder dec = {0};
    rk_alrom A = {0}, pre = {0}, probe = {0};
    int rc = -1;
    *worst = 0;
    if (scene_open(&f, bar(extra), err)) goto out;
    const rk_rom_entry *e = &f.scene.entries[0];
    const rk_alrom_options *o = &rk_adaptive_linear_of(e)->opt;
    if (rk_scene_alrom_decoder(&f.scene, &f.sim, e, NULL, 0, &dec, err) ||
        rk_alrom_init(&A, &f.sim.fem, &f.sim.options, &dec, o, err) ||
        rk_alrom_init(&pre, &f.sim.fem, &f.sim.options, &dec, o, err) ||
        rk_alrom_init(&probe, &f.sim.fem, &f.sim.options, &dec, o, err))
        goto out;
    uint64_t seed = 3;
    for (int t = 0; t < f.sim.steps; t++) {
        double g;
        if (rk_alrom_step_growth(&A, &pre, &probe, &f.M, &f.K, 4, 1e-6, &seed, &g, err)) goto out;
        *worst = fmax(*worst, g);
        if (getenv("GROWTH_VERBOSE")) printf("# step %d growth %.4f\n", t + 1, g);
    }
    *blended = A.stats.history_used;
    rc = 0;
out:
    rk_alrom_free(&A);
    rk_alrom_free(&pre);
    rk_alrom_free(&probe);
    rk_decoder_free(&dec);
    scene_close(&f);
    return rc;
}

/* The energy norm of a runtime state's difference (u and v of the stored vertices, every one
 * stored: vmap to the mesh's numbering) */
static double state_norm(const scene_fixture *f, const uint32_t *vmap, const double *du, const double *dv, int nv)
{
    int n = 3 * f->sim.mesh.nv;
    double *a = calloc(2 * (size_t)n, sizeof(double)), *b = a + n;
    for (int i = 0; i < 3 * nv; i++) {
        a[3 * vmap[i / 3] + i % 3] = du[i];
        b[3 * vmap[i / 3] + i % 3] = dv[i];
    }
    double s = sqrt(fmax(0, rk_sparse_dot(&f->K, a, a)) + fmax(0, rk_sparse_dot(&f->M, b, b)));
    free(a);
    return s;
}

/* u_t and v (doubles held as pairs of reals) of a runtime state: pairs from STATE_HEAD + 2 */
static void state_uv(const romrt_real *s, int nv, double *u, double *v)
{
    const romrt_real *p = s + STATE_HEAD + 2;
    for (int i = 0; i < 3 * nv; i++) u[i] = (double)p[2 * i] + (double)p[2 * i + 1];
    p += 6 * nv;
    for (int i = 0; i < 3 * nv; i++) v[i] = (double)p[2 * i] + (double)p[2 * i + 1];
}

static void put_pair(double x, romrt_real *p)
{
    p[0] = (romrt_real)x;
    p[1] = (romrt_real)(x - (double)p[0]);
}

static romrt_status steps(romrt_model *m, int count, romrt_error *err)
{
    romrt_status st = ROMRT_OK;
    for (int k = 0; k < count && !st; k++) st = romrt_step(m, err);
    return st;
}

/* The runtime on the baked bar: the same measurement through romrt_get_state and romrt_set_state,
 * the perturbation made in the quadratic decoder's K-space state (c and w: u's free part is B c, v's
 * B w), its size and growth measured on the u and v get_state forms from them. With a basis
 * cadence K (window K) the perturbation is stepped over K steps, a refresh (romrt_set_state forms
 * the basis afresh, in the perturbed run and the unperturbed alike) and K - 1 steps in the held
 * basis, and the growth is the K-th root of that window's: a step's share. */
static int runtime_growth(const char *extra, int window, double *worst, rk_error *err)
{
    scene_fixture f;
    rk_baked baked = {0};
    void *arena = NULL;
    romrt_model *m = NULL;
    romrt_real *s0 = NULL;
    double *buf = NULL;
    romrt_error rerr;
    int rc = -1;
    *worst = 0;
    if (scene_open(&f, bar(extra), err)) goto out;
    rk_bake_request req = {0};
    if (rk_scene_bake(&f.scene, &f.scene.entries[0], &req, &baked, err)) goto out;
    rombin_file file;
    rombin_chunk c;
    rombin_error re;
    if (rombin_open(&file, baked.data, baked.bytes, NULL, &re) || !rombin_find(&file, ROMBIN_VMAP, &c)) {
        rk_fail(err, "the asset has no VMAP");
        goto out;
    }
    const uint32_t *vmap = (const uint32_t *)(const void *)c.data;
    size_t need;
    if (romrt_arena_size(baked.data, baked.bytes, &need, &rerr)) goto rt_fail;
    arena = aligned_alloc(16, (need + 15) / 16 * 16);
    if (romrt_open(baked.data, baked.bytes, arena, need, &m, &rerr)) goto rt_fail;
    int nv = (int)(c.raw / sizeof(uint32_t));
    if (nv != f.sim.mesh.nv) {
        rk_fail(err, "%d of %d vertices stored: the norm needs them all", nv, f.sim.mesh.nv);
        goto out;
    }
    size_t ns = romrt_state_size(m);
    int R = 6 + 6 * 7 / 2; /* the quadratic decoder's K-space: the state is its c and w (runtime/alrom.c) */
    s0 = malloc(sizeof(romrt_real) * 3 * ns);
    buf = malloc(sizeof(double) * (18 * (size_t)nv + 2 * (size_t)R));
    romrt_real *s1 = s0 + ns, *sp = s1 + ns;
    double *u0 = buf, *v0 = u0 + 3 * nv, *u1 = v0 + 3 * nv, *v1 = u1 + 3 * nv, *du = v1 + 3 * nv, *dv = du + 3 * nv;
    double *dk = dv + 3 * nv; /* the perturbation of c then w */
    uint64_t seed = 3;
    for (int i = 0; i < 2 * R; i++) dk[i] = rk_uniform(&seed) - 0.5;
    const size_t at_c = STATE_HEAD + 2 + 12 * (size_t)nv; /* after u and v, pairs each */
    for (int t = 0; t + window <= f.sim.steps; t += window) {
        if (romrt_get_state(m, s0, ns, &rerr) || steps(m, window, &rerr) || romrt_get_state(m, s1, ns, &rerr)) goto rt_fail;
        state_uv(s0, nv, u0, v0);
        state_uv(s1, nv, u1, v1);
        double size = EPS * fmax(state_norm(&f, vmap, u0, v0, nv), 1e-3);
        for (int k = 0; k < 4; k++) {
            double d = 0, scale = 1;
            for (int pass = 0; pass < 2; pass++) { /* its norm in u and v (B c, B w), then scaled to size */
                memcpy(sp, s0, sizeof(romrt_real) * ns);
                for (int i = 0; i < 2 * R; i++) {
                    romrt_real *p = sp + at_c + 2 * (size_t)i;
                    put_pair((double)p[0] + (double)p[1] + scale * dk[i], p);
                }
                if (romrt_set_state(m, sp, ns, &rerr)) goto rt_fail;
                if (pass == 1) break;
                if (romrt_get_state(m, sp, ns, &rerr)) goto rt_fail;
                state_uv(sp, nv, du, dv);
                for (int i = 0; i < 3 * nv; i++) du[i] -= u0[i], dv[i] -= v0[i];
                d = state_norm(&f, vmap, du, dv, nv);
                if (!(d > 0)) break;
                scale = size / d;
            }
            if (!(d > 0)) break;
            if (steps(m, window, &rerr) || romrt_get_state(m, sp, ns, &rerr)) goto rt_fail;
            state_uv(sp, nv, du, dv);
            for (int i = 0; i < 3 * nv; i++) du[i] -= u1[i], dv[i] -= v1[i];
            *worst = fmax(*worst, pow(state_norm(&f, vmap, du, dv, nv) / size, 1.0 / window)); /* a step's share */
            for (int i = 0; i < 2 * R; i++) { /* the next direction: the perturbation stepped */
                const romrt_real *p = sp + at_c + 2 * (size_t)i, *q = s1 + at_c + 2 * (size_t)i;
                dk[i] = ((double)p[0] - (double)q[0]) + ((double)p[1] - (double)q[1]);
            }
        }
        if (romrt_set_state(m, s1, ns, &rerr)) goto rt_fail;
    }
    rc = 0;
    goto out;
rt_fail:
    rk_fail(err, "runtime: %s", rerr.message);
out:
    free(s0);
    free(buf);
    free(arena);
    rk_baked_free(&baked);
    scene_close(&f);
    return rc;
}

TEST(the_precompute_step_does_not_amplify_a_perturbation)
{
    rk_error err = {{0}};
    double now, paper;
    long blended, blended_paper;
    CHECK_OK(precompute_growth("", &now, &blended, &err));
    CHECK_OK(precompute_growth(", \"ridge\": 0, \"budget\": 0", &paper, &blended_paper, &err));
    printf("# precompute, double: largest growth per step %.4f (%ld of 30 steps blended; tol 1 + %g); the paper's "
           "Eq. 13 %.4g (%ld blended)\n",
           now, blended, TOL, paper, blended_paper);
    CHECK(blended >= 20, "the history was blended in only %ld steps: the test shows nothing", blended);
    CHECK(now <= 1 + TOL, "a step multiplies a perturbation by %.4f", now);
    CHECK(now >= 0.9, "growth %.4f: the perturbation vanished, the measurement is broken", now);
    CHECK(paper > 2, "the paper's step grows a perturbation only %.4f: the test would not see a regression", paper);
}

TEST(the_runtime_step_does_not_amplify_a_perturbation)
{
    rk_error err = {{0}};
    double now, paper;
    CHECK_OK(runtime_growth("", 1, &now, &err));
    CHECK_OK(runtime_growth(", \"ridge\": 0, \"budget\": 0", 1, &paper, &err));
    printf("# runtime, %s: largest growth per step %.4f (tol 1 + %g); the paper's Eq. 13 %.4g\n", ASSET_REAL, now, TOL,
           paper);
    CHECK(now <= 1 + TOL, "a runtime step multiplies a perturbation by %.4f", now);
    CHECK(now >= 0.9, "growth %.4f: the perturbation vanished, the measurement is broken", now);
    CHECK(paper > 2, "the paper's runtime step grows a perturbation only %.4f", paper);
}

/* With a basis cadence (issue 33: the basis formed every K steps, held between): a refresh and the
 * held steps after it, over a window of K steps, grow a perturbation by at most (1 + TOL)^K. */
TEST(the_runtime_step_with_a_cadence_does_not_amplify_a_perturbation)
{
    rk_error err = {{0}};
    double now;
    CHECK_OK(runtime_growth(", \"cadence\": 4", 4, &now, &err));
    printf("# runtime, %s, cadence 4: largest growth per step over a refresh and its held steps %.4f (tol 1 + %g)\n",
           ASSET_REAL, now, TOL);
    CHECK(now <= 1 + TOL, "a cadence-4 window multiplies a perturbation by %.4f a step", now);
    CHECK(now >= 0.9, "growth %.4f: the perturbation vanished, the measurement is broken", now);
}

int main(void)
{
    RUN(the_precompute_step_does_not_amplify_a_perturbation);
    RUN(the_runtime_step_does_not_amplify_a_perturbation);
    RUN(the_runtime_step_with_a_cadence_does_not_amplify_a_perturbation);
    return test_finish();
}
