/* A cloud's contact surface's faces bucketed on a grid, for the distance from a point to the
 * surface near it (points_proxy_impl.h): the last stage of rk_proxy_inset lets a point the surface
 * swept over lie outside it by at most t, and checks that bound at every pass.
 *
 * Each face goes into every cell its box (grown by pad) meets; a point's cell then lists every face
 * whose grown box holds it, so a face not listed is farther than pad from the point. The distance
 * to a listed face is physics.h's (rk_point_triangle_case, rk_contact_distance2: the contact
 * code's own, the closest feature pair in floating point). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "contact/points_proxy_impl.h"

static long cell_index(const rk_proxy_face_grid *F, double x, int d)
{
    long c = (long)floor((x - F->lo[d]) / F->h);
    return c < 0 ? 0 : c >= F->dim[d] ? F->dim[d] - 1 : c;
}

void rk_proxy_face_boxes(const double *x, const int *tris, int nf, double *boxes)
{
    for (int f = 0; f < nf; f++)
        for (int d = 0; d < 3; d++) {
            const int *t = tris + 3 * f;
            boxes[6 * f + d] = fmin(x[3 * t[0] + d], fmin(x[3 * t[1] + d], x[3 * t[2] + d]));
            boxes[6 * f + 3 + d] = fmax(x[3 * t[0] + d], fmax(x[3 * t[1] + d], x[3 * t[2] + d]));
        }
}

int rk_proxy_face_grid_build(rk_proxy_face_grid *F, const double *boxes, int nf, double pad, double h, rk_error *err)
{
    memset(F, 0, sizeof *F);
    F->h = h;
    double hi[3];
    for (int d = 0; d < 3; d++) {
        F->lo[d] = INFINITY, hi[d] = -INFINITY;
        for (int f = 0; f < nf; f++) F->lo[d] = fmin(F->lo[d], boxes[6 * f + d] - pad), hi[d] = fmax(hi[d], boxes[6 * f + 3 + d] + pad);
        if (nf == 0) F->lo[d] = hi[d] = 0;
        double cells = floor((hi[d] - F->lo[d]) / h) + 1;
        if (!(cells >= 1 && cells < 1e6)) return rk_fail(err, "contact proxy: face grid of %g cells along axis %d", cells, d);
        F->dim[d] = (long)cells;
    }
    size_t ncell = (size_t)(F->dim[0] * F->dim[1] * F->dim[2]);
    F->start = rk_calloc(ncell + 1, sizeof *F->start, err);
    if (!F->start) return -1;
    for (int pass = 0; pass < 2; pass++) { /* count, then fill */
        for (int f = 0; f < nf; f++) {
            long c0[3], c1[3], q[3];
            for (int d = 0; d < 3; d++) {
                double a = boxes[6 * f + d] - pad, b = boxes[6 * f + 3 + d] + pad;
                c0[d] = cell_index(F, a, d), c1[d] = cell_index(F, b, d);
            }
            for (q[2] = c0[2]; q[2] <= c1[2]; q[2]++)
                for (q[1] = c0[1]; q[1] <= c1[1]; q[1]++)
                    for (q[0] = c0[0]; q[0] <= c1[0]; q[0]++) {
                        size_t c = (size_t)(q[0] + F->dim[0] * (q[1] + F->dim[1] * q[2]));
                        if (pass == 0) F->start[c + 1]++;
                        else F->face[F->start[c]++] = f;
                    }
        }
        if (pass == 0) {
            for (size_t c = 0; c < ncell; c++) F->start[c + 1] += F->start[c];
            F->face = rk_calloc(F->start[ncell] + 1, sizeof *F->face, err);
            if (!F->face) {
                rk_proxy_face_grid_free(F);
                return -1;
            }
        } else {
            for (size_t c = ncell; c > 0; c--) F->start[c] = F->start[c - 1];
            F->start[0] = 0;
        }
    }
    return 0;
}

void rk_proxy_face_grid_free(rk_proxy_face_grid *F)
{
    free(F->start), free(F->face);
    F->start = NULL, F->face = NULL;
}

size_t rk_proxy_faces_near(const rk_proxy_face_grid *F, const double *p, size_t *first)
{
    long q[3];
    for (int d = 0; d < 3; d++) q[d] = cell_index(F, p[d], d);
    size_t c = (size_t)(q[0] + F->dim[0] * (q[1] + F->dim[1] * q[2]));
    *first = F->start[c];
    return F->start[c + 1];
}

double rk_proxy_face_distance(const double *p, const double *a, const double *b, const double *c)
{
    const double *x[4] = {p, a, b, c};
    return sqrt(rk_contact_distance2(rk_point_triangle_case(x), x, NULL, NULL));
}
