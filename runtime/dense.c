/* Dense r x r kernels for r <= ROMRT_MAX_R (column-major, leading dimension r). */
#include <math.h>

#include "runtime/romrt_impl.h"

void rt_symv(int r, const romrt_real *S, const romrt_real *x, romrt_real *y)
{
    int i, j;
    for (i = 0; i < r; i++) y[i] = 0;
    for (j = 0; j < r; j++) {
        const romrt_real *col = S + (size_t)r * j;
        romrt_real xj = x[j];
        for (i = 0; i < r; i++) y[i] += col[i] * xj;
    }
}

romrt_real rt_dot(int r, const romrt_real *a, const romrt_real *b)
{
    romrt_real s = 0;
    int i;
    for (i = 0; i < r; i++) s += a[i] * b[i];
    return s;
}

/* H = U^T U with U upper triangular, column by column (LAPACK's dpotrf 'U' order), and the solve
 * (U^T U) x = b with it: written once for a real type T, compiled for romrt_real and for double
 * (rt_cholesky_wide: the adaptive linear ROM's ill-conditioned small systems, in either build). */
#define RT_CHOLESKY(NAME, SOLVE, T, SQRT)                                                                              \
    int NAME(int r, T *H)                                                                                             \
    {                                                                                                                 \
        int i, j, k;                                                                                                  \
        for (j = 0; j < r; j++) {                                                                                     \
            T *cj = H + (size_t)r * j, d;                                                                             \
            for (i = 0; i < j; i++) {                                                                                 \
                const T *ci = H + (size_t)r * i;                                                                      \
                T s = cj[i];                                                                                          \
                for (k = 0; k < i; k++) s -= ci[k] * cj[k];                                                           \
                cj[i] = s / ci[i];                                                                                    \
            }                                                                                                         \
            d = cj[j];                                                                                                \
            for (k = 0; k < j; k++) d -= cj[k] * cj[k];                                                               \
            if (!(d > 0)) return j + 1;                                                                               \
            cj[j] = SQRT(d);                                                                                          \
        }                                                                                                             \
        return 0;                                                                                                     \
    }                                                                                                                 \
    void SOLVE(int r, const T *U, T *b)                                                                               \
    {                                                                                                                 \
        int i, k;                                                                                                     \
        for (i = 0; i < r; i++) { /* U^T y = b */                                                                     \
            const T *ci = U + (size_t)r * i;                                                                          \
            T s = b[i];                                                                                               \
            for (k = 0; k < i; k++) s -= ci[k] * b[k];                                                                \
            b[i] = s / ci[i];                                                                                         \
        }                                                                                                             \
        for (i = r - 1; i >= 0; i--) { /* U x = y */                                                                  \
            T s = b[i];                                                                                               \
            for (k = i + 1; k < r; k++) s -= U[i + (size_t)r * k] * b[k];                                            \
            b[i] = s / U[i + (size_t)r * i];                                                                          \
        }                                                                                                             \
    }

RT_CHOLESKY(rt_cholesky, rt_cholesky_solve, romrt_real, RT_SQRT)
RT_CHOLESKY(rt_cholesky_wide, rt_cholesky_solve_wide, double, sqrt)
