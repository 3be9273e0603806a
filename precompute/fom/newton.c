/* The full-order incremental potential as the solver's Newton problem (solver.h): CHOLMOD on the
 * PSD-projected Hessian for the direction, CCD step filtering with contact, |d|_inf as the step
 * size; moving obstacles in augmented-Lagrangian rounds. */
#include "fom/fom_impl.h"

#include <math.h>
#include <string.h>

#include "util/util.h"

/* Augmented-Lagrangian rounds before a moving obstacle that cannot reach its target counts as
 * stuck, and how close to it counts as there (a fraction of dhat). */
#define AL_ROUNDS 30
#define AL_TOLERANCE 1e-2

/* Each time step's Newton iteration builds its matrix from the elements' exact dP/dF first (the
 * tangent stiffness: Newton proper, and no SVD per element), which the inertia M / h^2 keeps
 * positive definite almost always; where CHOLMOD finds it is not, the same matrix with dP/dF
 * projected to PSD (Smith et al. 2019), factored again. The reduced simulator and the runtime do
 * the same (precompute/rom/newton.c, runtime/step.c). Static solves, with no inertia, project. */
static double energy(void *ctx, const double *y, double *g, int hessian, double *magnitude)
{
    rk_fom_problem_ctx *c = ctx;
    if (hessian) {
        c->s->impl->exact_elastic = c->T->w_inertia > 0;
        c->y = y;
    }
    return rk_fom_potential(c->s, c->T, y, g, hessian, magnitude, &c->failure);
}

static int solve(void *ctx, const double *g, double *d, rk_error *err)
{
    rk_fom_problem_ctx *c = ctx;
    rk_fom *s = c->s;
    int rc = rk_fom_chol_factor(s, err);
    if (rc == RK_FOM_NOT_POSDEF) {
        s->stats.projected_hessians++;
        rc = rk_fom_newton_matrix_projected(s, c->T, c->y, err) ? -1 : rk_fom_chol_factor(s, err);
    }
    s->impl->exact_elastic = 0;
    return rc || rk_fom_chol_solve(s, g, d, err) ? -1 : 0;
}

static double max_step(void *ctx, const double *y, const double *d)
{
    rk_fom_problem_ctx *c = ctx;
    rk_fom_impl *im = c->s->impl;
    if (im->nobs) memcpy(im->contact.ox, y + im->n, sizeof(double) * 3 * (size_t)im->nobs);
    double t0 = rk_now();
    double alpha = rk_fom_contact_ccd(im, y, d, im->nobs ? d + im->n : NULL, &c->failure);
    c->s->stats.seconds_contact += rk_now() - t0;
    return alpha >= 0 ? alpha : 0; /* a failed CCD (out of memory) takes no step */
}

void rk_fom_problem(rk_fom_problem_ctx *ctx, rk_newton_problem *p)
{
    rk_fom *s = ctx->s;
    rk_fom_impl *im = s->impl;
    ctx->failure.msg[0] = 0;
    *p = (rk_newton_problem){.n = im->ndof, .ctx = ctx, .what = "incremental potential", .energy = energy,
                             .solve = solve, .max_step = im->has_contact ? max_step : NULL,
                             .prescribed = s->opt.nprescribed || im->nobs ? im->prescribed_dof : NULL};
}

/* The largest distance of a moving obstacle vertex from its target. */
static double obstacle_residual(const rk_fom_impl *im)
{
    double r = 0;
    for (int i = 0; i < 3 * im->nobs; i++)
        if (!im->prescribed_dof[im->n + i]) r = fmax(r, fabs(im->y[im->n + i] - im->obs_target[i]));
    return r;
}

/* Moves the obstacles exactly onto their targets when CCD allows the last bit of the way. */
static int snap_obstacles(rk_fom *s, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    double *odx = im->g_barrier + im->n; /* scratch */
    memset(im->g_barrier, 0, sizeof(double) * (size_t)im->n);
    for (int i = 0; i < 3 * im->nobs; i++) odx[i] = im->prescribed_dof[im->n + i] ? 0 : im->obs_target[i] - im->y[im->n + i];
    double alpha = rk_fom_contact_ccd(im, im->y, im->g_barrier, odx, err);
    if (alpha < 0) return -1;
    if (alpha >= 1)
        for (int i = 0; i < 3 * im->nobs; i++) im->y[im->n + i] += odx[i];
    return 0;
}

int rk_fom_newton(rk_fom *s, const rk_fom_terms *T, double tol_d, int *converged, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    rk_fom_problem_ctx ctx = {.s = s, .T = T};
    rk_newton_problem p;
    rk_fom_problem(&ctx, &p);
    rk_newton_stats stats = {0};
    memcpy(im->y, s->x, sizeof(double) * (size_t)im->n);
    if (im->nobs) memcpy(im->y + im->n, im->contact.ox, sizeof(double) * 3 * (size_t)im->nobs);
    double tol_obs = AL_TOLERANCE * im->contact.opt.dhat, last = INFINITY;
    int rc = 0;
    for (int round = 0; round < (im->nobs ? AL_ROUNDS : 1) && !rc; round++) {
        rc = rk_newton_solve(&p, im->y, tol_d, rk_fom_max_iter(&s->opt, 0), im->newton_work, converged, &stats, err);
        rk_fom_iteration_end(im);
        if (rc || !im->nobs) break;
        double r = obstacle_residual(im);
        if (r <= tol_obs) break;
        /* the method of multipliers: lambda <- lambda - k m (y - target); k doubles while slow */
        double k = im->al_kappa * im->al_mass;
        for (int i = 0; i < 3 * im->nobs; i++)
            if (!im->prescribed_dof[im->n + i]) im->al_lambda[i] -= k * (im->y[im->n + i] - im->obs_target[i]);
        if (r > 0.5 * last) im->al_kappa *= 2;
        last = r;
        if (round == AL_ROUNDS - 1)
            rc = rk_fail(err, "a moving obstacle could not reach where it is due (still %.3g m off after %d rounds): "
                         "is something pinned between it and another obstacle?", r, AL_ROUNDS);
    }
    if (!rc && im->nobs) rc = snap_obstacles(s, err);
    memcpy(s->x, im->y, sizeof(double) * (size_t)im->n);
    if (im->nobs) memcpy(im->contact.ox, im->y + im->n, sizeof(double) * 3 * (size_t)im->nobs);
    s->stats.newton_iterations += stats.iterations;
    s->stats.line_search_halvings += stats.halvings;
    if (ctx.failure.msg[0]) { /* what made the potential or the step fail, rather than its symptom */
        *err = ctx.failure;
        return -1;
    }
    return rc;
}

const rk_sparse *rk_fom_newton_matrix(const rk_fom *s)
{
    return &s->impl->N.A;
}

int rk_fom_newton_direction(rk_fom *s, const double *g, double *d, rk_error *err)
{
    return rk_fom_chol_factor(s, err) || rk_fom_chol_solve(s, g, d, err) ? -1 : 0;
}
