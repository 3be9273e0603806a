/* Contact distances (precompute/contact): squared point-triangle and edge-edge distances against an
 * independent closest-point construction (Ericson, Real-Time Collision Detection, 5.1.5 and 5.1.9),
 * their gradients and Hessians against central differences in every feature case, the mollifier,
 * and the degenerate stencils (a point on the triangle, parallel and crossing edges). */
#include "contact/contact.h"
#include "testlib.h"
#include "util/util.h"

static uint64_t seed = 42;
static double rnd(void) { return 2 * rk_uniform(&seed) - 1; }

static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void sub(double *o, const double *a, const double *b)
{
    for (int i = 0; i < 3; i++) o[i] = a[i] - b[i];
}
static double dist2(const double *a, const double *b)
{
    double d[3];
    sub(d, a, b);
    return dot(d, d);
}
static double clamp01(double x) { return x < 0 ? 0 : x > 1 ? 1 : x; }

/* Ericson 5.1.5: the closest point of triangle abc to p, by Voronoi regions. */
static void closest_on_triangle(const double *p, const double *a, const double *b, const double *c, double *q)
{
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    sub(ab, b, a), sub(ac, c, a), sub(ap, p, a);
    double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) { memcpy(q, a, 3 * sizeof(double)); return; }
    sub(bp, p, b);
    double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) { memcpy(q, b, 3 * sizeof(double)); return; }
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        double v = d1 / (d1 - d3);
        for (int i = 0; i < 3; i++) q[i] = a[i] + v * ab[i];
        return;
    }
    sub(cp, p, c);
    double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) { memcpy(q, c, 3 * sizeof(double)); return; }
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        double w = d2 / (d2 - d6);
        for (int i = 0; i < 3; i++) q[i] = a[i] + w * ac[i];
        return;
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int i = 0; i < 3; i++) q[i] = b[i] + w * (c[i] - b[i]);
        return;
    }
    double den = 1 / (va + vb + vc), v = vb * den, w = vc * den;
    for (int i = 0; i < 3; i++) q[i] = a[i] + ab[i] * v + ac[i] * w;
}

/* Ericson 5.1.9: the squared distance between segments p1 q1 and p2 q2. */
static double segment_segment(const double *p1, const double *q1, const double *p2, const double *q2)
{
    double d1[3], d2[3], r[3], s, t;
    sub(d1, q1, p1), sub(d2, q2, p2), sub(r, p1, p2);
    double a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r), c = dot(d1, r), b = dot(d1, d2), den = a * e - b * b;
    s = den > 1e-300 ? clamp01((b * f - c * e) / den) : 0;
    t = (b * s + f) / e;
    if (t < 0) t = 0, s = clamp01(-c / a);
    else if (t > 1) t = 1, s = clamp01((b - c) / a);
    double x[3], y[3];
    for (int i = 0; i < 3; i++) x[i] = p1[i] + d1[i] * s, y[i] = p2[i] + d2[i] * t;
    return dist2(x, y);
}

static void random_point(double *p, double scale)
{
    for (int i = 0; i < 3; i++) p[i] = scale * rnd();
}

TEST(point_triangle_distance_matches_the_closest_point)
{
    int counts[4] = {0};
    double worst = 0;
    for (int k = 0; k < 4000; k++) {
        double P[4][3];
        for (int j = 0; j < 4; j++) random_point(P[j], 1.0);
        const double *x[4] = {P[0], P[1], P[2], P[3]};
        rk_distance_case c = rk_point_triangle_case(x);
        counts[c.kind]++;
        double d2 = rk_contact_distance2(c, x, NULL, NULL), q[3];
        closest_on_triangle(P[0], P[1], P[2], P[3], q);
        double ref = dist2(P[0], q);
        worst = fmax(worst, fabs(d2 - ref) / fmax(ref, 1e-3));
    }
    printf("# point-triangle: %d point-point, %d point-edge, %d point-plane cases; worst relative error %.2e\n",
           counts[0], counts[1], counts[2], worst);
    CHECK(counts[0] && counts[1] && counts[2] && !counts[3], "cases %d %d %d %d", counts[0], counts[1], counts[2], counts[3]);
    CHECK(worst < 1e-12, "worst relative error %g", worst);
}

TEST(edge_edge_distance_matches_the_closest_points)
{
    int counts[4] = {0};
    double worst = 0;
    for (int k = 0; k < 4000; k++) {
        double P[4][3];
        for (int j = 0; j < 4; j++) random_point(P[j], 1.0);
        const double *x[4] = {P[0], P[1], P[2], P[3]};
        rk_distance_case c = rk_edge_edge_case(x);
        counts[c.kind]++;
        double d2 = rk_contact_distance2(c, x, NULL, NULL), ref = segment_segment(P[0], P[1], P[2], P[3]);
        worst = fmax(worst, fabs(d2 - ref) / fmax(ref, 1e-3));
    }
    printf("# edge-edge: %d point-point, %d point-edge, %d line-line cases; worst relative error %.2e\n", counts[0],
           counts[1], counts[3], worst);
    CHECK(counts[0] && counts[1] && counts[3] && !counts[2], "cases %d %d %d %d", counts[0], counts[1], counts[2], counts[3]);
    CHECK(worst < 1e-10, "worst relative error %g", worst);
}

/* Central differences of the squared distance (same case throughout) and of its gradient. */
static double derivative_error(rk_distance_case c, double P[4][3], int mollifier)
{
    const double *x[4] = {P[0], P[1], P[2], P[3]};
    double g[12], H[144], worst = 0, eps = 1e-3;
    double v = mollifier ? rk_edge_edge_mollifier(x, eps, g, H) : rk_contact_distance2(c, x, g, H);
    double scale = fabs(v) + 1e-12;
    for (int k = 0; k < 12; k++) {
        double *coord = &P[k / 3][k % 3], keep = *coord, h = 1e-6;
        double gp[12], gm[12];
        *coord = keep + h;
        double vp = mollifier ? rk_edge_edge_mollifier(x, eps, gp, NULL) : rk_contact_distance2(c, x, gp, NULL);
        *coord = keep - h;
        double vm = mollifier ? rk_edge_edge_mollifier(x, eps, gm, NULL) : rk_contact_distance2(c, x, gm, NULL);
        *coord = keep;
        worst = fmax(worst, fabs((vp - vm) / (2 * h) - g[k]) / (scale + fabs(g[k])));
        for (int j = 0; j < 12; j++)
            worst = fmax(worst, fabs((gp[j] - gm[j]) / (2 * h) - H[12 * j + k]) / (scale + fabs(H[12 * j + k]) + 1));
    }
    return worst;
}

TEST(gradients_and_hessians_match_finite_differences_in_every_case)
{
    double worst[4] = {0};
    int tried[4] = {0};
    for (int k = 0; k < 400; k++) {
        double P[4][3];
        for (int j = 0; j < 4; j++) random_point(P[j], 1.0);
        const double *x[4] = {P[0], P[1], P[2], P[3]};
        rk_distance_case c = k % 2 ? rk_point_triangle_case(x) : rk_edge_edge_case(x);
        worst[c.kind] = fmax(worst[c.kind], derivative_error(c, P, 0));
        tried[c.kind]++;
    }
    printf("# finite differences: point-point %.1e, point-edge %.1e, point-plane %.1e, line-line %.1e\n", worst[0],
           worst[1], worst[2], worst[3]);
    for (int c = 0; c < 4; c++) CHECK(tried[c] > 0 && worst[c] < 1e-6, "case %d: %d tried, worst %g", c, tried[c], worst[c]);
}

TEST(the_mollifier_fades_parallel_edges_smoothly)
{
    /* two nearly parallel edges: |ea x eb|^2 below eps, so the mollifier is active */
    double P[4][3] = {{0, 0, 0}, {1, 0, 0}, {0.2, 0.1, 0.01}, {1.1, 0.1, 0.02}};
    const double *x[4] = {P[0], P[1], P[2], P[3]};
    double m = rk_edge_edge_mollifier(x, 1e-3, NULL, NULL);
    CHECK(m > 0 && m < 1, "mollifier %g", m);
    double err = derivative_error((rk_distance_case){RK_DIST_LINE_LINE, {0, 1, 2, 3}}, P, 1);
    CHECK(err < 1e-6, "mollifier derivatives off by %g", err);
    double Q[4][3] = {{0, 0, 0}, {1, 0, 0}, {0.5, -1, 0.3}, {0.5, 1, 0.3}}; /* crossing: no mollification */
    const double *y[4] = {Q[0], Q[1], Q[2], Q[3]};
    CHECK(rk_edge_edge_mollifier(y, 1e-3, NULL, NULL) == 1, "crossing edges mollified");
    /* exactly parallel edges at distance 0.1: distance by the endpoints, finite */
    double R[4][3] = {{0, 0, 0}, {1, 0, 0}, {0.5, 0.1, 0}, {1.5, 0.1, 0}};
    const double *z[4] = {R[0], R[1], R[2], R[3]};
    rk_distance_case c = rk_edge_edge_case(z);
    double d2 = rk_contact_distance2(c, z, NULL, NULL);
    CHECK(c.kind != RK_DIST_LINE_LINE && fabs(d2 - 0.01) < 1e-15, "parallel edges: case %d, d^2 %.17g", c.kind, d2);
}

/* Distance from p to segment (a, b), directly. */
static double point_segment_distance(const double *p, const double *a, const double *b)
{
    double ab[3], ap[3], t = 0, n = 0, d = 0;
    for (int k = 0; k < 3; k++) ab[k] = b[k] - a[k], ap[k] = p[k] - a[k], t += ab[k] * ap[k], n += ab[k] * ab[k];
    t = fmax(0, fmin(1, t / n));
    for (int k = 0; k < 3; k++) d += (a[k] + t * ab[k] - p[k]) * (a[k] + t * ab[k] - p[k]);
    return sqrt(d);
}

TEST(parallel_edges_in_any_orientation_keep_their_distance)
{
    /* Coplanar edges, parallel or within 1e-6 rad of it, 0.1 to 10 mm apart, turned to a random
     * orientation so that rounding touches every coordinate (the faces of a coiled rod). They do
     * not cross, so the distance is the least of the four endpoint-to-segment distances. With
     * |ea x eb|^2 taken as a c - b^2, rounding left a positive noise that picked the line-line
     * case, where coplanar lines meet: distances up to 55 times too small. */
    uint64_t rng = 7;
    double worst = 0;
    for (int it = 0; it < 20000; it++) {
        double L = 0.01 + 0.09 * rk_uniform(&rng), gap = pow(10, -4 + 2 * rk_uniform(&rng));
        double th = rk_uniform(&rng) < 0.3 ? 0 : pow(10, -16 + 10 * rk_uniform(&rng));
        double shift = L * (rk_uniform(&rng) - 0.5), az = 6.283 * rk_uniform(&rng), ax = 6.283 * rk_uniform(&rng);
        double o[3] = {rk_uniform(&rng), rk_uniform(&rng), rk_uniform(&rng)};
        double local[4][3] = {{0, 0, 0}, {L, 0, 0}, {shift, gap, 0}, {shift + L * cos(th), gap + L * sin(th), 0}};
        double P[4][3];
        for (int q = 0; q < 4; q++) {
            double X = cos(az) * local[q][0] - sin(az) * local[q][1], Y = sin(az) * local[q][0] + cos(az) * local[q][1];
            P[q][0] = o[0] + X;
            P[q][1] = o[1] + cos(ax) * Y - sin(ax) * local[q][2];
            P[q][2] = o[2] + sin(ax) * Y + cos(ax) * local[q][2];
        }
        const double *x[4] = {P[0], P[1], P[2], P[3]};
        double d = sqrt(rk_contact_distance2(rk_edge_edge_case(x), x, NULL, NULL));
        double ref = fmin(fmin(point_segment_distance(P[0], P[2], P[3]), point_segment_distance(P[1], P[2], P[3])),
                          fmin(point_segment_distance(P[2], P[0], P[1]), point_segment_distance(P[3], P[0], P[1])));
        worst = fmax(worst, fabs(d - ref) / ref);
    }
    printf("# nearly parallel coplanar edges, 20000 orientations: worst relative distance error %.2g\n", worst);
    CHECK(worst < 1e-9, "worst relative error %g", worst);
}

TEST(degenerate_stencils_have_exact_distances)
{
    double T[4][3] = {{0.25, 0.25, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const double *x[4] = {T[0], T[1], T[2], T[3]};
    rk_distance_case c = rk_point_triangle_case(x);
    CHECK(c.kind == RK_DIST_POINT_PLANE && rk_contact_distance2(c, x, NULL, NULL) == 0, "point on the triangle");
    memcpy(T[0], T[2], sizeof T[0]); /* the point on a vertex */
    c = rk_point_triangle_case(x);
    CHECK(rk_contact_distance2(c, x, NULL, NULL) == 0, "point on a vertex: %g", rk_contact_distance2(c, x, NULL, NULL));
    double E[4][3] = {{0, 0, 0}, {1, 0, 0}, {0.5, -1, 0}, {0.5, 1, 0}}; /* crossing edges */
    const double *y[4] = {E[0], E[1], E[2], E[3]};
    c = rk_edge_edge_case(y);
    CHECK(c.kind == RK_DIST_LINE_LINE && rk_contact_distance2(c, y, NULL, NULL) == 0, "crossing edges: %g",
          rk_contact_distance2(c, y, NULL, NULL));
}

int main(void)
{
    RUN(point_triangle_distance_matches_the_closest_point);
    RUN(edge_edge_distance_matches_the_closest_points);
    RUN(gradients_and_hessians_match_finite_differences_in_every_case);
    RUN(the_mollifier_fades_parallel_edges_smoothly);
    RUN(parallel_edges_in_any_orientation_keep_their_distance);
    RUN(degenerate_stencils_have_exact_distances);
    return test_finish();
}
