/* Static equilibrium: minimise Psi + B - f.x (no inertia, no damping) with the same Newton
 * solver; if the full load does not converge within newton_max_iter, restart from the initial
 * state and ramp the load (forces, gravity and the prescribed motions' time) over 4, then 16
 * increments, each solved from the previous one. */
#include "fom/impl.h"

#include "fem/element.h"
#include "util/timer.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Hessian shift, relative to the mean diagonal stiffness per unit mass: enough to keep the
 * Cholesky factorization of a singular projected Hessian (free rigid modes, e.g. sliding on a
 * plane) well defined, and small enough (against the lowest elastic mode of any sane mesh)
 * that Newton still converges in a few iterations. */
#define STATIC_REG 1e-10

static double static_reg(rk_fom *s)
{
    rk_fom_impl *im = s->impl;
    const rk_fem *f = s->fem;
    rk_sparse_zero(&im->H); /* scratch: it is rebuilt at each Newton iteration */
    rk_fem_add_rest_stiffness(f, 1.0, &im->H);
    double trace_k = 0, trace_m = 0;
    for (int v = 0; v < f->nv; v++)
        for (int i = 0; i < 3; i++) {
            trace_k += im->H.val[rk_fem_diag_slot(&im->H, v, i, i)];
            trace_m += f->vertex_mass[v];
        }
    return STATIC_REG * trace_k / trace_m;
}

static int has_load(const rk_fom *s)
{
    for (int i = 0; i < s->impl->n; i++)
        if (s->impl->f_ext[i] != 0) return 1;
    return 0;
}

static int solve(rk_fom *s, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    if (s->opt.nprescribed == 0 && s->opt.obstacles.count == 0 && has_load(s))
        return rk_fail(err, "a loaded body with no prescribed vertex and no obstacle has no equilibrium");
    rk_fom_terms T = {0};
    T.reg = static_reg(s);
    double t_end = s->opt.steps * s->opt.h;
    double *start = rk_calloc((size_t)im->n, sizeof(double), err); /* the start of every attempt */
    if (!start) return -1;
    memcpy(start, s->x, (size_t)im->n * sizeof(double));
    static const int increments[] = {1, 4, 16};
    int attempts = (int)(sizeof increments / sizeof increments[0]);
    for (int a = 0; a < attempts; a++) {
        int k = increments[a], converged = 1;
        memcpy(s->x, start, (size_t)im->n * sizeof(double));
        for (int i = 1; i <= k && converged; i++) {
            double lambda = (double)i / k;
            T.load = lambda;
            rk_fom_prescribe(s, lambda * t_end, s->x);
            if (rk_fom_check_planes(s, s->x, err) || rk_fom_newton(s, &T, im->tol_static, &converged, err)) {
                free(start);
                return rk_error_prefix(err, "load increment %d of %d", i, k);
            }
        }
        if (converged) {
            memset(s->v, 0, (size_t)im->n * sizeof(double));
            free(start);
            return 0;
        }
    }
    free(start);
    return rk_fail(err, "no convergence to |d|_inf <= %g m within %d Newton iterations, even in %d load increments",
                   im->tol_static, s->opt.newton_max_iter, increments[attempts - 1]);
}

int rk_fom_static(rk_fom *s, rk_error *err)
{
    double t0 = rk_now();
    int rc = solve(s, err);
    s->stats.seconds_total += rk_now() - t0;
    return rc ? rk_error_prefix(err, "static solve") : 0;
}
