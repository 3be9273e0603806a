/* rk_lbfgs_minimize on problems with known minima: the Rosenbrock valley (minimum at (1, 1, ...)),
 * an ill-conditioned quadratic (condition number 1e4, exact answer by construction), and the
 * refusals: bad options, a failing or non-finite objective. */
#include <math.h>
#include <string.h>

#include "neural/neural.h"
#include "testlib.h"

static int rosenbrock(void *ctx, const double *x, double *f, double *g, rk_error *err)
{
    int n = *(int *)ctx;
    *f = 0;
    memset(g, 0, sizeof(double) * n);
    for (int i = 0; i + 1 < n; i++) {
        double a = x[i + 1] - x[i] * x[i], b = 1 - x[i];
        *f += 100 * a * a + b * b;
        g[i] += -400 * a * x[i] - 2 * b;
        g[i + 1] += 200 * a;
    }
    return 0;
}

#define NQ 30
static double qd[NQ], qc[NQ];

static int quadratic(void *ctx, const double *x, double *f, double *g, rk_error *err)
{
    *f = 0;
    for (int i = 0; i < NQ; i++) {
        double e = x[i] - qc[i];
        *f += 0.5 * qd[i] * e * e;
        g[i] = qd[i] * e;
    }
    return 0;
}

static int failing(void *ctx, const double *x, double *f, double *g, rk_error *err)
{
    return rk_fail(err, "objective refused");
}

static int not_finite(void *ctx, const double *x, double *f, double *g, rk_error *err)
{
    *f = NAN;
    g[0] = 0;
    return 0;
}

TEST(reaches_the_rosenbrock_minimum)
{
    rk_error err;
    int n = 10;
    double x[10];
    for (int i = 0; i < n; i++) x[i] = i % 2 ? 1.0 : -1.2;
    rk_lbfgs_options o = {.iterations = 2000, .memory = 10, .tolerance = 1e-10};
    rk_lbfgs_report rep;
    CHECK_OK(rk_lbfgs_minimize(n, x, rosenbrock, &n, &o, &rep, &err));
    double worst = 0;
    for (int i = 0; i < n; i++) worst = fmax(worst, fabs(x[i] - 1));
    printf("# rosenbrock n = 10: f %.3g -> %.3g in %d iterations (%ld evaluations), max |x - 1| %.2e\n", rep.initial,
           rep.final, rep.iterations, rep.evaluations, worst);
    CHECK(worst < 1e-8, "max |x - 1| = %g", worst);
    CHECK(rep.final < 1e-16, "f = %g", rep.final);
}

TEST(solves_an_ill_conditioned_quadratic)
{
    rk_error err;
    double x[NQ];
    for (int i = 0; i < NQ; i++) {
        qd[i] = pow(1e4, (double)i / (NQ - 1)); /* eigenvalues 1 .. 1e4 */
        qc[i] = sin(1.0 + i);
        x[i] = 0;
    }
    rk_lbfgs_options o = {.iterations = 500, .memory = 30, .tolerance = 1e-9};
    rk_lbfgs_report rep;
    CHECK_OK(rk_lbfgs_minimize(NQ, x, quadratic, NULL, &o, &rep, &err));
    double worst = 0;
    for (int i = 0; i < NQ; i++) worst = fmax(worst, fabs(x[i] - qc[i]));
    printf("# quadratic, condition 1e4: %d iterations, max error %.2e\n", rep.iterations, worst);
    CHECK(worst < 1e-10, "max error %g", worst);
    CHECK(rep.final <= rep.initial, "f rose: %g -> %g", rep.initial, rep.final);
}

TEST(refuses_bad_options_and_bad_objectives)
{
    rk_error err;
    double x[2] = {0, 0};
    int n = 2;
    rk_lbfgs_options bad = {.iterations = 10, .memory = 0};
    CHECK(rk_lbfgs_minimize(2, x, rosenbrock, &n, &bad, NULL, &err) && strstr(err.msg, "memory 0"), "%s", err.msg);
    CHECK(rk_lbfgs_minimize(0, x, rosenbrock, &n, NULL, NULL, &err) && strstr(err.msg, "0 unknowns"), "%s", err.msg);
    CHECK(rk_lbfgs_minimize(2, x, failing, NULL, NULL, NULL, &err) && strstr(err.msg, "objective refused"), "%s",
          err.msg);
    CHECK(rk_lbfgs_minimize(1, x, not_finite, NULL, NULL, NULL, &err) && strstr(err.msg, "nan"), "%s", err.msg);
    CHECK(x[0] == 0 && x[1] == 0, "x moved on failure: %g %g", x[0], x[1]);
}

int main(void)
{
    RUN(reaches_the_rosenbrock_minimum);
    RUN(solves_an_ill_conditioned_quadratic);
    RUN(refuses_bad_options_and_bad_objectives);
    return test_finish();
}
