/* Between full-order and reduced states: the M-orthogonal projection onto the subspace and the
 * reconstruction x = X + U q. */
#include "rom/rom.h"

#include <cblas.h>
#include <lapacke.h>
#include <stdlib.h>
#include <string.h>

int rk_rom_project(const rk_rom_model *m, const rk_sparse *M, const double *U, int ndof, const double *X,
                   const double *x, double *q, rk_error *err)
{
    int r = m->r;
    double *d = rk_calloc((size_t)ndof, sizeof(double), err);
    double *Md = rk_calloc((size_t)ndof, sizeof(double), err);
    int rc = -1;
    if (d && Md) {
        for (int i = 0; i < ndof; i++) d[i] = x[i] - (X ? X[i] : 0);
        rk_sparse_mul(M, d, Md);
        cblas_dgemv(CblasColMajor, CblasTrans, ndof, r, 1.0, U, ndof, Md, 1, 0.0, q, 1);
        /* M_r q = U^T M (x - X): the normal equations of min |U q - (x - X)|_M, with the factor of
         * M_r the model made once (it refused a basis with dependent columns then). */
        LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'U', r, 1, m->M_proj_chol ? m->M_proj_chol : m->M_chol, r, q, r);
        rc = 0;
    }
    free(d);
    free(Md);
    return rc;
}

void rk_rom_positions(const double *U, int ndof, int r, const double *X, const double *q, double *x)
{
    memcpy(x, X, sizeof(double) * ndof);
    cblas_dgemv(CblasColMajor, CblasNoTrans, ndof, r, 1.0, U, ndof, q, 1, 1.0, x, 1);
}
