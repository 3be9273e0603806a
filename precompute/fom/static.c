/* Static equilibrium: minimise Psi + B - f.x (no inertia, no damping) with the same Newton
 * solver, the load (forces, gravity and the prescribed motions' time) ramped by the solver's load
 * stepping when the full load does not converge within newton_max_iter. */
#include "fom/fom_impl.h"

#include "fem/fem.h"
#include "util/util.h"

#include <math.h>
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

typedef struct {
    rk_fom *s;
    rk_fom_terms T;
    double t_end;
    double last_lambda;     /* the previous increment's load fraction */
} static_ctx;

typedef struct {
    static_ctx *c;
    int converged;
} static_solve;

static int solve_increment(rk_fom *s, void *ctx, rk_error *err)
{
    static_solve *c = ctx;
    return rk_fom_newton(s, &c->c->T, s->impl->tol_static, &c->converged, err);
}

/* One load increment: forces at lambda, the prescribed motions and obstacles at lambda t_end. */
static int increment(void *ctx, double lambda, double *x, int *converged, rk_error *err)
{
    static_ctx *c = ctx;
    /* a new attempt starts over from the initial state: the obstacles too */
    if (lambda <= c->last_lambda && c->s->impl->has_contact) rk_contact_set_time(&c->s->impl->contact, 0);
    c->last_lambda = lambda;
    rk_fom_obstacle_targets(c->s, lambda * c->t_end);
    c->T.load = lambda;
    static_solve sv = {c, 1};
    int rc = rk_fom_advance_kinematics(c->s, lambda * c->t_end, solve_increment, &sv, err);
    *converged = sv.converged;
    return rc;
}

static int solve(rk_fom *s, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    if (s->opt.nprescribed == 0 && !s->impl->has_contact && has_load(s))
        return rk_fail(err, "a loaded body with no prescribed vertex and no obstacle has no equilibrium");
    static_ctx c = {.s = s, .T = {.reg = static_reg(s)}, .t_end = s->opt.steps * s->opt.h};
    rk_fom_pressure_at(s, c.t_end);
    int converged, used;
    if (rk_load_stepping(im->n, s->x, increment, &c, &converged, &used, err)) return -1;
    if (!converged)
        return rk_fail(err, "no convergence to |d|_inf <= %g m within %d Newton iterations, even in %d load increments",
                       im->tol_static, rk_fom_max_iter(&s->opt, 0), used);
    memset(s->v, 0, (size_t)im->n * sizeof(double));
    return 0;
}

int rk_fom_static(rk_fom *s, rk_error *err)
{
    double t0 = rk_now();
    int rc = solve(s, err);
    s->stats.seconds_total += rk_now() - t0;
    rk_fom_sync_stats(s);
    return rc ? rk_error_prefix(err, "static solve") : 0;
}
