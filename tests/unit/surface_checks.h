/* Shared by the cloud contact-surface tests (test_contact_points_proxy, test_contact_proxy_march):
 * a closed triangle surface checked independently of the library's own checks. */
#ifndef RK_TEST_SURFACE_CHECKS_H
#define RK_TEST_SURFACE_CHECKS_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "contact/contact.h"

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
    for (int f = 0; f < nf; f++)
        for (int d = 0; d < 3; d++) {
            const int *t = tris + 3 * f;
            fb[6 * f + d] = fmin(x[3 * t[0] + d], fmin(x[3 * t[1] + d], x[3 * t[2] + d]));
            fb[6 * f + 3 + d] = fmax(x[3 * t[0] + d], fmax(x[3 * t[1] + d], x[3 * t[2] + d]));
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

#endif
