/* The factorization of A - sigma B (the one sparse Cholesky, fem.h), shared by the eigensolver
 * and the modal derivatives. */
#include "basis/shifted_impl.h"

#include "fem/fem.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Below this reciprocal condition estimate the shifted matrix counts as singular. */
#define RK_SHIFTED_MIN_RCOND 1e-14

static int same_pattern(const rk_sparse *A, const rk_sparse *B)
{
    return A->n == B->n && A->nnz == B->nnz &&
           !memcmp(A->colptr, B->colptr, (size_t)(A->n + 1) * sizeof(int)) &&
           !memcmp(A->rowind, B->rowind, (size_t)A->nnz * sizeof(int));
}

int rk_shifted_init(rk_shifted *s, const rk_sparse *A, const rk_sparse *B, double sigma, rk_error *err)
{
    memset(s, 0, sizeof *s);
    if (!same_pattern(A, B))
        return rk_fail(err, "shifted solve: the two matrices must share one sparsity pattern");
    s->n = A->n;
    s->S.n = A->n;
    s->S.nnz = A->nnz;
    s->S.colptr = rk_calloc((size_t)A->n + 1, sizeof(int), err);
    s->S.rowind = rk_calloc((size_t)A->nnz, sizeof(int), err);
    s->S.val = rk_calloc((size_t)A->nnz, sizeof(double), err);
    if (!s->S.colptr || !s->S.rowind || !s->S.val) { rk_shifted_free(s); return -1; }
    memcpy(s->S.colptr, A->colptr, (size_t)(A->n + 1) * sizeof(int));
    memcpy(s->S.rowind, A->rowind, (size_t)A->nnz * sizeof(int));
    for (int k = 0; k < A->nnz; k++) s->S.val[k] = A->val[k] - sigma * B->val[k];

    int rc = rk_chol_analyze(&s->chol, &s->S, err) ? -1 : rk_chol_factor(&s->chol, err);
    if (rc == RK_CHOL_NOT_POSDEF) {
        /* The shift lies above some eigenvalue: LDL^T handles the indefinite matrix. */
        s->indefinite = 1;
        rc = rk_chol_indefinite(&s->chol, err);
    }
    if (rc || s->chol.cc.status != CHOLMOD_OK || rk_chol_minor(&s->chol) != s->n) {
        int col = rk_chol_minor(&s->chol);
        rk_shifted_free(s);
        return rk_fail(err, "the shifted matrix A - %g B is singular (factorization stopped at "
                       "unknown %d of %d): sigma is an eigenvalue, or the problem has a "
                       "singular mass", sigma, col, A->n);
    }
    /* A factorization can finish on a singular matrix with roundoff-sized pivots; CHOLMOD's
     * rcond is the squared (LL^T) or plain (LDL^T) ratio of the extreme pivots. */
    double rcond = rk_chol_rcond(&s->chol);
    if (!(rcond > RK_SHIFTED_MIN_RCOND)) {
        rk_shifted_free(s);
        return rk_fail(err, "the shifted matrix A - %g B is numerically singular (pivot-ratio "
                       "condition estimate %.3g): sigma sits on an eigenvalue, or the problem has "
                       "a zero-mass or unconnected unknown", sigma, rcond);
    }
    return 0;
}

int rk_shifted_solve(rk_shifted *s, const double *b, double *x, rk_error *err)
{
    if (rk_chol_solve(&s->chol, b, x, err)) return -1;
    for (int i = 0; i < s->n; i++)
        if (!isfinite(x[i])) return rk_fail(err, "shifted solve produced a non-finite value at unknown %d", i);
    return 0;
}

void rk_shifted_free(rk_shifted *s)
{
    rk_chol_free(&s->chol);
    free(s->S.colptr);
    free(s->S.rowind);
    free(s->S.val);
    memset(s, 0, sizeof *s);
}
