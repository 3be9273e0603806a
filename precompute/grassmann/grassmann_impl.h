/* Private to precompute/grassmann: what its files share. */
#ifndef RK_GRASSMANN_IMPL_H
#define RK_GRASSMANN_IMPL_H

#include "grassmann/grassmann.h"

/* Q (n x r, orthonormal columns spanning A) of the thin QR of A (n x r, column-major; Q must not
 * overlap A); fails, naming `what`, when a diagonal entry of R is below 1e-6 of the largest
 * (rank below r, as the data decides it: interpolate.c). */
int rk_thin_q(int n, int r, const double *A, double *Q, const char *what, rk_error *err);

#endif
