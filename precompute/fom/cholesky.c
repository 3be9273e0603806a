/* The Newton solver's factorizations (fom_impl.h): impl->N.A through the one sparse Cholesky
 * (fem.h, rk_chol: its policy and the measurements behind it are in fem/cholesky.c), with the
 * seconds and counts the run reports. */
#include "fom/fom_impl.h"

#include "fem/fem.h"

#include "util/util.h"

int rk_fom_chol_analyze(rk_fom_impl *im, rk_error *err)
{
    return rk_fom_chol_reanalyze(im, err);
}

int rk_fom_chol_reanalyze(rk_fom_impl *im, rk_error *err)
{
    double t0 = rk_now();
    int rc = rk_chol_analyze(&im->chol, &im->N.A, err);
    im->seconds_analyze += rk_now() - t0;
    im->analyses++;
    return rc;
}

int rk_fom_chol_factor(rk_fom *s, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    double t0 = rk_now();
    int rc = rk_chol_factor(&im->chol, err);
    double dt = rk_now() - t0;
    s->stats.seconds_factor += dt;
    rk_fom_iteration_factor(im, dt);
    if (rc == RK_CHOL_NOT_POSDEF && im->exact_elastic) return RK_FOM_NOT_POSDEF;
    if (rc == RK_CHOL_NOT_POSDEF) /* impossible with projected Hessians unless a bug */
        return rk_fail(err, "Newton matrix is not positive definite (CHOLMOD stopped at column %d of %d)",
                       rk_chol_minor(&im->chol), im->ndof);
    return rc;
}

int rk_fom_chol_solve(rk_fom *s, const double *g, double *d, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    double t0 = rk_now();
    int rc = rk_chol_solve(&im->chol, g, d, err);
    if (!rc)
        for (int i = 0; i < im->ndof; i++) d[i] = -d[i];
    s->stats.seconds_solve += rk_now() - t0;
    return rc;
}

void rk_fom_chol_free(rk_fom_impl *im)
{
    rk_chol_free(&im->chol);
}
