/* Shared by the runtime tests: what an engine deforming on the GPU computes from romrt.h's
 * accessors, x = X + U q (romrt_rest_positions, romrt_basis_rows, romrt_reduced_coordinates), in
 * double, against romrt_positions. Uses only romrt.h. */
#ifndef RK_TEST_RUNTIME_GPU_H
#define RK_TEST_RUNTIME_GPU_H

#include <math.h>
#include <stdlib.h>

#include "runtime/romrt.h"

/* max |X + U q - x| over the shown coordinates, over max |x - X| (the motion): -1 when an accessor
 * refuses a buffer of the size it asks for. */
static inline double rt_gpu_mismatch(const romrt_model *m)
{
    int n = romrt_shown_count(m), r = romrt_reduced_size(m), ok;
    size_t nr = (size_t)3 * n * r;
    romrt_real *X = calloc((size_t)3 * n + 1, sizeof *X), *x = calloc((size_t)3 * n + 1, sizeof *x);
    romrt_real *U = calloc(nr + 1, sizeof *U), *q = calloc((size_t)r + 1, sizeof *q);
    double worst = 0, motion = 1e-300;
    ok = X && x && U && q && romrt_rest_positions(m, X, 3 * (size_t)n, 3, NULL) == ROMRT_OK && romrt_basis_rows(m, U, nr, NULL) == ROMRT_OK &&
         romrt_reduced_coordinates(m, q, r, NULL) == ROMRT_OK && romrt_positions(m, x, 3 * (size_t)n, 3, NULL) == ROMRT_OK;
    for (int k = 0; ok && k < 3 * n; k++) {
        double s = X[k];
        for (int j = 0; j < r; j++) s += (double)U[(size_t)k * r + j] * q[j];
        worst = fmax(worst, fabs(s - x[k]));
        motion = fmax(motion, fabs((double)x[k] - X[k]));
    }
    free(X), free(x), free(U), free(q);
    return ok ? worst / motion : -1;
}

#endif
