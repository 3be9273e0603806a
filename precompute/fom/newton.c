/* The full-order incremental potential as the solver's Newton problem (solver.h): CHOLMOD on the
 * PSD-projected Hessian for the direction, CCD step filtering with contact, |d|_inf as the step
 * size. */
#include "fom/fom_impl.h"

#include <math.h>
#include <string.h>

static double energy(void *ctx, const double *x, double *g, int hessian, double *magnitude)
{
    rk_fom_problem_ctx *c = ctx;
    return rk_fom_potential(c->s, c->T, x, g, hessian, magnitude, &c->failure);
}

static int solve(void *ctx, const double *g, double *d, rk_error *err)
{
    rk_fom *s = ((rk_fom_problem_ctx *)ctx)->s;
    return rk_fom_chol_factor(s, err) || rk_fom_chol_solve(s, g, d, err) ? -1 : 0;
}

static double max_step(void *ctx, const double *x, const double *d)
{
    rk_fom_problem_ctx *c = ctx;
    double alpha = rk_contact_max_step(&c->s->impl->contact, x, d, NAN, &c->failure);
    return alpha >= 0 ? alpha : 0; /* a failed CCD (out of memory) takes no step */
}

void rk_fom_problem(rk_fom_problem_ctx *ctx, rk_newton_problem *p)
{
    rk_fom *s = ctx->s;
    ctx->failure.msg[0] = 0;
    *p = (rk_newton_problem){.n = s->impl->n, .ctx = ctx, .what = "incremental potential", .energy = energy,
                             .solve = solve, .max_step = s->impl->has_contact ? max_step : NULL,
                             .prescribed = s->opt.nprescribed ? s->impl->prescribed_dof : NULL};
}

int rk_fom_newton(rk_fom *s, const rk_fom_terms *T, double tol_d, int *converged, rk_error *err)
{
    rk_fom_problem_ctx ctx = {.s = s, .T = T};
    rk_newton_problem p;
    rk_fom_problem(&ctx, &p);
    rk_newton_stats stats = {0};
    int rc = rk_newton_solve(&p, s->x, tol_d, s->opt.newton_max_iter, s->impl->newton_work, converged, &stats, err);
    s->stats.newton_iterations += stats.iterations;
    s->stats.line_search_halvings += stats.halvings;
    if (ctx.failure.msg[0]) { /* what made the potential or the step fail, rather than its symptom */
        *err = ctx.failure;
        return -1;
    }
    return rc;
}
