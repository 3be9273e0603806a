/* The history basis (adaptive-linear-rom paper, Eq. 13): the least-squares Phi with Phi P ~ D over
 * the last m steps, Phi = D P^T (P P^T + reg I)^-1. */
#include "grassmann/grassmann.h"

#include <cblas.h>
#include <lapacke.h>
#include <stdlib.h>
#include <string.h>

int rk_history_basis(int n, int r, int m, const double *D, const double *P, double reg, double *Phi, rk_error *err)
{
    if (m < 1 || r < 1) return rk_fail(err, "the history basis needs steps and latent coordinates (m %d, r %d)", m, r);
    double *A = malloc(sizeof(double) * ((size_t)r * r + (size_t)n * r));
    if (!A) return rk_fail(err, "out of memory for the history basis");
    double *B = A + (size_t)r * r;
    /* A = P P^T + reg I, B = D P^T */
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, r, r, m, 1.0, P, r, P, r, 0.0, A, r);
    for (int i = 0; i < r; i++) A[(size_t)i * r + i] += reg;
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, n, r, m, 1.0, D, n, P, r, 0.0, B, n);
    /* Phi = B A^-1: A symmetric positive definite, so solve A Phi^T = B^T by Cholesky on Phi^T */
    int rc = LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'L', r, A, r);
    if (!rc) {
        for (int i = 0; i < n; i++) /* Phi^T (r x n) built row by row from B */
            for (int j = 0; j < r; j++) Phi[(size_t)j * n + i] = B[(size_t)j * n + i];
        /* solve with n right-hand sides laid out as rows: X A = B  <=>  A X^T = B^T; use
         * dtrsm twice on the right: X = B L^-T L^-1 */
        cblas_dtrsm(CblasColMajor, CblasRight, CblasLower, CblasTrans, CblasNonUnit, n, r, 1.0, A, r, Phi, n);
        cblas_dtrsm(CblasColMajor, CblasRight, CblasLower, CblasNoTrans, CblasNonUnit, n, r, 1.0, A, r, Phi, n);
    }
    free(A);
    return rc ? rk_fail(err, "the history's P P^T + %g I is not positive definite (LAPACK %d)", reg, rc) : 0;
}
