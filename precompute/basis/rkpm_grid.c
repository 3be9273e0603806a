/* A uniform grid of cells over a point set: neighbour queries for the RKPM kernels (radii,
 * covering kernels) and nearest neighbours for point clouds. */
#include "basis/rkpm_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int rkpm_first_nonfinite(const double *X, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(X[3 * i]) || !isfinite(X[3 * i + 1]) || !isfinite(X[3 * i + 2])) return i;
    return -1;
}

int rkpm_cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

int rkpm_cmp_i64(const void *a, const void *b)
{
    long long x = *(const long long *)a, y = *(const long long *)b;
    return (x > y) - (x < y);
}

int rkpm_count_voxels(const double *X, int n, const double lo[3], const int dim[3], double g,
                      long long *key)
{
    for (int i = 0; i < n; i++) {
        long long c[3];
        for (int d = 0; d < 3; d++) {
            double t = floor((X[3 * i + d] - lo[d]) / g);
            c[d] = t < 0 ? 0 : t >= dim[d] ? dim[d] - 1 : (long long)t;
        }
        key[i] = c[0] + (long long)dim[0] * (c[1] + (long long)dim[1] * c[2]);
    }
    qsort(key, (size_t)n, sizeof *key, rkpm_cmp_i64);
    int count = n > 0;
    for (int i = 1; i < n; i++) count += key[i] != key[i - 1];
    return count;
}

static int clamp_cell(double t, int dim)
{
    if (!(t >= 0)) return 0; /* also NaN */
    if (t >= dim - 1) return dim - 1;
    return (int)t;
}

int rkpm_grid_build(rk_rkpm_grid *g, const double *X, int n, double h, rk_error *err)
{
    memset(g, 0, sizeof *g);
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}, emax = 0;
    for (int d = 0; d < 3; d++) {
        lo[d] = hi[d] = n > 0 ? X[d] : 0;
        for (int i = 1; i < n; i++) {
            lo[d] = fmin(lo[d], X[3 * i + d]);
            hi[d] = fmax(hi[d], X[3 * i + d]);
        }
        emax = fmax(emax, hi[d] - lo[d]);
    }
    if (!(h > 0) || !isfinite(h)) {
        double vol = 1;
        for (int d = 0; d < 3; d++) vol *= fmax(hi[d] - lo[d], 1e-3 * emax);
        h = cbrt(vol / (n > 0 ? n : 1));
    }
    if (!(h > 0) || !isfinite(h)) h = 1;
    double cap = 4.0 * n + 64;
    for (;;) {
        double cells = 1;
        for (int d = 0; d < 3; d++) cells *= floor((hi[d] - lo[d]) / h) + 1;
        if (cells <= cap) break;
        h *= cbrt(cells / cap) * 1.001;
    }
    g->h = h;
    for (int d = 0; d < 3; d++) {
        g->origin[d] = lo[d];
        g->dim[d] = (int)floor((hi[d] - lo[d]) / h) + 1;
    }
    int ncell = g->dim[0] * g->dim[1] * g->dim[2];
    g->start = rk_calloc((size_t)ncell + 1, sizeof(int), err);
    g->item = rk_calloc((size_t)n, sizeof(int), err);
    int *cell = rk_calloc((size_t)n, sizeof(int), err);
    if (!g->start || !g->item || !cell) {
        free(cell);
        rkpm_grid_free(g);
        return -1;
    }
    for (int i = 0; i < n; i++) {
        int c[3];
        for (int d = 0; d < 3; d++) c[d] = clamp_cell((X[3 * i + d] - lo[d]) / h, g->dim[d]);
        cell[i] = rkpm_grid_index(g, c[0], c[1], c[2]);
        g->start[cell[i] + 1]++;
    }
    for (int c = 0; c < ncell; c++) g->start[c + 1] += g->start[c];
    int *fill = rk_calloc((size_t)ncell, sizeof(int), err);
    if (!fill) {
        free(cell);
        rkpm_grid_free(g);
        return -1;
    }
    for (int i = 0; i < n; i++) g->item[g->start[cell[i]] + fill[cell[i]]++] = i;
    free(fill);
    free(cell);
    return 0;
}

void rkpm_grid_free(rk_rkpm_grid *g)
{
    free(g->start);
    free(g->item);
    memset(g, 0, sizeof *g);
}

/* Cell coordinates of the box [lo, hi], clamped to the grid: c0[3]..c1[3] inclusive. */
static void grid_range(const rk_rkpm_grid *g, const double lo[3], const double hi[3], int c0[3], int c1[3])
{
    for (int d = 0; d < 3; d++) {
        c0[d] = clamp_cell(floor((lo[d] - g->origin[d]) / g->h), g->dim[d]);
        c1[d] = clamp_cell(floor((hi[d] - g->origin[d]) / g->h), g->dim[d]);
    }
}

int rkpm_grid_visit(const rk_rkpm_grid *g, const double lo[3], const double hi[3],
                    int (*visit)(int item, void *ctx), void *ctx)
{
    int c0[3], c1[3];
    grid_range(g, lo, hi, c0, c1);
    for (int z = c0[2]; z <= c1[2]; z++)
        for (int y = c0[1]; y <= c1[1]; y++)
            for (int x = c0[0]; x <= c1[0]; x++) {
                int cell = rkpm_grid_index(g, x, y, z);
                for (int q = g->start[cell]; q < g->start[cell + 1]; q++) {
                    int rc = visit(g->item[q], ctx);
                    if (rc) return rc;
                }
            }
    return 0;
}

/* Keeps the `count` smallest (distance, index) pairs, ascending. */
static void offer(int count, double d, int i, double *dist, int *who, int *found)
{
    int pos = *found < count ? (*found)++ : count;
    if (pos == count) {
        if (d > dist[count - 1] || (d == dist[count - 1] && i > who[count - 1])) return;
        pos = count - 1;
    }
    while (pos > 0 && (dist[pos - 1] > d || (dist[pos - 1] == d && who[pos - 1] > i))) {
        dist[pos] = dist[pos - 1];
        who[pos] = who[pos - 1];
        pos--;
    }
    dist[pos] = d;
    who[pos] = i;
}

void rkpm_grid_nearest(const rk_rkpm_grid *g, const double *X, int self, int count, double *dist,
                       int *who)
{
    const double *x = &X[3 * self];
    int c[3], found = 0, smax = 0;
    grid_range(g, x, x, c, c);
    for (int d = 0; d < 3; d++) smax = g->dim[d] > smax ? g->dim[d] : smax;
    for (int s = 0; s <= smax; s++) {
        for (int dk = -s; dk <= s; dk++) {
            int k = c[2] + dk;
            if (k < 0 || k >= g->dim[2]) continue;
            for (int dj = -s; dj <= s; dj++) {
                int j = c[1] + dj;
                if (j < 0 || j >= g->dim[1]) continue;
                int shell = abs(dk) == s || abs(dj) == s;
                for (int di = -s; di <= s; di += shell || s == 0 ? 1 : 2 * s) {
                    int i = c[0] + di;
                    if (i < 0 || i >= g->dim[0]) continue;
                    int cell = rkpm_grid_index(g, i, j, k);
                    for (int q = g->start[cell]; q < g->start[cell + 1]; q++) {
                        int p = g->item[q];
                        if (p == self) continue;
                        const double *y = &X[3 * p];
                        double e0 = y[0] - x[0], e1 = y[1] - x[1], e2 = y[2] - x[2];
                        offer(count, sqrt(e0 * e0 + e1 * e1 + e2 * e2), p, dist, who, &found);
                    }
                }
            }
        }
        /* Every cell beyond ring s is at least s cells away from x's cell. */
        if (found == count && dist[count - 1] <= s * g->h) return;
    }
}
