/* contact_impl.h: the per-stencil math of incremental potential contact (IPC, Li et al. 2020),
 * written once for the precompute (precompute/contact, double) and the runtime; included by
 * physics_impl.h after collider_impl.h (same rules: C99, both precisions, no include guard, its
 * macros). A stencil is four points x[0..3]: a point x[0] and a triangle x[1..3], or an edge
 * x[0] x[1] and an edge x[2] x[3]; a thickness xi keeps it apart by xi (0 between meshes, the
 * radius of a sphere or capsule obstacle).
 *
 *   distances   unsigned, as IPC takes them (Sec. 4.1): each stencil reduced to its closest
 *               feature pair (point-point, point-edge, point-plane, line-line), squared, with
 *               exact gradients and Hessians of that piece by automatic differentiation
 *               (contact_ad_impl.h); the edge-edge mollifier of nearly parallel edges (Sec. 4.3)
 *   barrier     one pair's b(d^2 - xi^2, dhat^2 + 2 xi dhat) times the mollifier, and the PSD
 *               projection of its Hessian on the points that are unknowns
 *   CCD         additive CCD of one stencil (Li, Kaufman and Jiang 2021, "Codimensional
 *               Incremental Potential Contact", Sec. 4.1, Alg. 1) */

#include "physics/contact_ad_impl.h"

/* s in Alg. 1: each advance covers this fraction of the distance bound, and the advance stops
 * once the gap falls below 1 - s of the start's. */
#define PHYS_CCD_RESCALING_ PHYS_K_(0.9)
/* More advances than this means the stencil is grinding along at a tiny gap: report an impact
 * at the time reached, which stays conservative. */
#define PHYS_CCD_MAX_ADVANCES_ 100000

static void PHYS_FN(sub3_)(PHYS_REAL *out, const PHYS_REAL *a, const PHYS_REAL *b)
{
    int i;
    for (i = 0; i < 3; i++) out[i] = a[i] - b[i];
}

/* |a x b|^2, from the cross product itself: a a . b b - (a . b)^2 loses every digit for nearly
 * parallel vectors, where this keeps them. */
static PHYS_REAL PHYS_FN(cross2_)(const PHYS_REAL *a, const PHYS_REAL *b)
{
    PHYS_REAL n[3];
    n[0] = a[1] * b[2] - a[2] * b[1];
    n[1] = a[2] * b[0] - a[0] * b[2];
    n[2] = a[0] * b[1] - a[1] * b[0];
    return PHYS_FN(dot3_)(n, n);
}

static rk_distance_case PHYS_FN(distance_case_)(rk_distance_kind kind, int v0, int v1, int v2, int v3)
{
    rk_distance_case c;
    c.kind = kind;
    c.v[0] = v0, c.v[1] = v1, c.v[2] = v2, c.v[3] = v3;
    return c;
}

/* Point p against segment (a, b): which feature is closest, and the squared distance. */
static rk_distance_case PHYS_FN(point_segment_case_)(const PHYS_REAL *p, const PHYS_REAL *a, const PHYS_REAL *b,
                                                     int ip, int ia, int ib, PHYS_REAL *d2)
{
    PHYS_REAL e[3], w[3], x[3], ee, u;
    int i;
    PHYS_FN(sub3_)(e, b, a);
    PHYS_FN(sub3_)(w, p, a);
    ee = PHYS_FN(dot3_)(e, e);
    u = ee > 0 ? PHYS_FN(dot3_)(w, e) / ee : 0;
    if (u > 0 && u < 1) {
        for (i = 0; i < 3; i++) x[i] = a[i] + u * e[i] - p[i];
        *d2 = PHYS_FN(dot3_)(x, x);
        return PHYS_FN(distance_case_)(RK_DIST_POINT_EDGE, ip, ia, ib, -1);
    }
    PHYS_FN(sub3_)(x, p, u >= 1 ? b : a);
    *d2 = PHYS_FN(dot3_)(x, x);
    return PHYS_FN(distance_case_)(RK_DIST_POINT_POINT, ip, u >= 1 ? ib : ia, -1, -1);
}

PHYS_API rk_distance_case PHYS_FN(point_triangle_case)(const PHYS_REAL *const x[4])
{
    const PHYS_REAL *p = x[0], *t0 = x[1], *t1 = x[2], *t2 = x[3];
    PHYS_REAL e0[3], e1[3], w[3], a, b, c, r0, r1, det, d[3];
    rk_distance_case k[3];
    int best;
    PHYS_FN(sub3_)(e0, t1, t0);
    PHYS_FN(sub3_)(e1, t2, t0);
    PHYS_FN(sub3_)(w, p, t0);
    a = PHYS_FN(dot3_)(e0, e0), b = PHYS_FN(dot3_)(e0, e1), c = PHYS_FN(dot3_)(e1, e1);
    r0 = PHYS_FN(dot3_)(e0, w), r1 = PHYS_FN(dot3_)(e1, w);
    det = PHYS_FN(cross2_)(e0, e1); /* = a c - b^2, without its cancellation */
    if (det > PHYS_K_(1e-20) * a * c) {
        PHYS_REAL s = (c * r0 - b * r1) / det, t = (a * r1 - b * r0) / det;
        if (s > 0 && t > 0 && s + t < 1) return PHYS_FN(distance_case_)(RK_DIST_POINT_PLANE, 0, 1, 2, 3);
    }
    /* outside (or a degenerate triangle): the closest of the three edges */
    k[0] = PHYS_FN(point_segment_case_)(p, t0, t1, 0, 1, 2, &d[0]);
    k[1] = PHYS_FN(point_segment_case_)(p, t1, t2, 0, 2, 3, &d[1]);
    k[2] = PHYS_FN(point_segment_case_)(p, t2, t0, 0, 3, 1, &d[2]);
    best = d[1] < d[0] ? 1 : 0;
    if (d[2] < d[best]) best = 2;
    return k[best];
}

PHYS_API rk_distance_case PHYS_FN(edge_edge_case)(const PHYS_REAL *const x[4])
{
    const PHYS_REAL *a0 = x[0], *a1 = x[1], *b0 = x[2], *b1 = x[3];
    PHYS_REAL ea[3], eb[3], w[3], a, b, c, d, e, det, dd[4];
    rk_distance_case k[4];
    int best, i;
    PHYS_FN(sub3_)(ea, a1, a0);
    PHYS_FN(sub3_)(eb, b1, b0);
    PHYS_FN(sub3_)(w, a0, b0);
    a = PHYS_FN(dot3_)(ea, ea), b = PHYS_FN(dot3_)(ea, eb), c = PHYS_FN(dot3_)(eb, eb);
    d = PHYS_FN(dot3_)(ea, w), e = PHYS_FN(dot3_)(eb, w);
    det = PHYS_FN(cross2_)(ea, eb); /* = a c - b^2, without its cancellation */
    if (det > PHYS_K_(1e-20) * a * c) {
        PHYS_REAL s = (b * e - c * d) / det, t = (a * e - b * d) / det;
        if (s > 0 && s < 1 && t > 0 && t < 1) return PHYS_FN(distance_case_)(RK_DIST_LINE_LINE, 0, 1, 2, 3);
    }
    /* the closest points lie on an end of one segment (parallel edges included): the closest of
     * the four endpoint-to-segment distances */
    k[0] = PHYS_FN(point_segment_case_)(a0, b0, b1, 0, 2, 3, &dd[0]);
    k[1] = PHYS_FN(point_segment_case_)(a1, b0, b1, 1, 2, 3, &dd[1]);
    k[2] = PHYS_FN(point_segment_case_)(b0, a0, a1, 2, 0, 1, &dd[2]);
    k[3] = PHYS_FN(point_segment_case_)(b1, a0, a1, 3, 0, 1, &dd[3]);
    best = 0;
    for (i = 1; i < 4; i++)
        if (dd[i] < dd[best]) best = i;
    return k[best];
}

/* The squared distance of case c over the stencil x (4 points, 12 variables; unused points
 * contribute zero derivatives). */
static void PHYS_FN(case_distance2_)(rk_distance_case c, const PHYS_REAL *const x[4], PHYS_FN(ad_) *out)
{
    PHYS_FN(ad3_) P[4], A, B, C;
    const PHYS_FN(ad3_) *p, *q, *r, *s;
    PHYS_FN(ad_) num, den, f, f2;
    int k;
    for (k = 0; k < 4; k++) PHYS_FN(ad3_point_)(&P[k], 12, k, x[k]);
    p = &P[c.v[0]], q = &P[c.v[1]];
    switch (c.kind) {
    case RK_DIST_POINT_POINT:
        PHYS_FN(ad3_sub_)(&A, p, q);
        PHYS_FN(ad3_dot_)(out, &A, &A);
        return;
    case RK_DIST_POINT_EDGE: /* |(q - p) x (r - p)|^2 / |r - q|^2 */
        r = &P[c.v[2]];
        PHYS_FN(ad3_sub_)(&A, q, p);
        PHYS_FN(ad3_sub_)(&B, r, p);
        PHYS_FN(ad3_cross_)(&C, &A, &B);
        PHYS_FN(ad3_dot_)(&num, &C, &C);
        PHYS_FN(ad3_sub_)(&A, r, q);
        PHYS_FN(ad3_dot_)(&den, &A, &A);
        PHYS_FN(ad_div_)(out, &num, &den);
        return;
    case RK_DIST_POINT_PLANE:
    case RK_DIST_LINE_LINE: /* ((p - q) . n)^2 / |n|^2 with n = (r - q) x (s - q), or n = ea x eb */
        r = &P[c.v[2]], s = &P[c.v[3]];
        if (c.kind == RK_DIST_POINT_PLANE) {
            PHYS_FN(ad3_sub_)(&A, r, q);
            PHYS_FN(ad3_sub_)(&B, s, q);
        } else {
            PHYS_FN(ad3_sub_)(&A, q, p); /* ea = a1 - a0 */
            PHYS_FN(ad3_sub_)(&B, s, r); /* eb = b1 - b0 */
        }
        PHYS_FN(ad3_cross_)(&C, &A, &B);
        PHYS_FN(ad3_sub_)(&A, p, c.kind == RK_DIST_POINT_PLANE ? q : r);
        PHYS_FN(ad3_dot_)(&f, &A, &C);
        PHYS_FN(ad_mul_)(&f2, &f, &f);
        PHYS_FN(ad3_dot_)(&den, &C, &C);
        PHYS_FN(ad_div_)(out, &f2, &den);
        return;
    }
}

/* The value alone, in plain arithmetic. */
static PHYS_REAL PHYS_FN(case_distance2_value_)(rk_distance_case c, const PHYS_REAL *const x[4])
{
    const PHYS_REAL *p = x[c.v[0]], *q = x[c.v[1]], *r, *s;
    PHYS_REAL a[3], b[3], n[3], f;
    switch (c.kind) {
    case RK_DIST_POINT_POINT:
        PHYS_FN(sub3_)(a, p, q);
        return PHYS_FN(dot3_)(a, a);
    case RK_DIST_POINT_EDGE:
        r = x[c.v[2]];
        PHYS_FN(sub3_)(a, q, p);
        PHYS_FN(sub3_)(b, r, p);
        n[0] = a[1] * b[2] - a[2] * b[1], n[1] = a[2] * b[0] - a[0] * b[2], n[2] = a[0] * b[1] - a[1] * b[0];
        PHYS_FN(sub3_)(a, r, q);
        return PHYS_FN(dot3_)(n, n) / PHYS_FN(dot3_)(a, a);
    case RK_DIST_POINT_PLANE:
    case RK_DIST_LINE_LINE:
        break;
    }
    r = x[c.v[2]], s = x[c.v[3]];
    if (c.kind == RK_DIST_POINT_PLANE) PHYS_FN(sub3_)(a, r, q), PHYS_FN(sub3_)(b, s, q);
    else PHYS_FN(sub3_)(a, q, p), PHYS_FN(sub3_)(b, s, r);
    n[0] = a[1] * b[2] - a[2] * b[1], n[1] = a[2] * b[0] - a[0] * b[2], n[2] = a[0] * b[1] - a[1] * b[0];
    PHYS_FN(sub3_)(a, p, c.kind == RK_DIST_POINT_PLANE ? q : r);
    f = PHYS_FN(dot3_)(a, n);
    return f * f / PHYS_FN(dot3_)(n, n);
}

PHYS_API PHYS_REAL PHYS_FN(contact_distance2)(rk_distance_case c, const PHYS_REAL *const x[4], PHYS_REAL *g,
                                              PHYS_REAL *H)
{
    PHYS_FN(ad_) d;
    int i;
    if (!g && !H) return PHYS_FN(case_distance2_value_)(c, x);
    PHYS_FN(case_distance2_)(c, x, &d);
    if (g)
        for (i = 0; i < 12; i++) g[i] = d.g[i];
    if (H)
        for (i = 0; i < 144; i++) H[i] = d.h[i];
    return d.v;
}

/* The edge-edge mollifier (Li et al. 2020, Sec. 4.3): m = -x^2/eps^2 + 2x/eps for x < eps, else 1,
 * with x = |ea x eb|^2 and eps = 1e-3 |ea_rest|^2 |eb_rest|^2: the barrier of nearly parallel edges
 * fades out smoothly instead of jumping where the closest feature switches. */
PHYS_API PHYS_REAL PHYS_FN(edge_edge_mollifier)(const PHYS_REAL *const x[4], PHYS_REAL eps, PHYS_REAL *g,
                                                PHYS_REAL *H)
{
    PHYS_FN(ad3_) P[4], A, B, C;
    PHYS_FN(ad_) xx;
    PHYS_REAL v, m, m1, m2;
    int i, j, k;
    for (k = 0; k < 4; k++) PHYS_FN(ad3_point_)(&P[k], 12, k, x[k]);
    PHYS_FN(ad3_sub_)(&A, &P[1], &P[0]);
    PHYS_FN(ad3_sub_)(&B, &P[3], &P[2]);
    PHYS_FN(ad3_cross_)(&C, &A, &B);
    PHYS_FN(ad3_dot_)(&xx, &C, &C);
    v = xx.v;
    if (v >= eps) {
        if (g)
            for (i = 0; i < 12; i++) g[i] = 0;
        if (H)
            for (i = 0; i < 144; i++) H[i] = 0;
        return 1;
    }
    /* m(x) = (2 eps x - x^2) / eps^2: m' = 2 (eps - x) / eps^2, m'' = -2 / eps^2 */
    m = (2 * eps * v - v * v) / (eps * eps), m1 = 2 * (eps - v) / (eps * eps), m2 = -2 / (eps * eps);
    if (g)
        for (i = 0; i < 12; i++) g[i] = m1 * xx.g[i];
    if (H)
        for (i = 0; i < 12; i++)
            for (j = 0; j < 12; j++) H[12 * i + j] = m1 * xx.h[12 * i + j] + m2 * xx.g[i] * xx.g[j];
    return m;
}

/* The parameter in [0, 1] of the point of segment (a, b) closest to p (a degenerate segment: 0;
 * NaN and -0 clamp to +0). */
static PHYS_REAL PHYS_FN(segment_parameter_)(const PHYS_REAL *p, const PHYS_REAL *a, const PHYS_REAL *b)
{
    PHYS_REAL e[3], w[3], ee, u;
    PHYS_FN(sub3_)(e, b, a);
    PHYS_FN(sub3_)(w, p, a);
    ee = PHYS_FN(dot3_)(e, e);
    if (!(ee > 0)) return 0;
    u = PHYS_FN(dot3_)(w, e) / ee;
    return u > 0 ? (u < 1 ? u : 1) : 0;
}

PHYS_API void PHYS_FN(contact_closest_weights)(rk_distance_case c, const PHYS_REAL *const x[4], PHYS_REAL w[4])
{
    const int *v = c.v;
    PHYS_REAL e0[3], e1[3], r[3], a, b, cc, r0, r1, det, s, t, u;
    w[0] = w[1] = w[2] = w[3] = 0;
    switch (c.kind) {
    case RK_DIST_POINT_POINT:
        w[v[0]] = 1, w[v[1]] = -1;
        return;
    case RK_DIST_POINT_EDGE:
        u = PHYS_FN(segment_parameter_)(x[v[0]], x[v[1]], x[v[2]]);
        w[v[0]] = 1, w[v[1]] = -(1 - u), w[v[2]] = -u;
        return;
    case RK_DIST_POINT_PLANE: /* barycentric coordinates of the projection */
        PHYS_FN(sub3_)(e0, x[v[2]], x[v[1]]);
        PHYS_FN(sub3_)(e1, x[v[3]], x[v[1]]);
        PHYS_FN(sub3_)(r, x[v[0]], x[v[1]]);
        a = PHYS_FN(dot3_)(e0, e0), b = PHYS_FN(dot3_)(e0, e1), cc = PHYS_FN(dot3_)(e1, e1);
        r0 = PHYS_FN(dot3_)(e0, r), r1 = PHYS_FN(dot3_)(e1, r);
        det = PHYS_FN(cross2_)(e0, e1), s = (cc * r0 - b * r1) / det, t = (a * r1 - b * r0) / det;
        w[v[0]] = 1, w[v[1]] = -(1 - s - t), w[v[2]] = -s, w[v[3]] = -t;
        return;
    case RK_DIST_LINE_LINE: /* e0, e1: the edges ea, eb; r0, r1: d, e of edge_edge_case */
        PHYS_FN(sub3_)(e0, x[v[1]], x[v[0]]);
        PHYS_FN(sub3_)(e1, x[v[3]], x[v[2]]);
        PHYS_FN(sub3_)(r, x[v[0]], x[v[2]]);
        a = PHYS_FN(dot3_)(e0, e0), b = PHYS_FN(dot3_)(e0, e1), cc = PHYS_FN(dot3_)(e1, e1);
        r0 = PHYS_FN(dot3_)(e0, r), r1 = PHYS_FN(dot3_)(e1, r);
        det = PHYS_FN(cross2_)(e0, e1), s = (b * r1 - cc * r0) / det, t = (a * r1 - b * r0) / det;
        w[v[0]] = 1 - s, w[v[1]] = s, w[v[2]] = -(1 - t), w[v[3]] = -t;
        return;
    }
}

/* Helmert's contrasts of m points: h_j (j = 1 .. m - 1) is 1 / sqrt(j (j + 1)) on points 0 .. j - 1,
 * -j / sqrt(j (j + 1)) on point j, 0 after; orthonormal, and orthogonal to (1, .., 1). */
static PHYS_REAL PHYS_FN(helmert_)(int j, int i)
{
    PHYS_REAL s = PHYS_K_(1) / PHYS_SQRT_((PHYS_REAL)(j * (j + 1)));
    return i < j ? s : i == j ? -(PHYS_REAL)j * s : PHYS_K_(0);
}

/* B (3 m square, point-major: 3 k + a) <- Q P(Q^T B Q) Q^T, P the PSD projection and Q = h (x) I3
 * the contrasts over the points (pair_project). */
static void PHYS_FN(project_translation_free_)(int m, PHYS_REAL *B)
{
    PHYS_REAL h[4][4], C[12 * 9], A[81];
    int n = 3 * m, r = 3 * (m - 1), i, j, k, l, a;
    for (j = 1; j < m; j++)
        for (i = 0; i < m; i++) h[j - 1][i] = PHYS_FN(helmert_)(j, i);
    for (i = 0; i < n; i++) /* C = B Q (n x r): column 3 j + a = sum_l h_j[l] B[:, 3 l + a] */
        for (j = 0; j < m - 1; j++)
            for (a = 0; a < 3; a++) {
                PHYS_REAL s = PHYS_K_(0);
                for (l = 0; l < m; l++) s += B[n * i + 3 * l + a] * h[j][l];
                C[r * i + 3 * j + a] = s;
            }
    for (j = 0; j < m - 1; j++) /* A = Q^T C (r x r) */
        for (a = 0; a < 3; a++)
            for (k = 0; k < r; k++) {
                PHYS_REAL s = PHYS_K_(0);
                for (l = 0; l < m; l++) s += h[j][l] * C[r * (3 * l + a) + k];
                A[r * (3 * j + a) + k] = s;
            }
    PHYS_FN(project_psd)(r, A);
    for (i = 0; i < r; i++) /* C = A Q^T (r x n), then B = Q C */
        for (l = 0; l < m; l++)
            for (a = 0; a < 3; a++) {
                PHYS_REAL s = PHYS_K_(0);
                for (j = 0; j < m - 1; j++) s += A[r * i + 3 * j + a] * h[j][l];
                C[n * i + 3 * l + a] = s;
            }
    for (l = 0; l < m; l++)
        for (a = 0; a < 3; a++)
            for (k = 0; k < n; k++) {
                PHYS_REAL s = PHYS_K_(0);
                for (j = 0; j < m - 1; j++) s += h[j][l] * C[n * (3 * j + a) + k];
                B[n * (3 * l + a) + k] = s;
            }
}

/* Projects the Hessian H (12 x 12) to PSD on the points that take part (a non-zero row) and are
 * unknowns (dof[k] != 0): points outside the closest feature drop out, so a point-point pair
 * projects a 6 x 6 block. The other rows and columns are zeroed.
 *
 * When every point that takes part is an unknown (a pair between two objects' surfaces), the
 * distance does not see a common translation of them: H's rows and columns sum to zero over the
 * points, the 3 translations are an exact null space, and H = Q (Q^T H Q) Q^T with Q the
 * orthonormal complement of the translations (Helmert's contrasts of the m points, per axis). The
 * projection then runs on that (3 m - 3)-square block (9 x 9 for 4 points: the eigen-solver's
 * n^3 costs 0.42 of the 12 x 12, where it was a seventh of the 8-object pour's step); the
 * translation part of H it drops is its rounding. A block that is already positive
 * semi-definite (project_psd's Cholesky test) is left as it is, untransformed. */
PHYS_API void PHYS_FN(pair_project)(const int dof[4], PHYS_REAL *H)
{
    int keep[12], n = 0, pts = 0, all = 1, i, j, k, a;
    PHYS_REAL B[144];
    for (k = 0; k < 4; k++) {
        int used = 0;
        for (a = 0; a < 3; a++)
            for (j = 0; j < 12; j++) used |= H[12 * (3 * k + a) + j] != 0;
        if (used && !dof[k]) all = 0;
        if (!used || !dof[k]) continue;
        for (a = 0; a < 3; a++) keep[n++] = 3 * k + a;
        pts++;
    }
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++) B[n * i + j] = H[12 * keep[i] + keep[j]];
    if (all && pts > 1) {
        PHYS_REAL scale = PHYS_K_(0);
        for (i = 0; i < n; i++) scale = PHYS_FABS_(B[n * i + i]) > scale ? PHYS_FABS_(B[n * i + i]) : scale;
        if (PHYS_FN(is_positive_definite)(n, B, PHYS_K_(64) * PHYS_EPS_ * scale)) return; /* H as it is */
        PHYS_FN(project_translation_free_)(pts, B);
    } else {
        PHYS_FN(project_psd)(n, B);
    }
    memset(H, 0, 144 * sizeof(PHYS_REAL));
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++) H[12 * keep[i] + keep[j]] = B[n * i + j];
}

PHYS_API PHYS_REAL PHYS_FN(pair_barrier)(int edge_edge, const PHYS_REAL *const x[4], PHYS_REAL xi, PHYS_REAL dhat,
                                         PHYS_REAL eps, PHYS_REAL *g, PHYS_REAL *H, PHYS_REAL *dist)
{
    PHYS_REAL gd[12], Hd[144], gm[12], Hm[144], d2, s, shat, b, b1, b2, m = 1;
    rk_distance_case k = edge_edge ? PHYS_FN(edge_edge_case)(x) : PHYS_FN(point_triangle_case)(x);
    int i, j;
    d2 = PHYS_FN(contact_distance2)(k, x, g || H ? gd : NULL, H ? Hd : NULL); /* H needs gd too */
    s = d2 - xi * xi, shat = dhat * dhat + 2 * xi * dhat;
    if (dist) *dist = PHYS_SQRT_(d2) - xi;
    if (!(s > 0)) return (PHYS_REAL)INFINITY;
    if (s >= shat) {
        if (g) memset(g, 0, 12 * sizeof(PHYS_REAL));
        if (H) memset(H, 0, 144 * sizeof(PHYS_REAL));
        return 0;
    }
    b = PHYS_FN(barrier)(s, shat, &b1, &b2);
    for (i = 0; i < 12; i++) gm[i] = 0;
    for (i = 0; i < 144; i++) Hm[i] = 0;
    if (edge_edge && eps > 0) m = PHYS_FN(edge_edge_mollifier)(x, eps, g || H ? gm : NULL, H ? Hm : NULL);
    if (g)
        for (i = 0; i < 12; i++) g[i] = m * b1 * gd[i] + b * gm[i];
    if (H)
        for (i = 0; i < 12; i++)
            for (j = 0; j < 12; j++)
                H[12 * i + j] = m * (b2 * gd[i] * gd[j] + b1 * Hd[12 * i + j]) + b1 * (gd[i] * gm[j] + gm[i] * gd[j]) +
                                b * Hm[12 * i + j];
    return m * b;
}

/* Friction's lagged frame of one pair (IPC Sec. 5): the normal force kappa m |db/dd| with
 * s = d^2 - xi^2 (so |db/dd| = |b'(s)| 2 d), the closest points' weights w and the tangent basis T
 * of the normal sum_i w_i x_i; 0 when the pair exerts no force (out of reach, touching, or no
 * normal). */
PHYS_API PHYS_REAL PHYS_FN(pair_friction_lag)(int edge_edge, const PHYS_REAL *const x[4], PHYS_REAL xi,
                                              PHYS_REAL dhat, PHYS_REAL eps, PHYS_REAL kappa, PHYS_REAL w[4],
                                              PHYS_REAL T[6])
{
    rk_distance_case k = edge_edge ? PHYS_FN(edge_edge_case)(x) : PHYS_FN(point_triangle_case)(x);
    PHYS_REAL d2 = PHYS_FN(contact_distance2)(k, x, NULL, NULL), s = d2 - xi * xi;
    PHYS_REAL shat = dhat * dhat + 2 * xi * dhat, b1, b2, m, lambda, n[3], l;
    int a, i;
    if (!(s > 0 && s < shat)) return 0;
    PHYS_FN(barrier)(s, shat, &b1, &b2);
    m = edge_edge && eps > 0 ? PHYS_FN(edge_edge_mollifier)(x, eps, NULL, NULL) : 1;
    lambda = kappa * m * PHYS_FABS_(b1) * 2 * PHYS_SQRT_(d2);
    PHYS_FN(contact_closest_weights)(k, x, w);
    for (a = 0; a < 3; a++) {
        n[a] = 0;
        for (i = 0; i < 4; i++) n[a] += w[i] * x[i][a];
    }
    l = PHYS_SQRT_(PHYS_FN(dot3_)(n, n));
    if (!(l > 0)) return 0;
    for (a = 0; a < 3; a++) n[a] /= l;
    PHYS_FN(tangent_basis)(n, T);
    return lambda;
}

/* Smoothed Coulomb friction on one lagged pair's relative motion rel (3, since the step began)
 * in tangent basis T: scale f0(|u|) with u = T rel, its gradient g = scale f1/|u| T^T u (3) and
 * Hessian B = scale T^T M T (3 x 3, PSD) when g, B are not NULL (rk_friction_smoothed, threshold
 * eps = eps_v h; scale = mu lambda). */
PHYS_API PHYS_REAL PHYS_FN(friction_slip)(const PHYS_REAL T[6], const PHYS_REAL rel[3], PHYS_REAL eps,
                                          PHYS_REAL scale, PHYS_REAL g[3], PHYS_REAL B[9])
{
    PHYS_REAL u[2], f1y, M[4], E;
    int a, b;
    u[0] = PHYS_FN(dot3_)(T, rel), u[1] = PHYS_FN(dot3_)(T + 3, rel);
    E = scale * PHYS_FN(friction_smoothed)(u, eps, &f1y, M);
    for (a = 0; a < 3 && g; a++) g[a] = scale * f1y * (T[a] * u[0] + T[3 + a] * u[1]);
    for (a = 0; a < 3 && B; a++)
        for (b = 0; b < 3; b++)
            B[3 * a + b] = scale * (T[a] * (M[0] * T[b] + M[1] * T[3 + b]) + T[3 + a] * (M[2] * T[b] + M[3] * T[3 + b]));
    return E;
}

/* The squared distance of the stencil at x, by its closest feature; edge-edge stencils that come
 * out at or below the thickness through rounding of nearly parallel lines use the endpoints. */
static PHYS_REAL PHYS_FN(stencil_distance2_)(int edge_edge, const PHYS_REAL *const x[4], PHYS_REAL xi)
{
    rk_distance_case c = edge_edge ? PHYS_FN(edge_edge_case)(x) : PHYS_FN(point_triangle_case)(x);
    PHYS_REAL d2 = PHYS_FN(contact_distance2)(c, x, NULL, NULL), e[3], e2;
    int i, j, a;
    if (edge_edge && d2 <= xi * xi) {
        for (i = 0; i < 2; i++)
            for (j = 2; j < 4; j++) {
                for (a = 0; a < 3; a++) e[a] = x[i][a] - x[j][a];
                e2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
                d2 = i + j == 2 || e2 < d2 ? e2 : d2;
            }
    }
    return d2;
}

static PHYS_REAL PHYS_FN(norm3_)(const PHYS_REAL *a)
{
    return PHYS_SQRT_(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

static PHYS_REAL PHYS_FN(max_)(PHYS_REAL a, PHYS_REAL b)
{
    return b > a ? b : a;
}

/* The displacements are made relative (their mean removed); l_p bounds how fast the distance can
 * shrink per unit of time; the stencil then advances by steps s (d - xi) / l_p, each of which
 * provably cannot reach contact, until the distance falls below (1 - s) of the start's. The time
 * reached is a conservative time of impact: along the step, no closer than 10% of the start's
 * gap. The points are taken relative to x[0] and placed at x + t p afresh on every advance: added
 * up step by step onto absolute positions, each advance's float rounding (half an ulp of the
 * coordinates, 1.5e-8 m at 0.3 m) piled up over the hundreds of advances a small gap needs into
 * more than the gap, and a folded bar's edges passed through each other at a "time of impact"
 * twice the true one (test_runtime_object_contact). */
PHYS_API int PHYS_FN(ccd_stencil)(int edge_edge, const PHYS_REAL *const x[4], const PHYS_REAL *const dx[4],
                                  PHYS_REAL xi, PHYS_REAL tmax, PHYS_REAL *toi)
{
    PHYS_REAL p[4][3], mean[3] = {0, 0, 0}, x0[4][3], y[4][3], lp, d2, d, gap, t, step;
    const PHYS_REAL *yk[4];
    int k, a, it;
    for (k = 0; k < 4; k++)
        for (a = 0; a < 3; a++) mean[a] += dx[k][a] / 4;
    for (k = 0; k < 4; k++)
        for (a = 0; a < 3; a++) p[k][a] = dx[k][a] - mean[a];
    /* l_p: point-triangle |p_0| + max |p_t|; edge-edge max |p_a| + max |p_b| */
    lp = edge_edge ? PHYS_FN(max_)(PHYS_FN(norm3_)(p[0]), PHYS_FN(norm3_)(p[1])) +
                         PHYS_FN(max_)(PHYS_FN(norm3_)(p[2]), PHYS_FN(norm3_)(p[3]))
                   : PHYS_FN(norm3_)(p[0]) +
                         PHYS_FN(max_)(PHYS_FN(norm3_)(p[1]), PHYS_FN(max_)(PHYS_FN(norm3_)(p[2]), PHYS_FN(norm3_)(p[3])));
    for (k = 0; k < 4; k++) {
        for (a = 0; a < 3; a++) x0[k][a] = y[k][a] = x[k][a] - x[0][a];
        yk[k] = y[k];
    }
    d2 = PHYS_FN(stencil_distance2_)(edge_edge, yk, xi), d = PHYS_SQRT_(d2);
    *toi = 0;
    if (!(d > xi)) return 1; /* already touching */
    if (lp == 0) return 0;   /* rigidly translating together: the distance never changes */
    gap = (1 - PHYS_CCD_RESCALING_) * (d2 - xi * xi) / (d + xi), t = 0;
    for (it = 0; it < PHYS_CCD_MAX_ADVANCES_; it++) {
        step = PHYS_CCD_RESCALING_ * (d2 - xi * xi) / ((d + xi) * lp);
        for (k = 0; k < 4; k++)
            for (a = 0; a < 3; a++) y[k][a] = x0[k][a] + (t + step) * p[k][a];
        d2 = PHYS_FN(stencil_distance2_)(edge_edge, yk, xi);
        d = PHYS_SQRT_(d2);
        if (t > 0 && (d2 - xi * xi) / (d + xi) < gap) break;
        t += step;
        if (t > tmax) return 0;
    }
    *toi = t;
    return 1;
}

#undef PHYS_CCD_RESCALING_
#undef PHYS_CCD_MAX_ADVANCES_
