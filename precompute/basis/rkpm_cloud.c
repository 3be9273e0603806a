/* Integration points from a point cloud (Gaussian-splat centres): the points themselves,
 * voxel-downsampled above a budget, with uniform weights from an occupancy volume estimate
 * (freeform paper Sec. 7.1: "for 3DGS we directly use the given points as integration points,
 * after downsampling if necessary"). */
#include "basis/rkpm_impl.h"
#include "util/util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    long long key;
    int idx;
} keyed;

static int cmp_keyed(const void *a, const void *b)
{
    const keyed *x = a, *y = b;
    if (x->key != y->key) return (x->key > y->key) - (x->key < y->key);
    return (x->idx > y->idx) - (x->idx < y->idx);
}

static void bbox(const double *X, int n, double lo[3], double hi[3])
{
    for (int d = 0; d < 3; d++) lo[d] = hi[d] = X[d];
    for (int i = 1; i < n; i++)
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], X[3 * i + d]);
            hi[d] = fmax(hi[d], X[3 * i + d]);
        }
}

static void voxel_dims(const double lo[3], const double hi[3], double g, int dim[3])
{
    for (int d = 0; d < 3; d++) dim[d] = (int)floor((hi[d] - lo[d]) / g) + 1;
}

/* keep[*nk]: the lowest-index point of each occupied voxel, ascending, for the smallest voxel
 * edge (found by bisection) that leaves at most max_points. */
static int downsample(const double *X, int n, int max_points, int *keep, int *nk, rk_error *err)
{
    double lo[3], hi[3], emax = 0;
    bbox(X, n, lo, hi);
    for (int d = 0; d < 3; d++) emax = fmax(emax, hi[d] - lo[d]);
    long long *key = rk_calloc((size_t)n, sizeof *key, err);
    keyed *kd = rk_calloc((size_t)n, sizeof *kd, err);
    if (!key || !kd) {
        free(key);
        free(kd);
        return -1;
    }
    /* Edge 1e-5 emax: at most 1e5+1 voxels a side, so voxel keys fit in 64 bits. */
    double glo = 1e-5 * emax, ghi = 2 * emax;
    int dim[3];
    voxel_dims(lo, hi, glo, dim);
    if (rkpm_count_voxels(X, n, lo, dim, glo, key) <= max_points) ghi = glo;
    else
        while (ghi > 1.0001 * glo) {
            double g = sqrt(glo * ghi);
            voxel_dims(lo, hi, g, dim);
            if (rkpm_count_voxels(X, n, lo, dim, g, key) <= max_points) ghi = g;
            else glo = g;
        }
    voxel_dims(lo, hi, ghi, dim);
    for (int i = 0; i < n; i++) {
        long long c[3];
        for (int d = 0; d < 3; d++) {
            double t = floor((X[3 * i + d] - lo[d]) / ghi);
            c[d] = t < 0 ? 0 : t >= dim[d] ? dim[d] - 1 : (long long)t;
        }
        kd[i] = (keyed){c[0] + (long long)dim[0] * (c[1] + (long long)dim[1] * c[2]), i};
    }
    qsort(kd, (size_t)n, sizeof *kd, cmp_keyed);
    *nk = 0;
    for (int i = 0; i < n; i++)
        if (i == 0 || kd[i].key != kd[i - 1].key) keep[(*nk)++] = kd[i].idx;
    qsort(keep, (size_t)*nk, sizeof *keep, rkpm_cmp_int);
    free(key);
    free(kd);
    return 0;
}

/* Median of the positive nearest-neighbour distances; 0 when there is none. */
static int median_spacing(const double *X, int n, double *median, rk_error *err)
{
    rk_rkpm_grid g;
    double *nn = rk_calloc((size_t)n, sizeof *nn, err);
    if (!nn || rkpm_grid_build(&g, X, n, 0, err)) {
        free(nn);
        return -1;
    }
    int pos = 0;
    for (int i = 0; i < n; i++) {
        double dist;
        int who;
        rkpm_grid_nearest(&g, X, i, 1, &dist, &who);
        if (dist > 0) nn[pos++] = dist;
    }
    rkpm_grid_free(&g);
    qsort(nn, (size_t)pos, sizeof *nn, rk_cmp_double);
    *median = pos > 0 ? nn[pos / 2] : 0;
    free(nn);
    return 0;
}

int rk_rkpm_sample_cloud(const double *X, int n, int max_points, rk_rkpm_points *p, rk_error *err)
{
    memset(p, 0, sizeof *p);
    if (n < 4) return rk_fail(err, "point cloud: %d points, at least 4 are needed", n);
    if (max_points < 4) return rk_fail(err, "point cloud: max_points must be >= 4, got %d", max_points);
    int bad = rkpm_first_nonfinite(X, n);
    if (bad >= 0)
        return rk_fail(err, "point cloud: point %d has a non-finite coordinate (%g, %g, %g)", bad, X[3 * bad],
                       X[3 * bad + 1], X[3 * bad + 2]);
    double median;
    if (median_spacing(X, n, &median, err)) return -1;
    if (!(median > 0)) return rk_fail(err, "point cloud: all %d points coincide", n);
    int *keep = rk_calloc((size_t)n, sizeof *keep, err), nk = n;
    if (!keep) return -1;
    if (n > max_points) {
        if (downsample(X, n, max_points, keep, &nk, err)) {
            free(keep);
            return -1;
        }
    } else
        for (int i = 0; i < n; i++) keep[i] = i;
    p->n = nk;
    p->X = rk_calloc(3 * (size_t)nk, sizeof(double), err);
    p->weight = rk_calloc((size_t)nk, sizeof(double), err);
    p->source = keep;
    if (!p->X || !p->weight) {
        rk_rkpm_points_free(p);
        return -1;
    }
    for (int i = 0; i < nk; i++) memcpy(&p->X[3 * i], &X[3 * keep[i]], 3 * sizeof(double));

    /* Occupancy volume over all n input points (so it does not depend on max_points): voxels of
     * edge 2 x the median nearest-neighbour spacing that hold a point (see basis.h, RKPM). */
    double g = 2 * median, lo[3], hi[3];
    int dim[3];
    bbox(X, n, lo, hi);
    for (int d = 0; d < 3; d++)
        if ((hi[d] - lo[d]) / g > 2e6) {
            rk_rkpm_points_free(p);
            return rk_fail(err, "point cloud: extent %g is more than 4e6 x the median point spacing %g", hi[d] - lo[d], median);
        }
    voxel_dims(lo, hi, g, dim);
    long long *key = rk_calloc((size_t)n, sizeof *key, err);
    if (!key) {
        rk_rkpm_points_free(p);
        return -1;
    }
    int occupied = rkpm_count_voxels(X, n, lo, dim, g, key);
    p->spacing = g;
    p->volume = occupied * g * g * g;
    /* Each kept point's share of its voxel: g^3 over the kept points in it, scaled to the volume.
     * Uniform weights would give every point the same volume, and clouds are rarely uniform (a tet
     * mesh's vertices crowd its surface; splats, their edges): a dense patch then weighs more than
     * the space it fills. */
    long long *own = rk_calloc((size_t)nk, sizeof *own, err);
    if (!own) {
        free(key);
        rk_rkpm_points_free(p);
        return -1;
    }
    rkpm_count_voxels(p->X, nk, lo, dim, g, key); /* key: the kept points' voxels, sorted */
    for (int i = 0; i < nk; i++) {
        long long c[3];
        for (int d = 0; d < 3; d++) {
            double t = floor((p->X[3 * i + d] - lo[d]) / g);
            c[d] = t < 0 ? 0 : t >= dim[d] ? dim[d] - 1 : (long long)t;
        }
        own[i] = c[0] + (long long)dim[0] * (c[1] + (long long)dim[1] * c[2]);
    }
    double sum = 0;
    for (int i = 0; i < nk; i++) {
        long long *first = key, *end = key + nk; /* the run of own[i] in the sorted keys */
        size_t lo_i = 0, hi_i = (size_t)nk;
        while (lo_i < hi_i) {
            size_t mid = (lo_i + hi_i) / 2;
            if (first[mid] < own[i]) lo_i = mid + 1;
            else hi_i = mid;
        }
        size_t k = lo_i;
        while (first + k < end && first[k] == own[i]) k++;
        p->weight[i] = g * g * g / (double)(k - lo_i);
        sum += p->weight[i];
    }
    for (int i = 0; i < nk; i++) p->weight[i] *= p->volume / sum;
    free(own);
    free(key);
    return 0;
}
