/* Neural DMD across resolutions, measured against one converged run (issue 35, must-show 2;
 * koopman-dmd-log-linear paper, Sec. 5, Fig. 3). test_koopman_neural judges each model against its
 * own mesh's P1 full-order run, so the classical DMD fitted on the unseen mesh reproduces that
 * mesh's discretization error along with its dynamics. Here every error is taken against the
 * quadratic-tet (P2) run of the finest mesh (rk_p2_fom_run), at common material points:
 *   family: the cantilever of koopman_beam.h, cells 8x2x2 and 24x6x6 (training) and 12x3x3
 *   (unseen); all three vertex grids are subsets of the 24x6x6 grid, so the 12x3x3 vertices are
 *   24x6x6 vertices and nothing is interpolated;
 *   (a) the neural model trained on the 8x2x2 and 24x6x6 P1 runs, rolled out on 12x3x3;
 *   (b) a classical DMD (rk_koopman_fit, same rank) fitted on the 12x3x3 P1 run;
 * both from the same start (rest) under the same gravity, against the 24x6x6 P2 run at the 12x3x3
 * vertices, by the rollout's relative MSE (rk_koopman_rollout_error: 100 sum |u - u_ref|^2 /
 * sum |u_ref|^2 over every frame after the start). Also measured (and bounded below): how far the
 * P1 runs of the three meshes and the 12x3x3 and 8x2x2 P2 runs are from that reference (its own
 * convergence indication), and the neural model trained on the P2 runs of the two training
 * meshes instead. */
#include "testlib.h"
#include "koopman_beam.h"
#include "fom/fom.h"

#define RANK 10
/* seconds simulated: 45 steps of 0.01 s, the sag and its first swing (the first bending period is
 * about 0.44 s by beam theory) */
#define DURATION 0.45

typedef struct {
    const beam *b;
    rk_koopman_run *run;
} p2_recording;

/* Frame `step` of a P2 run as displacements of the mesh's vertices (the P2 run's first nodes),
 * at run frame step + 1 (frame 0 is u_{-1}, as rk_koopman_scene_run lays a run out). */
static int keep_p2(void *ctx, int step, const double *x, const double *v, double seconds, rk_error *err)
{
    p2_recording *r = ctx;
    int n3 = 3 * r->b->sim.mesh.nv;
    if (step + 1 >= r->run->t.frames) return rk_fail(err, "P2 step %d past the run's %d frames", step, r->run->t.frames);
    for (int i = 0; i < n3; i++) r->run->u[(size_t)n3 * (step + 1) + i] = x[i] - r->b->sim.mesh.X[i];
    return 0;
}

/* b's scene run on quadratic tets (same options: gravity, damping, clamp, step, duration), laid out
 * as b's P1 run is (its accel and frame before the start reused) at b's vertices. */
static int p2_run(const beam *b, rk_koopman_run *out, rk_error *err)
{
    int n3 = 3 * b->sim.mesh.nv, T = b->run.t.frames;
    memset(out, 0, sizeof *out);
    out->u = calloc((size_t)n3 * T, sizeof(double));
    out->accel = malloc(sizeof(double) * n3);
    if (!out->u || !out->accel) {
        rk_koopman_run_free(out);
        return rk_fail(err, "out of memory for a P2 run of %d values x %d frames", n3, T);
    }
    memcpy(out->accel, b->run.accel, sizeof(double) * n3);
    memcpy(out->u, b->run.u, sizeof(double) * n3); /* u_{-1} */
    out->t = (rk_koopman_trajectory){out->u, T, out->accel};
    p2_recording r = {b, out};
    rk_fom_stats st;
    if (rk_p2_fom_run(&b->sim.fem, &b->sim.options, keep_p2, &r, &st, err)) {
        rk_koopman_run_free(out);
        return -1;
    }
    printf("# P2 run on %d vertices: %ld steps, %ld Newton iterations, %.1f s (factor %.1f, assemble %.1f)\n",
           b->sim.mesh.nv, st.steps, st.newton_iterations, st.seconds_total, st.seconds_factor, st.seconds_assemble);
    return 0;
}

/* The run `src` on mesh `from` taken at the vertices of mesh `to` (each one a vertex of `from`),
 * with to's accelerations: a trajectory on to's vertices. */
static int restrict_run(const rk_koopman_run *src, const beam *from, const beam *to, rk_koopman_run *out, rk_error *err)
{
    int nf = 3 * from->sim.mesh.nv, nt = 3 * to->sim.mesh.nv, T = src->t.frames;
    memset(out, 0, sizeof *out);
    out->u = malloc(sizeof(double) * nt * T);
    out->accel = malloc(sizeof(double) * nt);
    if (!out->u || !out->accel) {
        rk_koopman_run_free(out);
        return rk_fail(err, "out of memory restricting a run");
    }
    memcpy(out->accel, to->run.accel, sizeof(double) * nt);
    for (int p = 0; p < to->sim.mesh.nv; p++) {
        const double *x = to->sim.mesh.X + 3 * p;
        int q = beam_vertex(from, x[0], x[1], x[2]);
        if (q < 0) {
            rk_koopman_run_free(out);
            return rk_fail(err, "vertex %d (%g, %g, %g) is no vertex of the finer mesh", p, x[0], x[1], x[2]);
        }
        for (int t = 0; t < T; t++)
            for (int c = 0; c < 3; c++) out->u[(size_t)nt * t + 3 * p + c] = src->u[(size_t)nf * t + 3 * q + c];
    }
    out->t = (rk_koopman_trajectory){out->u, T, out->accel};
    return 0;
}

/* Run a against reference r on the same vertices, as rk_koopman_rollout_error measures a rollout:
 * 100 sum |a - r|^2 / sum |r|^2 over every frame after the start (frames 2 on). */
static double run_mse(const rk_koopman_run *a, const rk_koopman_run *r, int n)
{
    double se = 0, sr = 0;
    for (int t = 2; t < r->t.frames; t++)
        for (int i = 0; i < n; i++) {
            double d = a->u[(size_t)n * t + i] - r->u[(size_t)n * t + i];
            se += d * d, sr += r->u[(size_t)n * t + i] * r->u[(size_t)n * t + i];
        }
    return 100 * se / sr;
}

/* The neural model trained on m[0..1] as an operator on the unseen mesh u, rolled out against its
 * own P1 run (*own) and against the reference ref (*conv). */
static int neural_on_unseen(const rk_koopman_neural_mesh *m, const beam *u, const rk_koopman_run *ref,
                            const char *label, double *own, double *conv, rk_error *err)
{
    rk_koopman_neural_options o;
    rk_koopman_neural_default_options(&o);
    /* Eq. 23's one-step loss (K = 1) and the default epochs: the K = 20 window and 3000 + 1000
     * epochs of test_koopman_neural take 6x as long on the 24x6x6 mesh, and against the P2 run
     * the discretization gap, not the rollout, dominates (a K = 20 run, 1 s simulated: neural
     * 16.5% against classical 17.7%) */
    o.rank = RANK;
    rk_koopman_neural nk;
    rk_koopman_neural_report rep;
    if (rk_koopman_neural_train(m, 2, &o, &nk, &rep, err)) return -1;
    printf("# neural DMD on %s: rank %d, L %.4g after the regression, %.4g after %d steps (%.1f s)\n", label, nk.r,
           rep.pretrained_loss, rep.final_loss, o.epochs, rep.seconds);
    rk_koopman k;
    double peak;
    int rc = rk_koopman_neural_operator(&nk, u->sim.mesh.X, u->sim.mesh.nv, NULL, &k, err);
    rk_koopman_neural_free(&nk);
    if (rc) return -1;
    rc = rk_koopman_rollout_error(&k, &u->run.t, own, &peak, err) || rk_koopman_rollout_error(&k, &ref->t, conv, &peak, err);
    rk_koopman_free(&k);
    return rc ? -1 : 0;
}

TEST(neural_across_resolutions_against_a_converged_run)
{
    rk_error err;
    static const int cells[3][3] = {{8, 2, 2}, {24, 6, 6}, {12, 3, 3}}; /* train, train, unseen */
    beam b[3];
    rk_koopman_run p2[3], ref;
    memset(b, 0, sizeof b);
    memset(p2, 0, sizeof p2);
    memset(&ref, 0, sizeof ref);
    int rc = 0, np2 = 0;
    double t0 = rk_now();
    for (int i = 0; i < 3 && !rc; i++) rc = beam_open(&b[i], cells[i][0], cells[i][1], cells[i][2], DURATION, &err);
    printf("# P1 runs: %.1f s\n", rk_now() - t0);
    t0 = rk_now();
    for (int i = 0; i < 3 && !rc; i++, np2++) rc = p2_run(&b[i], &p2[i], &err);
    printf("# P2 runs: %.1f s\n", rk_now() - t0);
    /* the reference at the unseen mesh's vertices */
    if (!rc) rc = restrict_run(&p2[1], &b[1], &b[2], &ref, &err);
    double pct[3][2] = {{0}}, p2_12 = 0, p2_8_pct = 0;
    {
        /* every P1 run and the coarser P2 runs against the 24x6x6 P2 run at their own vertices */
        printf("# %-8s %6s %22s %22s\n", "cells", "nv", "P1 vs P2 24x6x6 MSE%", "P2 vs P2 24x6x6 MSE%");
        for (int i = 0; i < 3 && !rc; i++) {
            rk_koopman_run r;
            if ((rc = restrict_run(&p2[1], &b[1], &b[i], &r, &err))) break;
            int n = 3 * b[i].sim.mesh.nv;
            pct[i][0] = run_mse(&b[i].run, &r, n);
            pct[i][1] = run_mse(&p2[i], &r, n);
            rk_koopman_run_free(&r);
            printf("# %2dx%dx%d   %6d %22.4g %22.4g\n", cells[i][0], cells[i][1], cells[i][2], b[i].sim.mesh.nv,
                   pct[i][0], pct[i][1]);
        }
        p2_12 = pct[2][1];
        p2_8_pct = pct[0][1];
    }
    double cl_own = 0, cl_conv = 0, nn_own = 0, nn_conv = 0, nq_own = 0, nq_conv = 0;
    if (!rc) {
        /* (b) the classical DMD fitted on the unseen mesh's own P1 run */
        rk_koopman_options ko;
        rk_koopman_default_options(&ko);
        ko.rank = RANK;
        ko.h = 0.01;
        rk_koopman kc;
        double peak;
        rc = rk_koopman_fit(&b[2].run.t, 1, 3 * b[2].sim.mesh.nv, &ko, &kc, &err);
        if (!rc) {
            rc = rk_koopman_rollout_error(&kc, &b[2].run.t, &cl_own, &peak, &err) ||
                 rk_koopman_rollout_error(&kc, &ref.t, &cl_conv, &peak, &err);
            rk_koopman_free(&kc);
        }
    }
    t0 = rk_now();
    if (!rc) {
        /* (a) the neural model trained on the training meshes' P1 runs */
        rk_koopman_neural_mesh m[2] = {beam_mesh(&b[0], NULL), beam_mesh(&b[1], NULL)};
        rc = neural_on_unseen(m, &b[2], &ref, "P1 runs", &nn_own, &nn_conv, &err);
    }
    if (!rc) {
        /* the same trained on the training meshes' P2 runs (at their vertices) */
        rk_koopman_neural_mesh m[2] = {{b[0].sim.mesh.X, b[0].sim.mesh.nv, &p2[0].t, 1, NULL},
                                       {b[1].sim.mesh.X, b[1].sim.mesh.nv, &p2[1].t, 1, NULL}};
        rc = neural_on_unseen(m, &b[2], &ref, "P2 runs", &nq_own, &nq_conv, &err);
    }
    printf("# neural training and rollouts: %.1f s\n", rk_now() - t0);
    for (int i = 0; i < np2; i++) rk_koopman_run_free(&p2[i]);
    rk_koopman_run_free(&ref);
    for (int i = 0; i < 3; i++) beam_close(&b[i]);
    CHECK(rc == 0, "%s", err.msg);
    printf("# on 12x3x3 (unseen), rank %d, rollout MSE%%:   %14s %18s\n", RANK, "own P1 run", "P2 24x6x6 run");
    printf("#   (a) neural, trained on P1 8x2x2 + 24x6x6 %14.4g %18.4g\n", nn_own, nn_conv);
    printf("#   (b) classical, fitted on P1 12x3x3      %14.4g %18.4g\n", cl_own, cl_conv);
    printf("#   neural, trained on P2 8x2x2 + 24x6x6    %14.4g %18.4g\n", nq_own, nq_conv);
    printf("#   the 12x3x3 P1 run itself                %14s %18.4g\n", "0", pct[2][0]);
    printf("# (a) <= 2 (b) against the P2 run: %s (%.4g%% against %.4g%%)\n", nn_conv <= 2 * cl_conv ? "met" : "NOT met",
           nn_conv, cl_conv);
    /* the reference is converged far beyond any P1 run: the 12x3x3 and 8x2x2 P2 runs are closer
     * to it than the 24x6x6 P1 run on its own mesh */
    CHECK(p2_12 < 0.1 * pct[1][0] && p2_8_pct < pct[1][0], "P2 12x3x3 %.4g%%, P2 8x2x2 %.4g%%, P1 24x6x6 %.4g%% MSE",
          p2_12, p2_8_pct, pct[1][0]);
    /* the classical fit on the unseen mesh reproduces its own P1 run; against the converged run it
     * carries that run's discretization error, a hundred times more than its own-run error shows */
    CHECK(cl_conv > 100 * cl_own && cl_conv > 0.5 * pct[2][0], "classical: %.4g%% own run, %.4g%% P2, P1 itself %.4g%%",
          cl_own, cl_conv, pct[2][0]);
    /* issue 35's bar, measured against one converged run: the neural model on the unseen mesh within
     * 2x of the classical DMD fitted on that mesh */
    CHECK(nn_conv <= 2 * cl_conv, "neural %.4g%% MSE, classical %.4g%% against the P2 run", nn_conv, cl_conv);
    /* trained on converged runs of the training meshes, the neural model on the unseen mesh is
     * closer to the converged run than anything fitted on that mesh's P1 run can be */
    CHECK(nq_conv < 0.1 * cl_conv, "neural on P2 runs %.4g%% MSE, classical %.4g%%", nq_conv, cl_conv);
}

int main(void)
{
    setenv("OPENBLAS_NUM_THREADS", "1", 0);
    RUN(neural_across_resolutions_against_a_converged_run);
    return test_finish();
}
