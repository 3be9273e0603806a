/* CHOLMOD factorization of A - sigma B, shared by the eigensolver and the modal derivatives. */
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

static int factor(rk_shifted *s, rk_error *err)
{
    if (s->L) cholmod_free_factor(&s->L, &s->cc);
    s->L = cholmod_analyze(&s->view, &s->cc);
    if (!s->L) return rk_fail(err, "CHOLMOD analysis failed (status %d) on %d unknowns", s->cc.status, s->n);
    cholmod_factorize(&s->view, s->L, &s->cc);
    return 0;
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

    rk_threads(); /* the thread counts set before CHOLMOD starts any (util.h) */
    cholmod_start(&s->cc);
    s->cc_started = 1;
    s->cc.print = 0;
    s->cc.error_handler = NULL;
    rk_cholmod_sparse_view(&s->S, &s->view);
    if (factor(s, err)) { rk_shifted_free(s); return -1; }
    if (s->cc.status == CHOLMOD_NOT_POSDEF) {
        /* The shift lies above some eigenvalue: LDL^T handles the indefinite matrix. */
        s->indefinite = 1;
        s->cc.supernodal = CHOLMOD_SIMPLICIAL;
        s->cc.final_ll = 0;
        if (factor(s, err)) { rk_shifted_free(s); return -1; }
    }
    if (s->cc.status != CHOLMOD_OK || !(s->L->minor == s->L->n)) {
        int col = s->L ? (int)s->L->minor : -1;
        rk_shifted_free(s);
        return rk_fail(err, "the shifted matrix A - %g B is singular (factorization stopped at "
                       "unknown %d of %d): sigma is an eigenvalue, or the problem has a "
                       "singular mass", sigma, col, A->n);
    }
    /* A factorization can finish on a singular matrix with roundoff-sized pivots; CHOLMOD's
     * rcond is the squared (LL^T) or plain (LDL^T) ratio of the extreme pivots. */
    double rcond = cholmod_rcond(s->L, &s->cc);
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
    cholmod_dense B;
    rk_cholmod_dense_view(b, s->n, &B);
    cholmod_dense *X = cholmod_solve(CHOLMOD_A, s->L, &B, &s->cc);
    if (!X) return rk_fail(err, "CHOLMOD solve failed (status %d)", s->cc.status);
    memcpy(x, X->x, (size_t)s->n * sizeof(double));
    cholmod_free_dense(&X, &s->cc);
    for (int i = 0; i < s->n; i++)
        if (!isfinite(x[i])) return rk_fail(err, "shifted solve produced a non-finite value at unknown %d", i);
    return 0;
}

void rk_shifted_free(rk_shifted *s)
{
    if (s->cc_started) {
        if (s->L) cholmod_free_factor(&s->L, &s->cc);
        cholmod_finish(&s->cc);
    }
    free(s->S.colptr);
    free(s->S.rowind);
    free(s->S.val);
    memset(s, 0, sizeof *s);
}
