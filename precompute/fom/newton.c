/* The full-order incremental potential as the solver's Newton problem (solver.h): CHOLMOD on the
 * PSD-projected Hessian for the direction, plane step filtering, |d|_inf as the step size. */
#include "fom/fom_impl.h"

static double energy(void *ctx, const double *x, double *g, int hessian, double *magnitude)
{
    rk_fom_problem_ctx *c = ctx;
    return rk_fom_potential(c->s, c->T, x, g, hessian ? &c->s->impl->H : NULL, magnitude);
}

static int solve(void *ctx, const double *g, double *d, rk_error *err)
{
    rk_fom *s = ((rk_fom_problem_ctx *)ctx)->s;
    return rk_fom_chol_factor(s, err) || rk_fom_chol_solve(s, g, d, err) ? -1 : 0;
}

static double max_step(void *ctx, const double *x, const double *d)
{
    const rk_fom *s = ((rk_fom_problem_ctx *)ctx)->s;
    return rk_planes_max_step(&s->opt.obstacles, s->fem->nv, x, d);
}

void rk_fom_problem(rk_fom_problem_ctx *ctx, rk_newton_problem *p)
{
    rk_fom *s = ctx->s;
    *p = (rk_newton_problem){.n = s->impl->n, .ctx = ctx, .what = "incremental potential", .energy = energy,
                             .solve = solve, .max_step = s->opt.obstacles.count ? max_step : NULL,
                             .prescribed = s->opt.nprescribed ? s->impl->prescribed_dof : NULL};
}

int rk_fom_newton(rk_fom *s, const rk_fom_terms *T, double tol_d, int *converged, rk_error *err)
{
    rk_fom_problem_ctx ctx = {s, T};
    rk_newton_problem p;
    rk_fom_problem(&ctx, &p);
    rk_newton_stats stats = {0};
    int rc = rk_newton_solve(&p, s->x, tol_d, s->opt.newton_max_iter, s->impl->newton_work, converged, &stats, err);
    s->stats.newton_iterations += stats.iterations;
    s->stats.line_search_halvings += stats.halvings;
    return rc;
}
