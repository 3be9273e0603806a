/* rk_koopman_marker_coords (koopman.h): tracked markers to basis coordinates, the sparse-to-dense
 * step of Sec. 7.5. The paper's neural fields evaluate the modes anywhere; with a mesh basis the
 * same role is played by the basis rows at the tracked vertices. */
#include "koopman/koopman.h"

#include <math.h>
#include <stdlib.h>

int rk_koopman_surface_coords(const double *Phi, int n3, int b, const int *tri, const double *bary, int k,
                              const double *markers, int T, double ridge, const double *weight, double *q, rk_error *err)
{
    if (b < 1 || k < 1 || T < 1) return rk_fail(err, "markers: %d basis columns, %d markers, %d frames", b, k, T);
    for (int j = 0; weight && j < b; j++)
        if (!(weight[j] > 0) || !isfinite(weight[j]))
            return rk_fail(err, "markers: ridge weight %d is %g; weights must be finite and > 0", j, weight[j]);
    if (3 * k < b)
        return rk_fail(err, "markers: %d markers give %d equations per frame for %d basis coordinates; track at least "
                       "%d %s or use a smaller basis", k, 3 * k, b, (b + 2) / 3, bary ? "markers" : "vertices");
    int m = 3 * k, per = bary ? 3 : 1;
    double *A = rk_calloc((size_t)m * b, sizeof(double), err);
    if (!A) return -1;
    for (int i = 0; i < k; i++)
        for (int a = 0; a < per; a++) {
            int v = tri[per * i + a];
            double w = bary ? bary[3 * i + a] : 1;
            if (v < 0 || 3 * v >= n3) {
                free(A);
                return rk_fail(err, "markers: marker %d is vertex %d, outside 0..%d", i, v, n3 / 3 - 1);
            }
            /* a surface point's row: its triangle's vertex rows mixed by its barycentric weights */
            for (int j = 0; j < b; j++)
                for (int c = 0; c < 3; c++)
                    A[(size_t)m * j + 3 * i + c] += w * Phi[(size_t)n3 * j + 3 * v + c] / (weight ? weight[j] : 1);
        }
    /* in p = W q (W = diag(weight)) the penalty lambda^2 |W q|^2 is rk_lstsq_tikhonov's lambda^2 |p|^2 */
    int rc = 0;
    for (int t = 0; t < T && !rc; t++) {
        double *qt = q + (size_t)b * t;
        rc = rk_lstsq_tikhonov(m, b, A, markers + (size_t)m * t, ridge, 0, qt, NULL, err);
        for (int j = 0; weight && j < b; j++) qt[j] /= weight[j];
    }
    free(A);
    return rc ? rk_error_prefix(err, "markers") : 0;
}

int rk_koopman_marker_coords(const double *Phi, int n3, int b, const int *vertex, int k, const double *markers, int T,
                             double ridge, const double *weight, double *q, rk_error *err)
{
    return rk_koopman_surface_coords(Phi, n3, b, vertex, NULL, k, markers, T, ridge, weight, q, err);
}
