/* rk_points_proxy: a closed surface around a point cloud, for contact (contact.h): the voxels that
 * hold points, grown where they meet only along an edge or at a corner so their surface is a
 * 2-manifold, as Kuhn ghost tets; then that surface moved in toward the points, to half a voxel
 * and on to half the points' spacing where the exact checks allow (proxy_inset.c), the last stage
 * letting a point end outside by at most RK_PROXY_OUTSIDE spacings (rk_proxy_near). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "contact/points_proxy_impl.h"

static int cmp_i64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

/* Sorts and drops duplicates; returns the new count. */
static size_t unique(int64_t *k, size_t n)
{
    if (n == 0) return 0;
    qsort(k, n, sizeof *k, cmp_i64);
    size_t m = 1;
    for (size_t i = 1; i < n; i++)
        if (k[i] != k[m - 1]) k[m++] = k[i];
    return m;
}

size_t rk_proxy_lower_bound(const int64_t *k, size_t n, int64_t key)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (k[mid] < key) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

/* Whether the voxels of mask (bit x | y << 1 | z << 2 of a 2 x 2 x 2 block) are face-connected. */
static int face_connected(int mask)
{
    int seen = mask & -mask, grew = 1;
    while (grew) {
        grew = 0;
        for (int b = 0; b < 8; b++)
            for (int s = 1; s < 8 && ((seen >> b) & 1); s <<= 1)
                if (((mask >> (b ^ s)) & 1) && !((seen >> (b ^ s)) & 1)) seen |= 1 << (b ^ s), grew = 1;
    }
    return seen == mask;
}

/* The voxel at place b of the 2 x 2 x 2 block around corner key c. */
static int64_t block_voxel(int64_t c, int b)
{
    const int64_t S = RK_PROXY_S;
    return c + ((b & 1) - 1) + S * ((((b >> 1) & 1) - 1) + S * (((b >> 2) & 1) - 1));
}

/* Grows the voxel set (sorted keys, *nvox of them, capacity *cap) until it is well-composed
 * (Latecki 1997): around every lattice corner the occupied voxels of its 2 x 2 x 2 block are
 * face-connected, and so are the empty ones. Then no two voxels meet only along an edge or at a
 * corner, and the boundary of their union is a 2-manifold (the voxel union's own is not: two
 * voxels on a diagonal share an edge that four faces use). A block that fails gets the voxels in
 * the box of its occupied ones: a box, and what is left of a 2 x 2 x 2 block around a box, are
 * face-connected. Only voxels inside the box of the cloud's voxels are added, so this ends. */
static int well_composed(int64_t **vox, size_t *nvox, rk_error *err)
{
    int ok[256];
    for (int mask = 0; mask < 256; mask++) ok[mask] = face_connected(mask) && face_connected(255 & ~mask);
    for (;;) {
        int64_t *corner = malloc(sizeof(int64_t) * 8 * *nvox), *grow = NULL;
        if (!corner) return rk_fail(err, "contact proxy: out of memory");
        for (size_t v = 0; v < *nvox; v++)
            for (int b = 0; b < 8; b++) corner[8 * v + b] = block_voxel((*vox)[v], b) + 1 + RK_PROXY_S * (1 + RK_PROXY_S);
        size_t ncorner = unique(corner, 8 * *nvox), ngrow = 0, capgrow = 0;
        for (size_t c = 0; c < ncorner; c++) {
            int mask = 0, lo[3] = {1, 1, 1}, hi[3] = {0, 0, 0};
            for (int b = 0; b < 8; b++) {
                int64_t k = block_voxel(corner[c], b);
                size_t at = rk_proxy_lower_bound(*vox, *nvox, k);
                if (at < *nvox && (*vox)[at] == k) {
                    mask |= 1 << b;
                    for (int d = 0; d < 3; d++) lo[d] = lo[d] < ((b >> d) & 1) ? lo[d] : (b >> d) & 1, hi[d] = hi[d] > ((b >> d) & 1) ? hi[d] : (b >> d) & 1;
                }
            }
            if (ok[mask]) continue;
            for (int b = 0; b < 8; b++) {
                int in = 1;
                for (int d = 0; d < 3; d++) in = in && ((b >> d) & 1) >= lo[d] && ((b >> d) & 1) <= hi[d];
                if (!in || ((mask >> b) & 1)) continue;
                if (ngrow == capgrow) {
                    capgrow = capgrow ? 2 * capgrow : 64;
                    int64_t *more = realloc(grow, sizeof *grow * capgrow);
                    if (!more) {
                        free(corner), free(grow);
                        return rk_fail(err, "contact proxy: out of memory");
                    }
                    grow = more;
                }
                grow[ngrow++] = block_voxel(corner[c], b);
            }
        }
        free(corner);
        if (ngrow == 0) return 0;
        int64_t *all = realloc(*vox, sizeof(int64_t) * (*nvox + ngrow));
        if (!all) {
            free(grow);
            return rk_fail(err, "contact proxy: out of memory");
        }
        memcpy(all + *nvox, grow, sizeof(int64_t) * ngrow);
        free(grow);
        *vox = all;
        *nvox = unique(all, *nvox + ngrow);
    }
}

/* Kuhn's split of the unit cube: the 6 tets around the diagonal 000-111, one per axis order;
 * corner bits are x | y << 1 | z << 2. Faces on the cube's sides are cut along the diagonal
 * through the lower corner in every cube alike, so neighbouring voxels' faces match. */
static const int KUHN[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

int rk_proxy_lattice(const double *X, int n, double g, rk_mesh *out, double lo[3], rk_error *err)
{
    memset(out, 0, sizeof *out);
    if (n < 1 || !(g > 0) || !isfinite(g)) return rk_fail(err, "contact proxy: %d points, voxel %g", n, g);
    for (int d = 0; d < 3; d++) lo[d] = X[d];
    for (int i = 1; i < n; i++)
        for (int d = 0; d < 3; d++) lo[d] = fmin(lo[d], X[3 * i + d]);
    for (int d = 0; d < 3; d++) lo[d] -= 0.5 * g; /* no point on a voxel's lower face at the edge */
    const int64_t S = RK_PROXY_S;
    int64_t *vox = malloc(sizeof(int64_t) * (size_t)n), *corner = NULL;
    if (!vox) return rk_fail(err, "contact proxy: out of memory");
    for (int i = 0; i < n; i++) {
        int64_t c[3];
        for (int d = 0; d < 3; d++) {
            /* range-checked as a double: converting a NaN, an infinity or anything past 2^63 to
             * int64_t is undefined (x86 gives INT64_MIN, which passed the check and wrapped) */
            double t = floor((X[3 * i + d] - lo[d]) / g);
            if (!isfinite(X[3 * i + d])) {
                free(vox);
                return rk_fail(err, "contact proxy: point %d is not finite (%g, %g, %g)", i, X[3 * i], X[3 * i + 1],
                               X[3 * i + 2]);
            }
            if (!(t >= 0 && t < (double)(S - 1))) {
                free(vox);
                return rk_fail(err, "contact proxy: voxel %g is too small for the cloud's extent", g);
            }
            c[d] = (int64_t)t;
        }
        vox[i] = c[0] + S * (c[1] + S * c[2]);
    }
    size_t nvox = unique(vox, (size_t)n);
    if (well_composed(&vox, &nvox, err)) {
        free(vox);
        return -1;
    }
    corner = malloc(sizeof(int64_t) * 8 * nvox);
    if (!corner) {
        free(vox);
        return rk_fail(err, "contact proxy: out of memory");
    }
    for (size_t v = 0; v < nvox; v++)
        for (int b = 0; b < 8; b++) corner[8 * v + b] = vox[v] + (b & 1) + S * (((b >> 1) & 1) + S * ((b >> 2) & 1));
    size_t ncorner = unique(corner, 8 * nvox);
    out->nv = n + (int)ncorner;
    out->X = malloc(sizeof(double) * 3 * (size_t)out->nv);
    out->nghost = 6 * (int)nvox;
    out->ghost = malloc(sizeof(int) * 4 * (size_t)out->nghost);
    out->tets = malloc(sizeof(int));
    if (!out->X || !out->ghost || !out->tets) {
        free(vox), free(corner);
        rk_mesh_free(out);
        return rk_fail(err, "contact proxy: out of memory");
    }
    memcpy(out->X, X, sizeof(double) * 3 * (size_t)n);
    for (size_t c = 0; c < ncorner; c++) {
        int64_t k = corner[c], idx[3] = {k % S, k / S % S, k / S / S};
        for (int d = 0; d < 3; d++) out->X[3 * (n + c) + d] = lo[d] + g * (double)idx[d];
    }
    for (size_t v = 0; v < nvox; v++) {
        int id[8];
        for (int b = 0; b < 8; b++)
            id[b] = n + (int)rk_proxy_lower_bound(corner, ncorner, vox[v] + (b & 1) + S * (((b >> 1) & 1) + S * ((b >> 2) & 1)));
        for (int t = 0; t < 6; t++) {
            int *T = out->ghost + 4 * (6 * v + t);
            for (int a = 0; a < 4; a++) T[a] = id[KUHN[t][a]];
            /* orientation: positive volume, as rk_mesh_check leaves every tet */
            if (rk_tet_signed_volume(&out->X[3 * T[0]], &out->X[3 * T[1]], &out->X[3 * T[2]], &out->X[3 * T[3]]) < 0) {
                int tmp = T[2];
                T[2] = T[3];
                T[3] = tmp;
            }
        }
    }
    free(vox);
    free(corner);
    return 0;
}

int rk_points_proxy(const double *X, int n, double g, double s, rk_mesh *out, rk_error *err)
{
    double lo[3];
    memset(out, 0, sizeof *out);
    if (!(s >= 0) || !isfinite(s)) return rk_fail(err, "contact proxy: points' spacing %g (expected 0 or more)", s);
    if (rk_proxy_lattice(X, n, g, out, lo, err)) return -1;
    /* half the spacing: a point stands for the cell of edge s around it, whose faces are s / 2 off
     * it (a lattice cloud's flat side then rests where its cells' union ends) */
    double tau = s > 0 ? fmin(RK_PROXY_SPACING_INSET * s, RK_PROXY_INSET * g) : RK_PROXY_INSET * g;
    /* the voxel surface, which every stage's turn and shrink checks compare with */
    double *lattice = rk_calloc(3 * (size_t)out->nv, sizeof *lattice, err);
    if (!lattice) {
        rk_mesh_free(out);
        return -1;
    }
    memcpy(lattice, out->X, sizeof(double) * 3 * (size_t)out->nv);
    /* then on to the points where only a noisy shell's outer splats held the surface back: those
     * may end outside it by RK_PROXY_OUTSIDE s (issue 30: the points are what is drawn, the surface
     * is what collides, so a splat overlaps what it rests on by at most that) */
    int rc = rk_proxy_inset(out, n, g, tau, lo, err) || rk_proxy_near(out, lattice, n, g, tau, RK_PROXY_OUTSIDE * s, lo, err);
    free(lattice);
    if (rc) rk_mesh_free(out);
    return rc ? -1 : 0;
}
