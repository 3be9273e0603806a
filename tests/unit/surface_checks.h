/* Shared by the cloud contact-surface tests (test_contact_points_proxy, test_contact_proxy_march):
 * a closed triangle surface checked independently of the library's own checks (closed, 2-manifold,
 * no self-crossing), and brute-force distances to segments, triangles and the nearest point. */
#ifndef RK_TEST_SURFACE_CHECKS_H
#define RK_TEST_SURFACE_CHECKS_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "contact/contact.h"
#include "contact/points_proxy_impl.h"
#include "util/util.h"

static int surface_cmp64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

/* Whether the nf triangles over nv vertices are closed, consistently oriented and 2-manifold: every
 * directed edge once and its reverse once, and around each vertex the links (b -> c of each face
 * (v, b, c)) one cycle (no pinch). 0 if so, *fans the vertices that have faces; else -1 and why. */
static inline int surface_closed_manifold(const int *tris, int nf, int nv, int *fans, char *why, size_t len)
{
    const int64_t V = nv;
    int rc = -1;
    int64_t *edges = malloc(sizeof(int64_t) * 3 * (size_t)nf), *link = malloc(sizeof(int64_t) * 3 * (size_t)nf);
    *fans = 0;
    if (!edges || !link) {
        snprintf(why, len, "out of memory");
        goto done;
    }
    for (int f = 0; f < nf; f++)
        for (int k = 0; k < 3; k++) edges[3 * f + k] = tris[3 * f + k] * V + tris[3 * f + (k + 1) % 3];
    qsort(edges, 3 * (size_t)nf, sizeof *edges, surface_cmp64);
    for (int e = 0; e < 3 * nf; e++) {
        int64_t rev = (edges[e] % V) * V + edges[e] / V;
        if (e > 0 && edges[e] == edges[e - 1]) {
            snprintf(why, len, "edge %lld -> %lld is used twice: not a 2-manifold", (long long)(edges[e] / V),
                     (long long)(edges[e] % V));
            goto done;
        }
        if (!bsearch(&rev, edges, 3 * (size_t)nf, sizeof rev, surface_cmp64)) {
            snprintf(why, len, "edge %lld -> %lld has no reverse: not closed", (long long)(edges[e] / V),
                     (long long)(edges[e] % V));
            goto done;
        }
    }
    for (int f = 0; f < nf; f++) /* v << 42 | b << 21 | c */
        for (int k = 0; k < 3; k++)
            link[3 * f + k] = (int64_t)tris[3 * f + k] << 42 | (int64_t)tris[3 * f + (k + 1) % 3] << 21 | tris[3 * f + (k + 2) % 3];
    qsort(link, 3 * (size_t)nf, sizeof *link, surface_cmp64);
    for (int a = 0; a < 3 * nf;) {
        int b = a, steps = 0;
        while (b < 3 * nf && link[b] >> 42 == link[a] >> 42) b++;
        /* from the first link, follow b -> c (each b once: edge-manifold above) and count */
        int64_t start = link[a] >> 21 & 0x1fffff, at = start;
        do {
            int64_t next = -1;
            for (int k = a; k < b; k++)
                if ((link[k] >> 21 & 0x1fffff) == at) next = link[k] & 0x1fffff;
            if (next < 0) {
                snprintf(why, len, "vertex %lld: its fan is open at %lld", (long long)(link[a] >> 42), (long long)at);
                goto done;
            }
            at = next, steps++;
        } while (at != start && steps <= b - a);
        if (steps != b - a) {
            snprintf(why, len, "vertex %lld: its %d faces make a fan of %d: not a 2-manifold (a pinch)",
                     (long long)(link[a] >> 42), b - a, steps);
            goto done;
        }
        ++*fans;
        a = b;
    }
    rc = 0;
done:
    free(edges), free(link);
    return rc;
}

/* Whether an edge of the surface (x: 3 per vertex) meets a face it shares no vertex with, by the
 * exact segment-triangle test over the broad phase's candidates: 0 if none; else -1 and why.
 * boxes (6 nf, may be NULL) gets each face's box (min xyz, max xyz). */
static inline int surface_crosses_itself(const double *x, const int *tris, int nf, double *boxes, char *why, size_t len)
{
    rk_error err;
    int rc = -1, *pairs = NULL, npairs = 0;
    double *fb = malloc(sizeof(double) * 6 * (size_t)nf), *eb = malloc(sizeof(double) * 18 * (size_t)nf);
    if (!fb || !eb) {
        snprintf(why, len, "out of memory");
        goto done;
    }
    rk_proxy_face_boxes(x, tris, nf, fb);
    for (int f = 0; f < nf; f++)
        for (int d = 0; d < 3; d++) {
            const int *t = tris + 3 * f;
            for (int k = 0; k < 3; k++) {
                eb[6 * (3 * f + k) + d] = fmin(x[3 * t[k] + d], x[3 * t[(k + 1) % 3] + d]);
                eb[6 * (3 * f + k) + 3 + d] = fmax(x[3 * t[k] + d], x[3 * t[(k + 1) % 3] + d]);
            }
        }
    if (rk_broad_phase(eb, 3 * nf, fb, nf, &pairs, &npairs, &err)) {
        snprintf(why, len, "broad phase: %.200s", err.msg);
        goto done;
    }
    for (int p = 0; p < npairs; p++) {
        int e = pairs[2 * p], f = pairs[2 * p + 1], a = tris[e], b = tris[3 * (e / 3) + (e % 3 + 1) % 3];
        const int *t = tris + 3 * f;
        if (a == t[0] || a == t[1] || a == t[2] || b == t[0] || b == t[1] || b == t[2]) continue;
        if (rk_segment_triangle_intersect(x + 3 * a, x + 3 * b, x + 3 * t[0], x + 3 * t[1], x + 3 * t[2])) {
            snprintf(why, len, "edge (%d, %d) meets face %d (%d, %d, %d): the surface intersects itself", a, b, f, t[0],
                     t[1], t[2]);
            goto done;
        }
    }
    if (boxes) memcpy(boxes, fb, sizeof(double) * 6 * (size_t)nf);
    rc = 0;
done:
    free(fb), free(eb), free(pairs);
    return rc;
}

/* The distance from p to segment ab and to triangle abc, by brute force (not the library's). */
static inline double segment_distance(const double *p, const double *a, const double *b)
{
    double u[3], w[3], uu = 0, uw = 0, d2 = 0;
    for (int d = 0; d < 3; d++) u[d] = b[d] - a[d], w[d] = p[d] - a[d], uu += u[d] * u[d], uw += u[d] * w[d];
    double t = uu > 0 ? fmin(1, fmax(0, uw / uu)) : 0;
    for (int d = 0; d < 3; d++) d2 += (w[d] - t * u[d]) * (w[d] - t * u[d]);
    return sqrt(d2);
}

static inline double triangle_distance(const double *p, const double *a, const double *b, const double *c)
{
    double u[3], v[3], w[3], nrm[3];
    for (int d = 0; d < 3; d++) u[d] = b[d] - a[d], v[d] = c[d] - a[d], w[d] = p[d] - a[d];
    nrm[0] = u[1] * v[2] - u[2] * v[1], nrm[1] = u[2] * v[0] - u[0] * v[2], nrm[2] = u[0] * v[1] - u[1] * v[0];
    double nn = nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2];
    double best = fmin(segment_distance(p, a, b), fmin(segment_distance(p, b, c), segment_distance(p, c, a)));
    if (nn > 0) {
        double h = (w[0] * nrm[0] + w[1] * nrm[1] + w[2] * nrm[2]) / nn, q[3], e1[3], e2[3];
        for (int d = 0; d < 3; d++) q[d] = w[d] - h * nrm[d];
        e1[0] = q[1] * v[2] - q[2] * v[1], e1[1] = q[2] * v[0] - q[0] * v[2], e1[2] = q[0] * v[1] - q[1] * v[0];
        e2[0] = u[1] * q[2] - u[2] * q[1], e2[1] = u[2] * q[0] - u[0] * q[2], e2[2] = u[0] * q[1] - u[1] * q[0];
        double beta = (e1[0] * nrm[0] + e1[1] * nrm[1] + e1[2] * nrm[2]) / nn;
        double gamma = (e2[0] * nrm[0] + e2[1] * nrm[1] + e2[2] * nrm[2]) / nn;
        if (beta >= 0 && gamma >= 0 && beta + gamma <= 1) best = fmin(best, fabs(h) * sqrt(nn));
    }
    return best;
}

/* The distance from x to the nearest of the n points within 1.5 cells of edge h of it, from a
 * sorted list of cell keys (cell << 24 | point); INFINITY past that. */
typedef struct {
    const double *X;
    int n;
    double h, lo[3];
    int64_t *key;
} bucket;

static inline int64_t cell_of(const bucket *B, const double *x, int dx, int dy, int dz)
{
    int64_t c[3];
    for (int d = 0; d < 3; d++) c[d] = (int64_t)floor((x[d] - B->lo[d]) / B->h) + 8;
    return (c[0] + dx) + 4096 * ((c[1] + dy) + 4096 * (c[2] + dz));
}

static inline void bucket_init(bucket *B, const double *X, int n, double h)
{
    B->X = X, B->n = n, B->h = h;
    for (int d = 0; d < 3; d++) {
        B->lo[d] = X[d];
        for (int i = 1; i < n; i++) B->lo[d] = fmin(B->lo[d], X[3 * i + d]);
    }
    B->key = malloc(sizeof(int64_t) * (size_t)n);
    for (int i = 0; i < n; i++) B->key[i] = cell_of(B, X + 3 * i, 0, 0, 0) << 24 | i;
    qsort(B->key, (size_t)n, sizeof(int64_t), surface_cmp64);
}

/* The nearest point to x other than point skip (-1: any), within h (INFINITY past h). */
static inline double bucket_nearest(const bucket *B, const double *x, int skip)
{
    double best = INFINITY;
    for (int dz = -1; dz <= 1; dz++)
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                int64_t k = cell_of(B, x, dx, dy, dz) << 24;
                int lo = 0, hi = B->n;
                while (lo < hi) {
                    int mid = (lo + hi) / 2;
                    if (B->key[mid] < k) lo = mid + 1;
                    else hi = mid;
                }
                for (int a = lo; a < B->n && B->key[a] >> 24 == k >> 24; a++) {
                    int i = (int)(B->key[a] & 0xffffff);
                    double d2 = 0;
                    for (int d = 0; d < 3; d++) d2 += (B->X[3 * i + d] - x[d]) * (B->X[3 * i + d] - x[d]);
                    if (i != skip && d2 > 0) best = fmin(best, sqrt(d2));
                    if (skip < 0 && d2 == 0) best = 0;
                }
            }
    return best <= B->h ? best : INFINITY;
}

/* The points' median spacing: the median of their positive nearest-neighbour distances (those
 * within h, the bucket's cell), as rk_rkpm_sample_cloud's occupancy voxel halves it. */
static inline double median_spacing(const double *X, int n, double h)
{
    bucket B;
    bucket_init(&B, X, n, h);
    double *nn = malloc(sizeof(double) * (size_t)n);
    int pos = 0;
    for (int i = 0; i < n; i++) {
        double d = bucket_nearest(&B, X + 3 * i, i);
        if (d < INFINITY) nn[pos++] = d;
    }
    qsort(nn, (size_t)pos, sizeof *nn, rk_cmp_double);
    double m = pos > 0 ? nn[pos / 2] : 0;
    free(nn), free(B.key);
    return m;
}

#endif
