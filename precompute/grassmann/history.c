/* The history basis (adaptive-linear-rom paper, Eq. 13): the least-squares Phi with Phi P ~ D over
 * the last m steps, Phi = D P^T (P P^T + reg I)^-1, here with a ridge toward the decoder's basis U
 * (issue 33): Phi = argmin |Phi P - D|^2 + rho |Phi - U|^2 = (D P^T + rho U)(P P^T + rho I)^-1,
 * rho = ridge tr(P P^T) (+ reg).
 *
 * Why: only Phi's span matters (the Grassmann step QRs it), and for reg -> 0 that span is D's image
 * of P's right singular vectors b_k whatever their singular values sigma_k: a direction the history
 * barely excites (sigma_k ~ 0, D b_k at the level of the decoder's misfit or of round-off) is
 * normalised up to a full basis vector whose orientation is set by that misfit, so a perturbation
 * e of the newest state turns it by about e / |D b_k|. On the armadillo's bend one step multiplied
 * a perturbation by 5,300 (lambda 0: the history basis alone; 1.0002 with the decoder's basis
 * alone). With the ridge such a direction falls back to the decoder's column there (the prior the
 * data does not overrule), and Phi is Lipschitz in (D, P) with a constant of 1 / sqrt(rho). */
#include "grassmann/grassmann.h"

#include <cblas.h>
#include <lapacke.h>
#include <stdlib.h>
#include <string.h>

int rk_history_basis(int n, int r, int m, const double *D, const double *P, const double *U, double ridge, double reg,
                     double *Phi, rk_error *err)
{
    if (m < 1 || r < 1) return rk_fail(err, "the history basis needs steps and latent coordinates (m %d, r %d)", m, r);
    double *A = malloc(sizeof(double) * ((size_t)r * r + (size_t)n * r));
    if (!A) return rk_fail(err, "out of memory for the history basis");
    double *B = A + (size_t)r * r;
    /* A = P P^T + (rho + reg) I, B = D P^T + rho U */
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, r, r, m, 1.0, P, r, P, r, 0.0, A, r);
    double trace = 0;
    for (int i = 0; i < r; i++) trace += A[(size_t)i * r + i];
    double rho = ridge > 0 ? ridge * trace : 0;
    for (int i = 0; i < r; i++) A[(size_t)i * r + i] += rho + reg;
    if (rho > 0) memcpy(B, U, sizeof(double) * (size_t)n * r);
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, n, r, m, 1.0, D, n, P, r, rho > 0 ? rho : 0.0, B, n);
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
