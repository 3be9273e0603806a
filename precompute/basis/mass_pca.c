/* Mass-weighted PCA / SVD by the method of snapshots: G = A^T M A (one BLAS-3 product), its
 * symmetric eigendecomposition (LAPACK dsyevd) gives sigma_i^2 and the right singular vectors
 * v_i, and u_i = A v_i / sigma_i. The u_i are re-orthonormalized in the M inner product (two
 * Gram-Schmidt passes) because the Gram matrix squares the condition number. Shared by POD and
 * by the modal-derivative basis (Barbic & James 2005, Sec. 4: mass-PCA of the scaled set).
 * Squaring puts a floor under what can be resolved: singular values below about sqrt(machine
 * epsilon) of the largest are noise, so a direction below RK_PCA_FLOOR counts as absent. */
#include "basis/basis.h"

#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define RK_PCA_FLOOR 1e-7

double rk_mass_dot(const rk_sparse *M, const double *x, const double *y, int rows)
{
    return M ? rk_sparse_dot(M, x, y) : cblas_ddot(rows, x, 1, y, 1);
}

int rk_mass_pca(const double *A, int rows, int cols, const rk_sparse *M, int max_r, double tol,
                double *U, int *r_out, double *sigma_all, rk_error *err)
{
    int kmax = rows < cols ? rows : cols;
    if (max_r < 1 || max_r > kmax)
        return rk_fail(err, "asked for %d directions from %d vectors of length %d (at most %d)",
                       max_r, cols, rows, kmax);
    if (M && M->n != rows) return rk_fail(err, "mass matrix is %d x %d, vectors have %d rows", M->n, M->n, rows);
    for (size_t i = 0; i < (size_t)rows * cols; i++)
        if (!isfinite(A[i]))
            return rk_fail(err, "vector %zu, entry %zu is not finite", i / rows, i % rows);

    double *MA = rk_calloc((size_t)rows * cols, sizeof(double), err);
    double *G = rk_calloc((size_t)cols * cols, sizeof(double), err);
    double *w = rk_calloc((size_t)cols, sizeof(double), err);
    int rc = -1;
    if (!MA || !G || !w) goto out;
    if (M) for (int c = 0; c < cols; c++) rk_sparse_mul(M, A + (size_t)c * rows, MA + (size_t)c * rows);
    else memcpy(MA, A, (size_t)rows * cols * sizeof(double));
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, cols, cols, rows, 1.0, A, rows, MA, rows, 0.0, G, cols);
    for (int i = 0; i < cols; i++)
        for (int j = 0; j < i; j++) G[(size_t)j * cols + i] = G[(size_t)i * cols + j] = 0.5 * (G[(size_t)j * cols + i] + G[(size_t)i * cols + j]);
    if (LAPACKE_dsyevd(LAPACK_COL_MAJOR, 'V', 'U', cols, G, cols, w) != 0) {
        rk_fail(err, "LAPACK dsyevd failed on the %d x %d Gram matrix", cols, cols);
        goto out;
    }
    /* Descending singular values; eigenvectors are G's columns in ascending order. */
    double total = 0;
    for (int i = 0; i < cols; i++) total += fmax(w[i], 0.0);
    if (!(total > 0)) { rk_fail(err, "all %d vectors are zero in the mass norm", cols); goto out; }
    int r = max_r;
    if (tol > 0) {
        double tail = total;
        for (r = 1; r <= max_r; r++) {
            tail -= fmax(w[cols - r], 0.0);
            if (sqrt(fmax(tail, 0.0) / total) <= tol) break;
        }
        if (r > max_r) r = max_r;
    }
    if (sigma_all)
        for (int i = 0; i < kmax; i++) sigma_all[i] = sqrt(fmax(w[cols - 1 - i], 0.0));
    double s1 = sqrt(fmax(w[cols - 1], 0.0));
    for (int j = 0; j < r; j++) {
        double s = sqrt(fmax(w[cols - 1 - j], 0.0));
        if (!(s > RK_PCA_FLOOR * s1)) {
            rk_fail(err, "asked for %d directions but the vectors span only %d (singular value %d is "
                    "%.3g of the largest)", r, j, j + 1, s / s1);
            goto out;
        }
        cblas_dgemv(CblasColMajor, CblasNoTrans, rows, cols, 1.0 / s, A, rows,
                    G + (size_t)(cols - 1 - j) * cols, 1, 0.0, U + (size_t)j * rows, 1);
    }
    for (int pass = 0; pass < 2; pass++)
        for (int j = 0; j < r; j++) {
            double *u = U + (size_t)j * rows;
            for (int i = 0; i < j; i++) {
                double *q = U + (size_t)i * rows;
                cblas_daxpy(rows, -rk_mass_dot(M, q, u, rows), q, 1, u, 1);
            }
            double nrm = sqrt(rk_mass_dot(M, u, u, rows));
            if (!(nrm > 0)) { rk_fail(err, "direction %d vanished in orthonormalization", j); goto out; }
            cblas_dscal(rows, 1.0 / nrm, u, 1);
        }
    *r_out = r;
    rc = 0;
out:
    free(MA); free(G); free(w);
    return rc;
}
