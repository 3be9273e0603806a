/* Control by fast time stepping (koopman/koopman.h; paper Sec. 7.3, Eq. 25):
 *  - the closed-form summed propagator against explicit sums, at and near lambda = 1;
 *  - the forced N-step map against N single forced steps and the true dynamics;
 *  - on exactly linear data (a damped mass-spring chain) the solve recovers known inputs;
 *  - tracking a trajectory made with inputs that change every step returns those inputs;
 *  - NNLS finds the optimum that brute force over all supports finds;
 *  - on a neo-Hookean cantilever pulled by two cables (forces whose direction follows the
 *    deformed tip, so A(X) changes with the state) the inputs it finds bring the full-order
 *    simulation's tip to a goal the full-order model reached with inputs the solver was not told;
 *  - nonsense is refused with a message. */
#include <lapacke.h>

#include "scene_run.h"
#include "koopman/koopman.h"
#include "pipeline/pipeline.h"
#include "pipeline/control.h"
#include "util/util.h"

/* ---- the summed propagator ---- */

/* sum_{t=1}^N lambda^t by repeated multiplication in long double. */
static void loop_sum(double re, double im, long long N, double *s_re, double *s_im)
{
    long double pr = 1, pi = 0, sr = 0, si = 0;
    for (long long t = 1; t <= N; t++) {
        long double nr = pr * re - pi * im;
        pi = pr * im + pi * re;
        pr = nr;
        sr += pr;
        si += pi;
    }
    *s_re = (double)sr;
    *s_im = (double)si;
}

TEST(power_sum_matches_explicit_sums)
{
    const double lam[][2] = {
        {1, 0}, {1 - 1e-9, 0}, {0.95, 0}, {-0.95, 0}, {0, 0},
        {0.9 * cos(0.3), 0.9 * sin(0.3)},             /* complex, |lambda| < 1 */
        {cos(0.7), sin(0.7)},                         /* complex on the unit circle */
        {(1 - 1e-9) * cos(1e-7), (1 - 1e-9) * sin(1e-7)}, /* complex, next to 1 */
    };
    const long long Ns[] = {1, 7, 1000};
    double worst = 0;
    for (size_t i = 0; i < sizeof lam / sizeof lam[0]; i++)
        for (size_t q = 0; q < 3; q++) {
            double sr, si, er, ei;
            rk_koopman_power_sum(lam[i][0], lam[i][1], Ns[q], &sr, &si);
            loop_sum(lam[i][0], lam[i][1], Ns[q], &er, &ei);
            double rel = hypot(sr - er, si - ei) / fmax(hypot(er, ei), 1e-300);
            if (hypot(er, ei) == 0) rel = hypot(sr, si);
            worst = fmax(worst, rel);
            CHECK(rel < 1e-12, "lambda %.17g%+.17gi, N %lld: closed form %.17g%+.17gi, loop %.17g%+.17gi (rel %.3g)",
                  lam[i][0], lam[i][1], Ns[q], sr, si, er, ei, rel);
        }
    double sr, si;
    rk_koopman_power_sum(1, 0, 1000, &sr, &si);
    CHECK(sr == 1000 && si == 0, "lambda = 1 must give exactly N: %.17g%+.17gi", sr, si);
    printf("# power sums: worst relative difference from the loop %.2e\n", worst);
}

/* A hand-made operator (r = 6) with blocks: 1, 1 - 1e-9, a pair inside and a pair on the unit
 * circle, W well conditioned; K' = W B W^-1. */
#define R6 6
static void synthetic(rk_koopman *k, double *mem, double *K)
{
    static int block[R6] = {1, 1, 2, 0, 2, 0};
    double *W = mem, *Winv = mem + R6 * R6, *lr = mem + 2 * R6 * R6, *li = lr + R6, B[R6 * R6] = {0};
    memset(k, 0, sizeof *k);
    k->r = R6;
    k->W = W;
    k->Winv = Winv;
    k->lambda_re = lr;
    k->lambda_im = li;
    k->block = block;
    const double l[R6][2] = {{1, 0}, {1 - 1e-9, 0}, {0.9 * cos(0.3), 0.9 * sin(0.3)}, {0.9 * cos(0.3), -0.9 * sin(0.3)},
                             {cos(0.7), sin(0.7)}, {cos(0.7), -sin(0.7)}};
    for (int j = 0; j < R6; j++) lr[j] = l[j][0], li[j] = l[j][1];
    for (int j = 0; j < R6; j++) { /* column-major B: [[a, b], [-b, a]] on the pairs */
        B[j * R6 + j] = lr[j];
        if (block[j] == 2) B[(j + 1) * R6 + j] = li[j], B[j * R6 + j + 1] = -li[j];
    }
    for (int i = 0; i < R6 * R6; i++) W[i] = (i % (R6 + 1) == 0) + 0.3 * sin(1.7 * i + 0.4);
    int piv[R6];
    memcpy(Winv, W, sizeof(double) * R6 * R6);
    LAPACKE_dgetrf(LAPACK_COL_MAJOR, R6, R6, Winv, R6, piv);
    LAPACKE_dgetri(LAPACK_COL_MAJOR, R6, Winv, R6, piv);
    double T[R6 * R6];
    for (int i = 0; i < R6; i++) /* K = W B Winv */
        for (int j = 0; j < R6; j++) {
            T[j * R6 + i] = 0;
            for (int m = 0; m < R6; m++) T[j * R6 + i] += W[m * R6 + i] * B[j * R6 + m];
        }
    for (int i = 0; i < R6; i++)
        for (int j = 0; j < R6; j++) {
            K[j * R6 + i] = 0;
            for (int m = 0; m < R6; m++) K[j * R6 + i] += T[m * R6 + i] * Winv[j * R6 + m];
        }
}

TEST(summed_propagator_matches_the_sum_of_powers)
{
    double mem[2 * R6 * R6 + 2 * R6], K[R6 * R6];
    rk_koopman k;
    rk_error err;
    synthetic(&k, mem, K);
    const long long Ns[] = {1, 7, 1000};
    double worst = 0;
    for (int q = 0; q < 3; q++) {
        double z[R6], p[R6], np[R6], sum[R6] = {0};
        for (int i = 0; i < R6; i++) z[i] = p[i] = cos(2.1 * i + 0.5);
        for (long long t = 1; t <= Ns[q]; t++) {
            for (int i = 0; i < R6; i++) {
                np[i] = 0;
                for (int j = 0; j < R6; j++) np[i] += K[j * R6 + i] * p[j];
            }
            for (int i = 0; i < R6; i++) p[i] = np[i], sum[i] += p[i];
        }
        CHECK_OK(rk_koopman_summed_apply(&k, Ns[q], z, &err));
        double d[R6];
        for (int i = 0; i < R6; i++) d[i] = z[i] - sum[i];
        double rel = test_norm(d, R6) / test_norm(sum, R6);
        worst = fmax(worst, rel);
        CHECK(rel < 1e-10, "N %lld: W S_N W^-1 z differs from sum K^t z by %.3g relative", Ns[q], rel);
    }
    printf("# W S_N W^-1 against sum_t K'^t (blocks 1, 1-1e-9, 0.9e^0.3i, e^0.7i): worst %.2e\n", worst);
}

/* ---- an exactly linear damped chain ---- */

#define D 6
#define H 0.01
#define G_Y (-9.81)

/* Masses m_i, springs and dashpots between neighbours and to both walls, backward Euler:
 * (M + h C + h^2 K) delta' = M (delta + a h^2) - h^2 K u, u' = u + delta', which is exactly the
 * impulse convention of Eq. 19 for an acceleration a. */
typedef struct {
    double m[D], K[D * D], Ainv[D * D]; /* row-major */
} chain;

static void chain_init(chain *c)
{
    double C[D * D] = {0}, A[D * D];
    memset(c, 0, sizeof *c);
    for (int i = 0; i < D; i++) {
        c->m[i] = 1 + 0.25 * i;
        double kl = 300.0 + 40 * i, kr = 300.0 + 40 * (i + 1);
        c->K[i * D + i] = kl + kr;
        C[i * D + i] = 2 * 0.8;
        if (i + 1 < D) c->K[i * D + i + 1] = c->K[(i + 1) * D + i] = -kr, C[i * D + i + 1] = C[(i + 1) * D + i] = -0.8;
    }
    for (int i = 0; i < D * D; i++) A[i] = (i % (D + 1) == 0 ? c->m[i / D] : 0) + H * C[i] + H * H * c->K[i];
    int piv[D];
    memcpy(c->Ainv, A, sizeof A);
    LAPACKE_dgetrf(LAPACK_ROW_MAJOR, D, D, c->Ainv, D, piv);
    LAPACKE_dgetri(LAPACK_ROW_MAJOR, D, c->Ainv, D, piv);
}

/* One step of (u, delta) under the acceleration a. */
static void chain_step(const chain *c, double *u, double *delta, const double *a)
{
    double rhs[D];
    for (int i = 0; i < D; i++) {
        rhs[i] = c->m[i] * (delta[i] + a[i] * H * H);
        for (int j = 0; j < D; j++) rhs[i] -= H * H * c->K[i * D + j] * u[j];
    }
    for (int i = 0; i < D; i++) {
        delta[i] = 0;
        for (int j = 0; j < D; j++) delta[i] += c->Ainv[i * D + j] * rhs[j];
    }
    for (int i = 0; i < D; i++) u[i] += delta[i];
}

/* Three input fields: a push on mass 5, one on mass 2, a uniform one (m/s^2). */
#define KIN 3
static const double chain_fields[KIN][D] = {
    {0, 0, 0, 0, 0, 2.0}, {0, 0, 1.5, 0, 0, 0}, {0.5, 0.5, 0.5, 0.5, 0.5, 0.5}};

static int constant_field(void *ctx, const double *u, int j, double *a)
{
    (void)u;
    memcpy(a, (const double *)ctx + (size_t)D * j, sizeof(double) * D);
    return 0;
}

/* Training: two random starts under each input field alone, 12 frames each; full-rank fit. */
static int fit_chain(const chain *c, rk_koopman *k, rk_error *err)
{
    enum { FR = 12, NT = 2 * KIN };
    static double buf[NT * D * FR];
    rk_koopman_trajectory traj[NT];
    for (int t = 0; t < NT; t++) {
        double u[D], delta[D], *f = buf + (size_t)t * D * FR;
        for (int i = 0; i < D; i++) u[i] = 0.01 * sin(3.1 * t + i), delta[i] = 0.002 * cos(1.3 * t + 2 * i);
        for (int i = 0; i < D; i++) f[i] = u[i] - delta[i]; /* frame 0: u_prev */
        for (int s = 1; s < FR; s++) {
            memcpy(f + (size_t)D * s, u, sizeof u);
            chain_step(c, u, delta, chain_fields[t % KIN]);
        }
        traj[t] = (rk_koopman_trajectory){f, FR, chain_fields[t % KIN]};
    }
    rk_koopman_options o;
    rk_koopman_default_options(&o);
    o.rank = 2 * D;
    o.h = H;
    return rk_koopman_fit(traj, NT, D, &o, k, err);
}

/* The true chain from (u, delta) for N steps under gravity + sum C_j field_j. */
static void chain_run(const chain *c, double *u, double *delta, const double *C, int N)
{
    double a[D];
    for (int i = 0; i < D; i++) {
        a[i] = G_Y;
        for (int j = 0; j < KIN; j++) a[i] += C[j] * chain_fields[j][i];
    }
    for (int s = 0; s < N; s++) chain_step(c, u, delta, a);
}

TEST(forced_map_equals_single_forced_steps)
{
    chain c;
    rk_koopman k;
    rk_error err;
    chain_init(&c);
    CHECK_OK(fit_chain(&c, &k, &err));
    const double C[KIN] = {0.4, -0.7, 1.1};
    double u[D], delta[D], up[D], a[D], z1[2 * D], zN[2 * D], p1[D], pN[D];
    for (int i = 0; i < D; i++) {
        u[i] = 0.003 * (i + 1), delta[i] = -0.001 * i, up[i] = u[i] - delta[i];
        a[i] = G_Y + C[0] * chain_fields[0][i] + C[1] * chain_fields[1][i] + C[2] * chain_fields[2][i];
    }
    rk_koopman_lift(&k, u, up, z1);
    memcpy(zN, z1, sizeof z1);
    const int N = 300;
    for (int s = 0; s < N; s++) { /* Eq. 19: impulse, then the step */
        rk_koopman_impulse(&k, a, z1);
        rk_koopman_advance(&k, z1, 1, 1, 0);
    }
    CHECK_OK(rk_koopman_forced(&k, N, a, zN, &err));
    chain_run(&c, u, delta, C, N);
    rk_koopman_positions(&k, z1, p1);
    rk_koopman_positions(&k, zN, pN);
    double d1[D], dt[D];
    for (int i = 0; i < D; i++) d1[i] = pN[i] - p1[i], dt[i] = pN[i] - u[i];
    double scale = test_norm(u, D), e1 = test_norm(d1, D) / scale, et = test_norm(dt, D) / scale;
    printf("# forced map over %d steps: %.2e from %d single steps, %.2e from the true chain\n", N, e1, N, et);
    CHECK(e1 < 1e-10, "forced map differs from single forced steps by %.3g", e1);
    CHECK(et < 1e-8, "forced map differs from the true chain by %.3g", et);
    rk_koopman_free(&k);
}

/* C from the final frame of a true run with C_true, by LS and by NNLS. */
TEST(recovers_known_inputs_of_a_linear_chain)
{
    chain c;
    rk_koopman k;
    rk_error err;
    chain_init(&c);
    CHECK_OK(fit_chain(&c, &k, &err));
    const double C_true[KIN] = {0.3, 1.2, 0.7};
    const int N = 40;
    double u[D], delta[D], up[D], z0[2 * D], grav[D];
    for (int i = 0; i < D; i++) u[i] = 0.002 * cos(i), delta[i] = 0.0005 * sin(2.0 * i), up[i] = u[i] - delta[i];
    for (int i = 0; i < D; i++) grav[i] = G_Y;
    rk_koopman_lift(&k, u, up, z0); /* start from a moving state, not rest */
    chain_run(&c, u, delta, C_true, N);
    rk_koopman_target tg[4] = {{0, u[0]}, {2, u[2]}, {3, u[3]}, {5, u[5]}};
    rk_koopman_control_problem p;
    rk_koopman_control_default(&p);
    p.steps = N;
    p.z0 = z0;
    p.accel = grav;
    p.inputs = KIN;
    p.input_field = constant_field;
    p.ctx = (void *)chain_fields;
    p.targets = tg;
    p.ntargets = 4;
    p.iterations = 3;
    for (int nn = 0; nn < 2; nn++) {
        double C[KIN], res[3];
        p.nonnegative = nn;
        CHECK_OK(rk_koopman_control(&k, &p, C, res, NULL, &err));
        double worst = 0;
        for (int j = 0; j < KIN; j++) worst = fmax(worst, fabs(C[j] - C_true[j]) / C_true[j]);
        printf("# chain, %s: C = [%.12f, %.12f, %.12f] (true [0.3, 1.2, 0.7]), worst rel. error %.2e, residuals "
               "%.1e %.1e %.1e\n", nn ? "NNLS" : "LS", C[0], C[1], C[2], worst, res[0], res[1], res[2]);
        CHECK(worst < 1e-6, "%s recovered C with relative error %.3g", nn ? "NNLS" : "LS", worst);
    }
    /* fewer equations than inputs: the minimum-norm C, which still meets the one goal */
    double C[KIN], zf[2 * D], pf[D];
    p.nonnegative = 0;
    p.ntargets = 1;
    CHECK_OK(rk_koopman_control(&k, &p, C, NULL, zf, &err));
    rk_koopman_positions(&k, zf, pf);
    printf("# one goal, three inputs: minimum-norm C = [%.6f, %.6f, %.6f], goal missed by %.2e m\n", C[0], C[1], C[2],
           fabs(pf[0] - u[0]));
    CHECK(fabs(pf[0] - u[0]) < 1e-9 * fabs(u[0]), "underdetermined solve misses its goal by %.3g", pf[0] - u[0]);
    rk_koopman_free(&k);
}

/* |A x - b| for A m x n column-major. */
static double misfit(int m, int n, const double *A, const double *b, const double *x)
{
    double s = 0;
    for (int i = 0; i < m; i++) {
        double e = -b[i];
        for (int j = 0; j < n; j++) e += A[j * m + i] * x[j];
        s += e * e;
    }
    return sqrt(s);
}

/* Tracking (rk_koopman_track): a target made by the true chain under inputs that change every
 * step; with horizon 1 and every value followed, the solve must return those inputs and the model
 * must sit on the target at every frame. A longer horizon holds each input constant over it, so
 * it can only approximate inputs that change every step: printed. Nonsense is refused. */
TEST(tracking_recovers_time_varying_inputs_of_a_linear_chain)
{
    enum { T = 60 };
    chain c;
    rk_koopman k;
    rk_error err;
    chain_init(&c);
    CHECK_OK(fit_chain(&c, &k, &err));
    static double goal[D * T], C_true[KIN * (T - 1)], C[KIN * (T - 1)], u_model[D * T];
    double u[D] = {0}, delta[D] = {0}, up[D] = {0}, z0[2 * D], grav[D];
    int index[D];
    for (int i = 0; i < D; i++) grav[i] = G_Y, index[i] = i;
    rk_koopman_lift(&k, u, up, z0); /* from rest */
    memcpy(goal, u, sizeof u);
    for (int t = 0; t + 1 < T; t++) {
        double *Ct = C_true + KIN * t;
        Ct[0] = 0.3 + 0.2 * sin(0.3 * t), Ct[1] = 1.2 * cos(0.11 * t), Ct[2] = 0.7 - 0.01 * t;
        chain_run(&c, u, delta, Ct, 1);
        memcpy(goal + D * (t + 1), u, sizeof u);
    }
    rk_koopman_track_problem p = {.frames = T, .horizon = 1, .m = D, .index = index, .goal = goal, .z0 = z0,
                                  .accel = grav, .inputs = KIN, .input_field = constant_field,
                                  .ctx = (void *)chain_fields, .iterations = 1};
    for (int hz = 1; hz <= 5; hz += 4) {
        p.horizon = hz;
        CHECK_OK(rk_koopman_track(&k, &p, C, u_model, &err));
        double worst_c = 0, worst_u = 0, scale = 0;
        for (int i = 0; i < KIN * (T - 1); i++) worst_c = fmax(worst_c, fabs(C[i] - C_true[i]));
        for (int i = 0; i < D * T; i++) worst_u = fmax(worst_u, fabs(u_model[i] - goal[i])), scale = fmax(scale, fabs(goal[i]));
        printf("# tracking the chain, horizon %d: inputs off by %.2e at most, model off the target by %.2e of its "
               "largest value\n", hz, worst_c, worst_u / scale);
        if (hz == 1) {
            CHECK(worst_c < 1e-6, "horizon 1: inputs off by %.3g", worst_c);
            CHECK(worst_u < 1e-9 * scale, "horizon 1: the model is off the target by %.3g", worst_u / scale);
        }
    }
    rk_koopman_track_problem q = p;
    q.frames = 1;
    CHECK(rk_koopman_track(&k, &q, C, NULL, &err) && strstr(err.msg, "at least 2"), "%s", err.msg);
    q = p, q.horizon = 0;
    CHECK(rk_koopman_track(&k, &q, C, NULL, &err) && strstr(err.msg, "horizon 0"), "%s", err.msg);
    goal[D * 7 + 2] = NAN;
    CHECK(rk_koopman_track(&k, &p, C, NULL, &err) && strstr(err.msg, "value 2 at frame 7 is not finite"), "%s", err.msg);
    rk_koopman_free(&k);
}

/* NNLS on its own, against brute force: the optimum is the best feasible least-squares solution
 * over all 2^n supports. Random 6 x 4 problems, most with some entries held at 0. */
TEST(nnls_matches_brute_force)
{
    enum { M = 6, N = 4 };
    rk_error err;
    uint64_t rng = 11; /* the project's generator (util/util.h): the same problems everywhere */
    int bound = 0;
    for (int trial = 0; trial < 20; trial++) {
        double A[M * N], b[M], x[N], best = INFINITY;
        for (int i = 0; i < M * N; i++) A[i] = 2 * rk_uniform(&rng) - 1;
        for (int i = 0; i < M; i++) b[i] = 2 * rk_uniform(&rng) - 1;
        CHECK_OK(rk_nnls(M, N, A, b, x, &err));
        for (int mask = 0; mask < 1 << N; mask++) {
            double As[M * N], xs[N], full[N] = {0};
            int q = 0, feasible = 1;
            for (int j = 0; j < N; j++)
                if (mask >> j & 1) memcpy(As + M * q++, A + M * j, sizeof(double) * M);
            if (q && rk_lstsq(M, q, As, b, xs, &err)) CHECK(0, "%s", err.msg);
            for (int j = 0, t = 0; j < N; j++)
                if (mask >> j & 1) feasible &= (full[j] = xs[t++]) >= 0;
            if (feasible) best = fmin(best, misfit(M, N, A, b, full));
        }
        for (int j = 0; j < N; j++) {
            CHECK(x[j] >= 0, "trial %d: x[%d] = %g", trial, j, x[j]);
            bound += x[j] == 0;
        }
        double got = misfit(M, N, A, b, x);
        CHECK(got <= best * (1 + 1e-12) + 1e-15, "trial %d: NNLS misfit %.17g, brute force %.17g", trial, got, best);
    }
    printf("# NNLS: 20 random 6 x 4 problems match brute force; %d of 80 entries held at 0\n", bound);
}

/* x = (A^T A + lam^2 I)^-1 A^T b by Cholesky on the n x n normal equations (n <= 8), independent
 * of the stacked-rows solve under test. */
static void ridge_normal(int m, int n, const double *A, const double *b, double lam, double *x)
{
    double G[64], L[64] = {0}, y[8];
    for (int i = 0; i < n; i++) {
        x[i] = 0;
        for (int r = 0; r < m; r++) x[i] += A[i * m + r] * b[r];
        for (int j = 0; j < n; j++) {
            G[i * n + j] = i == j ? lam * lam : 0;
            for (int r = 0; r < m; r++) G[i * n + j] += A[i * m + r] * A[j * m + r];
        }
    }
    for (int j = 0; j < n; j++)
        for (int i = j; i < n; i++) {
            double s = G[i * n + j];
            for (int k = 0; k < j; k++) s -= L[i * n + k] * L[j * n + k];
            L[i * n + j] = i == j ? sqrt(s) : s / L[j * n + j];
        }
    for (int i = 0; i < n; i++) {
        y[i] = x[i];
        for (int k = 0; k < i; k++) y[i] -= L[i * n + k] * y[k];
        y[i] /= L[i * n + i];
    }
    for (int i = n - 1; i >= 0; i--) {
        x[i] = y[i];
        for (int k = i + 1; k < n; k++) x[i] -= L[k * n + i] * x[k];
        x[i] /= L[i * n + i];
    }
}

/* sigma_max by power iteration on A^T A (a separate route from the dgesvd under test). */
static double power_sigma(int m, int n, const double *A)
{
    double v[8], w[8], s = 0;
    for (int j = 0; j < n; j++) v[j] = 1 + 0.1 * j;
    for (int it = 0; it < 5000; it++) {
        double Av[16] = {0}, nw = 0;
        for (int r = 0; r < m; r++)
            for (int j = 0; j < n; j++) Av[r] += A[j * m + r] * v[j];
        for (int j = 0; j < n; j++) {
            w[j] = 0;
            for (int r = 0; r < m; r++) w[j] += A[j * m + r] * Av[r];
            nw += w[j] * w[j];
        }
        nw = sqrt(nw);
        for (int j = 0; j < n; j++) v[j] = w[j] / nw;
        s = sqrt(nw);
    }
    return s;
}

/* The Tikhonov solve (rk_lstsq_tikhonov, the control's --regularize) against the normal equations
 * with the added term, (A^T A + lam^2 I) x = A^T b, lam = rho sigma_max(A): tall, square and wide
 * random systems (the wide ones have no unique plain least-squares answer, the regularised one
 * has). With nonnegative, the penalised problem's KKT conditions: its gradient
 * (A^T A + lam^2 I) x - A^T b is zero where x > 0 and >= 0 where x = 0. rho = 0 is the plain
 * solve bit for bit; a negative or NaN rho is refused. */
TEST(tikhonov_matches_the_normal_equations)
{
    static const int shapes[3][2] = {{12, 4}, {5, 5}, {3, 6}};
    static const double rhos[3] = {1e-3, 0.2, 1.0};
    rk_error err;
    uint64_t rng = 29;
    double worst = 0, worst_lam = 0, worst_kkt = 0;
    int bound = 0;
    for (int sh = 0; sh < 3; sh++)
        for (int trial = 0; trial < 5; trial++) {
            int m = shapes[sh][0], n = shapes[sh][1];
            double A[72], b[12], x[8], want[8], xp[8], lam;
            for (int i = 0; i < m * n; i++) A[i] = 2 * rk_uniform(&rng) - 1;
            for (int i = 0; i < n; i++) A[i * m] *= 1e-3;               /* a row every input barely moves */
            for (int j = 0; j < m; j++) A[(n - 1) * m + j] *= 1e-4; /* an input the system barely sees */
            for (int i = 0; i < m; i++) b[i] = 2 * rk_uniform(&rng) - 1;
            double smax = power_sigma(m, n, A);
            for (int ri = 0; ri < 3; ri++) {
                CHECK_OK(rk_lstsq_tikhonov(m, n, A, b, rhos[ri], 0, x, &lam, &err));
                worst_lam = fmax(worst_lam, fabs(lam - rhos[ri] * smax) / (rhos[ri] * smax));
                ridge_normal(m, n, A, b, lam, want);
                double d = 0, nx = 0;
                for (int j = 0; j < n; j++) d = fmax(d, fabs(x[j] - want[j])), nx = fmax(nx, fabs(want[j]));
                worst = fmax(worst, d / nx);
                CHECK_OK(rk_lstsq_tikhonov(m, n, A, b, rhos[ri], 1, x, &lam, &err));
                for (int j = 0; j < n; j++) {
                    double g = lam * lam * x[j];
                    for (int r = 0; r < m; r++) {
                        double e = -b[r];
                        for (int k = 0; k < n; k++) e += A[k * m + r] * x[k];
                        g += A[j * m + r] * e;
                    }
                    CHECK(x[j] >= 0, "shape %d, rho %g: x[%d] = %g", sh, rhos[ri], j, x[j]);
                    if (x[j] > 0) worst_kkt = fmax(worst_kkt, fabs(g) / (smax * smax));
                    else CHECK(g >= -1e-12 * smax * smax, "shape %d, rho %g: gradient %g at the bound x[%d] = 0", sh, rhos[ri], g, j);
                    bound += x[j] == 0;
                }
            }
            CHECK_OK(rk_lstsq_tikhonov(m, n, A, b, 0, 0, x, &lam, &err));
            CHECK_OK(rk_lstsq(m, n, A, b, xp, &err));
            CHECK(lam == 0 && !memcmp(x, xp, sizeof(double) * (size_t)n), "shape %d: rho 0 is not the plain solve", sh);
        }
    printf("# Tikhonov solve: 45 random systems (12x4, 5x5, 3x6; rho 1e-3, 0.2, 1) against the normal equations: "
           "%.2e relative; lambda against rho times a power-iteration sigma_max: %.2e; NNLS KKT residual %.2e "
           "(%d entries held at 0)\n", worst, worst_lam, worst_kkt, bound);
    CHECK(worst < 1e-9, "Tikhonov solve off the normal equations by %.3g", worst);
    CHECK(worst_lam < 1e-9, "lambda off rho sigma_max by %.3g", worst_lam);
    CHECK(worst_kkt < 1e-9, "NNLS with the Tikhonov term: gradient %.3g on a free entry", worst_kkt);
    double A[4] = {1, 0, 0, 1}, b[2] = {1, 1}, x[2];
    CHECK(rk_lstsq_tikhonov(2, 2, A, b, -1, 0, x, NULL, &err) && strstr(err.msg, "regularization -1"), "%s", err.msg);
    CHECK(rk_lstsq_tikhonov(2, 2, A, b, NAN, 1, x, NULL, &err) && strstr(err.msg, "must be finite"), "%s", err.msg);
}

/* ---- a neo-Hookean cantilever steered by two cables ---- */

#define BEAM_STEPS 100
static const char *beam_json =
    "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1, 0.2, 0.2], \"cells\": [10, 2, 2]}},"
    " \"material\": {\"model\": \"neohookean\", \"young\": 1e7, \"poisson\": 0.3, \"density\": 1000},"
    " \"fixed\": [{\"box\": [[-1, -1, -1], [0.001, 1, 1]]}]}],"
    " \"gravity\": [0, -9.81, 0], \"damping\": {\"mass\": 25, \"stiffness\": 0.002},"
    " \"time\": {\"step\": 0.01, \"duration\": 1.0}}";

/* Two cables from the tip face to anchors, each pulling with F0 newtons per unit input, spread
 * over the tip vertices by mass (a uniform acceleration). The pull points from the deformed tip
 * centroid to the anchor, so it turns as the tip moves: A(X) depends on the state. */
typedef struct {
    const rk_scene_sim *sim;
    int ntip, tip[64], probe; /* tip vertices; the vertex steered to the goal */
    double tip_mass, F0;
    double anchor[2][3];
} cables;

static void cables_init(cables *cb, const rk_scene_sim *sim)
{
    const double *X = sim->mesh.X;
    memset(cb, 0, sizeof *cb);
    cb->sim = sim;
    double best = INFINITY;
    for (int v = 0; v < sim->mesh.nv && cb->ntip < 64; v++)
        if (X[3 * v] > 1 - 1e-9) {
            cb->tip[cb->ntip++] = v;
            cb->tip_mass += sim->fem.vertex_mass[v];
            double d = hypot(X[3 * v + 1] - 0.1, X[3 * v + 2] - 0.1);
            if (d < best) best = d, cb->probe = v;
        }
    cb->F0 = 2000; /* one cable alone at C = 1 deflects the 1 m beam's tip by about 0.2 m */
    /* anchors 0.5 m above the tip and beside it: at the goal the pulls have turned by 10 to 15 degrees */
    const double anchors[2][3] = {{1.0, 0.6, 0.1}, {1.0, 0.1, 0.6}};
    memcpy(cb->anchor, anchors, sizeof anchors);
}

/* a = the tip acceleration of a pull of F0 newtons along the unit vector dir, 0 elsewhere. */
static void tip_pull(const cables *cb, const double dir[3], double *a)
{
    memset(a, 0, sizeof(double) * 3 * (size_t)cb->sim->mesh.nv);
    for (int q = 0; q < cb->ntip; q++)
        for (int i = 0; i < 3; i++) a[3 * cb->tip[q] + i] = cb->F0 / cb->tip_mass * dir[i];
}

static int cable_field(void *ctx, const double *u, int j, double *a)
{
    const cables *cb = ctx;
    const double *X = cb->sim->mesh.X;
    double c[3] = {0, 0, 0}, dir[3];
    for (int q = 0; q < cb->ntip; q++)
        for (int i = 0; i < 3; i++) c[i] += (X[3 * cb->tip[q] + i] + u[3 * cb->tip[q] + i]) / cb->ntip;
    for (int i = 0; i < 3; i++) dir[i] = cb->anchor[j][i] - c[i];
    double len = test_norm(dir, 3);
    for (int i = 0; i < 3; i++) dir[i] /= len;
    tip_pull(cb, dir, a);
    return 0;
}

/* Full order, BEAM_STEPS steps from rest under gravity and the cables with inputs C, the pull
 * re-evaluated every step (a follower load: rk_fom keeps its load fixed, so each step restarts
 * backward Euler, a one-step method, from (x, v) with the new load). x: the final positions. */
static int beam_fom(const cables *cb, const double *C, double *x, rk_error *err)
{
    const rk_scene_sim *sim = cb->sim;
    int n3 = 3 * sim->mesh.nv, rc = -1;
    double *v = calloc((size_t)n3, sizeof(double)), *u = calloc((size_t)n3, sizeof(double));
    double *a = calloc((size_t)n3, sizeof(double)), *f = calloc((size_t)n3, sizeof(double));
    if (!v || !u || !a || !f) goto done;
    memcpy(x, sim->mesh.X, sizeof(double) * (size_t)n3);
    for (int s = 0; s < BEAM_STEPS; s++) {
        for (int i = 0; i < n3; i++) u[i] = x[i] - sim->mesh.X[i], f[i] = 0;
        for (int j = 0; j < 2; j++) {
            cable_field((void *)cb, u, j, a);
            for (int i = 0; i < n3; i++) f[i] += C[j] * a[i] * sim->fem.vertex_mass[i / 3];
        }
        rk_fom_options o = sim->options;
        o.force = f;
        o.position0 = x;
        o.velocity0 = v;
        rk_fom fom;
        if (rk_fom_init(&fom, &sim->fem, &o, err)) goto done;
        int bad = rk_fom_step(&fom, err);
        memcpy(x, fom.x, sizeof(double) * (size_t)n3);
        memcpy(v, fom.v, sizeof(double) * (size_t)n3);
        rk_fom_free(&fom);
        if (bad) goto done;
    }
    rc = 0;
done:
    free(v);
    free(u);
    free(a);
    free(f);
    return rc;
}

/* Koopman operator from four full-order runs: gravity alone, and gravity with a tip pull of F0
 * along x, y and z in turn. A cable's pull turns as the tip moves, so the training must show the
 * model the response to every direction it may take, the axial one included: a linear model
 * answers an impulse it never saw with whatever its fit happens to say. */
static int beam_fit(const cables *cb, rk_koopman *k, rk_error *err)
{
    const rk_scene_sim *sim = cb->sim;
    int n3 = 3 * sim->mesh.nv, rc = -1;
    rk_koopman_run runs[4];
    rk_koopman_trajectory t[4];
    memset(runs, 0, sizeof runs);
    double *f = calloc((size_t)n3, sizeof(double));
    if (!f) goto done;
    for (int j = 0; j < 4; j++) {
        rk_scene_sim s = *sim; /* a shallow copy with its own load */
        if (j > 0) {
            double dir[3] = {j == 1, j == 2, j == 3};
            tip_pull(cb, dir, f);
            for (int i = 0; i < n3; i++) f[i] *= sim->fem.vertex_mass[i / 3];
            s.options.force = f;
        }
        if (rk_koopman_scene_run(&s, NULL, &runs[j], err)) goto done;
        t[j] = runs[j].t;
    }
    rk_koopman_options o;
    rk_koopman_default_options(&o);
    o.h = sim->options.h;
    o.rank = 40; /* 20 to 60 give the same inputs to 4 digits */
    o.clamp = 1;
    rc = rk_koopman_fit(t, 4, n3, &o, k, err);
done:
    for (int j = 0; j < 4; j++) rk_koopman_run_free(&runs[j]);
    free(f);
    return rc;
}

/* |tip - goal| / |goal - rest| after the full-order run under C. */
static double beam_miss(const cables *cb, const double *C, const double *goal, rk_error *err)
{
    int p = cb->probe;
    double *x = calloc((size_t)3 * cb->sim->mesh.nv, sizeof(double)), d[3], g[3];
    if (!x || beam_fom(cb, C, x, err)) {
        free(x);
        return INFINITY;
    }
    for (int i = 0; i < 3; i++) d[i] = x[3 * p + i] - goal[i], g[i] = goal[i] - cb->sim->mesh.X[3 * p + i];
    free(x);
    return test_norm(d, 3) / test_norm(g, 3);
}

/* The goal: where the full-order probe vertex ends under C_hidden (which the solver is not told). */
static int beam_goal(const cables *cb, const double *C_hidden, double goal[3], rk_error *err)
{
    double *x = calloc((size_t)3 * cb->sim->mesh.nv, sizeof(double));
    int rc = !x || beam_fom(cb, C_hidden, x, err) ? -1 : 0;
    for (int i = 0; !rc && i < 3; i++) goal[i] = x[3 * cb->probe + i];
    free(x);
    return rc;
}

/* The control problem: the probe's three coordinates to the goal, at rest at the end, gravity
 * throughout, the two cables as inputs, from rest. tg and grav are filled here. */
static void beam_problem(const cables *cb, const double goal[3], rk_koopman_target tg[3], double *grav,
                         rk_koopman_control_problem *pr)
{
    const rk_scene_sim *sim = cb->sim;
    for (int i = 0; i < 3; i++) tg[i] = (rk_koopman_target){3 * cb->probe + i, goal[i] - sim->mesh.X[3 * cb->probe + i]};
    for (int i = 0; i < 3 * sim->mesh.nv; i++) grav[i] = sim->options.gravity[i % 3];
    rk_koopman_control_default(pr);
    pr->steps = BEAM_STEPS;
    pr->accel = grav;
    pr->inputs = 2;
    pr->input_field = cable_field;
    pr->ctx = (void *)cb;
    pr->targets = tg;
    pr->ntargets = 3;
    pr->velocity_weight = 1; /* quasi-static (Sec. 7.3): the probe at rest at the end */
}

/* Solves with the paper's 5 iterations and, from `first`= 0, also with 1 (A at the unforced
 * final state), and runs the full-order model under each answer: miss[1], miss[0]. */
static int beam_solve(const rk_koopman *k, const cables *cb, rk_koopman_control_problem *pr, const double *goal,
                      int first, double miss[2], rk_error *err)
{
    double C[2], res[5];
    for (int it = first; it < 2; it++) {
        pr->iterations = it ? 5 : 1;
        if (rk_koopman_control(k, pr, C, res, NULL, err)) return -1;
        miss[it] = beam_miss(cb, C, goal, err);
        if (!isfinite(miss[it])) return -1;
        printf("#   %s, %d iteration%s: C = [%.4f, %.4f] (hidden [0.8, 0.5]), residual", pr->nonnegative ? "NNLS" : "LS",
               pr->iterations, it ? "s" : "", C[0], C[1]);
        for (int i = 0; i < pr->iterations; i++) printf(" %.2e", res[i]);
        printf(" m; full-order tip misses the goal by %.2f%% of its displacement\n", 100 * miss[it]);
    }
    return 0;
}

TEST(cables_steer_a_neo_hookean_cantilever_to_a_goal)
{
    rk_error err;
    rk_scene scene;
    rk_scene_sim sim;
    CHECK_OK(rk_scene_parse(beam_json, "beam.json", &scene, &err));
    if (rk_scene_build(&scene, &sim, &err)) {
        rk_scene_free(&scene);
        CHECK(0, "scene build: %s", err.msg);
    }
    cables cb;
    cables_init(&cb, &sim);
    const double C_hidden[2] = {0.8, 0.5};
    double goal[3], miss[2][2] = {{0}}, *grav = calloc((size_t)3 * sim.mesh.nv, sizeof(double));
    rk_koopman k;
    rk_koopman_target tg[3];
    rk_koopman_control_problem pr;
    memset(&k, 0, sizeof k);
    int ok = grav && beam_fit(&cb, &k, &err) == 0 && beam_goal(&cb, C_hidden, goal, &err) == 0;
    if (ok) {
        const double *X = sim.mesh.X + 3 * cb.probe;
        printf("# cantilever, %d vertices, Koopman rank %d: goal %.4f m from the probe's rest position\n", sim.mesh.nv,
               k.r, hypot(hypot(goal[0] - X[0], goal[1] - X[1]), goal[2] - X[2]));
        beam_problem(&cb, goal, tg, grav, &pr);
    }
    for (int nn = 0; ok && nn < 2; nn++) {
        pr.nonnegative = nn;
        ok = beam_solve(&k, &cb, &pr, goal, nn, miss[nn], &err) == 0; /* NNLS: only 5 (C > 0 here) */
    }
    free(grav);
    rk_koopman_free(&k);
    rk_scene_sim_free(&sim);
    rk_scene_free(&scene);
    CHECK(ok, "%s", err.msg);
    for (int nn = 0; nn < 2; nn++)
        CHECK(miss[nn][1] < 0.05, "%s: the full-order tip misses the goal by %.2f%%", nn ? "NNLS" : "LS",
              100 * miss[nn][1]);
    CHECK(miss[0][1] <= miss[0][0], "5 iterations (%.2f%%) did worse than 1 (%.2f%%)", 100 * miss[0][1],
          100 * miss[0][0]);
}

/* ---- nonsense ---- */

static int failing_field(void *ctx, const double *u, int j, double *a)
{
    (void)ctx, (void)u, (void)j, (void)a;
    return -1;
}

/* field 0 sane, field 1 with a NaN */
static int nan_field(void *ctx, const double *u, int j, double *a)
{
    constant_field(ctx, u, j, a);
    if (j == 1) a[3] = NAN;
    return 0;
}

TEST(bad_problems_get_clear_messages)
{
    chain c;
    rk_koopman k;
    rk_error err;
    chain_init(&c);
    CHECK_OK(fit_chain(&c, &k, &err));
    rk_koopman_target tg[1] = {{2, 0.01}};
    rk_koopman_control_problem p, q;
    rk_koopman_control_default(&p);
    p.steps = 10;
    p.inputs = 2;
    p.input_field = constant_field;
    p.ctx = (void *)chain_fields;
    p.targets = tg;
    p.ntargets = 1;
    double C[KIN];
    CHECK(rk_koopman_control(&k, &p, C, NULL, NULL, &err) == 0, "a sane problem failed: %s", err.msg);
    q = p, q.inputs = 0;
    CHECK(rk_koopman_control(&k, &q, C, NULL, NULL, &err) && strstr(err.msg, "at least one input"), "%s", err.msg);
    q = p, q.steps = 0;
    CHECK(rk_koopman_control(&k, &q, C, NULL, NULL, &err) && strstr(err.msg, "N must be at least 1"), "%s", err.msg);
    q = p, q.ntargets = 0;
    CHECK(rk_koopman_control(&k, &q, C, NULL, NULL, &err) && strstr(err.msg, "no targets"), "%s", err.msg);
    q = p, q.iterations = 0;
    CHECK(rk_koopman_control(&k, &q, C, NULL, NULL, &err) && strstr(err.msg, "iterations"), "%s", err.msg);
    q = p, q.input_field = NULL;
    CHECK(rk_koopman_control(&k, &q, C, NULL, NULL, &err) && strstr(err.msg, "callback"), "%s", err.msg);
    q = p, q.regularize = -0.5;
    CHECK(rk_koopman_control(&k, &q, C, NULL, NULL, &err) && strstr(err.msg, "regularization -0.5"), "%s", err.msg);
    q = p, q.velocity_weight = -1;
    CHECK(rk_koopman_control(&k, &q, C, NULL, NULL, &err) && strstr(err.msg, "velocity weight"), "%s", err.msg);
    rk_koopman_target bad[1] = {{2, NAN}};
    q = p, q.targets = bad;
    CHECK(rk_koopman_control(&k, &q, C, NULL, NULL, &err) && strstr(err.msg, "goal") && strstr(err.msg, "not finite"),
          "%s", err.msg);
    bad[0] = (rk_koopman_target){D, 0.01};
    CHECK(rk_koopman_control(&k, &q, C, NULL, NULL, &err) && strstr(err.msg, "outside 0..5"), "%s", err.msg);
    q = p, q.input_field = failing_field;
    CHECK(rk_koopman_control(&k, &q, C, NULL, NULL, &err) && strstr(err.msg, "input field 0: the callback failed"),
          "%s", err.msg);
    q = p, q.input_field = nan_field;
    CHECK(rk_koopman_control(&k, &q, C, NULL, NULL, &err) && strstr(err.msg, "input field 1") &&
          strstr(err.msg, "not finite"), "%s", err.msg);
    rk_koopman_free(&k);
}

int main(void)
{
    RUN(power_sum_matches_explicit_sums);
    RUN(summed_propagator_matches_the_sum_of_powers);
    RUN(forced_map_equals_single_forced_steps);
    RUN(recovers_known_inputs_of_a_linear_chain);
    RUN(tracking_recovers_time_varying_inputs_of_a_linear_chain);
    RUN(nnls_matches_brute_force);
    RUN(tikhonov_matches_the_normal_equations);
    RUN(cables_steer_a_neo_hookean_cantilever_to_a_goal);
    RUN(bad_problems_get_clear_messages);
    return test_finish();
}
