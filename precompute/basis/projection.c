/* How well a basis reproduces full-order frames: the relative M-norm projection error as
 * columns are added, and truncation to the size that a tolerance asks for. */
#include "basis/basis.h"

#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int rk_projection_errors(const double *U, int rows, int r, int group, const double *D, int T,
                         const rk_sparse *M, double *err_out, rk_error *err)
{
    double *Q = rk_calloc((size_t)rows * r, sizeof(double), err);
    double *MD = rk_calloc((size_t)rows * T, sizeof(double), err);
    if (!Q || !MD) { free(Q); free(MD); return -1; }
    double total = 0, captured = 0;
    for (int t = 0; t < T; t++) {
        const double *d = D + (size_t)t * rows;
        if (M) rk_sparse_mul(M, d, MD + (size_t)t * rows);
        else memcpy(MD + (size_t)t * rows, d, sizeof(double) * rows);
        total += cblas_ddot(rows, d, 1, MD + (size_t)t * rows, 1);
    }
    int nq = 0;
    for (int j = 0; j < r; j++) {
        double *q = Q + (size_t)nq * rows;
        memcpy(q, U + (size_t)j * rows, sizeof(double) * rows);
        double n0 = sqrt(rk_mass_dot(M, q, q, rows));
        for (int pass = 0; pass < 2; pass++)
            for (int i = 0; i < nq; i++) {
                const double *p = Q + (size_t)i * rows;
                cblas_daxpy(rows, -rk_mass_dot(M, p, q, rows), p, 1, q, 1);
            }
        double n1 = sqrt(rk_mass_dot(M, q, q, rows));
        if (n1 > 1e-10 * n0) {
            cblas_dscal(rows, 1.0 / n1, q, 1);
            for (int t = 0; t < T; t++) {
                double c = cblas_ddot(rows, q, 1, MD + (size_t)t * rows, 1);
                captured += c * c;
            }
            nq++;
        }
        if ((j + 1) % group == 0)
            err_out[j / group] = total > 0 ? sqrt(fmax(total - captured, 0.0) / total) : 0.0;
    }
    free(Q);
    free(MD);
    return 0;
}

void rk_basis_truncate(rk_basis *b, int r)
{
    if (r >= b->r) return;
    b->r = r;
    if (b->W) { /* weights, values and nodal values are column-major: a prefix stays in place */
        b->m = r / 12;
        b->nvalues = b->m;
    } else if (b->type == RK_BASIS_MODES) {
        b->nvalues = r;
    }
}
