/* Private to the rkpm_*.c files: the uniform grid, nearest neighbours, the tapered kernel and
 * the corrected shape functions at one point. */
#ifndef RK_RKPM_INTERNAL_H
#define RK_RKPM_INTERNAL_H

#include "basis/basis.h"

#include <math.h>

/* Grid over n points (3n coordinates) with cells of edge about h (h <= 0: about one point per
 * cell). The edge grows when the grid would have more than 4n + 64 cells. */
int rkpm_grid_build(rk_rkpm_grid *g, const double *X, int n, double h, rk_error *err);
void rkpm_grid_free(rk_rkpm_grid *g);
/* Calls visit(item, ctx) for every point in the grid cells that meet the box [lo, hi] (a
 * superset of the points inside it), cell by cell; stops at and returns the first non-zero
 * value visit returns, else 0. */
int rkpm_grid_visit(const rk_rkpm_grid *g, const double lo[3], const double hi[3],
                    int (*visit)(int item, void *ctx), void *ctx);
static inline int rkpm_grid_index(const rk_rkpm_grid *g, int i, int j, int k)
{
    return i + g->dim[0] * (j + g->dim[1] * k);
}
/* The `count` (1 or 2) nearest points of X other than point `self` (an index into X, which the
 * grid was built over): dist[count] ascending, who[count]. Needs n > count. */
void rkpm_grid_nearest(const rk_rkpm_grid *g, const double *X, int self, int count, double *dist,
                       int *who);

/* Lowest index of a non-finite coordinate among 3n, or -1. */
int rkpm_first_nonfinite(const double *X, int n);
/* qsort comparators */
int rkpm_cmp_int(const void *a, const void *b);
int rkpm_cmp_i64(const void *a, const void *b);
/* Number of distinct cells of edge g (origin lo) holding a point; *key gets n scratch int64. */
int rkpm_count_voxels(const double *X, int n, const double lo[3], const int dim[3], double g,
                      long long *key);

/* Kernel k's tapered Gaussian at X: the value, and its gradient in grad[3] when grad != NULL.
 * Zero outside the support. Inline: it runs for every (point, kernel) pair. */
static inline double rkpm_window(const rk_rkpm *k, int kid, const double X[3], double *grad)
{
    const double *p = &k->centers[3 * kid];
    double e[3] = {X[0] - p[0], X[1] - p[1], X[2] - p[2]};
    double d2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2], R = k->support[kid];
    if (grad) grad[0] = grad[1] = grad[2] = 0;
    if (d2 >= R * R) return 0;
    double r = k->radius[kid], gauss = exp(-d2 / (r * r)), S = 1, dS = 0, d = 0;
    const double width = (RK_RKPM_TAPER_END - RK_RKPM_TAPER_START) * r;
    if (d2 > RK_RKPM_TAPER_START * RK_RKPM_TAPER_START * r * r) {
        d = sqrt(d2);
        double t = (d - RK_RKPM_TAPER_START * r) / width;
        t = t < 1 ? t : 1;
        double u = 1 - t;
        S = 1 - t * t * t * (10 - 15 * t + 6 * t * t); /* C^2 smoothstep, S(0) = 1, S(1) = 0 */
        dS = -30 * t * t * u * u;                      /* dS/dt */
    }
    if (grad) {
        /* grad (gauss S) = gauss S (-2 e / r^2) + gauss S'(t) e / (d width) */
        double a = -2 * gauss * S / (r * r) + (dS != 0 ? gauss * dS / (d * width) : 0);
        for (int i = 0; i < 3; i++) grad[i] = a * e[i];
    }
    return gauss * S;
}

/* The corrected shape functions at X from the n kernels kid[] that cover X (in that order):
 * phi[n], grad[3n] (may be NULL). point >= 0 names the point in messages ("point 17 at ..."),
 * point < 0 calls it "the point at ...". */
int rkpm_shape_at(const rk_rkpm *k, const double X[3], int point, int n, const int *kid, double *phi,
                  double *grad, int *regularized, rk_error *err);
/* The clamp mask d at X (1 without a clamp is the caller's business) and its gradient grad[3]. */
double rkpm_clamp_at(const rk_rkpm_clamp *c, const double X[3], double grad[3]);
void rkpm_clamp_free(rk_rkpm_clamp *c);
/* The region of the points flagged in fixed (rk_rkpm_set_clamp's), its mask rising over `rise`. */
int rkpm_region_build(rk_rkpm_clamp *c, const double *X, int n, const unsigned char *fixed, const int *tets, int nt,
                      double rise, rk_error *err);
/* The distance from X to the region (0 inside) and, when it is below range, its gradient grad[3]
 * (the unit direction away from the region's nearest point); range or more (INFINITY: nothing
 * within range + the pieces' extent) with grad 0 otherwise. */
double rkpm_region_distance(const rk_rkpm_clamp *c, const double X[3], double range, double grad[3]);

/* The kernels covering X, ascending: count, or -1 (with err) when more than cap. */
int rkpm_cover(const rk_rkpm *k, const double X[3], int cap, int *idx, rk_error *err);

#endif
