/* Smallest eigenpairs of a sparse symmetric pencil: ARPACK dsaupd/dseupd in shift-invert mode 3
 * (OP = (A - sigma B)^{-1} B, inner product B), around one CHOLMOD factorization (shifted.c).
 * The eigenvalues nearest sigma converge first; with sigma below the spectrum those are the
 * smallest. Fixed starting vector (deterministic results, DESIGN.md "Determinism"). */
#include "basis/basis.h"
#include "basis/shifted_impl.h"

#include <arpack/arpack.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "util/util.h"

/* ARPACK's info codes, in words. */
static const char *arpack_reason(int info)
{
    switch (info) {
    case 1: return "maximum number of iterations reached";
    case 3: return "no shifts could be applied (try a larger ncv)";
    case -9: return "the starting vector is zero";
    case -9999: return "could not build an Arnoldi factorization";
    default: return "internal error";
    }
}

int rk_eigs_smallest(const rk_sparse *A, const rk_sparse *B, int count, double sigma,
                     double *values, double *vectors, rk_error *err)
{
    int n = A->n;
    if (count < 1 || count >= n)
        return rk_fail(err, "asked for %d eigenpairs of a problem with %d unknowns (at most %d)",
                       count, n, n - 1);
    double trB = rk_sparse_trace(B);
    if (!(trB > 0)) return rk_fail(err, "the mass matrix has a non-positive trace (%g)", trB);
    if (isnan(sigma)) sigma = -1e-6 * fabs(rk_sparse_trace(A)) / trB;

    rk_shifted fac;
    if (rk_shifted_init(&fac, A, B, sigma, err)) return rk_error_prefix(err, "eigenproblem");

    int ncv = 2 * count + 1 > count + 20 ? 2 * count + 1 : count + 20;
    if (ncv > n) ncv = n;
    int lworkl = ncv * (ncv + 8);
    double *resid = rk_calloc((size_t)n, sizeof(double), err);
    double *V = rk_calloc((size_t)n * ncv, sizeof(double), err);
    double *workd = rk_calloc(3 * (size_t)n, sizeof(double), err);
    double *workl = rk_calloc((size_t)lworkl, sizeof(double), err);
    double *d = rk_calloc((size_t)ncv, sizeof(double), err);
    double *Z = rk_calloc((size_t)n * count, sizeof(double), err);
    a_int *select = rk_calloc((size_t)ncv, sizeof(a_int), err);
    int rc = -1;
    if (!resid || !V || !workd || !workl || !d || !Z || !select) goto out;

    /* A fixed starting vector (deterministic results), perturbed so that no mode is missed by
     * being orthogonal to it through a symmetry of the object. */
    for (int i = 0; i < n; i++) resid[i] = 1.0 + 0.5 * sin(1.7 * i + 0.3);

    a_int iparam[11] = {0}, ipntr[11] = {0};
    iparam[0] = 1;               /* exact shifts */
    iparam[2] = 10 * n + 1000;   /* max Arnoldi restarts */
    iparam[6] = 3;               /* mode 3: shift-invert, generalized */
    a_int ido = 0, info = 1;     /* info = 1: resid holds the starting vector */
    long solves = 0;
    for (;;) {
        /* ARPACK's own BLAS (its dgemv reductions) on one thread: a threaded dgemv splits the sums
         * by the thread count, and the modes would differ with it in the last bits (issue 34) */
        int blas = rk_threads_blas(1);
        dsaupd_c(&ido, "G", n, "LM", count, 0.0, resid, ncv, V, n, iparam, ipntr, workd, workl,
                 lworkl, &info);
        rk_threads_blas(blas);
        if (ido == -1 || ido == 1) {
            double *x = workd + ipntr[0] - 1, *y = workd + ipntr[1] - 1;
            if (ido == -1) rk_sparse_mul(B, x, y);          /* y = B x, then solve in place */
            else memcpy(y, workd + ipntr[2] - 1, (size_t)n * sizeof(double)); /* B x given */
            if (rk_shifted_solve(&fac, y, y, err)) goto out;
            rk_progress("eigen-solve (shift-invert solves)", ++solves, 0);
        } else if (ido == 2) {
            rk_sparse_mul(B, workd + ipntr[0] - 1, workd + ipntr[1] - 1);
        } else {
            break;
        }
    }
    rk_progress_done("eigen-solve (shift-invert solves)");
    if (info < 0 || info == 1 || info == 3) {
        rk_fail(err, "ARPACK dsaupd failed (info %d: %s) after %d restarts, %d of %d eigenpairs converged",
                (int)info, arpack_reason((int)info), (int)iparam[2], (int)iparam[4], count);
        goto out;
    }
    int blas = rk_threads_blas(1); /* as dsaupd_c's */
    dseupd_c(1, "A", select, d, Z, n, sigma, "G", n, "LM", count, 0.0, resid, ncv, V, n, iparam,
             ipntr, workd, workl, lworkl, &info);
    rk_threads_blas(blas);
    if (info != 0) {
        rk_fail(err, "ARPACK dseupd failed (info %d)", (int)info);
        goto out;
    }
    int nconv = (int)iparam[4];
    if (nconv < count) {
        rk_fail(err, "ARPACK converged %d of %d eigenpairs", nconv, count);
        goto out;
    }
    /* dseupd returns ascending values already; sort anyway (cheap, and order is part of the contract). */
    int *order = rk_calloc((size_t)count, sizeof(int), err);
    if (!order) goto out;
    for (int i = 0; i < count; i++) order[i] = i;
    for (int i = 1; i < count; i++)
        for (int j = i; j > 0 && d[order[j]] < d[order[j - 1]]; j--) {
            int t = order[j]; order[j] = order[j - 1]; order[j - 1] = t;
        }
    for (int i = 0; i < count; i++) {
        values[i] = d[order[i]];
        if (vectors) {
            double *z = Z + (size_t)order[i] * n, *v = vectors + (size_t)i * n;
            /* Sign convention: the largest-magnitude entry is positive (deterministic output). */
            int imax = 0;
            for (int k = 1; k < n; k++) if (fabs(z[k]) > fabs(z[imax]) + 1e-12 * fabs(z[imax])) imax = k;
            double s = z[imax] < 0 ? -1.0 : 1.0;
            for (int k = 0; k < n; k++) v[k] = s * z[k];
        }
    }
    free(order);
    rc = 0;
out:
    rk_shifted_free(&fac);
    free(resid); free(V); free(workd); free(workl); free(d); free(Z); free(select);
    return rc;
}
