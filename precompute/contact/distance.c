/* Unsigned distances between contact primitives (contact.h), as IPC takes them (Li et al. 2020,
 * Sec. 4.1): point-triangle and edge-edge, each reduced to the feature pair that is closest
 * (point-point, point-edge, point-plane of the triangle, line-line of the edges), squared, with
 * exact gradients and Hessians of that piece by automatic differentiation (ad_impl.h). */
#include "contact/contact.h"

#include <math.h>

#include "contact/ad_impl.h"

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void sub3(double *out, const double *a, const double *b)
{
    for (int i = 0; i < 3; i++) out[i] = a[i] - b[i];
}

/* |a x b|^2, from the cross product itself: a a . b b - (a . b)^2 loses every digit for nearly
 * parallel vectors, where this keeps them. */
static double cross2(const double *a, const double *b)
{
    double n[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    return dot3(n, n);
}

/* Point p against segment (a, b): which feature is closest, and the squared distance. */
static rk_distance_case point_segment_case(const double *p, const double *a, const double *b, int ip, int ia, int ib,
                                           double *d2)
{
    double e[3], w[3];
    sub3(e, b, a);
    sub3(w, p, a);
    double ee = dot3(e, e), u = ee > 0 ? dot3(w, e) / ee : 0;
    double x[3];
    if (u > 0 && u < 1) {
        for (int i = 0; i < 3; i++) x[i] = a[i] + u * e[i] - p[i];
        *d2 = dot3(x, x);
        return (rk_distance_case){.kind = RK_DIST_POINT_EDGE, .v = {ip, ia, ib, -1}};
    }
    sub3(x, p, u >= 1 ? b : a);
    *d2 = dot3(x, x);
    return (rk_distance_case){.kind = RK_DIST_POINT_POINT, .v = {ip, u >= 1 ? ib : ia, -1, -1}};
}

rk_distance_case rk_point_triangle_case(const double *const x[4])
{
    const double *p = x[0], *t0 = x[1], *t1 = x[2], *t2 = x[3];
    double e0[3], e1[3], w[3];
    sub3(e0, t1, t0);
    sub3(e1, t2, t0);
    sub3(w, p, t0);
    double a = dot3(e0, e0), b = dot3(e0, e1), c = dot3(e1, e1), r0 = dot3(e0, w), r1 = dot3(e1, w);
    double det = cross2(e0, e1); /* = a c - b^2, without its cancellation */
    if (det > 1e-20 * a * c) {
        double s = (c * r0 - b * r1) / det, t = (a * r1 - b * r0) / det;
        if (s > 0 && t > 0 && s + t < 1) return (rk_distance_case){.kind = RK_DIST_POINT_PLANE, .v = {0, 1, 2, 3}};
    }
    /* outside (or a degenerate triangle): the closest of the three edges */
    double d[3];
    rk_distance_case k[3] = {point_segment_case(p, t0, t1, 0, 1, 2, &d[0]), point_segment_case(p, t1, t2, 0, 2, 3, &d[1]),
                             point_segment_case(p, t2, t0, 0, 3, 1, &d[2])};
    int best = d[1] < d[0] ? 1 : 0;
    if (d[2] < d[best]) best = 2;
    return k[best];
}

rk_distance_case rk_edge_edge_case(const double *const x[4])
{
    const double *a0 = x[0], *a1 = x[1], *b0 = x[2], *b1 = x[3];
    double ea[3], eb[3], w[3];
    sub3(ea, a1, a0);
    sub3(eb, b1, b0);
    sub3(w, a0, b0);
    double a = dot3(ea, ea), b = dot3(ea, eb), c = dot3(eb, eb), d = dot3(ea, w), e = dot3(eb, w);
    double det = cross2(ea, eb); /* = a c - b^2, without its cancellation */
    if (det > 1e-20 * a * c) {
        double s = (b * e - c * d) / det, t = (a * e - b * d) / det;
        if (s > 0 && s < 1 && t > 0 && t < 1) return (rk_distance_case){.kind = RK_DIST_LINE_LINE, .v = {0, 1, 2, 3}};
    }
    /* the closest points lie on an end of one segment (parallel edges included): the closest of
     * the four endpoint-to-segment distances */
    double dd[4];
    rk_distance_case k[4] = {point_segment_case(a0, b0, b1, 0, 2, 3, &dd[0]), point_segment_case(a1, b0, b1, 1, 2, 3, &dd[1]),
                             point_segment_case(b0, a0, a1, 2, 0, 1, &dd[2]), point_segment_case(b1, a0, a1, 3, 0, 1, &dd[3])};
    int best = 0;
    for (int i = 1; i < 4; i++)
        if (dd[i] < dd[best]) best = i;
    return k[best];
}

/* The squared distance of case c over the stencil x (4 points, 12 variables; unused points
 * contribute zero derivatives). */
static void case_distance2(rk_distance_case c, const double *const x[4], rk_ad *out)
{
    rk_ad3 P[4], A, B, C;
    int n = 12;
    for (int k = 0; k < 4; k++) rk_ad3_point(&P[k], n, k, x[k]);
    const rk_ad3 *p = &P[c.v[0]], *q = &P[c.v[1]];
    switch (c.kind) {
    case RK_DIST_POINT_POINT:
        rk_ad3_sub(&A, p, q);
        rk_ad3_dot(out, &A, &A);
        return;
    case RK_DIST_POINT_EDGE: { /* |(q - p) x (r - p)|^2 / |r - q|^2 */
        const rk_ad3 *r = &P[c.v[2]];
        rk_ad num, den;
        rk_ad3_sub(&A, q, p);
        rk_ad3_sub(&B, r, p);
        rk_ad3_cross(&C, &A, &B);
        rk_ad3_dot(&num, &C, &C);
        rk_ad3_sub(&A, r, q);
        rk_ad3_dot(&den, &A, &A);
        rk_ad_div(out, &num, &den);
        return;
    }
    case RK_DIST_POINT_PLANE:
    case RK_DIST_LINE_LINE: { /* ((p - q) . n)^2 / |n|^2 with n = (r - q) x (s - q), or n = ea x eb */
        const rk_ad3 *r = &P[c.v[2]], *s = &P[c.v[3]];
        rk_ad f, f2, nn;
        if (c.kind == RK_DIST_POINT_PLANE) {
            rk_ad3_sub(&A, r, q);
            rk_ad3_sub(&B, s, q);
        } else {
            rk_ad3_sub(&A, q, p); /* ea = a1 - a0 */
            rk_ad3_sub(&B, s, r); /* eb = b1 - b0 */
        }
        rk_ad3_cross(&C, &A, &B);
        rk_ad3_sub(&A, p, c.kind == RK_DIST_POINT_PLANE ? q : r);
        rk_ad3_dot(&f, &A, &C);
        rk_ad_mul(&f2, &f, &f);
        rk_ad3_dot(&nn, &C, &C);
        rk_ad_div(out, &f2, &nn);
        return;
    }
    }
}

double rk_contact_distance2(rk_distance_case c, const double *const x[4], double *g, double *H)
{
    if (!g && !H) { /* the value alone, in plain arithmetic */
        const double *p = x[c.v[0]], *q = x[c.v[1]];
        double a[3], b[3], n[3];
        switch (c.kind) {
        case RK_DIST_POINT_POINT:
            sub3(a, p, q);
            return dot3(a, a);
        case RK_DIST_POINT_EDGE: {
            const double *r = x[c.v[2]];
            sub3(a, q, p);
            sub3(b, r, p);
            n[0] = a[1] * b[2] - a[2] * b[1], n[1] = a[2] * b[0] - a[0] * b[2], n[2] = a[0] * b[1] - a[1] * b[0];
            sub3(a, r, q);
            return dot3(n, n) / dot3(a, a);
        }
        default: {
            const double *r = x[c.v[2]], *s = x[c.v[3]];
            if (c.kind == RK_DIST_POINT_PLANE) sub3(a, r, q), sub3(b, s, q);
            else sub3(a, q, p), sub3(b, s, r);
            n[0] = a[1] * b[2] - a[2] * b[1], n[1] = a[2] * b[0] - a[0] * b[2], n[2] = a[0] * b[1] - a[1] * b[0];
            sub3(a, p, c.kind == RK_DIST_POINT_PLANE ? q : r);
            double f = dot3(a, n);
            return f * f / dot3(n, n);
        }
        }
    }
    rk_ad d;
    case_distance2(c, x, &d);
    if (g)
        for (int i = 0; i < 12; i++) g[i] = d.g[i];
    if (H)
        for (int i = 0; i < 144; i++) H[i] = d.h[i];
    return d.v;
}

/* The edge-edge mollifier (Li et al. 2020, Sec. 4.3): m = -x^2/eps^2 + 2x/eps for x < eps, else 1,
 * with x = |ea x eb|^2 and eps = 1e-3 |ea_rest|^2 |eb_rest|^2: the barrier of nearly parallel edges
 * fades out smoothly instead of jumping where the closest feature switches. */
double rk_edge_edge_mollifier(const double *const x[4], double eps, double *g, double *H)
{
    rk_ad3 P[4], A, B, C;
    rk_ad xx;
    for (int k = 0; k < 4; k++) rk_ad3_point(&P[k], 12, k, x[k]);
    rk_ad3_sub(&A, &P[1], &P[0]);
    rk_ad3_sub(&B, &P[3], &P[2]);
    rk_ad3_cross(&C, &A, &B);
    rk_ad3_dot(&xx, &C, &C);
    double v = xx.v;
    if (v >= eps) {
        if (g)
            for (int i = 0; i < 12; i++) g[i] = 0;
        if (H)
            for (int i = 0; i < 144; i++) H[i] = 0;
        return 1;
    }
    /* m(x) = (2 eps x - x^2) / eps^2: m' = 2 (eps - x) / eps^2, m'' = -2 / eps^2 */
    double m = (2 * eps * v - v * v) / (eps * eps), m1 = 2 * (eps - v) / (eps * eps), m2 = -2 / (eps * eps);
    if (g)
        for (int i = 0; i < 12; i++) g[i] = m1 * xx.g[i];
    if (H)
        for (int i = 0; i < 12; i++)
            for (int j = 0; j < 12; j++) H[12 * i + j] = m1 * xx.h[12 * i + j] + m2 * xx.g[i] * xx.g[j];
    return m;
}

/* The parameter in [0, 1] of the point of segment (a, b) closest to p. */
static double segment_parameter(const double *p, const double *a, const double *b)
{
    double e[3], w[3];
    sub3(e, b, a);
    sub3(w, p, a);
    double ee = dot3(e, e);
    return ee > 0 ? fmin(1, fmax(0, dot3(w, e) / ee)) : 0;
}

void rk_contact_closest_weights(rk_distance_case c, const double *const x[4], double w[4])
{
    w[0] = w[1] = w[2] = w[3] = 0;
    const int *v = c.v;
    switch (c.kind) {
    case RK_DIST_POINT_POINT:
        w[v[0]] = 1, w[v[1]] = -1;
        return;
    case RK_DIST_POINT_EDGE: {
        double u = segment_parameter(x[v[0]], x[v[1]], x[v[2]]);
        w[v[0]] = 1, w[v[1]] = -(1 - u), w[v[2]] = -u;
        return;
    }
    case RK_DIST_POINT_PLANE: { /* barycentric coordinates of the projection */
        double e0[3], e1[3], r[3];
        sub3(e0, x[v[2]], x[v[1]]);
        sub3(e1, x[v[3]], x[v[1]]);
        sub3(r, x[v[0]], x[v[1]]);
        double a = dot3(e0, e0), b = dot3(e0, e1), cc = dot3(e1, e1), r0 = dot3(e0, r), r1 = dot3(e1, r);
        double det = cross2(e0, e1), s = (cc * r0 - b * r1) / det, t = (a * r1 - b * r0) / det;
        w[v[0]] = 1, w[v[1]] = -(1 - s - t), w[v[2]] = -s, w[v[3]] = -t;
        return;
    }
    case RK_DIST_LINE_LINE: {
        double ea[3], eb[3], r[3];
        sub3(ea, x[v[1]], x[v[0]]);
        sub3(eb, x[v[3]], x[v[2]]);
        sub3(r, x[v[0]], x[v[2]]);
        double a = dot3(ea, ea), b = dot3(ea, eb), cc = dot3(eb, eb), d = dot3(ea, r), e = dot3(eb, r);
        double det = cross2(ea, eb), s = (b * e - cc * d) / det, t = (a * e - b * d) / det;
        w[v[0]] = 1 - s, w[v[1]] = s, w[v[2]] = -(1 - t), w[v[3]] = -t;
        return;
    }
    }
}
