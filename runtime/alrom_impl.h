/* Private to the runtime's adaptive linear ROM (alrom*.c): what its files share. */
#ifndef ROMRT_ALROM_IMPL_H
#define ROMRT_ALROM_IMPL_H

#include "runtime/romrt_impl.h"

/* A QR diagonal below this fraction of the largest is rank loss, the precompute's rk_thin_q floor
 * (precompute/grassmann/interpolate.c: the history's missing directions are amplified round-off
 * above 1e-12, so the data decides only from well above it). */
#define RT_ALROM_RANK_TOL 1e-6

/* Pair (i, j) of QDRV's r (r + 1) / 2, row-major over i <= j (the precompute's rk_quadratic_pairs). */
static inline int rt_alrom_pair(int r, int i, int j)
{
    if (i > j) {
        int t = i;
        i = j;
        j = t;
    }
    return i * r - i * (i - 1) / 2 + (j - i);
}
/* The quadratic decoder's pieces' mass Gram B^T W B into al->gram (alrom_decoder.c; at open). */
void rt_alrom_gram(romrt_model *m);
/* Whether row (a dof) of the stored vertices is prescribed (its basis row is zero). */
static inline int rt_alrom_prescribed(const rt_alrom *al, int row) { return al->motion_of[row / 3] != ROMBIN_NO_MOTION; }
/* The prescribed rows of A (n x r, a row's r doubles contiguous) zeroed. */
void rt_alrom_zero_prescribed(const romrt_model *m, double *A);
/* p = e(u) of al->u into al->p, and U = dg/dp at p into al->U (alrom_decoder.c). */
romrt_status rt_alrom_encode(romrt_model *m, romrt_error *err);
/* The step's basis into al->rows (alrom_basis.c, Algorithm 3 lines 3-6): the code of the state,
 * the decoder's basis there, the history written and, when it has rank r, the Grassmann point. */
romrt_status rt_alrom_step_basis(romrt_model *m, romrt_error *err);

#endif
