/* Several objects in one asset (ROMBIN.md "Object chunks", 1.5): the object of each collision
 * vertex (COBJ) and each object's proxy radius rho (CRAD). The runtime keeps every pair of
 * collision vertices of different objects a and b at |x_i - x_j| > rho_a + rho_b
 * (runtime/objects.c). rho_a is the largest distance from any point of object a's boundary
 * triangles (the contact stage's surface: a mesh's boundary, a point cloud's voxel proxy) to the
 * nearest corner of its triangle, at rest: the spheres of radius rho_a at a's collision vertices
 * then cover a's whole surface, so a vertex of b kept outside them never reaches that surface. */
#include "asset/bake_impl.h"

#include <math.h>
#include <stdlib.h>

static double dist(const double *p, const double *q)
{
    return sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
}

/* The distance from p to the nearest of the corners v[0..2]. */
static double nearest_corner(const double *p, const double *const v[3])
{
    return fmin(dist(p, v[0]), fmin(dist(p, v[1]), dist(p, v[2])));
}

/* max over the triangle's points p of min_k |p - v_k|, exactly: the corners' Voronoi cells cut the
 * triangle into convex polygons, and on each the distance to its corner is convex, so the maximum
 * sits at a polygon vertex: where a bisector of two corners crosses an edge, or the circumcentre
 * when it lies inside (a corner itself gives 0). */
double rk_triangle_cover_radius(const double *const v[3])
{
    double best = 0;
    for (int e = 0; e < 3; e++) { /* edge v[e] -> v[e1]; bisectors of (v[e], v[c]) and (v[e1], v[c]) */
        const double *a = v[e], *b = v[(e + 1) % 3], *c = v[(e + 2) % 3];
        for (int k = 0; k < 3; k++) {
            /* p = a + t (b - a) equidistant from the pair (s, u): |p - s|^2 = |p - u|^2 is linear in t */
            const double *s = k == 0 ? a : k == 1 ? a : b, *u = k == 0 ? b : c;
            double A = 0, B = 0;
            for (int i = 0; i < 3; i++) {
                double d = b[i] - a[i];
                A += 2 * d * (u[i] - s[i]);
                B += (u[i] * u[i] - s[i] * s[i]) - 2 * a[i] * (u[i] - s[i]);
            }
            if (!(fabs(A) > 0)) continue;
            double t = B / A, p[3];
            if (!(t >= 0 && t <= 1)) continue;
            for (int i = 0; i < 3; i++) p[i] = a[i] + t * (b[i] - a[i]);
            best = fmax(best, nearest_corner(p, v));
        }
    }
    /* the circumcentre: v0 + alpha e1 + beta e2 with (e_i . (p - v0)) = |e_i|^2 / 2 */
    double e1[3], e2[3], a11 = 0, a12 = 0, a22 = 0;
    for (int i = 0; i < 3; i++) {
        e1[i] = v[1][i] - v[0][i], e2[i] = v[2][i] - v[0][i];
        a11 += e1[i] * e1[i], a12 += e1[i] * e2[i], a22 += e2[i] * e2[i];
    }
    double det = a11 * a22 - a12 * a12;
    if (det > 1e-30 * a11 * a22) {
        double al = (0.5 * a11 * a22 - 0.5 * a22 * a12) / det, be = (0.5 * a22 * a11 - 0.5 * a11 * a12) / det;
        if (al >= 0 && be >= 0 && al + be <= 1) {
            double p[3];
            for (int i = 0; i < 3; i++) p[i] = v[0][i] + al * e1[i] + be * e2[i];
            best = fmax(best, nearest_corner(p, v));
        }
    }
    return best;
}

int rk_bake_objects(const rk_rom_model *m, int ncv, rombin_writer *w, rk_error *err)
{
    if (!m->has_contact || ncv == 0) return 0;
    const rk_contact *c = &m->contact;
    int K = 0;
    for (int i = 0; i < c->nv; i++) K = c->object[c->vertex[i]] + 1 > K ? c->object[c->vertex[i]] + 1 : K;
    if (K < 2) return 0; /* one object: the planes and colliders only */
    if (ncv != c->nv || ncv != m->ncv) return rk_fail(err, "COBJ: %d collision vertices, the contact stage has %d", ncv, c->nv);
    int *obj = rk_calloc((size_t)ncv, sizeof(int), err);
    double *rho = rk_calloc((size_t)K, sizeof(double), err);
    int rc = -1;
    if (obj && rho) {
        for (int i = 0; i < ncv; i++) obj[i] = c->object[m->cv[i]];
        for (int f = 0; f < c->nf; f++) {
            const int *F = c->faces + 3 * (size_t)f;
            const double *v[3] = {c->X + 3 * (size_t)F[0], c->X + 3 * (size_t)F[1], c->X + 3 * (size_t)F[2]};
            int k = c->object[F[0]];
            rho[k] = fmax(rho[k], rk_triangle_cover_radius(v));
        }
        rc = 0;
        for (int k = 0; k < K && !rc; k++)
            if (!(rho[k] > 0)) rc = rk_fail(err, "object %d has no boundary triangle to size its contact proxy by", k);
        if (!rc)
            rc = rk_bake_add_u32s(w, ROMBIN_COBJ, 1, obj, (size_t)ncv, err) || rombin_add_reals(w, ROMBIN_CRAD, 1, rho, (size_t)K, err)
                     ? -1
                     : 0;
    }
    free(obj);
    free(rho);
    return rc;
}
