/* Symmetric upper-triangular CSC matrices on the fem pattern. */
#include "fem/fem.h"

#include <stdlib.h>
#include <string.h>

int rk_sparse_alloc_pattern(const rk_fem *f, rk_sparse *S, rk_error *err)
{
    const rk_sparse *P = &f->pattern;
    memset(S, 0, sizeof *S);
    S->n = P->n;
    S->nnz = P->nnz;
    S->colptr = rk_calloc((size_t)P->n + 1, sizeof(int), err);
    S->rowind = rk_calloc((size_t)P->nnz, sizeof(int), err);
    S->val = rk_calloc((size_t)P->nnz, sizeof(double), err);
    if (!S->colptr || !S->rowind || !S->val) {
        rk_sparse_free(S);
        return -1;
    }
    memcpy(S->colptr, P->colptr, ((size_t)P->n + 1) * sizeof(int));
    memcpy(S->rowind, P->rowind, (size_t)P->nnz * sizeof(int));
    return 0;
}

void rk_sparse_free(rk_sparse *S)
{
    free(S->colptr);
    free(S->rowind);
    free(S->val);
    memset(S, 0, sizeof *S);
}

void rk_sparse_zero(rk_sparse *S) { memset(S->val, 0, (size_t)S->nnz * sizeof(double)); }

void rk_sparse_mul(const rk_sparse *S, const double *x, double *y)
{
    memset(y, 0, (size_t)S->n * sizeof(double));
    for (int j = 0; j < S->n; j++) {
        double xj = x[j], yj = 0;
        for (int k = S->colptr[j]; k < S->colptr[j + 1]; k++) {
            int i = S->rowind[k];
            double a = S->val[k];
            y[i] += a * xj;
            if (i != j) yj += a * x[i]; /* the mirrored lower entry (j, i) */
        }
        y[j] += yj;
    }
}

double rk_sparse_dot(const rk_sparse *S, const double *x, const double *y)
{
    double sum = 0;
    for (int j = 0; j < S->n; j++)
        for (int k = S->colptr[j]; k < S->colptr[j + 1]; k++) {
            int i = S->rowind[k];
            double a = S->val[k];
            sum += i == j ? a * x[i] * y[j] : a * (x[i] * y[j] + x[j] * y[i]);
        }
    return sum;
}

int rk_sparse_find(const rk_sparse *S, int row, int col)
{
    if (row < 0 || col < 0 || col >= S->n || row > col) return -1;
    int lo = S->colptr[col], hi = S->colptr[col + 1];
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (S->rowind[mid] < row) lo = mid + 1;
        else hi = mid;
    }
    return lo < S->colptr[col + 1] && S->rowind[lo] == row ? lo : -1;
}

double rk_sparse_trace(const rk_sparse *S)
{
    double t = 0;
    for (int j = 0; j < S->n; j++)
        for (int k = S->colptr[j]; k < S->colptr[j + 1]; k++)
            if (S->rowind[k] == j) t += S->val[k];
    return t;
}
