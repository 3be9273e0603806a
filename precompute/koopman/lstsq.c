/* Dense least squares for the control solve (koopman.h): the minimum-norm solution by LAPACK's
 * SVD solver, non-negative least squares by the cubature stage's Lawson-Hanson active set
 * (LAPACK has none), and either of them with a Tikhonov term on x (stacked rows). */
#include "koopman/koopman.h"

#include "cubature/cubature.h"

#include <cblas.h>
#include <float.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define LSTSQ_RCOND 1e-12

int rk_lstsq(int m, int n, const double *A, const double *b, double *x, rk_error *err)
{
    int ldb = m > n ? m : n, rank = 0, mn = m < n ? m : n;
    double *a = rk_calloc((size_t)m * n, sizeof(double), err);
    double *bb = rk_calloc((size_t)ldb, sizeof(double), err);
    double *s = rk_calloc((size_t)mn, sizeof(double), err);
    int rc = -1;
    if (!a || !bb || !s) goto done;
    memcpy(a, A, sizeof(double) * (size_t)m * n); /* dgelsd overwrites A and b */
    memcpy(bb, b, sizeof(double) * (size_t)m);
    int info = LAPACKE_dgelsd(LAPACK_COL_MAJOR, m, n, 1, a, m, bb, ldb, s, LSTSQ_RCOND, &rank);
    if (info != 0) {
        rk_fail(err, "least squares on a %d x %d system failed (LAPACK dgelsd info %d)", m, n, info);
        goto done;
    }
    memcpy(x, bb, sizeof(double) * (size_t)n);
    rc = 0;
done:
    free(a);
    free(bb);
    free(s);
    return rc;
}

int rk_nnls(int m, int n, const double *A, const double *b, double *x, rk_error *err)
{
    double *gram = rk_calloc((size_t)n * n, sizeof(double), err), *atb = rk_calloc((size_t)n, sizeof(double), err);
    int rc = -1;
    if (gram && atb) {
        /* the cubature stage's Lawson-Hanson on the normal equations: k is a few inputs here */
        cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, n, n, m, 1.0, A, m, A, m, 0.0, gram, n);
        cblas_dgemv(CblasColMajor, CblasTrans, m, n, 1.0, A, m, b, 1, 0.0, atb, 1);
        memset(x, 0, sizeof(double) * (size_t)n);
        rc = rk_nnls_normal(n, gram, atb, x, 0, err);
    }
    free(gram);
    free(atb);
    return rc;
}

/* The largest singular value of A (m x n): LAPACK's dgesvd, values only. */
static int sigma_max(int m, int n, const double *A, double *smax, rk_error *err)
{
    int mn = m < n ? m : n, rc = -1;
    double *a = rk_calloc((size_t)m * n, sizeof(double), err), *s = rk_calloc((size_t)mn + 1, sizeof(double), err);
    double *work = rk_calloc((size_t)mn + 1, sizeof(double), err);
    if (a && s && work) {
        memcpy(a, A, sizeof(double) * (size_t)m * n);
        int info = LAPACKE_dgesvd(LAPACK_COL_MAJOR, 'N', 'N', m, n, a, m, s, NULL, 1, NULL, 1, work);
        *smax = s[0];
        rc = info ? rk_fail(err, "singular values of a %d x %d system failed (LAPACK dgesvd info %d)", m, n, info) : 0;
    }
    free(a);
    free(s);
    free(work);
    return rc;
}

int rk_lstsq_tikhonov(int m, int n, const double *A, const double *b, double rho, int nonnegative, double *x,
                      double *lambda, rk_error *err)
{
    if (!(rho >= 0) || !isfinite(rho)) return rk_fail(err, "regularization %g: must be finite and >= 0", rho);
    double lam = 0;
    if (lambda) *lambda = 0;
    if (rho == 0) return nonnegative ? rk_nnls(m, n, A, b, x, err) : rk_lstsq(m, n, A, b, x, err);
    if (sigma_max(m, n, A, &lam, err)) return -1;
    lam *= rho;
    if (lambda) *lambda = lam;
    /* [A; lam I] x ~ [b; 0]: its normal equations are (A^T A + lam^2 I) x = A^T b, so one stacked
     * system serves both solvers (NNLS then minimises the same penalised misfit over x >= 0) */
    int M = m + n, rc = -1;
    double *As = rk_calloc((size_t)M * n, sizeof(double), err), *bs = rk_calloc((size_t)M, sizeof(double), err);
    if (As && bs) {
        for (int j = 0; j < n; j++) {
            memcpy(As + (size_t)M * j, A + (size_t)m * j, sizeof(double) * (size_t)m);
            As[(size_t)M * j + m + j] = lam;
        }
        memcpy(bs, b, sizeof(double) * (size_t)m);
        rc = nonnegative ? rk_nnls(M, n, As, bs, x, err) : rk_lstsq(M, n, As, bs, x, err);
    }
    free(As);
    free(bs);
    return rc;
}
