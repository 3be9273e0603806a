/* The one Newton solver and the integrators (precompute/solver) on problems whose answers are
 * known in closed form: a quadratic (one Newton step), a smooth convex function (quadratic
 * convergence), a barrier that the line search must never cross, prescribed entries, bad
 * potentials, and the convergence orders of backward Euler (1) and BDF2 (2) on an oscillator. */
#include "solver/solver.h"
#include "testlib.h"

#define N 4

/* E(x) = 1/2 x^T A x - b.x + c sum_i (exp(x_i) - x_i), A SPD; c = 0 is a quadratic. The Newton
 * matrix is dense and solved by Gaussian elimination (no pivoting: SPD). */
typedef struct {
    double A[N * N], b[N], c;
    double H[N * N];
    double lower;          /* > -INF: E is +INF for x_0 <= lower (a barrier -log(x_0 - lower)) */
    int calls_outside;     /* energy evaluations at x_0 <= lower */
    int nan_at;            /* evaluation count at which E is NaN (0: never) */
    int calls;
    const char *fixed;     /* prescribed entries: identity rows and columns in H, as fom/dirichlet.c does */
} problem;

static double energy(void *ctx, const double *x, double *g, int hessian, double *magnitude)
{
    problem *p = ctx;
    p->calls++;
    if (p->nan_at && p->calls >= p->nan_at) return NAN;
    if (p->lower > -INFINITY && !(x[0] > p->lower)) {
        p->calls_outside++;
        return INFINITY;
    }
    double E = 0, mag = 0;
    for (int i = 0; i < N; i++) {
        double Ax = 0;
        for (int j = 0; j < N; j++) Ax += p->A[N * i + j] * x[j];
        E += 0.5 * x[i] * Ax - p->b[i] * x[i] + p->c * (exp(x[i]) - x[i]);
        if (g) g[i] = Ax - p->b[i] + p->c * (exp(x[i]) - 1);
        for (int j = 0; j < N && hessian; j++) p->H[N * i + j] = p->A[N * i + j] + (i == j ? p->c * exp(x[i]) : 0);
    }
    for (int i = 0; i < N && hessian && p->fixed; i++)
        for (int j = 0; j < N; j++)
            if (p->fixed[i] || p->fixed[j]) p->H[N * i + j] = i == j;
    if (p->lower > -INFINITY) {
        double s = x[0] - p->lower;
        E -= log(s);
        if (g) g[0] -= 1 / s;
        if (hessian) p->H[0] += 1 / (s * s);
    }
    mag = fabs(E);
    if (magnitude) *magnitude = mag;
    return E;
}

static int solve(void *ctx, const double *g, double *d, rk_error *err)
{
    problem *p = ctx;
    double M[N * N], r[N];
    memcpy(M, p->H, sizeof M);
    for (int i = 0; i < N; i++) r[i] = -g[i];
    for (int k = 0; k < N; k++)
        for (int i = k + 1; i < N; i++) {
            double f = M[N * i + k] / M[N * k + k];
            for (int j = k; j < N; j++) M[N * i + j] -= f * M[N * k + j];
            r[i] -= f * r[k];
        }
    for (int i = N - 1; i >= 0; i--) {
        double s = r[i];
        for (int j = i + 1; j < N; j++) s -= M[N * i + j] * d[j];
        d[i] = s / M[N * i + i];
    }
    (void)err;
    return 0;
}

/* Keeps x_0 above lower with 10% of its distance left, as the barriers' filters do. */
static double max_step(void *ctx, const double *x, const double *d)
{
    problem *p = ctx;
    return d[0] < 0 ? fmin(1.0, 0.9 * (x[0] - p->lower) / -d[0]) : 1.0;
}

static void setup(problem *p, rk_newton_problem *np, double c)
{
    memset(p, 0, sizeof *p);
    static const double A[N * N] = {4, 1, 0, 0.5, 1, 3, 0.2, 0, 0, 0.2, 2, 0.1, 0.5, 0, 0.1, 5};
    static const double b[N] = {1, -2, 0.5, 3};
    memcpy(p->A, A, sizeof A);
    memcpy(p->b, b, sizeof b);
    p->c = c;
    p->lower = -INFINITY;
    *np = (rk_newton_problem){.n = N, .ctx = p, .what = "test potential", .energy = energy, .solve = solve};
}

static double gradient_norm(problem *p, const double *x, const char *skip)
{
    double g[N], m = 0;
    energy(p, x, g, 0, NULL);
    for (int i = 0; i < N; i++)
        if (!skip || !skip[i]) m = fmax(m, fabs(g[i]));
    return m;
}

TEST(a_quadratic_takes_one_newton_step)
{
    problem p;
    rk_newton_problem np;
    setup(&p, &np, 0);
    double x[N] = {0}, work[RK_NEWTON_WORK(N)];
    int converged;
    rk_newton_stats stats = {0};
    rk_error err;
    CHECK_OK(rk_newton_solve(&np, x, 1e-12, 20, work, &converged, &stats, &err));
    CHECK(converged, "not converged");
    /* one step to the minimiser, and one more whose direction is (round-off) zero */
    CHECK(stats.iterations == 2 && stats.halvings == 0, "%ld iterations, %ld halvings", stats.iterations,
          stats.halvings);
    CHECK(gradient_norm(&p, x, NULL) < 1e-14, "gradient %g", gradient_norm(&p, x, NULL));
}

TEST(a_convex_function_converges_quadratically)
{
    problem p;
    rk_newton_problem np;
    setup(&p, &np, 2.0);
    double x[N] = {2, -2, 1, 1}, work[RK_NEWTON_WORK(N)];
    int converged;
    rk_newton_stats stats = {0};
    rk_error err;
    CHECK_OK(rk_newton_solve(&np, x, 1e-13, 50, work, &converged, &stats, &err));
    CHECK(converged && stats.iterations <= 8, "converged %d after %ld iterations", converged, stats.iterations);
    CHECK(gradient_norm(&p, x, NULL) < 1e-12, "gradient %g", gradient_norm(&p, x, NULL));
    /* max_iter bounds the work and leaves it unconverged */
    double y[N] = {2, -2, 1, 1};
    rk_newton_stats one = {0};
    CHECK_OK(rk_newton_solve(&np, y, 1e-13, 1, work, &converged, &one, &err));
    CHECK(!converged && one.iterations == 1, "one iteration: converged %d, %ld iterations", converged, one.iterations);
}

TEST(the_line_search_never_crosses_a_barrier)
{
    problem p;
    rk_newton_problem np;
    setup(&p, &np, 0);
    /* b pulls x_0 far below the barrier at x_0 = 0.9: the minimiser sits just above it */
    p.b[0] = -40;
    p.lower = 0.9;
    np.max_step = max_step;
    double x[N] = {1, 0, 0, 0}, work[RK_NEWTON_WORK(N)];
    int converged;
    rk_error err;
    CHECK_OK(rk_newton_solve(&np, x, 1e-12, 100, work, &converged, NULL, &err));
    CHECK(converged && x[0] > 0.9, "converged %d, x_0 = %.17g", converged, x[0]);
    CHECK(p.calls_outside == 0, "%d evaluations beyond the barrier", p.calls_outside);
    CHECK(gradient_norm(&p, x, NULL) < 1e-8, "gradient %g", gradient_norm(&p, x, NULL));
    /* without the filter the full Newton step crosses it and backtracking has to find the way back */
    problem q;
    setup(&q, &np, 0);
    q.b[0] = -40;
    q.lower = 0.9;
    double y[N] = {1, 0, 0, 0};
    CHECK_OK(rk_newton_solve(&np, y, 1e-12, 100, work, &converged, NULL, &err));
    CHECK(q.calls_outside > 0 && fabs(y[0] - x[0]) < 1e-9, "unfiltered: %d outside, x_0 %.17g vs %.17g",
          q.calls_outside, y[0], x[0]);
}

TEST(prescribed_entries_never_move)
{
    problem p;
    rk_newton_problem np;
    setup(&p, &np, 1.0);
    char fixed[N] = {0, 1, 0, 1};
    np.prescribed = fixed;
    p.fixed = fixed;
    double x[N] = {0.3, 0.7, -0.2, -1.5}, work[RK_NEWTON_WORK(N)];
    int converged;
    rk_error err;
    CHECK_OK(rk_newton_solve(&np, x, 1e-13, 50, work, &converged, NULL, &err));
    CHECK(converged, "not converged");
    CHECK(x[1] == 0.7 && x[3] == -1.5, "prescribed entries moved: %.17g %.17g", x[1], x[3]);
    CHECK(gradient_norm(&p, x, fixed) < 1e-12, "free gradient %g", gradient_norm(&p, x, fixed));
}

TEST(a_potential_that_is_not_finite_is_an_error_naming_the_iteration)
{
    problem p;
    rk_newton_problem np;
    setup(&p, &np, 1.0);
    p.nan_at = 1;
    double x[N] = {0}, work[RK_NEWTON_WORK(N)];
    int converged = 1;
    rk_error err;
    CHECK(rk_newton_solve(&np, x, 1e-12, 20, work, &converged, NULL, &err) != 0, "accepted a NaN potential");
    CHECK(strstr(err.msg, "test potential is not finite at Newton iteration 0") && !converged, "message: %s",
          err.msg);
    /* NaN on a later evaluation (a line-search trial) is rejected by the line search, and the first
     * evaluation of the next iteration names iteration 1 */
    setup(&p, &np, 1.0);
    p.nan_at = 3;
    double y[N] = {0};
    CHECK(rk_newton_solve(&np, y, 1e-12, 20, work, &converged, NULL, &err) != 0, "accepted a NaN potential");
    CHECK(strstr(err.msg, "Newton iteration 1"), "message: %s", err.msg);
}

/* x'' = -w^2 x from x = 1, v = 0 to time T with step h: error against cos(w T). The potential of a
 * step is w_inertia/2 |x - x~|^2 + w^2/2 x^2. */
typedef struct {
    const rk_stepper *st;
    double k, H;
} oscillator;

static double osc_energy(void *ctx, const double *x, double *g, int hessian, double *magnitude)
{
    oscillator *o = ctx;
    double r = x[0] - o->st->xtilde[0], E = 0.5 * o->st->w_inertia * r * r + 0.5 * o->k * x[0] * x[0];
    if (g) g[0] = o->st->w_inertia * r + o->k * x[0];
    if (hessian) o->H = o->st->w_inertia + o->k;
    if (magnitude) *magnitude = fabs(E);
    return E;
}

static int osc_solve(void *ctx, const double *g, double *d, rk_error *err)
{
    (void)err;
    d[0] = -g[0] / ((oscillator *)ctx)->H;
    return 0;
}

static double oscillator_error(rk_integrator integ, double h, double T)
{
    rk_stepper st;
    rk_error err;
    if (rk_stepper_init(&st, 1, integ, h, &err)) return NAN;
    oscillator o = {&st, 4.0, 0};
    rk_newton_problem np = {.n = 1, .ctx = &o, .energy = osc_energy, .solve = osc_solve};
    double x = 1, v = 0, work[RK_NEWTON_WORK(1)];
    int steps = (int)lround(T / h), converged;
    for (int s = 0; s < steps; s++) {
        rk_stepper_predict(&st, &x, &v);
        rk_stepper_start(&st, &np, &x);
        if (rk_newton_solve(&np, &x, 1e-14, 10, work, &converged, NULL, &err) || !converged) return NAN;
        rk_stepper_finish(&st, &x, &v);
    }
    rk_stepper_free(&st);
    return fabs(x - cos(2.0 * T));
}

TEST(backward_euler_is_first_order_and_bdf2_second)
{
    double T = 1.0;
    double be1 = oscillator_error(RK_BACKWARD_EULER, 1e-3, T), be2 = oscillator_error(RK_BACKWARD_EULER, 5e-4, T);
    double bd1 = oscillator_error(RK_BDF2, 1e-3, T), bd2 = oscillator_error(RK_BDF2, 5e-4, T);
    double order_be = log2(be1 / be2), order_bdf2 = log2(bd1 / bd2);
    printf("# oscillator to t = 1: BE errors %.3g, %.3g (order %.2f); BDF2 %.3g, %.3g (order %.2f)\n", be1, be2,
           order_be, bd1, bd2, order_bdf2);
    CHECK(fabs(order_be - 1) < 0.05, "backward Euler order %.3f", order_be);
    /* BDF2's first step is backward Euler: an O(h^2) local error, so the global order stays 2 */
    CHECK(fabs(order_bdf2 - 2) < 0.1, "BDF2 order %.3f", order_bdf2);
    CHECK(bd1 < be1 / 100, "BDF2 %.3g not far below BE %.3g", bd1, be1);
}

/* A load step converges only when lambda moves by at most 0.25 from the last converged one (a
 * Newton basin); x tracks lambda. */
typedef struct {
    double last;
    int calls, fail_at;
} ramp;

static int ramp_increment(void *ctx, double lambda, double *x, int *converged, rk_error *err)
{
    ramp *r = ctx;
    if (++r->calls == r->fail_at) return rk_fail(err, "solve broke");
    if (x[0] != r->last && x[0] != 0) return rk_fail(err, "increment did not start where the last ended");
    *converged = lambda - x[0] <= 0.25 + 1e-15;
    x[0] = *converged ? lambda : x[0] + 0.1;
    r->last = x[0];
    return 0;
}

TEST(load_stepping_ramps_a_load_newton_cannot_take_at_once)
{
    ramp r = {0};
    double x = 0;
    int converged, used;
    rk_error err;
    CHECK_OK(rk_load_stepping(1, &x, ramp_increment, &r, &converged, &used, &err));
    /* 1 increment fails; 4 increments of 0.25 converge, each from the last, restarting from 0 */
    CHECK(converged && used == 4 && x == 1.0 && r.calls == 5, "converged %d, %d increments, x %g, %d calls", converged,
          used, x, r.calls);
    ramp broken = {.fail_at = 3};
    x = 0;
    CHECK(rk_load_stepping(1, &x, ramp_increment, &broken, &converged, &used, &err) != 0, "error not passed on");
    CHECK(strstr(err.msg, "load increment 2 of 4: solve broke"), "message: %s", err.msg);
}

int main(void)
{
    RUN(a_quadratic_takes_one_newton_step);
    RUN(a_convex_function_converges_quadratically);
    RUN(the_line_search_never_crosses_a_barrier);
    RUN(prescribed_entries_never_move);
    RUN(a_potential_that_is_not_finite_is_an_error_naming_the_iteration);
    RUN(backward_euler_is_first_order_and_bdf2_second);
    RUN(load_stepping_ramps_a_load_newton_cannot_take_at_once);
    return test_finish();
}
