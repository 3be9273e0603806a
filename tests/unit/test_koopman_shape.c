/* Neural DMD with a shape code gamma (koopman-dmd-log-linear paper, Sec. 5, Figs. 8, 11) and
 * shape optimisation through the Koopman jump (Sec. 7.4):
 *   1. the loss gradient with g = 1 (the modes network's gamma input, the eigenvalue network
 *      Lambda(gamma)) against central differences;
 *   2. a family of cantilevers whose thickness is gamma, each its own box mesh and full-order run:
 *      trained on four thicknesses, rolled out at an unseen one inside the range against that
 *      thickness's own full-order run, beside a classical DMD (rk_koopman_fit) fitted on that run
 *      itself and beside the nearest training thickness's run taken as the answer;
 *   3. the thickness for which the tip's height 1 s after release is a target, by Newton on
 *      gamma with central differences through the closed-form jump (rk_koopman_shape_optimize),
 *      then the full-order run at that thickness against the target; and its bad-input errors. */
#include "testlib.h"
#include "koopman_beam.h"

/* ---------------------------------------------------------------- 1. gradient */

TEST(loss_gradient_with_a_shape_code_matches_finite_differences)
{
    rk_error err;
    beam b[2];
    const double gamma[2] = {0.15, 0.25};
    CHECK_OK(beam_open_thick(&b[0], gamma[0], 4, 1, 1, 0.3, &err));
    if (beam_open_thick(&b[1], gamma[1], 4, 1, 1, 0.3, &err)) beam_close(&b[0]);
    CHECK(b[1].ready, "%s", err.msg);
    rk_koopman_neural_mesh m[2] = {beam_mesh(&b[0], &gamma[0]), beam_mesh(&b[1], &gamma[1])};
    rk_koopman_neural_options o;
    rk_koopman_neural_default_options(&o);
    o.hidden = 8;
    o.depth = 2;
    o.eig_hidden = 6;
    o.pretrain_epochs = 20;
    o.epochs = 5; /* leaves the eigenvalue network's output weights non-zero, so every layer counts */
    o.window = 3;
    o.shape_dim = 1;
    rk_koopman_neural nk;
    int rc = -1;
    for (int r = 6; r >= 4 && rc; r--) { /* a rank that splits no complex pair of the classical start */
        o.rank = r;
        rc = rk_koopman_neural_train(m, 2, &o, &nk, NULL, &err);
    }
    if (rc) beam_close(&b[0]), beam_close(&b[1]);
    CHECK(rc == 0, "training: %s", err.msg);
    long np = rk_mlp_params(&nk.net), ne;
    double *eig = rk_koopman_neural_eig_params(&nk, &ne);
    double *gn = calloc((size_t)np, sizeof(double)), *ge = calloc((size_t)ne, sizeof(double)), L;
    CHECK_OK(rk_koopman_neural_loss(&nk, m, 2, gn, ge, &L, &err));
    double worst = 0;
    /* a spread of both networks' parameters (first layer to last), and the modes network's weights
     * on its gamma input (column 3 of its first layer, W_0 row-major hidden x 4) */
    for (int q = 0; q < 24 + o.hidden; q++) {
        double *p, g;
        if (q < 12) {
            long i = (long)q * (ne - 1) / 11;
            p = &eig[i], g = ge[i];
        } else if (q < 24) {
            long i = (long)(q - 12) * (np - 1) / 11;
            p = &nk.net.params[i], g = gn[i];
        } else {
            long i = 4L * (q - 24) + 3;
            p = &nk.net.params[i], g = gn[i];
        }
        double keep = *p, hstep = 1e-5 * fmax(1, fabs(keep)), lp, lm;
        *p = keep + hstep;
        rk_koopman_neural_loss(&nk, m, 2, NULL, NULL, &lp, &err);
        *p = keep - hstep;
        rk_koopman_neural_loss(&nk, m, 2, NULL, NULL, &lm, &err);
        *p = keep;
        double fd = (lp - lm) / (2 * hstep), rel = fabs(fd - g) / fmax(1e-6 * L, fabs(fd) + fabs(g));
        worst = fmax(worst, rel);
    }
    /* Lambda(gamma) differs between the two codes after training, inside the unit circle (Eq. 24) */
    double re[2][8], im[2][8], dl = 0, lmax = 0;
    for (int i = 0; i < 2; i++) CHECK_OK(rk_koopman_neural_eigenvalues(&nk, &gamma[i], re[i], im[i], &err));
    for (int j = 0; j < nk.r; j++) {
        dl = fmax(dl, hypot(re[0][j] - re[1][j], im[0][j] - im[1][j]));
        lmax = fmax(lmax, fmax(hypot(re[0][j], im[0][j]), hypot(re[1][j], im[1][j])));
    }
    printf("# gradient check, g = 1: rank %d, L %.6g, %ld + %ld parameters, worst relative difference %.3g; "
           "max |Lambda(0.15) - Lambda(0.25)| %.3g, max |lambda| %.6f\n", nk.r, L, np, ne, worst, dl, lmax);
    free(gn);
    free(ge);
    rk_koopman_neural_free(&nk);
    beam_close(&b[0]);
    beam_close(&b[1]);
    CHECK(worst < 1e-5, "analytic against central-difference gradient: %.3g", worst);
    CHECK(dl > 0 && lmax < 1, "Lambda(gamma): difference %.3g, max |lambda| %.9g", dl, lmax);
}

/* ---------------------------------------------------------------- 2. an unseen thickness */

#define NTRAIN 4
#define NUNSEEN 3
#define RANK 10
#define CX 8
#define CY 2
#define CZ 2
#define DURATION 1.0
#define STEPS 100 /* the objective's time: the runs' last frame, 1 s */
/* training thicknesses, then unseen ones inside their range (m) */
static const double thickness[NTRAIN + NUNSEEN] = {0.14, 0.18, 0.22, 0.26, 0.16, 0.20, 0.24};

/* trained once by test 2, used by tests 3 and 4 */
static rk_koopman_neural family;
static int family_ready;

/* The lowest frequency (Hz) among an operator's weakly damped pairs (|lambda| > 0.9): the beam's
 * first bending mode, whose frequency grows with the thickness (as gamma for a beam in bending). */
static double slowest_hz(const rk_koopman *k)
{
    double f = INFINITY;
    for (int j = 0; j < k->r; j++)
        if (k->block[j] == 2 && hypot(k->lambda_re[j], k->lambda_im[j]) > 0.9)
            f = fmin(f, atan2(k->lambda_im[j], k->lambda_re[j]) / (2 * M_PI * k->h));
    return f;
}

/* The % MSE of nk at code gamma on beam b (neural) and of a classical DMD fitted on b's own run;
 * hz[0], hz[1]: their slowest frequencies. */
static int errors_at(const rk_koopman_neural *nk, const beam *b, double gamma, double *npct, double *cpct, double hz[2],
                     rk_error *err)
{
    rk_koopman kn, kc;
    rk_koopman_options ko;
    double peak;
    if (rk_koopman_neural_operator(nk, b->sim.mesh.X, b->sim.mesh.nv, &gamma, &kn, err)) return -1;
    int rc = rollout_error(&kn, &b->run, npct, &peak, err);
    hz[0] = slowest_hz(&kn);
    rk_koopman_free(&kn);
    rk_koopman_default_options(&ko);
    ko.rank = RANK;
    ko.h = 0.01;
    if (rc || rk_koopman_fit(&b->run.t, 1, 3 * b->sim.mesh.nv, &ko, &kc, err)) return -1;
    rc = rollout_error(&kc, &b->run, cpct, &peak, err);
    hz[1] = slowest_hz(&kc);
    rk_koopman_free(&kc);
    return rc;
}

/* 100 sum |a - b|^2 / sum |b|^2 over the frames of two runs on meshes of the same cells (the
 * vertices in the same order), displacements only: one run taken as the answer for the other. */
static double run_against(const beam *a, const beam *b)
{
    int n = 3 * b->sim.mesh.nv;
    double se = 0, sr = 0;
    for (size_t i = 2 * (size_t)n; i < (size_t)n * b->run.t.frames; i++)
        se += (a->run.u[i] - b->run.u[i]) * (a->run.u[i] - b->run.u[i]), sr += b->run.u[i] * b->run.u[i];
    return 100 * se / sr;
}

/* The nearest training thickness's run against unseen beam i's (the one below or above). */
static double nearest_run(const beam *b, int i)
{
    double best = INFINITY, dist = INFINITY;
    for (int j = 0; j < NTRAIN; j++) {
        double d = fabs(thickness[j] - thickness[i]), e = run_against(&b[j], &b[i]);
        if (d < dist - 1e-12 || (fabs(d - dist) <= 1e-12 && e < best)) best = e, dist = d;
    }
    return best;
}

/* The shape function: the beam of thickness gamma[0] (the mesh alone), its gravity as an
 * acceleration per value, and the tip corner (1, 0, 0)'s y as the objective. */
typedef struct {
    beam b;
    double *accel;
} shape_ctx;

static int beam_shape(void *ctx, const double *gamma, rk_koopman_shape *s, rk_error *err)
{
    shape_ctx *c = ctx;
    beam_close(&c->b);
    free(c->accel);
    c->accel = NULL;
    if (beam_build(&c->b, gamma[0], CX, CY, CZ, DURATION, err)) return -1;
    int nv = c->b.sim.mesh.nv, tip = beam_vertex(&c->b, 1, 0, 0);
    c->accel = rk_calloc((size_t)3 * nv, sizeof(double), err);
    if (!c->accel) return -1;
    rk_koopman_scene_accel(&c->b.sim, c->b.sim.options.gravity, NULL, c->accel);
    *s = (rk_koopman_shape){c->b.sim.mesh.X, nv, c->accel, 3 * tip + 1, NULL, 0, 0};
    return tip < 0 ? rk_fail(err, "no vertex at the tip corner") : 0;
}

/* The family's shape problem over the beams beam_shape builds into c, N = STEPS, the library's
 * defaults for the rest. */
static void shape_problem(rk_koopman_shape_problem *p, shape_ctx *c)
{
    rk_koopman_shape_default(p);
    p->nk = &family;
    p->shape = beam_shape;
    p->ctx = c;
    p->steps = STEPS;
}

/* The tip corner's height 1 s after release: the model's, by the jump (rk_koopman_shape_objective),
 * and the full-order run's. */
static int tip_heights(const beam *b, double gamma, double *model, double *full, rk_error *err)
{
    shape_ctx c;
    memset(&c, 0, sizeof c);
    rk_koopman_shape_problem p;
    shape_problem(&p, &c);
    int rc = rk_koopman_shape_objective(&p, &gamma, model, err);
    beam_close(&c.b);
    free(c.accel);
    *full = b->run.u[(size_t)3 * b->sim.mesh.nv * (1 + STEPS) + 3 * beam_vertex(b, 1, 0, 0) + 1];
    return rc;
}

TEST(generalizes_to_unseen_thicknesses)
{
    rk_error err;
    enum { NB = NTRAIN + NUNSEEN };
    beam b[NB];
    memset(b, 0, sizeof b);
    int rc = 0;
    for (int i = 0; i < NB && !rc; i++) rc = beam_open_thick(&b[i], thickness[i], CX, CY, CZ, DURATION, &err);
    rk_koopman_neural_mesh m[NTRAIN];
    for (int i = 0; i < NTRAIN; i++) m[i] = beam_mesh(&b[i], &thickness[i]);
    rk_koopman_neural_options o;
    rk_koopman_neural_default_options(&o);
    o.rank = RANK;
    o.shape_dim = 1;
    o.window = 10;
    o.epochs = 600;
    rk_koopman_neural_report rep;
    if (!rc) rc = rk_koopman_neural_train(m, NTRAIN, &o, &family, &rep, &err);
    family_ready = !rc;
    double npct[NB], cpct[NB], near[NB], tm[NB], tf[NB], hz[NB][2], worst = 0, peak = 0;
    if (!rc)
        printf("# neural DMD with shape code (thickness), rank %d, %d x %d modes MLP, %d x %d eigenvalue MLP, window "
               "K = %d: L %.4g after the regression, %.4g after %d steps (%.1f s)\n", family.r, o.depth, o.hidden,
               o.eig_depth, o.eig_hidden, o.window, rep.pretrained_loss, rep.final_loss, o.epochs, rep.seconds);
    printf("# %-20s %12s %15s %22s %15s %14s %18s\n", "thickness gamma (m)", "neural MSE%", "classical MSE%",
           "nearest training run%", "model tip 1s(m)", "full tip 1s(m)", "slowest Hz (n / c)");
    for (int i = 0; i < NB && !rc; i++) {
        rc = errors_at(&family, &b[i], thickness[i], &npct[i], &cpct[i], hz[i], &err) ||
             tip_heights(&b[i], thickness[i], &tm[i], &tf[i], &err);
        near[i] = i < NTRAIN ? 0 : nearest_run(b, i);
        if (rc) break;
        char nr[32] = "-";
        if (i >= NTRAIN) snprintf(nr, sizeof nr, "%.4g", near[i]);
        printf("# %.2f %-15s %12.4g %15.4g %22s %15.5f %14.5f %8.3f / %-7.3f\n", thickness[i],
               i < NTRAIN ? "(training)" : "(unseen)", npct[i], cpct[i], nr, tm[i], tf[i], hz[i][0], hz[i][1]);
    }
    /* the operator at an unseen code is an ordinary one: baked and stepped by the runtime */
    rk_koopman k;
    if (!rc) rc = rk_koopman_neural_operator(&family, b[NTRAIN + 1].sim.mesh.X, b[NTRAIN + 1].sim.mesh.nv,
                                             &thickness[NTRAIN + 1], &k, &err);
    if (!rc) {
        rc = runtime_against_rollout(&k, &b[NTRAIN + 1], &worst, &peak, &err);
        rk_koopman_free(&k);
    }
    for (int i = 0; i < NB; i++) beam_close(&b[i]);
    CHECK(rc == 0, "%s", err.msg);
    printf("# runtime (float) against the rollout of the operator at gamma %.2f: max |du| %.3g m, peak |u| %.3g m\n",
           thickness[NTRAIN + 1], worst, peak);
    CHECK(worst <= 1e-3 * peak, "runtime frames differ by %.3g m (peak %.3g m)", worst, peak);
    /* Lambda(gamma) learned the family's trend: the slowest mode's frequency rises with the
     * thickness, at the unseen codes too (thickness[] sorted: 0.14 .. 0.26 then 0.16 .. 0.24) */
    static const int order[NB] = {0, 4, 1, 5, 2, 6, 3};
    for (int i = 1; i < NB; i++)
        CHECK(hz[order[i]][0] > hz[order[i - 1]][0], "slowest frequency %.4g Hz at gamma %.2f, %.4g Hz at %.2f",
              hz[order[i]][0], thickness[order[i]], hz[order[i - 1]][0], thickness[order[i - 1]]);
    double worst_train = 0;
    for (int i = 0; i < NTRAIN; i++) worst_train = fmax(worst_train, npct[i]);
    for (int i = NTRAIN; i < NB; i++) {
        /* measured 0.25-1.15% (this machine, OpenBLAS on one thread): the training is sensitive to
         * its data (the full-order runs' Newton moving them by ~1e-6 moved 0.16's error from 0.79%
         * to 1.15%), so the bound has a factor of about two of margin */
        CHECK(npct[i] < 2.0, "unseen thickness %.2f: %.4g%% MSE (bound 2%%)", thickness[i], npct[i]);
        CHECK(npct[i] <= worst_train, "unseen %.2f: %.4g%% MSE above the worst training thickness's %.4g%%",
              thickness[i], npct[i], worst_train);
        CHECK(npct[i] < near[i], "unseen %.2f: %.4g%% MSE, the nearest training run as the answer %.4g%%", thickness[i],
              npct[i], near[i]);
    }
}

/* ---------------------------------------------------------------- 3. shape optimisation */

/* One optimisation from `start` to `target`, then the full-order run at the optimum: its tip
 * height 1 s after release in *full. */
static int optimize_case(double start, double target, double *gamma, double *f0, double *full,
                         rk_koopman_shape_report *rep, rk_error *err)
{
    shape_ctx c;
    memset(&c, 0, sizeof c);
    rk_koopman_shape_problem p;
    shape_problem(&p, &c); /* epsilon 1e-4, the paper's (Sec. 7.4) */
    p.target = target;
    p.tolerance = 1e-5;
    *gamma = start;
    int rc = rk_koopman_shape_objective(&p, gamma, f0, err);
    if (!rc) rc = rk_koopman_shape_optimize(&p, gamma, rep, err);
    beam_close(&c.b);
    free(c.accel);
    beam fom;
    if (rc || beam_open_thick(&fom, *gamma, CX, CY, CZ, DURATION, err)) return -1;
    int n = 3 * fom.sim.mesh.nv, tip = beam_vertex(&fom, 1, 0, 0);
    *full = fom.run.u[(size_t)n * (1 + STEPS) + 3 * tip + 1];
    beam_close(&fom);
    return 0;
}

TEST(shape_optimization_reaches_a_target_tip_height)
{
    CHECK(family_ready, "the family model of the previous test did not train");
    rk_error err;
    /* the tip corner's height (m) 1 s after release: from the thin end and from the thick end */
    static const double start[2] = {0.14, 0.26}, target[2] = {-0.030, -0.045};
    printf("# %-8s %-10s %10s %9s %12s %14s %14s %10s\n", "start", "target(m)", "iterations", "jumps", "gamma(m)",
           "model tip(m)", "full tip(m)", "full off");
    for (int i = 0; i < 2; i++) {
        double gamma, f0, full;
        rk_koopman_shape_report rep;
        CHECK_OK(optimize_case(start[i], target[i], &gamma, &f0, &full, &rep, &err));
        printf("# %-8.2f %-10.3f %10d %9d %12.5f %14.6f %14.5f %9.1f%%\n", start[i], target[i], rep.iterations,
               rep.evaluations, gamma, rep.value, full, 100 * fabs(full - target[i]) / fabs(target[i]));
        printf("#   (model tip at the start %.5f m; %d closed-form jumps of %d steps in %.4f s)\n", f0, rep.evaluations,
               STEPS, rep.seconds);
        CHECK(fabs(rep.value - target[i]) <= 1e-5, "model tip %.6g against target %.6g", rep.value, target[i]);
        CHECK(rep.iterations <= 10, "%d iterations", rep.iterations);
        /* measured within 1% (this machine); bound 5% of the target */
        CHECK(fabs(full - target[i]) <= 0.05 * fabs(target[i]), "full order at the optimum %.5f m, target %.3f m", full,
              target[i]);
    }
}

TEST(shape_optimization_rejects_bad_input)
{
    CHECK(family_ready, "the family model of the previous test did not train");
    rk_error err;
    shape_ctx c;
    memset(&c, 0, sizeof c);
    rk_koopman_shape_problem p;
    shape_problem(&p, &c);
    p.target = -0.03;
    double g = NAN;
    CHECK(rk_koopman_shape_optimize(&p, &g, NULL, &err) != 0 && strstr(err.msg, "gamma[0] is nan"), "NaN: %s", err.msg);
    g = 0.30;
    CHECK(rk_koopman_shape_optimize(&p, &g, NULL, &err) != 0 && strstr(err.msg, "outside the training range"),
          "out of range: %s", err.msg);
    g = 0.2;
    p.target = INFINITY;
    CHECK(rk_koopman_shape_optimize(&p, &g, NULL, &err) != 0 && strstr(err.msg, "target"), "target: %s", err.msg);
    p.target = -0.03;
    p.steps = 0;
    CHECK(rk_koopman_shape_optimize(&p, &g, NULL, &err) != 0 && strstr(err.msg, "steps 0"), "steps: %s", err.msg);
    /* a target outside what the range reaches: the iteration stops at the edge and says so */
    p.steps = STEPS;
    p.target = 1.0;
    CHECK(rk_koopman_shape_optimize(&p, &g, NULL, &err) != 0 && strstr(err.msg, "above the tolerance"),
          "unreachable: %s", err.msg);
    /* the operator takes any finite code but no NaN */
    rk_koopman k;
    rk_koopman_shape s;
    g = 0.2;
    CHECK_OK(beam_shape(&c, &g, &s, &err));
    g = NAN;
    CHECK(rk_koopman_neural_operator(&family, s.X, s.nv, &g, &k, &err) != 0 && strstr(err.msg, "shape code"),
          "operator: %s", err.msg);
    CHECK(rk_koopman_neural_operator(&family, s.X, s.nv, NULL, &k, &err) != 0 && strstr(err.msg, "no shape code"),
          "operator: %s", err.msg);
    printf("# last error: %s\n", err.msg);
    beam_close(&c.b);
    free(c.accel);
}

int main(void)
{
    setenv("OPENBLAS_NUM_THREADS", "1", 0);
    RUN(loss_gradient_with_a_shape_code_matches_finite_differences);
    RUN(generalizes_to_unseen_thicknesses);
    RUN(shape_optimization_reaches_a_target_tip_height);
    RUN(shape_optimization_rejects_bad_input);
    if (family_ready) rk_koopman_neural_free(&family);
    return test_finish();
}
