/* Private to precompute/basis: solves with A - sigma B (symmetric, upper CSC, one shared
 * pattern) through CHOLMOD. Used by the shift-invert eigensolver and by the modal-derivative
 * solves, so each problem is factorized once. */
#ifndef RK_BASIS_SHIFTED_H
#define RK_BASIS_SHIFTED_H

#include "fem/fem.h"
#include "util/util.h"

typedef struct {
    int n;
    int indefinite;        /* 1 when LL^T failed and LDL^T was used */
    rk_sparse S;           /* A - sigma B (own copy of the values) */
    rk_chol chol;          /* its factor (fem.h: the one sparse Cholesky) */
} rk_shifted;

/* Factorizes A - sigma B: LL^T, or LDL^T when the shifted matrix is not positive definite. Fails if A and B differ in pattern, or on a zero pivot (sigma is an
 * eigenvalue: a singular problem). */
int rk_shifted_init(rk_shifted *s, const rk_sparse *A, const rk_sparse *B, double sigma, rk_error *err);
/* x = (A - sigma B)^{-1} b; x and b may alias. */
int rk_shifted_solve(rk_shifted *s, const double *b, double *x, rk_error *err);
void rk_shifted_free(rk_shifted *s);

#endif
