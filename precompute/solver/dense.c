/* A small dense symmetric positive definite solve with a growing diagonal shift (solver.h,
 * rk_spd_solve_shifted): the reduced Newton systems of the adaptive methods. */
#include "solver/solver.h"

#include <lapacke.h>
#include <math.h>
#include <string.h>

int rk_spd_solve_shifted(int n, const double *H, double *L, const double *b, double *z, int attempts)
{
    if (n == 0) return 0;
    double scale = 0;
    for (int i = 0; i < n; i++) scale = fmax(scale, fabs(H[(size_t)i * n + i]));
    if (!(scale > 0)) scale = 1; /* a zero matrix (every column masked out): the shift alone */
    for (int attempt = 0; attempt < attempts; attempt++) {
        double shift = attempt ? scale * pow(10.0, -12 + 2 * attempt) : 0;
        memcpy(L, H, sizeof(double) * (size_t)n * n);
        for (int i = 0; i < n; i++) L[(size_t)i * n + i] += shift;
        if (LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'L', n, L, n) != 0) continue;
        memcpy(z, b, sizeof(double) * (size_t)n);
        LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'L', n, 1, L, n, z, n);
        return 0;
    }
    return -1;
}
