/* Projected Newton with a backtracking line search (adaptive-subspace paper, Sec. 3.10): the
 * direction from the problem's PSD-projected Hessian, the line search from the problem's largest
 * feasible step, termination on the size of the Newton step. */
#include "solver/solver.h"

#include <math.h>
#include <string.h>

static double inf_norm(const double *a, int n)
{
    double m = 0;
    for (int i = 0; i < n; i++) m = fmax(m, fabs(a[i])); /* fmax drops NaN: checked separately */
    return m;
}

static int all_finite(const double *a, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(a[i])) return 0;
    return 1;
}

static void zero_prescribed(const char *prescribed, double *a, int n)
{
    if (prescribed)
        for (int i = 0; i < n; i++)
            if (prescribed[i]) a[i] = 0;
}

int rk_newton_solve(const rk_newton_problem *p, double *x, double tol, int max_iter, double *work,
                    int *converged, rk_newton_stats *stats, rk_error *err)
{
    int n = p->n;
    double *g = work, *d = work + n, *trial = work + 2 * (size_t)n;
    const char *what = p->what ? p->what : "incremental potential";
    *converged = 0;
    for (int it = 0; it < max_iter; it++) {
        double magnitude;
        double E = p->energy(p->ctx, x, g, 1, &magnitude);
        zero_prescribed(p->prescribed, g, n);
        if (!isfinite(E) || !all_finite(g, n))
            return rk_fail(err, "%s is not finite at Newton iteration %d", what, it);
        if (p->solve(p->ctx, g, d, err)) return rk_error_prefix(err, "Newton iteration %d", it);
        zero_prescribed(p->prescribed, d, n);
        if (stats) stats->iterations++;
        if (!all_finite(d, n)) return rk_fail(err, "Newton direction is not finite at iteration %d", it);
        if ((p->step_norm ? p->step_norm(p->ctx, d) : inf_norm(d, n)) <= tol) {
            *converged = 1;
            return 0;
        }
        double gd = 0;
        for (int i = 0; i < n; i++) gd += g[i] * d[i];
        double alpha = p->max_step ? p->max_step(p->ctx, x, d) : 1.0;
        int accepted = 0;
        for (int k = 0; k <= RK_MAX_HALVINGS && !accepted; k++) {
            if (k > 0) {
                alpha *= 0.5;
                if (stats) stats->halvings++;
            }
            for (int i = 0; i < n; i++) trial[i] = x[i] + alpha * d[i];
            double Et = p->energy(p->ctx, trial, NULL, 0, NULL);
            accepted = Et <= E + RK_ARMIJO_C * alpha * gd ||
                       (isfinite(Et) && Et - E <= RK_ENERGY_NOISE_DOUBLE * magnitude);
        }
        if (!accepted) return 0; /* no decrease along d: stop, unconverged */
        memcpy(x, trial, (size_t)n * sizeof(double));
    }
    return 0;
}
