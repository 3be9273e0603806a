/* Projected Newton on the incremental potential (paper Sec. 3.10 in full space): direction from
 * the PSD-projected Hessian by CHOLMOD, plane step filtering, backtracking line search with the
 * Armijo condition, termination on the size of the Newton step. */
#include "fom/impl.h"

#include <math.h>
#include <string.h>

#define ARMIJO_C 1e-4
#define MAX_HALVINGS 40 /* alpha down to ~1e-12: below that the direction is useless */
/* Energy differences below this fraction of the terms' magnitude are round-off: near the
 * solution the true decrease (~ d^T H d) falls under it, and a plain Armijo test would then
 * reject every step and stall Newton short of a tight tolerance. */
#define ENERGY_NOISE 1e-13

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

int rk_fom_newton(rk_fom *s, const rk_fom_terms *T, double tol_d, int *converged, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    int n = im->n;
    double *x = s->x, *g = im->g, *d = im->d, *trial = im->x_trial;
    *converged = 0;
    for (int it = 0; it < s->opt.newton_max_iter; it++) {
        double magnitude;
        double E = rk_fom_potential(s, T, x, g, &im->H, &magnitude);
        if (!isfinite(E) || !all_finite(g, n))
            return rk_fail(err, "incremental potential is not finite at Newton iteration %d", it);
        if (rk_fom_chol_factor(s, err) || rk_fom_chol_solve(s, g, d, err))
            return rk_error_prefix(err, "Newton iteration %d", it);
        s->stats.newton_iterations++;
        if (!all_finite(d, n)) return rk_fail(err, "Newton direction is not finite at iteration %d", it);
        /* Checked before the line search: near the solution the decrease of E drowns in
         * round-off, and a step this small is the answer anyway. */
        if (inf_norm(d, n) <= tol_d) {
            *converged = 1;
            return 0;
        }
        double gd = 0;
        for (int i = 0; i < n; i++) gd += g[i] * d[i];
        double alpha = s->opt.obstacles.count ? rk_planes_max_step(&s->opt.obstacles, s->fem->nv, x, d) : 1.0;
        int accepted = 0;
        for (int k = 0; k <= MAX_HALVINGS && !accepted; k++) {
            if (k > 0) {
                alpha *= 0.5;
                s->stats.line_search_halvings++;
            }
            for (int i = 0; i < n; i++) trial[i] = x[i] + alpha * d[i];
            double Et = rk_fom_potential(s, T, trial, NULL, NULL, NULL);
            accepted = Et <= E + ARMIJO_C * alpha * gd || (isfinite(Et) && Et - E <= ENERGY_NOISE * magnitude);
        }
        if (!accepted) return 0; /* no decrease along d: stop, unconverged */
        memcpy(x, trial, (size_t)n * sizeof(double));
    }
    return 0;
}
