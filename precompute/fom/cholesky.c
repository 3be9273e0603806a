/* CHOLMOD behind the Newton solver: impl->N.A is wrapped (no copy) as a symmetric upper matrix;
 * the fill-reducing ordering and symbolic factorization are computed at init and again only when
 * contact changes which vertices the matrix couples (never without contact); each Newton
 * iteration refactorizes numerically into the same L and solves with cholmod_solve2, which reuses
 * its dense workspaces (no per-iteration allocation). */
#include "fom/fom_impl.h"

#include "fem/fem.h"

#include "util/util.h"

#include <string.h>

int rk_fom_chol_analyze(rk_fom_impl *im, rk_error *err)
{
    cholmod_start(&im->cc);
    im->cc_started = 1;
    im->cc.print = 0; /* errors come back through rk_error, not stderr */
    im->cc.error_handler = NULL;
    return rk_fom_chol_reanalyze(im, err);
}

int rk_fom_chol_reanalyze(rk_fom_impl *im, rk_error *err)
{
    if (im->L) cholmod_free_factor(&im->L, &im->cc);
    rk_cholmod_sparse_view(&im->N.A, &im->A);
    im->L = cholmod_analyze(&im->A, &im->cc);
    if (!im->L || im->cc.status < CHOLMOD_OK)
        return rk_fail(err, "CHOLMOD symbolic analysis failed (status %d) on %d dofs, %d nonzeros",
                       im->cc.status, im->N.A.n, im->N.A.nnz);
    return 0;
}

int rk_fom_chol_factor(rk_fom *s, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    double t0 = rk_now();
    int ok = cholmod_factorize(&im->A, im->L, &im->cc);
    s->stats.seconds_factor += rk_now() - t0;
    if (im->cc.status == CHOLMOD_NOT_POSDEF) /* impossible with projected Hessians unless a bug */
        return rk_fail(err, "Newton matrix is not positive definite (CHOLMOD stopped at column %d of %d)",
                       (int)im->L->minor, im->ndof);
    if (!ok || im->cc.status < CHOLMOD_OK)
        return rk_fail(err, "CHOLMOD factorization failed (status %d)", im->cc.status);
    return 0;
}

int rk_fom_chol_solve(rk_fom *s, const double *g, double *d, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    double t0 = rk_now();
    cholmod_dense B;
    rk_cholmod_dense_view(g, im->ndof, &B);
    int ok = cholmod_solve2(CHOLMOD_A, im->L, &B, NULL, &im->sol, NULL, &im->Y, &im->E, &im->cc);
    if (ok) {
        const double *y = im->sol->x;
        for (int i = 0; i < im->ndof; i++) d[i] = -y[i];
    }
    s->stats.seconds_solve += rk_now() - t0;
    return ok ? 0 : rk_fail(err, "CHOLMOD solve failed (status %d)", im->cc.status);
}

void rk_fom_chol_free(rk_fom_impl *im)
{
    if (!im->cc_started) return;
    cholmod_free_factor(&im->L, &im->cc);
    cholmod_free_dense(&im->sol, &im->cc);
    cholmod_free_dense(&im->Y, &im->cc);
    cholmod_free_dense(&im->E, &im->cc);
    cholmod_finish(&im->cc);
    im->cc_started = 0;
}
