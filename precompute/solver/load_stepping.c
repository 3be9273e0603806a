/* Load stepping for static equilibria (solver.h): a load that Newton cannot take at once is
 * ramped, which keeps each increment inside Newton's basin. */
#include "solver/solver.h"

#include <stdlib.h>
#include <string.h>

int rk_load_stepping(int n, double *x, rk_load_increment increment, void *ctx, int *converged, int *used,
                     rk_error *err)
{
    static const int schedule[] = {1, 4, 16, 64};
    int attempts = (int)(sizeof schedule / sizeof schedule[0]);
    double *start = rk_calloc((size_t)(n > 0 ? n : 1), sizeof(double), err);
    if (!start) return -1;
    memcpy(start, x, (size_t)n * sizeof(double));
    int rc = 0, k = 1;
    *converged = 0;
    for (int a = 0; a < attempts && !rc && !*converged; a++) {
        k = schedule[a];
        memcpy(x, start, (size_t)n * sizeof(double));
        *converged = 1;
        for (int i = 1; i <= k && *converged && !rc; i++)
            if (increment(ctx, (double)i / k, x, converged, err)) rc = rk_error_prefix(err, "load increment %d of %d", i, k);
    }
    if (used) *used = k;
    free(start);
    return rc;
}
