/* Integration points uniformly random inside a tet mesh (freeform paper Table 4: random against
 * grid sampling at simulation time). */
#include "basis/rkpm_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* First index with cdf[i] > u (cdf ascending, cdf[n - 1] = total > u). */
static int pick(const double *cdf, int n, double u)
{
    int lo = 0, hi = n - 1;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (cdf[mid] > u) hi = mid;
        else lo = mid + 1;
    }
    return lo;
}

int rk_rkpm_sample_mesh_random(const rk_mesh *m, int count, unsigned long long seed, rk_rkpm_points *p, rk_error *err)
{
    memset(p, 0, sizeof *p);
    if (count < 1) return rk_fail(err, "random sampling: the number of points must be >= 1, got %d", count);
    if (m->nt < 1) return rk_fail(err, "random sampling: the mesh has no tetrahedra");
    double *cdf = rk_calloc((size_t)m->nt, sizeof(double), err);
    p->X = rk_calloc(3 * (size_t)count, sizeof(double), err);
    p->weight = rk_calloc((size_t)count, sizeof(double), err);
    p->tet = rk_calloc((size_t)count, sizeof(int), err);
    if (!cdf || !p->X || !p->weight || !p->tet) {
        free(cdf);
        rk_rkpm_points_free(p);
        return -1;
    }
    double volume = 0;
    for (int t = 0; t < m->nt; t++) {
        const int *T = &m->tets[4 * t];
        volume += fabs(rk_tet_signed_volume(&m->X[3 * T[0]], &m->X[3 * T[1]], &m->X[3 * T[2]], &m->X[3 * T[3]]));
        cdf[t] = volume;
    }
    if (!(volume > 0) || !isfinite(volume)) {
        free(cdf);
        rk_rkpm_points_free(p);
        return rk_fail(err, "random sampling: the mesh has zero or non-finite volume");
    }
    uint64_t state = seed;
    for (int i = 0; i < count; i++) {
        int t = pick(cdf, m->nt, rk_uniform(&state) * volume);
        /* Uniform in the unit tet by folding the unit cube (Rocchini & Cignoni 2000, "Generating
         * random points in a tetrahedron"), then mapped affinely: the density stays uniform. */
        double s = rk_uniform(&state), u = rk_uniform(&state), v = rk_uniform(&state), tmp;
        if (s + u > 1) s = 1 - s, u = 1 - u;
        if (u + v > 1) tmp = v, v = 1 - s - u, u = 1 - tmp;
        else if (s + u + v > 1) tmp = v, v = s + u + v - 1, s = 1 - u - tmp;
        double b[4] = {1 - s - u - v, s, u, v};
        const int *T = &m->tets[4 * t];
        for (int d = 0; d < 3; d++) {
            double x = 0;
            for (int k = 0; k < 4; k++) x += b[k] * m->X[3 * T[k] + d];
            p->X[3 * i + d] = x;
        }
        p->weight[i] = volume / count;
        p->tet[i] = t;
    }
    free(cdf);
    p->n = count;
    p->volume = volume;
    p->spacing = cbrt(volume / count);
    return 0;
}
