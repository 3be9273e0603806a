/* The exact intersection test (contact.h): does a segment cross a triangle, decided by the signs
 * of orientation determinants computed exactly (exact.c), so touching counts and rounding never
 * hides a crossing. */
#include "contact/contact.h"

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
