/* The linear-solve baseline of the adaptive-subspace paper's Table 3 and Fig. 16 (IPC-CG): the
 * full-space Newton system solved by conjugate gradients with a 3 x 3 block-Jacobi
 * preconditioner, to the same relative residual as the Schur complement. */
#include "adaptive/adaptive.h"

#include <lapacke.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    const rk_sparse *A;
    double *Dinv; /* 9 per vertex */
} bj;

static void apply(void *ctx, const double *x, double *y)
{
    rk_sparse_mul(((bj *)ctx)->A, x, y);
}

static void precondition(void *ctx, const double *r, double *z)
{
    bj *b = ctx;
    for (int v = 0; v < b->A->n / 3; v++)
        for (int i = 0; i < 3; i++) {
            const double *D = &b->Dinv[9 * v + 3 * i];
            z[3 * v + i] = D[0] * r[3 * v] + D[1] * r[3 * v + 1] + D[2] * r[3 * v + 2];
        }
}

int rk_block_jacobi_cg(const rk_sparse *A, const double *g, double *d, double tol, int max_iter, rk_error *err)
{
    int n = A->n, nv = n / 3;
    if (n % 3) return rk_fail(err, "block-Jacobi CG needs 3 dofs per vertex, the matrix has %d rows", n);
    double *Dinv = malloc(sizeof(double) * (9 * (size_t)nv + 4 * (size_t)n + (size_t)n + 1));
    if (!Dinv) return rk_fail(err, "out of memory for block-Jacobi CG (%d unknowns)", n);
    double *work = Dinv + 9 * (size_t)nv, *b = work + 4 * (size_t)n;
    for (int v = 0; v < nv; v++) {
        double B[9];
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                int r = i < j ? i : j, c = i < j ? j : i;
                B[3 * i + j] = A->val[rk_fem_diag_slot(A, v, r, c)];
            }
        double *D = &Dinv[9 * v];
        int ok = LAPACKE_dpotrf(LAPACK_ROW_MAJOR, 'L', 3, B, 3) == 0;
        for (int i = 0; i < 3; i++) {
            double col[3] = {i == 0, i == 1, i == 2};
            if (ok) LAPACKE_dpotrs(LAPACK_ROW_MAJOR, 'L', 3, 1, B, 3, col, 1);
            for (int r = 0; r < 3; r++) D[3 * r + i] = col[r];
        }
    }
    for (int i = 0; i < n; i++) b[i] = -g[i];
    memset(d, 0, sizeof(double) * (size_t)n);
    bj ctx = {A, Dinv};
    rk_pcg_problem p = {n, &ctx, apply, precondition};
    int it = rk_pcg(&p, b, d, tol, max_iter, work, NULL);
    free(Dinv);
    return it;
}
