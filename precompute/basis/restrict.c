/* A symmetric sparse matrix restricted to a subset of its unknowns (the free degrees of
 * freedom of a constrained object). */
#include "basis/basis.h"

#include <stdlib.h>

int rk_sparse_restrict(const rk_sparse *S, const int *keep, int nkeep, rk_sparse *out, rk_error *err)
{
    out->n = nkeep;
    out->nnz = 0;
    out->colptr = rk_calloc((size_t)nkeep + 1, sizeof(int), err);
    int nnz = 0;
    for (int j = 0; j < S->n; j++)
        if (keep[j] >= 0)
            for (int k = S->colptr[j]; k < S->colptr[j + 1]; k++) nnz += keep[S->rowind[k]] >= 0;
    out->rowind = rk_calloc((size_t)nnz + 1, sizeof(int), err);
    out->val = rk_calloc((size_t)nnz + 1, sizeof(double), err);
    if (!out->colptr || !out->rowind || !out->val) { rk_sparse_free(out); return -1; }
    /* keep[] is increasing over the kept unknowns, so kept columns come out in order and rows
     * stay sorted. */
    for (int j = 0; j < S->n; j++) {
        int jj = keep[j];
        if (jj < 0) continue;
        for (int k = S->colptr[j]; k < S->colptr[j + 1]; k++) {
            int ii = keep[S->rowind[k]];
            if (ii < 0) continue;
            out->rowind[out->nnz] = ii;
            out->val[out->nnz++] = S->val[k];
        }
        out->colptr[jj + 1] = out->nnz;
    }
    return 0;
}
