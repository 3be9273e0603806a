/* A quadratic manifold fitted to displacement frames (grassmann.h, rk_quadratic_fit): the frames'
 * codes on a linear basis, then the second-order term that best explains what the basis misses,
 * g(p) = V p + 1/2 sum_ij Psi_ij p_i p_j (the quadratic-manifold form of Jain et al. 2017 and
 * Geelen et al. 2023, fitted to data as in the latter), for the adaptive linear ROM's decoder
 * interface: trained, yet as cheap per vertex as the modal-derivative one. */
#include "grassmann/grassmann_impl.h"

#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int rk_quadratic_fit(int n, int r, const double *V, const rk_sparse *M, const double *D, int T, double *Psi,
                     double *linear_miss, double *fit_miss, rk_error *err)
{
    int np = r * (r + 1) / 2, rc = -1;
    if (T < 1 || r < 1) return rk_fail(err, "a quadratic fit needs frames and columns (T %d, r %d)", T, r);
    double *MV = malloc(sizeof(double) * (size_t)n * r), *P = malloc(sizeof(double) * (size_t)r * T);
    double *R = malloc(sizeof(double) * (size_t)n * T), *K = malloc(sizeof(double) * (size_t)np * T);
    double *A = malloc(sizeof(double) * (size_t)np * np), *B = malloc(sizeof(double) * (size_t)np * n);
    if (!MV || !P || !R || !K || !A || !B) {
        rk_fail(err, "out of memory for a quadratic fit of %d frames (r %d)", T, r);
        goto out;
    }
    for (int j = 0; j < r; j++) rk_sparse_mul(M, V + (size_t)j * n, MV + (size_t)j * n);
    /* P = V^T M D, R = D - V P */
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, r, T, n, 1.0, MV, n, D, n, 0.0, P, r);
    memcpy(R, D, sizeof(double) * (size_t)n * T);
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n, T, r, -1.0, V, n, P, r, 1.0, R, n);
    for (int t = 0; t < T; t++) /* K: the pairs i <= j, row-major over r, each with its 1/2 or 1 */
        for (int i = 0, k = 0; i < r; i++)
            for (int j = i; j < r; j++, k++)
                K[(size_t)t * np + k] = (i == j ? 0.5 : 1.0) * P[(size_t)t * r + i] * P[(size_t)t * r + j];
    /* (K K^T + gamma I) Psi^T = K R^T */
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, np, np, T, 1.0, K, np, K, np, 0.0, A, np);
    double top = 0;
    for (int k = 0; k < np; k++) top = fmax(top, A[(size_t)k * np + k]);
    if (!(top > 0)) {
        rk_fail(err, "the frames have no extent on the basis: nothing to fit a quadratic term to");
        goto out;
    }
    for (int k = 0; k < np; k++) A[(size_t)k * np + k] += 1e-6 * top;
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, np, n, T, 1.0, K, np, R, n, 0.0, B, np);
    int info = LAPACKE_dposv(LAPACK_COL_MAJOR, 'L', np, n, A, np, B, np);
    if (info) {
        rk_fail(err, "the quadratic fit's normal equations failed (LAPACK %d)", info);
        goto out;
    }
    for (int k = 0; k < np; k++)
        for (int i = 0; i < n; i++) Psi[(size_t)k * n + i] = B[(size_t)i * np + k];
    if (linear_miss || fit_miss) { /* energies in the mass norm */
        double total = 0, lin = 0, fit = 0;
        double *Mu = malloc(sizeof(double) * (size_t)n);
        if (!Mu) {
            rk_fail(err, "out of memory");
            goto out;
        }
        for (int t = 0; t < T; t++) {
            const double *u = D + (size_t)t * n;
            double *res = R + (size_t)t * n;
            rk_sparse_mul(M, u, Mu);
            total += cblas_ddot(n, u, 1, Mu, 1);
            rk_sparse_mul(M, res, Mu);
            lin += cblas_ddot(n, res, 1, Mu, 1);
            cblas_dgemv(CblasColMajor, CblasNoTrans, n, np, -1.0, Psi, n, K + (size_t)t * np, 1, 1.0, res, 1);
            rk_sparse_mul(M, res, Mu);
            fit += cblas_ddot(n, res, 1, Mu, 1);
        }
        free(Mu);
        if (linear_miss) *linear_miss = total > 0 ? lin / total : 0;
        if (fit_miss) *fit_miss = total > 0 ? fit / total : 0;
    }
    rc = 0;
out:
    free(MV);
    free(P);
    free(R);
    free(K);
    free(A);
    free(B);
    return rc;
}
