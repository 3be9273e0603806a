/* rk_sparse and plain vectors seen by CHOLMOD without copying: the one place that knows how an
 * upper-triangle CSC rk_sparse maps onto cholmod_sparse (stype = 1). Used by the full-order
 * Newton solver and the shift-invert eigensolver. */
#ifndef RK_FEM_CHOLMOD_VIEW_H
#define RK_FEM_CHOLMOD_VIEW_H

#include <string.h>
#include <suitesparse/cholmod.h>

#include "fem/fem.h"

static inline void rk_cholmod_sparse_view(const rk_sparse *S, cholmod_sparse *A)
{
    memset(A, 0, sizeof *A);
    A->nrow = A->ncol = (size_t)S->n;
    A->nzmax = (size_t)S->nnz;
    A->p = S->colptr;
    A->i = S->rowind;
    A->x = S->val;
    A->stype = 1; /* upper triangle stored */
    A->itype = CHOLMOD_INT;
    A->xtype = CHOLMOD_REAL;
    A->dtype = CHOLMOD_DOUBLE;
    A->sorted = 1;
    A->packed = 1;
}

static inline void rk_cholmod_dense_view(const double *x, int n, cholmod_dense *B)
{
    memset(B, 0, sizeof *B);
    B->nrow = B->d = B->nzmax = (size_t)n;
    B->ncol = 1;
    B->x = (void *)x;
    B->xtype = CHOLMOD_REAL;
    B->dtype = CHOLMOD_DOUBLE;
}

#endif
