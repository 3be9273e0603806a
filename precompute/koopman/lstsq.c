/* Dense least squares for the control solve (koopman.h): the minimum-norm solution by LAPACK's
 * SVD solver, and non-negative least squares by the cubature stage's Lawson-Hanson active set
 * (LAPACK has none). */
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
