/* The outward offset of the simplified surface (cage_impl.h): how far the original rises above
 * it, and each simplified vertex moved out along its normal by that much and a margin. */
#include "cage/cage_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Unit normal of triangle f of c (zero when degenerate), times its double area in *area2. */
static void face_normal(const rk_surface *c, int f, double *n, double *area2)
{
    const double *a = c->X + 3 * (size_t)c->tris[3 * f], *b = c->X + 3 * (size_t)c->tris[3 * f + 1],
                 *d = c->X + 3 * (size_t)c->tris[3 * f + 2];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    *area2 = len;
    for (int i = 0; i < 3; i++) n[i] = len > 0 ? n[i] / len : 0;
}

int rk_cage_heights_measure(const rk_surface *c, const rk_surface *orig, rk_cage_heights *h, rk_error *err)
{
    memset(h, 0, sizeof *h);
    int *first = rk_calloc((size_t)c->nv + 1, sizeof(int), err), *list = rk_calloc(3 * (size_t)c->nf, sizeof(int), err);
    h->n = orig->nv;
    h->tri = rk_calloc((size_t)orig->nv + 1, sizeof(int), err);
    h->height = rk_calloc((size_t)orig->nv + 1, sizeof(double), err);
    double *ball = rk_calloc(4 * (size_t)c->nf, sizeof(double), err);
    if (!first || !list || !h->tri || !h->height || !ball) {
        free(ball);
        free(first);
        free(list);
        rk_cage_heights_free(h);
        return -1;
    }
    /* the triangles around each vertex of c */
    for (int k = 0; k < 3 * c->nf; k++) first[c->tris[k] + 1]++;
    for (int v = 0; v < c->nv; v++) first[v + 1] += first[v];
    for (int f = 0; f < c->nf; f++)
        for (int k = 0; k < 3; k++) list[first[c->tris[3 * f + k]]++] = f;
    for (int v = c->nv; v > 0; v--) first[v] = first[v - 1];
    first[0] = 0;
    for (int f = 0; f < c->nf; f++) { /* each triangle's centroid and the radius around it */
        double *o = ball + 4 * (size_t)f;
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 3; a++) o[a] += c->X[3 * (size_t)c->tris[3 * f + k] + a] / 3;
        for (int k = 0; k < 3; k++) {
            const double *x = c->X + 3 * (size_t)c->tris[3 * f + k];
            o[3] = fmax(o[3], sqrt((x[0] - o[0]) * (x[0] - o[0]) + (x[1] - o[1]) * (x[1] - o[1]) + (x[2] - o[2]) * (x[2] - o[2])));
        }
    }
    for (int i = 0; i < orig->nv; i++) {
        const double *p = orig->X + 3 * (size_t)i;
        /* the nearest vertex of c: every one (the cage has a few thousand; this is a fraction of
         * a second for a 43k-vertex scan) */
        double best = INFINITY;
        int nearest = 0;
        for (int v = 0; v < c->nv; v++) {
            const double *q = c->X + 3 * (size_t)v;
            double d = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
            if (d < best) best = d, nearest = v;
        }
        double closest = INFINITY;
        for (int k = first[nearest]; k < first[nearest + 1]; k++) {
            const int *t = c->tris + 3 * (size_t)list[k];
            double d2 = rk_cage_triangle_distance2(p, c->X + 3 * (size_t)t[0], c->X + 3 * (size_t)t[1], c->X + 3 * (size_t)t[2]);
            if (d2 < closest) closest = d2, h->tri[i] = list[k];
        }
        /* then every triangle that may be nearer (a big triangle's vertices can all be far from a
         * point just above its middle): bounding spheres skip most */
        for (int f = 0; f < c->nf; f++) {
            const double *o = ball + 4 * (size_t)f;
            double dc = sqrt((p[0] - o[0]) * (p[0] - o[0]) + (p[1] - o[1]) * (p[1] - o[1]) + (p[2] - o[2]) * (p[2] - o[2]));
            if (dc - o[3] > 0 && (dc - o[3]) * (dc - o[3]) >= closest) continue;
            const int *t = c->tris + 3 * (size_t)f;
            double d2 = rk_cage_triangle_distance2(p, c->X + 3 * (size_t)t[0], c->X + 3 * (size_t)t[1], c->X + 3 * (size_t)t[2]);
            if (d2 < closest) closest = d2, h->tri[i] = f;
        }
        double n[3], area2;
        face_normal(c, h->tri[i], n, &area2);
        const double *a = c->X + 3 * (size_t)c->tris[3 * h->tri[i]];
        h->height[i] = (p[0] - a[0]) * n[0] + (p[1] - a[1]) * n[1] + (p[2] - a[2]) * n[2];
    }
    free(ball);
    free(first);
    free(list);
    return 0;
}

void rk_cage_heights_free(rk_cage_heights *h)
{
    free(h->tri);
    free(h->height);
    memset(h, 0, sizeof *h);
}

/* n_v . n_f below this counts as this: a vertex whose normal is nearly in a face's plane would
 * otherwise be sent far out to lift that face */
#define MIN_COSINE 0.3
#define RK_CAGE_DILATE 2

int rk_cage_offset(const rk_surface *c, const rk_cage_heights *h, double margin, const double *extra, rk_surface *out,
                   double *max_offset, rk_error *err)
{
    memset(out, 0, sizeof *out);
    double *normal = rk_calloc(3 * (size_t)c->nv, sizeof(double), err);
    double *face = rk_calloc(3 * (size_t)(c->nf > c->nv ? c->nf : c->nv), sizeof(double), err);
    double *d = rk_calloc((size_t)c->nv, sizeof(double), err);
    out->X = rk_calloc(3 * (size_t)c->nv, sizeof(double), err);
    out->tris = rk_calloc(3 * (size_t)c->nf, sizeof(int), err);
    int rc = -1;
    if (!normal || !face || !d || !out->X || !out->tris) goto done;
    out->nv = c->nv;
    out->nf = c->nf;
    memcpy(out->tris, c->tris, 3 * sizeof(int) * (size_t)c->nf);
    for (int f = 0; f < c->nf; f++) {
        double area2;
        face_normal(c, f, face + 3 * (size_t)f, &area2);
        for (int k = 0; k < 3; k++)
            for (int i = 0; i < 3; i++) normal[3 * (size_t)c->tris[3 * f + k] + i] += area2 * face[3 * (size_t)f + i];
    }
    for (int v = 0; v < c->nv; v++) {
        double *n = normal + 3 * (size_t)v, len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int i = 0; i < 3; i++) n[i] = len > 0 ? n[i] / len : 0;
        d[v] = margin + (extra ? extra[v] : 0);
    }
    for (int i = 0; i < h->n; i++) {
        if (!(h->height[i] > 0)) continue;
        int f = h->tri[i];
        for (int k = 0; k < 3; k++) {
            int v = c->tris[3 * f + k];
            const double *n = normal + 3 * (size_t)v, *nf = face + 3 * (size_t)f;
            double cosine = fmax(MIN_COSINE, n[0] * nf[0] + n[1] * nf[1] + n[2] * nf[2]);
            d[v] = fmax(d[v], margin + (extra ? extra[v] : 0) + h->height[i] / cosine);
        }
    }
    /* each vertex takes the largest offset of its neighbours, RK_CAGE_DILATE times: neighbours
     * that move by very different amounts along diverging normals fold adjacent triangles into
     * each other (measured on spot.obj: TetGen found such folds at every simplification from 3332
     * triangles down), and a smoother offset only ever moves the cage further out */
    for (int pass = 0; pass < RK_CAGE_DILATE; pass++) {
        memcpy(face, d, sizeof(double) * (size_t)c->nv); /* (face normals no longer needed) */
        for (int f = 0; f < c->nf; f++)
            for (int k = 0; k < 3; k++)
                for (int j = 0; j < 3; j++) d[c->tris[3 * f + k]] = fmax(d[c->tris[3 * f + k]], face[c->tris[3 * f + j]]);
    }
    *max_offset = 0;
    for (int v = 0; v < c->nv; v++) {
        for (int i = 0; i < 3; i++) out->X[3 * (size_t)v + i] = c->X[3 * (size_t)v + i] + d[v] * normal[3 * (size_t)v + i];
        *max_offset = fmax(*max_offset, d[v]);
    }
    rc = 0;
done:
    free(normal);
    free(face);
    free(d);
    if (rc) rk_surface_free(out);
    return rc;
}
