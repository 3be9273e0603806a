/* Koopman/DMD on full-order runs of a box cantilever (koopman-dmd-log-linear paper):
 *   1. force generalization (Sec. 6.2, Fig. 5 and Fig. 10): trained on one gravity magnitude
 *      (and on two directions), tested on 0.5x, 2x and an unseen direction against the
 *      full-order run; neo-Hookean and linear material;
 *   2. a jump of N steps with the constant gravity impulse (Sec. 4.3, Eq. 20) equals N single
 *      steps;
 *   3. time-step invariance (Sec. 4.3 Eq. 21, Sec. 6.1 Fig. 2): the model at h and at 10 h gives
 *      the same kinetic energy over time, while backward Euler at 10 h is visibly damped;
 *   4. hard cases: a body standing still, a rank above the data's, noisy data with the clamp.
 *
 * Rollouts follow Eq. 19: per step z <- K'(z + [0; a h^2]) (rk_koopman_impulse, then
 * rk_koopman_advance by one step). The rescaled rollouts here are unforced; under a force, a
 * step of s h is s training steps with the impulse before each (rk_koopman_forced; the runtime
 * sums it in closed form, runtime/koopman.c). */
#include <complex.h>

#include "testlib.h"
#include "util/util.h"
#include "koopman/koopman.h"
#include "pipeline/pipeline.h"
#include "pipeline/method_koopman.h"
#include "mesh/mesh.h"
#include "pipeline/pipeline.h"

/* The measurement noise: the project's generator (util/util.h), the same everywhere. */
static uint64_t rng = 11;

#define G0 9.81

/* ---------------------------------------------------------------- scenes */

/* A box cantilever along x, 1 x 0.2 x 0.2 m, 12 x 2 x 2 cells (117 vertices), clamped at x = 0. */
typedef struct {
    const char *model;     /* "neohookean" or "linear" */
    double young;          /* Pa */
    double h, duration;    /* s */
    double damping_mass, damping_stiffness;
} beam_spec;

typedef struct {
    rk_scene scene;
    rk_scene_sim sim;
    int ready;
} beam;

static int beam_open(beam *b, const beam_spec *s, rk_error *err)
{
    char json[1024];
    snprintf(json, sizeof json,
             "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1, 0.2, 0.2], \"cells\": [12, 2, 2]}},"
             " \"material\": {\"model\": \"%s\", \"young\": %.17g, \"poisson\": 0.35, \"density\": 1000},"
             " \"fixed\": [{\"box\": [[-1, -1, -1], [0.001, 1, 1]]}]}],"
             " \"gravity\": [0, %.17g, 0], \"damping\": {\"mass\": %.17g, \"stiffness\": %.17g},"
             " \"time\": {\"step\": %.17g, \"duration\": %.17g}}",
             s->model, s->young, -G0, s->damping_mass, s->damping_stiffness, s->h, s->duration);
    memset(b, 0, sizeof *b);
    if (rk_scene_parse(json, "cantilever.json", &b->scene, err)) return -1;
    if (rk_scene_build(&b->scene, &b->sim, err)) {
        rk_scene_free(&b->scene);
        return -1;
    }
    b->ready = 1;
    return 0;
}

static void beam_close(beam *b)
{
    if (!b->ready) return;
    rk_scene_sim_free(&b->sim);
    rk_scene_free(&b->scene);
    b->ready = 0;
}

static rk_koopman_variation gravity_along(double gx, double gy, double gz)
{
    rk_koopman_variation v;
    memset(&v, 0, sizeof v);
    v.has_gravity = 1;
    v.gravity[0] = gx;
    v.gravity[1] = gy;
    v.gravity[2] = gz;
    v.load_scale = 1;
    return v;
}

/* ---------------------------------------------------------------- rollouts and errors */

/* z += [0; s a h^2]: the impulse of acceleration a over one step of s h (see the top). */
static void impulse_scaled(const rk_koopman *k, const double *a, double s, double *z, double *tmp)
{
    for (int i = 0; i < k->n; i++) tmp[i] = s * a[i];
    rk_koopman_impulse(k, tmp, z);
}

/* The model rolled out like a full-order run: out gets `frames` frames of n values, frame 0 =
 * u_{-1} and frame 1 = u_0 copied from start (2 frames), then one per step of dt_scale h under
 * the constant acceleration a (NULL: none). */
static void rollout(const rk_koopman *k, const double *start, const double *a, int frames, double dt_scale, double *out)
{
    int n = k->n;
    double *z = calloc((size_t)k->r, sizeof(double)), *tmp = calloc((size_t)n, sizeof(double));
    memcpy(out, start, sizeof(double) * 2 * n);
    rk_koopman_lift(k, start + n, start, z);
    for (int t = 2; t < frames; t++) {
        if (a) impulse_scaled(k, a, dt_scale, z, tmp);
        rk_koopman_advance(k, z, 1, dt_scale, 0);
        rk_koopman_positions(k, z, out + (size_t)n * t);
    }
    free(z);
    free(tmp);
}

typedef struct {
    double percent;  /* 100 sum |du|^2 / sum |u_fom|^2 over frames u_1 .. u_T: the Koopman paper's % MSE,
                      * 100 times the squared relative error of util/util.h */
    double nmse;     /* the normalized MSE of util/util.h over those frames */
    double peak;     /* largest |u_fom| over vertices and frames (m) */
} traj_error;

/* Displacement frames u against fom (frames x 3 nv each, frame 0 the start) on rest positions X. */
static traj_error compare(const double *u, const double *fom, int frames, int nv, const double *X)
{
    int n = 3 * nv;
    double *x = calloc((size_t)n, sizeof(double)), *ref = calloc((size_t)n, sizeof(double)), peak = 0;
    rk_run_error e;
    rk_run_error_init(&e, X, nv);
    for (int t = 1; t < frames; t++) {
        for (int i = 0; i < n; i++) {
            x[i] = X[i] + u[(size_t)n * t + i];
            ref[i] = X[i] + fom[(size_t)n * t + i];
        }
        rk_run_error_add(&e, x, ref);
        for (int p = 0; p < nv; p++) {
            const double *b = fom + (size_t)n * t + 3 * p;
            peak = fmax(peak, sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]));
        }
    }
    free(x);
    free(ref);
    double rel = rk_relative_error(&e);
    return (traj_error){100 * rel * rel, rk_normalized_mse(&e), peak};
}

/* The model from the run's start under the run's acceleration against the run itself. */
static traj_error against_run(const beam *b, const rk_koopman *k, const char *label, const rk_koopman_run *run)
{
    int n = 3 * b->sim.mesh.nv;
    double *u = calloc((size_t)n * run->t.frames, sizeof(double));
    rollout(k, run->u, run->accel, run->t.frames, 1, u);
    traj_error e = compare(u, run->u, run->t.frames, b->sim.mesh.nv, b->sim.mesh.X);
    printf("# %-40s %10.3e %12.3e %10.4f\n", label, e.percent, e.nmse, e.peak);
    free(u);
    return e;
}

static double max_abs_lambda(const rk_koopman *k)
{
    return rk_max_abs_eigenvalue(k->lambda_re, k->lambda_im, k->r);
}

/* The training run most tests share: the neo-Hookean cantilever (E 5 MPa, tip moving about 6%
 * of its length) falling from rest under g0 along -y, 150 steps of 10 ms, mild Rayleigh damping. */
static const beam_spec TRAIN = {"neohookean", 5e6, 0.01, 1.5, 0.5, 0.002};

static struct {
    beam b;
    rk_koopman_run run;
    int ready;
} fixture;

static int fixture_open(rk_error *err)
{
    if (fixture.ready) return 0;
    if (beam_open(&fixture.b, &TRAIN, err)) return -1;
    rk_koopman_variation v = gravity_along(0, -G0, 0);
    if (rk_koopman_scene_run(&fixture.b.sim, &v, &fixture.run, err)) {
        beam_close(&fixture.b);
        return -1;
    }
    fixture.ready = 1;
    return 0;
}

static void fixture_close(void)
{
    if (!fixture.ready) return;
    rk_koopman_run_free(&fixture.run);
    beam_close(&fixture.b);
    fixture.ready = 0;
}

/* ---------------------------------------------------------------- 1. force generalization */

enum { RUN_Y, RUN_Z, RUN_HALF, RUN_TWICE, RUN_DIAG, RUN_TILT, NRUNS };

/* Trains on g0 along -y (magnitude test) and jointly on g0 along -y and -z (direction test, the
 * paper's Fig. 10), then compares each case with its full-order run. pct[i]: the percentage MSE
 * of case i (pct[RUN_Z] unused). ndir: 0, the magnitudes only; 1, and the diagonal direction; 2,
 * and the tilted one. train_y: the -y run if already done on this spec, else NULL. */
static int force_generalization(const beam_spec *s, const rk_koopman_run *train_y, double energy, int ndir,
                                double pct[NRUNS], rk_error *err)
{
    beam b;
    if (beam_open(&b, s, err)) return -1;
    const double r2 = 1 / sqrt(2), r3 = 1 / sqrt(3);
    /* The diagonal (-y - z)/sqrt2 lies in the span of the two trained directions: for the linear
     * model its response is exactly the superposition (run_y + run_z)/sqrt2, so that row measures
     * how far the full-order run is from superposing, which is what Fig. 10 shows. A direction
     * with an x part, (x - y - z)/sqrt3, leaves that span: the model takes its x impulse only
     * through the projection on the data's subspace, and a load along the beam's axis stretches
     * it and (nonlinear material) stiffens it in bending, which no training run shows. Printed
     * for information only. */
    rk_koopman_variation v[NRUNS] = {
        gravity_along(0, -G0, 0),             gravity_along(0, 0, -G0),
        gravity_along(0, -0.5 * G0, 0),       gravity_along(0, -2 * G0, 0),
        gravity_along(0, -G0 * r2, -G0 * r2), gravity_along(G0 * r3, -G0 * r3, -G0 * r3)};
    const char *label[NRUNS] = {"train -y, test 1x -y (seen)",    "",
                                "train -y, test 0.5x -y",         "train -y, test 2x -y",
                                "train -y,-z, test (-y-z)/sqrt2", "train -y,-z, test (x-y-z)/sqrt3 (info)"};
    rk_koopman_run run[NRUNS];
    memset(run, 0, sizeof run);
    rk_koopman k;
    memset(&k, 0, sizeof k);
    int rc = -1, n = 3 * b.sim.mesh.nv;
    int nruns = ndir == 0 ? RUN_DIAG : ndir == 1 ? RUN_TILT : NRUNS;
    for (int i = 0; i < nruns; i++) {
        if ((i == RUN_Y && train_y) || (i == RUN_Z && !ndir)) continue;
        if (rk_koopman_scene_run(&b.sim, &v[i], &run[i], err)) goto done;
    }
    const rk_koopman_run *ry = train_y ? train_y : &run[RUN_Y];
    rk_koopman_options o;
    rk_koopman_default_options(&o);
    o.h = s->h;
    o.energy = energy;
    rk_koopman_trajectory train[2] = {ry->t, run[RUN_Z].t};
    if (rk_koopman_fit(train, 1, n, &o, &k, err)) goto done;
    printf("# %s, E = %g Pa, %d vertices, %d steps of %g s, energy %.9g: rank %d, max |lambda| %.6f\n", s->model,
           s->young, b.sim.mesh.nv, b.sim.steps, s->h, energy, k.r, max_abs_lambda(&k));
    printf("# %-40s %10s %12s %10s\n", "case", "MSE %", "nmse (L^2)", "peak |u| m");
    pct[RUN_Y] = against_run(&b, &k, label[RUN_Y], ry).percent;
    pct[RUN_HALF] = against_run(&b, &k, label[RUN_HALF], &run[RUN_HALF]).percent;
    pct[RUN_TWICE] = against_run(&b, &k, label[RUN_TWICE], &run[RUN_TWICE]).percent;
    rk_koopman_free(&k);
    if (ndir) {
        if (rk_koopman_fit(train, 2, n, &o, &k, err)) goto done;
        printf("# (two directions: rank %d, max |lambda| %.6f)\n", k.r, max_abs_lambda(&k));
        pct[RUN_DIAG] = against_run(&b, &k, label[RUN_DIAG], &run[RUN_DIAG]).percent;
        if (ndir > 1) pct[RUN_TILT] = against_run(&b, &k, label[RUN_TILT], &run[RUN_TILT]).percent;
        rk_koopman_free(&k);
    }
    rc = 0;
done:
    for (int i = 0; i < NRUNS; i++) rk_koopman_run_free(&run[i]);
    beam_close(&b);
    return rc;
}

/* The paper: under 0.5% at 0.5x and 2x (Sec. 6.2). On this moderately deforming beam the data
 * supports that with a margin, and the diagonal direction as well. A beam five times softer (tip
 * moving 30% of its length, 50% at 2x) breaks it: printed as the hard case, not asserted. */
TEST(force_generalization_neohookean)
{
    rk_error err;
    double pct[NRUNS], hard[NRUNS];
    CHECK_OK(fixture_open(&err));
    CHECK_OK(force_generalization(&TRAIN, &fixture.run, 0.999999, 2, pct, &err));
    beam_spec soft = TRAIN;
    soft.young = 1e6;
    printf("# hard case (printed only):\n");
    CHECK_OK(force_generalization(&soft, NULL, 0.999999, 0, hard, &err));
    CHECK(pct[RUN_Y] < 0.01, "the training run itself is reproduced with %.3g%% MSE", pct[RUN_Y]);
    CHECK(pct[RUN_HALF] < 0.5 && pct[RUN_TWICE] < 0.5, "0.5x: %.3g%%, 2x: %.3g%% MSE (paper: under 0.5%%)",
          pct[RUN_HALF], pct[RUN_TWICE]);
    CHECK(pct[RUN_DIAG] < 0.5, "unseen direction: %.3g%% MSE", pct[RUN_DIAG]);
}

/* Linear material: every run is exactly linear in [u; u - u_prev; a], so a model keeping the
 * data's whole numerical rank (energy 1) recovers 0.5x, 2x and any direction in the trained span
 * to round-off. */
TEST(force_generalization_linear_is_exact)
{
    rk_error err;
    double pct[NRUNS];
    beam_spec lin = TRAIN;
    lin.model = "linear";
    CHECK_OK(force_generalization(&lin, NULL, 1.0, 1, pct, &err));
    for (int i = 0; i <= RUN_DIAG; i++)
        CHECK(i == RUN_Z || pct[i] < 1e-6, "linear material, case %d: %.3g%% MSE", i, pct[i]);
}

/* ---------------------------------------------------------------- 2. jumps */

static double max_abs_diff(const double *a, const double *b, int n, double *scale)
{
    double d = 0, s = 0;
    for (int i = 0; i < n; i++) {
        d = fmax(d, fabs(a[i] - b[i]));
        s = fmax(s, fabs(b[i]));
    }
    *scale = s;
    return d;
}

TEST(a_forced_jump_equals_single_steps)
{
    rk_error err;
    CHECK_OK(fixture_open(&err));
    const beam *b = &fixture.b;
    const rk_koopman_run *run = &fixture.run;
    int n = 3 * b->sim.mesh.nv;
    rk_koopman_options o;
    rk_koopman_default_options(&o);
    o.h = TRAIN.h;
    o.clamp = 1;
    /* the full-order static equilibrium under the same gravity, for where the jump ends up
     * (information: 1000 steps of 10 ms with Rayleigh damping have settled) */
    rk_fom fom;
    CHECK_OK(rk_fom_init(&fom, &b->sim.fem, &b->sim.options, &err));
    int st = rk_fom_static(&fom, &err);
    double *equilibrium = calloc((size_t)n, sizeof(double));
    for (int i = 0; i < n; i++) equilibrium[i] = fom.x[i] - b->sim.mesh.X[i];
    rk_fom_free(&fom);
    if (st) free(equilibrium);
    CHECK(st == 0, "static solve: %s", err.msg);
    rk_koopman k;
    CHECK_OK(rk_koopman_fit(&run->t, 1, n, &o, &k, &err));
    int r = k.r;
    double *z1 = calloc((size_t)r, sizeof(double)), *zN = calloc((size_t)r, sizeof(double));
    double *u1 = calloc((size_t)n, sizeof(double)), *uN = calloc((size_t)n, sizeof(double));
    /* start mid-swing (frame 40: u_39, u_38), so both halves of the state are non-zero */
    const double *u = run->u + (size_t)n * 40, *up = run->u + (size_t)n * 39;
    const long long N = 1000;
    rk_koopman_lift(&k, u, up, z1);
    memcpy(zN, z1, sizeof(double) * r);
    for (long long s = 0; s < N; s++) {
        rk_koopman_impulse(&k, run->accel, z1);
        rk_koopman_advance(&k, z1, 1, 1, 0);
    }
    CHECK_OK(rk_koopman_forced(&k, N, run->accel, zN, &err)); /* the closed-form forced map (koopman.h) */
    double zs, us, dz = max_abs_diff(zN, z1, r, &zs);
    rk_koopman_positions(&k, z1, u1);
    rk_koopman_positions(&k, zN, uN);
    double du = max_abs_diff(uN, u1, n, &us);
    double ss, ds = max_abs_diff(uN, equilibrium, n, &ss);
    printf("# rank %d, %d clamped; jump of %lld steps with gravity vs %lld single steps: positions %.2e, "
           "reduced state %.2e (relative, max norm)\n", r, k.clamped, N, N, du / us, dz / zs);
    printf("# the jump's end vs the full-order static equilibrium: %.2e relative (largest |u| %.4f m)\n", ds / ss,
           ss);
    free(z1);
    free(zN);
    free(u1);
    free(uN);
    free(equilibrium);
    rk_koopman_free(&k);
    CHECK(du <= 1e-6 * us && dz <= 1e-6 * zs, "forced jump of %lld: positions off by %.3g, state by %.3g (relative)",
          N, du / us, dz / zs);
}

/* ---------------------------------------------------------------- 3. time-step invariance */

/* 1/2 sum_v m_v |v|^2 for velocities v (3 nv values). */
static double kinetic(const double *mass, int nv, const double *v)
{
    double e = 0;
    for (int p = 0; p < nv; p++)
        e += 0.5 * mass[p] * (v[3 * p] * v[3 * p] + v[3 * p + 1] * v[3 * p + 1] + v[3 * p + 2] * v[3 * p + 2]);
    return e;
}

/* Kinetic energy of each frame 1 .. frames-1 of a displacement trajectory stepped by dt. */
static void run_kinetic(const double *u, int frames, int nv, const double *mass, double dt, double *ke)
{
    int n = 3 * nv;
    double *v = calloc((size_t)n, sizeof(double));
    for (int t = 1; t < frames; t++) {
        for (int i = 0; i < n; i++) v[i] = (u[(size_t)n * t + i] - u[(size_t)n * (t - 1) + i]) / dt;
        ke[t - 1] = kinetic(mass, nv, v);
    }
    free(v);
}

/* The model's kinetic energy over `steps` steps of dt_scale h without forcing, from the lift of
 * (u_0, u_{-1}): the velocity is the state's own velocity part over the data step h (the part
 * is u_t - u_{t-1} in the data's units whatever the step), so ke[0 .. steps]. */
static void model_kinetic(const rk_koopman *k, const double *start, int steps, double dt_scale, const double *mass,
                          double *ke)
{
    int n = k->n, r = k->r;
    double *z = calloc((size_t)r, sizeof(double)), *v = calloc((size_t)n, sizeof(double));
    rk_koopman_lift(k, start + n, start, z);
    for (int t = 0; t <= steps; t++) {
        if (t) rk_koopman_advance(k, z, 1, dt_scale, 0);
        rk_koopman_velocities(k, z, v);
        for (int i = 0; i < n; i++) v[i] /= k->h;
        ke[t] = kinetic(mass, n / 3, v);
    }
    free(z);
    free(v);
}

/* A pluck: the full-order run of b's scene released at rest from positions x0 with gravity
 * switched off, as displacement frames u_{-1} = u_0 = x0 - X, then one per step (frames =
 * steps + 2, the layout rk_koopman_scene_run gives). */
static double *pluck_run(const beam *b, const double *x0, rk_error *err)
{
    int n = 3 * b->sim.mesh.nv, steps = b->sim.steps;
    rk_fom_options opt = b->sim.options;
    memset(opt.gravity, 0, sizeof opt.gravity);
    opt.position0 = (double *)x0;
    opt.velocity0 = NULL;
    rk_fom fom;
    double *u = calloc((size_t)n * (steps + 2), sizeof(double));
    if (!u || rk_fom_init(&fom, &b->sim.fem, &opt, err)) {
        free(u);
        return NULL;
    }
    for (int i = 0; i < n; i++) u[i] = u[n + i] = x0[i] - b->sim.mesh.X[i];
    for (int s = 0; s < steps; s++) {
        if (rk_fom_step(&fom, err)) {
            free(u);
            rk_fom_free(&fom);
            return NULL;
        }
        for (int i = 0; i < n; i++) u[(size_t)n * (s + 2) + i] = fom.x[i] - b->sim.mesh.X[i];
    }
    rk_fom_free(&fom);
    return u;
}

/* Fig. 2: the cantilever bent by its static sag under 2 g0 along -y, then released with gravity
 * off and no Rayleigh damping, so the only loss is backward Euler's own. The model fitted on the
 * run at h and stepped at h and at 10 h (Eq. 21) gives one kinetic-energy curve (with no forcing
 * this is exact by construction: K'^10 either way); backward Euler at 10 h loses nearly all the
 * energy within a few periods. */
TEST(time_step_invariance_against_backward_euler)
{
    rk_error err;
    beam_spec fine = {"neohookean", 5e6, 0.005, 1.0, 0, 0}, coarse = fine;
    coarse.h = 10 * fine.h;
    beam bf, bc;
    CHECK_OK(beam_open(&bf, &fine, &err));
    CHECK_OK(beam_open(&bc, &coarse, &err));
    int nv = bf.sim.mesh.nv, n = 3 * nv, S = bf.sim.steps, Sc = bc.sim.steps;
    rk_fom_options so = bf.sim.options;
    so.gravity[1] = -2 * G0;
    rk_fom st;
    CHECK_OK(rk_fom_init(&st, &bf.sim.fem, &so, &err));
    CHECK_OK(rk_fom_static(&st, &err));
    double *uf = pluck_run(&bf, st.x, &err), *uc = pluck_run(&bc, st.x, &err);
    rk_fom_free(&st);
    CHECK(uf && uc, "pluck run: %s", err.msg);
    rk_koopman_options o;
    rk_koopman_default_options(&o);
    o.h = fine.h;
    o.clamp = 1;
    rk_koopman k;
    rk_koopman_trajectory t = {uf, S + 2, NULL};
    CHECK_OK(rk_koopman_fit(&t, 1, n, &o, &k, &err));
    const double *mass = bf.sim.fem.vertex_mass;
    double *ke_f = calloc((size_t)S + 1, sizeof(double)), *ke_c = calloc((size_t)Sc + 1, sizeof(double));
    double *km_f = calloc((size_t)S + 1, sizeof(double)), *km_c = calloc((size_t)Sc + 1, sizeof(double));
    run_kinetic(uf, S + 2, nv, mass, fine.h, ke_f);
    run_kinetic(uc, Sc + 2, nv, mass, coarse.h, ke_c);
    model_kinetic(&k, uf, S, 1, mass, km_f);
    model_kinetic(&k, uf, Sc, 10, mass, km_c);
    double amp = 0;
    for (int i = 0; i < n; i++) amp = fmax(amp, fabs(uf[n + i]));
    printf("# %d vertices, released from the static sag under 2 g0 (largest |u_i| %.4f m), no gravity, no damping;\n"
           "# h = %g s (%d steps), 10 h = %g s (%d steps); rank %d, %d clamped, max |lambda| %.9f\n",
           nv, amp, fine.h, S, coarse.h, Sc, k.r, k.clamped, max_abs_lambda(&k));
    printf("# %7s %12s %12s %12s %12s\n", "t (s)", "KE fom h", "KE koop h", "KE koop 10h", "KE fom 10h");
    double peak = 0, d_model = 0, d_fom = 0, late_f = 0, late_c = 0;
    int nlate = 0;
    for (int i = 0; i <= S; i++) peak = fmax(peak, ke_f[i]);
    for (int j = 0; j <= Sc; j++) {
        int i = 10 * j;
        printf("# %7.3f %12.5e %12.5e %12.5e %12.5e\n", i * fine.h, ke_f[i], km_f[i], km_c[j], ke_c[j]);
        d_model = fmax(d_model, fabs(km_f[i] - km_c[j]));
        if (3 * j >= 2 * Sc) { /* the last third: after a few periods */
            late_f += ke_f[i];
            late_c += ke_c[j];
            nlate++;
        }
    }
    for (int i = 0; i <= S; i++) d_fom = fmax(d_fom, fabs(km_f[i] - ke_f[i]));
    late_f /= nlate;
    late_c /= nlate;
    printf("# peak KE %.4e J; model at 10 h vs at h: %.2e of the peak; model at h vs full order at h: %.2e of the "
           "peak\n# mean KE over the last third: full order at h %.4e J, at 10 h %.4e J (ratio %.2e)\n",
           peak, d_model / peak, d_fom / peak, late_f, late_c, late_c / late_f);
    free(ke_f);
    free(ke_c);
    free(km_f);
    free(km_c);
    free(uf);
    free(uc);
    rk_koopman_free(&k);
    beam_close(&bf);
    beam_close(&bc);
    CHECK(d_model < 1e-6 * peak, "the model's KE at 10 h differs from that at h by %.3g of the peak", d_model / peak);
    CHECK(d_fom < 0.02 * peak, "the model's KE at h differs from the full-order run's by %.3g of the peak",
          d_fom / peak);
    CHECK(late_c < 0.05 * late_f, "backward Euler at 10 h keeps %.3g of the energy at h: not visibly damped",
          late_c / late_f);
}

/* ---------------------------------------------------------------- 4. hard cases */

/* Repeated frames: the training run's last frame held for 20 frames (rank-deficient data). */
TEST(a_body_standing_still)
{
    rk_error err;
    CHECK_OK(fixture_open(&err));
    int n = 3 * fixture.b.sim.mesh.nv, frames = 20;
    const double *last = fixture.run.u + (size_t)n * (fixture.run.t.frames - 1);
    double *u = calloc((size_t)n * frames, sizeof(double)), *out = calloc((size_t)n * 202, sizeof(double));
    for (int t = 0; t < frames; t++) memcpy(u + (size_t)n * t, last, sizeof(double) * n);
    rk_koopman_options o;
    rk_koopman_default_options(&o);
    o.h = TRAIN.h;
    rk_koopman k;
    /* held under gravity: every pair says K'(X + [0; a h^2]) = X, rank 1, one eigenvalue
     * |u|^2 / (|u|^2 + |a h^2|^2) < 1, and X is the fixed point of the forced rollout */
    rk_koopman_trajectory still = {u, frames, fixture.run.accel};
    CHECK_OK(rk_koopman_fit(&still, 1, n, &o, &k, &err));
    rollout(&k, u, fixture.run.accel, 202, 1, out);
    double s, drift = max_abs_diff(out + (size_t)n * 201, out + (size_t)n * 2, n, &s);
    double off = max_abs_diff(out + (size_t)n * 201, last, n, &s);
    /* The lift keeps X = [u; 0] exactly as the fixed point, but with one basis vector (along
     * [u; a h^2]) the positions read back are u |u|^2 / (|u|^2 + |a h^2|^2): a little short. */
    printf("# standing still under gravity: rank %d, lambda %.12f%+.3gi; 200 steps drift %.2e, positions off the "
           "held frame by %.2e (relative)\n", k.r, k.lambda_re[0], k.lambda_im[0], drift / s, off / s);
    CHECK(k.r == 1 && max_abs_lambda(&k) <= 1 && drift < 1e-9 * s && off < 1e-2 * s,
          "rank %d, |lambda| %.17g, drift %.3g, off by %.3g", k.r, max_abs_lambda(&k), drift / s, off / s);
    rk_koopman_free(&k);
    /* no force: the one eigenvalue is 1, the model stays put */
    still.accel = NULL;
    CHECK_OK(rk_koopman_fit(&still, 1, n, &o, &k, &err));
    CHECK(k.r == 1 && fabs(k.lambda_re[0] - 1) < 1e-12 && k.lambda_im[0] == 0, "no force: rank %d, lambda %.17g",
          k.r, k.lambda_re[0]);
    rk_koopman_free(&k);
    /* a body that never left rest: nothing to learn, said so */
    memset(u, 0, sizeof(double) * n * frames);
    err.msg[0] = 0;
    CHECK(rk_koopman_fit(&still, 1, n, &o, &k, &err) != 0 && strstr(err.msg, "nothing moves"), "all zero: %s",
          err.msg);
    printf("# all frames at rest: \"%s\"\n", err.msg);
    free(u);
    free(out);
}

TEST(a_rank_above_the_data_is_refused)
{
    rk_error err;
    CHECK_OK(fixture_open(&err));
    rk_koopman_trajectory shortrun = fixture.run.t;
    shortrun.frames = 12; /* 10 pairs: numerical rank 10 at most */
    rk_koopman_options o;
    rk_koopman_default_options(&o);
    o.h = TRAIN.h;
    o.rank = 20;
    rk_koopman k;
    err.msg[0] = 0;
    CHECK(rk_koopman_fit(&shortrun, 1, 3 * fixture.b.sim.mesh.nv, &o, &k, &err) != 0 &&
              strstr(err.msg, "numerical rank"), "rank 20 from 10 pairs: %s", err.msg);
    printf("# rank 20 from 12 frames: \"%s\"\n", err.msg);
}

/* The shared training run with uniform noise of 1e-3 of its largest |u_i| on every value, fitted
 * by energy (which then keeps many noise directions). Noise in the snapshots biases DMD's
 * eigenvalues inward, so on this damped run none leaves the unit circle even unclamped (printed):
 * the clamp is asserted, and the rollout from rest over ten times the training length must stay
 * finite and within twice the training's largest displacement. */
TEST(noisy_data_with_the_clamp_stays_bounded)
{
    rk_error err;
    CHECK_OK(fixture_open(&err));
    const rk_koopman_run *run = &fixture.run;
    int nv = fixture.b.sim.mesh.nv, n = 3 * nv, frames = run->t.frames, long_frames = 10 * (frames - 2) + 2;
    double peak = 0;
    for (size_t i = 0; i < (size_t)n * frames; i++) peak = fmax(peak, fabs(run->u[i]));
    double *noisy = calloc((size_t)n * frames, sizeof(double)), *out = calloc((size_t)n * long_frames, sizeof(double));
    for (size_t i = 0; i < (size_t)n * frames; i++)
        noisy[i] = run->u[i] + 1e-3 * peak * (2 * rk_uniform(&rng) - 1);
    rk_koopman_options o;
    rk_koopman_default_options(&o);
    o.h = TRAIN.h;
    rk_koopman k;
    rk_koopman_trajectory t = {noisy, frames, run->accel};
    CHECK_OK(rk_koopman_fit(&t, 1, n, &o, &k, &err));
    double unclamped = max_abs_lambda(&k);
    rk_koopman_free(&k);
    o.clamp = 1;
    CHECK_OK(rk_koopman_fit(&t, 1, n, &o, &k, &err));
    rollout(&k, run->u, run->accel, long_frames, 1, out); /* from the clean rest state */
    double grow = 0;
    int finite = 1;
    for (size_t i = 0; i < (size_t)n * long_frames; i++) {
        finite &= isfinite(out[i]);
        grow = fmax(grow, fabs(out[i]));
    }
    traj_error e = compare(out, run->u, frames, nv, fixture.b.sim.mesh.X);
    double s, tail = max_abs_diff(out + (size_t)n * (long_frames - 1), run->u + (size_t)n * (frames - 1), n, &s);
    printf("# noise 1e-3 of the largest |u_i|: rank %d (energy %g), max |lambda| %.15g unclamped, %d clamped, %.15g "
           "after;\n# training window %.3e%% MSE against the clean run; over %d steps largest |u_i| %.4f m (training "
           "%.4f m), last frame vs the training's last %.2e relative\n", k.r, o.energy, unclamped, k.clamped,
           max_abs_lambda(&k), e.percent, long_frames - 2, grow, peak, tail / s);
    free(noisy);
    free(out);
    double top = max_abs_lambda(&k);
    rk_koopman_free(&k);
    CHECK(top <= 1 + 1e-15, "max |lambda| %.17g after the clamp", top);
    CHECK(finite && grow < 2 * peak, "rollout over 10x the training length reached %.3g m (training peak %.3g m)",
          grow, peak);
}

int main(void)
{
    RUN(force_generalization_neohookean);
    RUN(force_generalization_linear_is_exact);
    RUN(a_forced_jump_equals_single_steps);
    RUN(time_step_invariance_against_backward_euler);
    RUN(a_body_standing_still);
    RUN(a_rank_above_the_data_is_refused);
    RUN(noisy_data_with_the_clamp_stays_bounded);
    fixture_close();
    return test_finish();
}
