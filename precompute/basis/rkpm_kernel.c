/* The RKPM kernels: tapered Gaussians (freeform paper Eq. 6) with radii from the centre spacing
 * (Sec. 7.1), hashed on a uniform grid for neighbour queries. */
#include "basis/rkpm_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void rk_rkpm_free(rk_rkpm *k)
{
    free(k->centers);
    free(k->radius);
    free(k->support);
    rkpm_grid_free(&k->hash);
    rkpm_clamp_free(&k->clamp);
    rk_lift_free(&k->lift);
    memset(k, 0, sizeof *k);
}

int rk_rkpm_max_support(const rk_rkpm *k) { return k->max_support; }

static double dist2(const double *a, const double *b)
{
    double e0 = a[0] - b[0], e1 = a[1] - b[1], e2 = a[2] - b[2];
    return e0 * e0 + e1 * e1 + e2 * e2;
}

/* r_k = distance to the 2nd nearest other centre (Sec. 7.1). */
static int radii(rk_rkpm *k, rk_error *err)
{
    rk_rkpm_grid g;
    if (rkpm_grid_build(&g, k->centers, k->K, 0, err)) return -1;
    for (int c = 0; c < k->K; c++) {
        double dist[2];
        int who[2];
        rkpm_grid_nearest(&g, k->centers, c, 2, dist, who);
        if (!(dist[0] > 0)) {
            const double *p = &k->centers[3 * c];
            rkpm_grid_free(&g);
            return rk_fail(err, "RKPM kernels: centres %d and %d coincide at (%g, %g, %g)", c < who[0] ? c : who[0],
                           c < who[0] ? who[0] : c, p[0], p[1], p[2]);
        }
        k->radius[c] = dist[1];
        k->support[c] = RK_RKPM_TAPER_END * dist[1];
        k->max_support_radius = fmax(k->max_support_radius, k->support[c]);
    }
    rkpm_grid_free(&g);
    return 0;
}

/* Counts the centres l whose support overlaps that of centre c. */
typedef struct {
    const rk_rkpm *k;
    int c, count;
} overlap_count;

static int count_overlap(int l, void *ctx)
{
    overlap_count *o = ctx;
    double R = o->k->support[o->c] + o->k->support[l];
    o->count += dist2(&o->k->centers[3 * o->c], &o->k->centers[3 * l]) < R * R;
    return 0;
}

/* max over k of #{l : |p_k - p_l| < R_k + R_l}: a point covered by k and l is within R_k of p_k
 * and within R_l of p_l, and every point that is covered at all is covered by some k. */
static void support_bound(rk_rkpm *k)
{
    for (int c = 0; c < k->K; c++) {
        const double *p = &k->centers[3 * c];
        double reach = k->support[c] + k->max_support_radius, lo[3], hi[3];
        for (int d = 0; d < 3; d++) lo[d] = p[d] - reach, hi[d] = p[d] + reach;
        overlap_count o = {k, c, 0};
        rkpm_grid_visit(&k->hash, lo, hi, count_overlap, &o);
        if (o.count > k->max_support) k->max_support = o.count;
    }
}

int rk_rkpm_init(rk_rkpm *k, const double *centers, int K, rk_error *err)
{
    memset(k, 0, sizeof *k);
    if (K < 4) return rk_fail(err, "RKPM kernels: %d centres, at least 4 are needed for linear reproduction", K);
    int bad = rkpm_first_nonfinite(centers, K);
    if (bad >= 0)
        return rk_fail(err, "RKPM kernels: centre %d has a non-finite coordinate (%g, %g, %g)", bad, centers[3 * bad],
                       centers[3 * bad + 1], centers[3 * bad + 2]);
    k->K = K;
    k->centers = rk_calloc(3 * (size_t)K, sizeof(double), err);
    k->radius = rk_calloc((size_t)K, sizeof(double), err);
    k->support = rk_calloc((size_t)K, sizeof(double), err);
    if (!k->centers || !k->radius || !k->support) {
        rk_rkpm_free(k);
        return -1;
    }
    memcpy(k->centers, centers, 3 * (size_t)K * sizeof(double));
    if (radii(k, err) || rkpm_grid_build(&k->hash, k->centers, K, k->max_support_radius, err)) {
        rk_rkpm_free(k);
        return -1;
    }
    support_bound(k);
    return 0;
}

/* Collects the kernels whose support holds X; 1 when the room runs out. */
typedef struct {
    const rk_rkpm *k;
    const double *X;
    int cap, count;
    int *idx;
} cover_list;

static int add_cover(int l, void *ctx)
{
    cover_list *c = ctx;
    if (dist2(c->X, &c->k->centers[3 * l]) >= c->k->support[l] * c->k->support[l]) return 0;
    if (c->count == c->cap) return 1;
    c->idx[c->count++] = l;
    return 0;
}

int rkpm_cover(const rk_rkpm *k, const double X[3], int cap, int *idx, rk_error *err)
{
    double lo[3], hi[3], R = k->max_support_radius;
    for (int d = 0; d < 3; d++) lo[d] = X[d] - R, hi[d] = X[d] + R;
    cover_list c = {k, X, cap, 0, idx};
    if (rkpm_grid_visit(&k->hash, lo, hi, add_cover, &c))
        return rk_fail(err, "the point at (%g, %g, %g) is covered by more than %d kernels (the room given)",
                       X[0], X[1], X[2], cap);
    qsort(idx, (size_t)c.count, sizeof *idx, rkpm_cmp_int);
    return c.count;
}
