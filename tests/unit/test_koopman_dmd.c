/* Koopman/DMD on data whose dynamics are exactly linear in [u_t; u_t - u_{t-1}]: a damped
 * mass-spring chain stepped by backward Euler. DMD must recover the true one-step operator's
 * eigenvalues, jump N steps as N single steps, rescale the step, and refuse bad data clearly. */
#include <lapacke.h>

#include "testlib.h"
#include "koopman/koopman.h"
#include "util/util.h"

/* The random starts and noise: the project's generator (util/util.h), the same everywhere. */
static uint64_t rng = 7;

#define D 6               /* masses */
#define N2 (2 * D)
#define H 0.01

/* The chain's exact one-step map G on X = [u; delta], delta = u - u_prev (M = I, springs k,
 * dampers c between neighbours and to the walls): with A = I + h C + h^2 K,
 * delta' = A^-1 (delta - h^2 K u), u' = u + delta'. */
static void chain_map(double G[N2 * N2])
{
    double K[D * D] = {0}, C[D * D] = {0}, A[D * D], Ainv[D * D];
    for (int i = 0; i < D; i++) {
        K[i * D + i] = 2 * (400.0 + 50 * i);
        C[i * D + i] = 2 * 0.3;
        if (i + 1 < D) {
            K[i * D + i + 1] = K[(i + 1) * D + i] = -(400.0 + 50 * i);
            C[i * D + i + 1] = C[(i + 1) * D + i] = -0.3;
        }
    }
    for (int i = 0; i < D * D; i++) A[i] = (i % (D + 1) == 0) + H * C[i] + H * H * K[i];
    int piv[D];
    for (int i = 0; i < D * D; i++) Ainv[i] = A[i];
    LAPACKE_dgetrf(LAPACK_ROW_MAJOR, D, D, Ainv, D, piv);
    LAPACKE_dgetri(LAPACK_ROW_MAJOR, D, Ainv, D, piv);
    /* row-major G: rows 0..D-1 give u', rows D..2D-1 give delta' */
    for (int i = 0; i < D; i++)
        for (int j = 0; j < D; j++) {
            double AK = 0;
            for (int m = 0; m < D; m++) AK += Ainv[i * D + m] * H * H * K[m * D + j];
            G[(D + i) * N2 + j] = -AK;
            G[(D + i) * N2 + D + j] = Ainv[i * D + j];
            G[i * N2 + j] = (i == j) - AK;
            G[i * N2 + D + j] = Ainv[i * D + j];
        }
}

static void apply(const double G[N2 * N2], const double *x, double *y)
{
    for (int i = 0; i < N2; i++) {
        y[i] = 0;
        for (int j = 0; j < N2; j++) y[i] += G[i * N2 + j] * x[j];
    }
}

/* ntraj trajectories of `frames` frames from random starts (u and delta). */
static void trajectories(const double G[N2 * N2], int ntraj, int frames, double *buf, rk_koopman_trajectory *traj)
{
    for (int k = 0; k < ntraj; k++) {
        double x[N2], y[N2];
        double *u = buf + (size_t)k * D * frames;
        for (int i = 0; i < N2; i++) x[i] = 0.01 * (2 * rk_uniform(&rng) - 1);
        for (int i = 0; i < D; i++) u[i] = x[i] - x[D + i]; /* frame 0 = u_prev */
        for (int t = 1; t < frames; t++) {
            for (int i = 0; i < D; i++) u[(size_t)D * t + i] = x[i];
            apply(G, x, y);
            for (int i = 0; i < N2; i++) x[i] = y[i];
        }
        traj[k] = (rk_koopman_trajectory){u, frames, NULL};
    }
}

/* The chain's map G and a full-rank fit to 4 trajectories of 8 frames. */
static int fit_chain(double G[N2 * N2], rk_koopman *k, rk_error *err)
{
    static double buf[4 * D * 8];
    rk_koopman_trajectory traj[4];
    chain_map(G);
    trajectories(G, 4, 8, buf, traj);
    rk_koopman_options o;
    rk_koopman_default_options(&o);
    o.rank = N2;
    o.h = H;
    return rk_koopman_fit(traj, 4, D, &o, k, err);
}

TEST(recovers_the_exact_eigenvalues_of_linear_dynamics)
{
    double G[N2 * N2], wr[N2], wi[N2], Gc[N2 * N2], vr[1];
    rk_error err;
    rk_koopman k;
    CHECK_OK(fit_chain(G, &k, &err));
    for (int i = 0; i < N2 * N2; i++) Gc[i] = G[i];
    LAPACKE_dgeev(LAPACK_ROW_MAJOR, 'N', 'N', N2, Gc, N2, wr, wi, vr, 1, vr, 1);
    double worst = 0, worst_res = 0;
    for (int i = 0; i < N2; i++) { /* each true eigenvalue has a fitted one next to it */
        double best = INFINITY;
        for (int j = 0; j < k.r; j++) best = fmin(best, hypot(wr[i] - k.lambda_re[j], wi[i] - k.lambda_im[j]));
        worst = fmax(worst, best);
        worst_res = fmax(worst_res, k.residual[i]);
    }
    printf("# %d eigenvalues from 4 trajectories of 8 frames: worst distance %.2e, worst residual %.2e\n", N2, worst,
           worst_res);
    CHECK(worst < 1e-8, "eigenvalues off by %.3g", worst);
    CHECK(worst_res < 1e-8, "residual %.3g on exactly linear data", worst_res);
    rk_koopman_free(&k);
}

TEST(a_jump_of_n_steps_equals_n_single_steps)
{
    double G[N2 * N2];
    rk_error err;
    rk_koopman k;
    CHECK_OK(fit_chain(G, &k, &err));
    double u[D], up[D], z1[N2], zN[N2], x[N2], y[N2], a[D], b[D];
    for (int i = 0; i < D; i++) {
        u[i] = 0.01 * (i + 1);
        up[i] = 0.008 * (i + 1);
        x[i] = u[i];
        x[D + i] = u[i] - up[i];
    }
    rk_koopman_lift(&k, u, up, z1);
    rk_koopman_lift(&k, u, up, zN);
    const int n = 1000;
    for (int s = 0; s < n; s++) {
        rk_koopman_advance(&k, z1, 1, 1, 0);
        apply(G, x, y);
        for (int i = 0; i < N2; i++) x[i] = y[i];
    }
    rk_koopman_advance(&k, zN, n, 1, 0);
    rk_koopman_positions(&k, z1, a);
    rk_koopman_positions(&k, zN, b);
    double diff = 0, truth = 0, scale = 0;
    for (int i = 0; i < D; i++) {
        diff = fmax(diff, fabs(a[i] - b[i]));
        truth = fmax(truth, fabs(b[i] - x[i]));
        scale = fmax(scale, fabs(x[i]));
    }
    printf("# jump of %d: %.2e from %d single steps, %.2e from the exact map (relative to %.2e)\n", n, diff / scale, n,
           truth / scale, scale);
    CHECK(diff <= 1e-6 * scale, "jump differs from single steps by %.3g", diff / scale);
    CHECK(truth <= 1e-6 * scale, "jump differs from the exact dynamics by %.3g", truth / scale);
    /* the step rescale of Eq. 21: one step at 2h is two steps at h */
    rk_koopman_lift(&k, u, up, z1);
    rk_koopman_lift(&k, u, up, zN);
    rk_koopman_advance(&k, z1, 2, 1, 0);
    rk_koopman_advance(&k, zN, 1, 2, 0);
    diff = 0;
    for (int i = 0; i < k.r; i++) diff = fmax(diff, fabs(z1[i] - zN[i]));
    CHECK(diff < 1e-12, "a step of 2h differs from two of h by %.3g", diff);
    rk_koopman_free(&k);
}

TEST(bad_data_gets_a_clear_message)
{
    double buf[2 * D * 6];
    rk_koopman_trajectory traj[2] = {{buf, 6, NULL}, {buf + D * 6, 6, NULL}};
    rk_error err;
    rk_koopman_options o;
    rk_koopman_default_options(&o);
    rk_koopman k;
    err.msg[0] = 0;
    for (int i = 0; i < 2 * D * 6; i++) buf[i] = 0.5; /* repeated frames: a stable model that stays put */
    CHECK(rk_koopman_fit(traj, 2, D, &o, &k, &err) == 0, "repeated frames: %s", err.msg);
    CHECK(k.r == 1 && fabs(k.lambda_re[0] - 1) < 1e-12 && k.lambda_im[0] == 0,
          "repeated frames: r = %d, lambda %g%+gi (expected one eigenvalue 1)", k.r, k.lambda_re[0], k.lambda_im[0]);
    rk_koopman_free(&k);
    for (int i = 0; i < 2 * D * 6; i++) buf[i] = 0; /* all zero: nothing to learn from */
    CHECK(rk_koopman_fit(traj, 2, D, &o, &k, &err) != 0 && strstr(err.msg, "nothing moves"), "%s", err.msg);
    double G[N2 * N2], tb[D * 5];
    rk_koopman_trajectory one[1];
    chain_map(G);
    trajectories(G, 1, 5, tb, one); /* 3 pairs: numerical rank 3 at most */
    o.rank = 8;
    CHECK(rk_koopman_fit(one, 1, D, &o, &k, &err) != 0 && strstr(err.msg, "numerical rank"), "%s", err.msg);
    tb[7] = NAN;
    o.rank = 2;
    CHECK(rk_koopman_fit(one, 1, D, &o, &k, &err) != 0 && strstr(err.msg, "not finite"), "%s", err.msg);
    one[0].frames = 2;
    CHECK(rk_koopman_fit(one, 1, D, &o, &k, &err) != 0 && strstr(err.msg, "frames"), "%s", err.msg);
}

TEST(noisy_growing_data_is_clamped_to_the_unit_circle)
{
    double G[N2 * N2], buf[4 * D * 10];
    rk_koopman_trajectory traj[4];
    rk_error err;
    chain_map(G);
    for (int i = 0; i < N2 * N2; i++) G[i] *= 1.02; /* a growing system */
    trajectories(G, 4, 10, buf, traj);
    for (int i = 0; i < 4 * D * 10; i++) buf[i] += 1e-5 * (2 * rk_uniform(&rng) - 1);
    rk_koopman_options o;
    rk_koopman_default_options(&o);
    o.rank = N2; /* the whole state, so the fit sees the growth whichever directions a truncation
                  * would keep (with balanced blocks, rank 10 keeps only decaying ones) */
    o.clamp = 1;
    rk_koopman k;
    CHECK_OK(rk_koopman_fit(traj, 4, D, &o, &k, &err));
    double top = rk_max_abs_eigenvalue(k.lambda_re, k.lambda_im, k.r);
    printf("# noisy growing data: %d eigenvalues clamped, largest |lambda| %.15g\n", k.clamped, top);
    CHECK(k.clamped > 0 && top <= 1 + 1e-15, "largest |lambda| %.17g after the clamp", top);
    rk_koopman_free(&k);
}

int main(void)
{
    RUN(recovers_the_exact_eigenvalues_of_linear_dynamics);
    RUN(a_jump_of_n_steps_equals_n_single_steps);
    RUN(bad_data_gets_a_clear_message);
    RUN(noisy_growing_data_is_clamped_to_the_unit_circle);
    return test_finish();
}
