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

/* H = U^T U with U upper triangular, column by column (LAPACK's dpotrf 'U' order). */
int rt_cholesky(int r, romrt_real *H)
{
    int i, j, k;
    for (j = 0; j < r; j++) {
        romrt_real *cj = H + (size_t)r * j, d;
        for (i = 0; i < j; i++) {
            const romrt_real *ci = H + (size_t)r * i;
            romrt_real s = cj[i];
            for (k = 0; k < i; k++) s -= ci[k] * cj[k];
            cj[i] = s / ci[i];
        }
        d = cj[j];
        for (k = 0; k < j; k++) d -= cj[k] * cj[k];
        if (!(d > 0)) return j + 1;
        cj[j] = RT_SQRT(d);
    }
    return 0;
}

void rt_cholesky_solve(int r, const romrt_real *U, romrt_real *b)
{
    int i, k;
    for (i = 0; i < r; i++) { /* U^T y = b */
        const romrt_real *ci = U + (size_t)r * i;
        romrt_real s = b[i];
        for (k = 0; k < i; k++) s -= ci[k] * b[k];
        b[i] = s / ci[i];
    }
    for (i = r - 1; i >= 0; i--) { /* U x = y */
        romrt_real s = b[i];
        for (k = i + 1; k < r; k++) s -= U[i + (size_t)r * k] * b[k];
        b[i] = s / U[i + (size_t)r * i];
    }
}
