/* Tet and surface measures shared by the checks, the box and the tests. */
#include <math.h>

#include "mesh/mesh.h"

static void sub(const double *a, const double *b, double *out)
{
    for (int k = 0; k < 3; k++) out[k] = a[k] - b[k];
}

static void cross(const double *u, const double *v, double *out)
{
    out[0] = u[1] * v[2] - u[2] * v[1];
    out[1] = u[2] * v[0] - u[0] * v[2];
    out[2] = u[0] * v[1] - u[1] * v[0];
}

static double dot(const double *u, const double *v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; }

static double dist(const double *a, const double *b)
{
    double d[3];
    sub(a, b, d);
    return sqrt(dot(d, d));
}

static double triangle_area(const double *a, const double *b, const double *c)
{
    double u[3], v[3], n[3];
    sub(b, a, u);
    sub(c, a, v);
    cross(u, v, n);
    return 0.5 * sqrt(dot(n, n));
}

double rk_tet_signed_volume(const double *a, const double *b, const double *c, const double *d)
{
    double u[3], v[3], w[3], n[3];
    sub(b, a, u);
    sub(c, a, v);
    sub(d, a, w);
    cross(v, w, n);
    return dot(u, n) / 6.0;
}

double rk_tet_radius_ratio(const double *a, const double *b, const double *c, const double *d)
{
    double vol = fabs(rk_tet_signed_volume(a, b, c, d));
    double area = triangle_area(b, c, d) + triangle_area(a, c, d) + triangle_area(a, b, d) + triangle_area(a, b, c);
    if (!(vol > 0) || !(area > 0)) return 0;
    double r_in = 3 * vol / area;
    /* Circumradius from the products of opposite edge lengths:
     * 24 V R = sqrt((p+q+s)(p+q-s)(p-q+s)(-p+q+s)). */
    double p = dist(a, b) * dist(c, d), q = dist(a, c) * dist(b, d), s = dist(a, d) * dist(b, c);
    double h = (p + q + s) * (p + q - s) * (p - q + s) * (-p + q + s);
    if (!(h > 0)) return 0;
    double r_out = sqrt(h) / (24 * vol);
    double ratio = 3 * r_in / r_out;
    return ratio > 1 ? 1 : ratio; /* rounding on a regular tet */
}

double rk_surface_volume(const rk_surface *s)
{
    /* Sum of the tets (o, face): measured from a vertex, not the origin, for precision. */
    double vol = 0;
    if (s->nv <= 0) return 0;
    const double *o = s->X;
    for (int f = 0; f < s->nf; f++) {
        const int *t = s->tris + 3 * (size_t)f;
        vol += rk_tet_signed_volume(o, s->X + 3 * (size_t)t[0], s->X + 3 * (size_t)t[1], s->X + 3 * (size_t)t[2]);
    }
    return vol;
}

void rk_mesh_transform(rk_mesh *m, double scale, const double translate[3])
{
    for (int i = 0; i < m->nv; i++)
        for (int k = 0; k < 3; k++) m->X[3 * (size_t)i + k] = scale * m->X[3 * (size_t)i + k] + translate[k];
}
