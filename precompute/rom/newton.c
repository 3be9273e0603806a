/* The reduced incremental potential as the solver's Newton problem (solver.h): a dense Cholesky
 * (LAPACK dpotrf) of the r x r Hessian in place of CHOLMOD. Each iteration first tries the exact
 * Hessian (the elements' dP/dF unprojected): the reduced matrix is almost always positive definite
 * anyway, its inertia M_r / h^2 outweighing the elements' small negative twist eigenvalues, and it
 * is then Newton's own matrix at no SVD per element; where Cholesky fails, the projected Hessian
 * (each element's dP/dF clamped to PSD) is assembled at the same point and used instead. The
 * runtime does the same (runtime/step.c), so both take the same iterates. */
#include "rom/rom_impl.h"

#include <cblas.h>
#include <lapacke.h>
#include <math.h>

static double *hessian_of(rk_rom *s)
{
    return s->work + RK_ROM_WORK_VECTORS * (size_t)s->model->r;
}

static double energy(void *ctx, const double *q, double *g, int hessian, double *magnitude)
{
    rk_rom_problem_ctx *c = ctx;
    if (hessian) c->q = q;
    c->s->exact_hessian = hessian != 0;
    double E = rk_rom_potential(c->s, c->T, q, g, hessian ? hessian_of(c->s) : NULL, magnitude, &c->failure);
    c->s->exact_hessian = 0;
    return E;
}

/* d = -H^-1 g by Cholesky of H (upper triangle, overwritten); the projected H where the exact one
 * is not positive definite. */
static int solve(void *ctx, const double *g, double *d, rk_error *err)
{
    rk_rom_problem_ctx *c = ctx;
    rk_rom *s = c->s;
    int r = s->model->r;
    double *H = hessian_of(s);
    for (int i = 0; i < r; i++) d[i] = -g[i];
    int info = LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'U', r, H, r);
    if (info != 0 && c->q) {
        if (!isfinite(rk_rom_potential(s, c->T, c->q, NULL, H, NULL, &c->failure)))
            return rk_fail(err, "the reduced potential is not finite where its Hessian was asked for");
        s->stats.projected_hessians++;
        info = LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'U', r, H, r);
    }
    if (info != 0)
        return rk_fail(err, "the %d x %d reduced Newton matrix is not positive definite (pivot %d); the basis may "
                       "have dependent columns", r, r, info);
    LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'U', r, 1, H, r, d, r);
    return 0;
}

static double max_step(void *ctx, const double *q, const double *d)
{
    rk_rom_problem_ctx *c = ctx;
    double alpha = rk_rom_contact_max_step(c->s, q, d, NAN, &c->failure);
    return alpha >= 0 ? alpha : 0; /* a failed CCD (out of memory) takes no step */
}

/* sqrt(d^T M_r d / total mass): the step as an RMS displacement. */
double rk_rom_step_rms(rk_rom *s, const double *d)
{
    const rk_rom_model *m = s->model;
    double *tmp = s->work + RK_ROM_WORK_TMP * (size_t)m->r;
    cblas_dsymv(CblasColMajor, CblasUpper, m->r, 1.0, m->M, m->r, d, 1, 0.0, tmp, 1);
    return sqrt(fmax(cblas_ddot(m->r, d, 1, tmp, 1), 0.0) / m->mass);
}

static double step_norm(void *ctx, const double *d)
{
    return rk_rom_step_rms(((rk_rom_problem_ctx *)ctx)->s, d);
}

int rk_rom_dense_solve(double *H, int n, const double *g, double *d, const char *what, rk_error *err)
{
    for (int i = 0; i < n; i++) d[i] = -g[i];
    int info = LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'U', n, H, n);
    if (info != 0) return rk_fail(err, "the Newton matrix of %s is not positive definite (pivot %d)", what, info);
    LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'U', n, 1, H, n, d, n);
    return 0;
}

void rk_rom_problem(rk_rom_problem_ctx *ctx, rk_newton_problem *p)
{
    const rk_rom_model *m = ctx->s->model;
    ctx->failure.msg[0] = 0;
    *p = (rk_newton_problem){.n = m->r, .ctx = ctx, .what = "reduced incremental potential", .energy = energy,
                             .solve = solve, .max_step = rk_rom_contact_on(m) || ctx->s->ncolliders ? max_step : NULL, .step_norm = step_norm};
}

int rk_rom_newton(rk_rom *s, const rk_rom_terms *T, double tol_d, int *converged, rk_error *err)
{
    rk_rom_problem_ctx ctx = {.s = s, .T = T};
    rk_newton_problem p;
    rk_rom_problem(&ctx, &p);
    rk_newton_stats stats = {0};
    double *work = s->work + RK_ROM_WORK_NEWTON * (size_t)s->model->r;
    int rc = rk_newton_solve(&p, s->q, tol_d, s->model->newton_max_iter, work, converged, &stats, err);
    s->stats.newton_iterations += stats.iterations;
    s->stats.line_search_halvings += stats.halvings;
    if (ctx.failure.msg[0]) { /* what made the potential or the step fail, rather than its symptom */
        *err = ctx.failure;
        return -1;
    }
    return rc;
}
