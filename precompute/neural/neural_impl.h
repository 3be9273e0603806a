/* precompute/neural, inside: what the passes share (neural.h has the public side). */
#ifndef RK_NEURAL_IMPL_H
#define RK_NEURAL_IMPL_H

#include "neural/neural.h"

#include <math.h>

/* ELU (alpha = 1), inline for the passes' loops; rk_elu is the same. expm1 keeps the small
 * negative values' relative precision that exp(z) - 1 would cancel away. */
static inline double elu(double z)
{
    return z > 0 ? z : expm1(z);
}

/* ELU's derivative from its value a = ELU(z): 1 where a > 0 (z > 0), exp(z) = a + 1 elsewhere.
 * a + 1 is exp(z) to within an ulp of 1 (absolute), which is all a gradient needs, and it spares
 * the workspace a second copy of every layer (the pre-activations). */
static inline double elu_grad_from_value(double a)
{
    return a > 0 ? 1.0 : a + 1.0;
}

/* Fails unless w was made for m's shape (same layer count and sizes). */
int mlp_work_check(const rk_mlp *m, const rk_mlp_work *w, rk_error *err);

#endif
