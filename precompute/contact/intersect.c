/* The exact intersection test (contact.h): does a segment cross a triangle, decided by the signs
 * of orientation determinants computed exactly (exact.c), so touching counts and rounding never
 * hides a crossing. */
#include "contact/pairs_impl.h"

#include <stdlib.h>

#include "util/util.h"

#include <math.h>

/* The sign of the 2D orientation of a, b, c in the coordinate plane (i, j), exactly: orient3d of
 * the points lifted to a plane that is not vertical. */
static int orient2d_sign(const double *a, const double *b, const double *c, int i, int j)
{
    double A[3] = {a[i], a[j], 0}, B[3] = {b[i], b[j], 0}, C[3] = {c[i], c[j], 0}, D[3] = {0, 0, 1};
    /* orient3d(A, B, C, D) with D above the plane z = 0 is minus the 2D orientation of A, B, C */
    return -rk_orient3d_sign(A, B, C, D);
}

static int segments_cross_2d(const double *p, const double *q, const double *a, const double *b, int i, int j)
{
    int s1 = orient2d_sign(p, q, a, i, j), s2 = orient2d_sign(p, q, b, i, j);
    int s3 = orient2d_sign(a, b, p, i, j), s4 = orient2d_sign(a, b, q, i, j);
    if (s1 * s2 > 0 || s3 * s4 > 0) return 0;
    if (s1 || s2 || s3 || s4) return 1;
    /* collinear: overlap of the projections on the wider axis */
    int k = fabs(p[i] - q[i]) + fabs(a[i] - b[i]) >= fabs(p[j] - q[j]) + fabs(a[j] - b[j]) ? i : j;
    return fmax(fmin(p[k], q[k]), fmin(a[k], b[k])) <= fmin(fmax(p[k], q[k]), fmax(a[k], b[k]));
}

static int point_in_triangle_2d(const double *p, const double *a, const double *b, const double *c, int i, int j)
{
    int s1 = orient2d_sign(a, b, p, i, j), s2 = orient2d_sign(b, c, p, i, j), s3 = orient2d_sign(c, a, p, i, j);
    return !((s1 < 0 || s2 < 0 || s3 < 0) && (s1 > 0 || s2 > 0 || s3 > 0));
}

int rk_segment_triangle_intersect(const double *p, const double *q, const double *a, const double *b, const double *c)
{
    int sp = rk_orient3d_sign(a, b, c, p), sq = rk_orient3d_sign(a, b, c, q);
    if (sp * sq > 0) return 0;
    if (sp == 0 && sq == 0) {
        /* coplanar: a 2D test in the coordinate plane the triangle's normal is most along */
        double n[3] = {(b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]),
                       (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]),
                       (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])};
        int drop = fabs(n[0]) >= fabs(n[1]) && fabs(n[0]) >= fabs(n[2]) ? 0 : fabs(n[1]) >= fabs(n[2]) ? 1 : 2;
        int i = (drop + 1) % 3, j = (drop + 2) % 3;
        return point_in_triangle_2d(p, a, b, c, i, j) || point_in_triangle_2d(q, a, b, c, i, j) ||
               segments_cross_2d(p, q, a, b, i, j) || segments_cross_2d(p, q, b, c, i, j) ||
               segments_cross_2d(p, q, c, a, i, j);
    }
    /* the segment meets the triangle's plane: inside when the line pq passes the three edges on
     * one side (or on them) */
    int s1 = rk_orient3d_sign(p, q, a, b), s2 = rk_orient3d_sign(p, q, b, c), s3 = rk_orient3d_sign(p, q, c, a);
    return !((s1 < 0 || s2 < 0 || s3 < 0) && (s1 > 0 || s2 > 0 || s3 > 0));
}

/* Boxes of n primitives of `size` points each (ids into x / ox). */
static double *boxes_of(const rk_contact *c, const double *x, const int *ids, int n, int size, int obstacle, rk_error *err)
{
    double *b = rk_calloc(6 * (size_t)n + 6, sizeof(double), err);
    for (int i = 0; b && i < n; i++) {
        for (int a = 0; a < 3; a++) b[6 * i + a] = INFINITY, b[6 * i + 3 + a] = -INFINITY;
        for (int k = 0; k < size; k++) {
            int id = ids[size * i + k];
            const double *p = obstacle ? &c->ox[3 * id] : &x[3 * id];
            for (int a = 0; a < 3; a++) {
                b[6 * i + a] = fmin(b[6 * i + a], p[a]);
                b[6 * i + 3 + a] = fmax(b[6 * i + 3 + a], p[a]);
            }
        }
    }
    return b;
}

/* Crossings of edges (ne, of x or ox) with triangles (nf, of x or ox): object-object pairs follow
 * the self-contact rule. */
static int count_crossings(const rk_contact *c, const double *x, const int *edges, int ne, int edges_obstacle,
                           const int *tris, int nf, int tris_obstacle, long *count, rk_error *err)
{
    double *eb = boxes_of(c, x, edges, ne, 2, edges_obstacle, err), *fb = boxes_of(c, x, tris, nf, 3, tris_obstacle, err);
    int mesh = !edges_obstacle && !tris_obstacle, *pairs = NULL, np = 0;
    int rc = !eb || !fb ? -1
             : mesh  ? rk_contact_object_broad_phase(c, eb, edges, 2, ne, fb, tris, 3, nf, &pairs, &np, err)
                     : rk_broad_phase(eb, ne, fb, nf, &pairs, &np, err);
    for (int p = 0; !rc && p < np; p++) {
        const int *e = &edges[2 * pairs[2 * p]], *t = &tris[3 * pairs[2 * p + 1]];
        if (mesh) {
            if (e[0] == t[0] || e[0] == t[1] || e[0] == t[2] || e[1] == t[0] || e[1] == t[1] || e[1] == t[2]) continue;
            if (c->object[e[0]] == c->object[t[0]] && !c->opt.self) continue;
        }
        const double *ex = edges_obstacle ? c->ox : x, *tx = tris_obstacle ? c->ox : x;
        *count += rk_segment_triangle_intersect(&ex[3 * e[0]], &ex[3 * e[1]], &tx[3 * t[0]], &tx[3 * t[1]], &tx[3 * t[2]]);
    }
    free(eb), free(fb), free(pairs);
    return rc;
}

int rk_contact_intersections(rk_contact *c, const double *x, rk_error *err)
{
    long count = 0;
    if ((c->mesh_pairs && count_crossings(c, x, c->edges, c->ne, 0, c->faces, c->nf, 0, &count, err)) ||
        count_crossings(c, x, c->edges, c->ne, 0, c->ofaces, c->onf, 1, &count, err) ||
        count_crossings(c, x, c->oedges, c->one, 1, c->faces, c->nf, 0, &count, err))
        return -1;
    /* points behind planes; surfaces within a sphere's or capsule's radius */
    for (int k = 0; k < c->nobstacles; k++)
        if (c->obstacles[k].kind == RK_OBSTACLE_PLANE)
            for (int i = 0; i < c->nv; i++) count += !(rk_contact_plane_distance(c, k, &x[3 * c->vertex[i]]) > 0);
    rk_contact_set near = {0};
    rk_motion_frame f = {x, NULL, c->ox, NULL};
    if (rk_contact_candidates(c, &f, 0, &near, err)) return -1;
    for (int i = 0; i < near.n; i++)
        if (near.pairs[i].xi > 0 && !(rk_contact_pair_distance2(c, &near.pairs[i], x, c->ox) > near.pairs[i].xi * near.pairs[i].xi))
            count++;
    rk_contact_set_free(&near);
    return count > 2147483647L ? 2147483647 : (int)count;
}

double rk_contact_min_distance(rk_contact *c, const double *x, rk_error *err)
{
    double closest = INFINITY, reach = fmax(c->opt.dhat, 1e-2 * c->bbox_diagonal);
    for (int k = 0; k < c->nobstacles; k++)
        if (c->obstacles[k].kind == RK_OBSTACLE_PLANE)
            for (int i = 0; i < c->nv; i++) closest = fmin(closest, rk_contact_plane_distance(c, k, &x[3 * c->vertex[i]]));
    double cached = rk_contact_cached_closest(c, x, reach);
    if (!isnan(cached)) return fmin(closest, cached);
    rk_contact_set near = {0};
    rk_motion_frame f = {x, NULL, c->ox, NULL};
    if (rk_contact_candidates(c, &f, reach, &near, err)) return NAN;
    for (int i = 0; i < near.n; i++)
        closest = fmin(closest, sqrt(rk_contact_pair_distance2(c, &near.pairs[i], x, c->ox)) - near.pairs[i].xi);
    rk_contact_set_free(&near);
    return closest;
}
