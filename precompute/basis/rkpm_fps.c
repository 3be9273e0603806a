/* Farthest point sampling of the RKPM kernel centres among the integration points, "to ensure
 * that kernels are equidistantly distributed" (freeform paper Sec. 7.1). */
#include "basis/rkpm_impl.h"

#include <math.h>
#include <stdlib.h>

static double dist2(const double *a, const double *b)
{
    double e0 = a[0] - b[0], e1 = a[1] - b[1], e2 = a[2] - b[2];
    return e0 * e0 + e1 * e1 + e2 * e2;
}

int rk_fps(const double *X, int n, int K, int *chosen, rk_error *err)
{
    if (K < 1) return rk_fail(err, "farthest point sampling: %d centres asked, at least 1 is needed", K);
    if (K > n) return rk_fail(err, "farthest point sampling: %d centres asked from only %d points", K, n);
    int bad = rkpm_first_nonfinite(X, n);
    if (bad >= 0)
        return rk_fail(err, "farthest point sampling: point %d has a non-finite coordinate (%g, %g, %g)", bad,
                       X[3 * bad], X[3 * bad + 1], X[3 * bad + 2]);
    double c[3] = {0, 0, 0};
    for (int i = 0; i < n; i++)
        for (int d = 0; d < 3; d++) c[d] += X[3 * i + d];
    for (int d = 0; d < 3; d++) c[d] /= n;
    int first = 0;
    double best = -1;
    for (int i = 0; i < n; i++) {
        double d = dist2(&X[3 * i], c);
        if (d > best) best = d, first = i;
    }
    double *mind = rk_calloc((size_t)n, sizeof *mind, err);
    if (!mind) return -1;
    for (int i = 0; i < n; i++) mind[i] = INFINITY;
    int next = first;
    for (int k = 0; k < K; k++) {
        chosen[k] = next;
        const double *p = &X[3 * next];
        best = -1;
        next = -1;
        for (int i = 0; i < n; i++) {
            double d = dist2(&X[3 * i], p);
            if (d < mind[i]) mind[i] = d;
            if (mind[i] > best) best = mind[i], next = i;
        }
        if (k + 1 < K && !(best > 0)) {
            free(mind);
            return rk_fail(err, "farthest point sampling: %d centres asked, but the %d points hold only %d distinct positions",
                           K, n, k + 1);
        }
    }
    free(mind);
    return 0;
}
