/* Integration points inside a tet mesh: a uniform grid over its bounding box, kept where some
 * tet contains the point (freeform paper Sec. 7.1).
 *
 * The grid's cells tile the bounding box exactly: n_d = ceil(extent_d / s) cells per axis of
 * extent_d / n_d each (s = cbrt(volume / target)), a point at each cell's centre weighing its
 * volume. A grid of spacing s on every axis (before issue 37) put ceil(extent / s) points per
 * axis, so its cells overhung a box by up to a cell: on the FreeForm beam at 10,000 points, 13
 * across the 1 m width covering 1.032 m, 6.5% more mass and (width times height cubed) 13% more
 * bending stiffness; the m = 32 model sagged 94.3% of beam theory at nu = 0 (5,000 points, whose
 * cells tile the beam: 99.8%; 20,000: 99.0%) and its Table 1 error moved 100x with the point
 * count. */
#include "basis/rkpm_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Barycentric tolerance: a point this far outside a tet (in barycentric units) still counts as
 * inside, so points on shared faces or the boundary are not lost to roundoff. */
#define INSIDE_TOL 1e-9

typedef struct {
    long long cell; /* grid index */
    int tet;
} hit;

static int cmp_hit(const void *a, const void *b)
{
    const hit *x = a, *y = b;
    if (x->cell != y->cell) return (x->cell > y->cell) - (x->cell < y->cell);
    return (x->tet > y->tet) - (x->tet < y->tet);
}

void rk_rkpm_points_free(rk_rkpm_points *p)
{
    free(p->X);
    free(p->weight);
    free(p->tet);
    free(p->source);
    memset(p, 0, sizeof *p);
}

/* Inverse of the 3x3 matrix with columns e1 e2 e3 (rows of the result are the dual vectors). */
static void inverse3(const double e[3][3], double inv[3][3])
{
    double c[3][3];
    for (int i = 0; i < 3; i++) {
        const double *u = e[(i + 1) % 3], *v = e[(i + 2) % 3];
        c[i][0] = u[1] * v[2] - u[2] * v[1];
        c[i][1] = u[2] * v[0] - u[0] * v[2];
        c[i][2] = u[0] * v[1] - u[1] * v[0];
    }
    double det = e[0][0] * c[0][0] + e[0][1] * c[0][1] + e[0][2] * c[0][2];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) inv[i][j] = c[i][j] / det;
}

int rk_rkpm_sample_mesh(const rk_mesh *m, int target, rk_rkpm_points *p, rk_error *err)
{
    memset(p, 0, sizeof *p);
    if (target < 1) return rk_fail(err, "RKPM sampling: the target number of points must be >= 1, got %d", target);
    if (m->nt < 1 || m->nv < 4) return rk_fail(err, "RKPM sampling: the mesh has no tetrahedra");
    double lo[3], hi[3], volume = 0;
    for (int d = 0; d < 3; d++) lo[d] = hi[d] = m->X[d];
    for (int v = 1; v < m->nv; v++)
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], m->X[3 * v + d]);
            hi[d] = fmax(hi[d], m->X[3 * v + d]);
        }
    for (int t = 0; t < m->nt; t++) {
        const int *T = &m->tets[4 * t];
        volume += fabs(rk_tet_signed_volume(&m->X[3 * T[0]], &m->X[3 * T[1]], &m->X[3 * T[2]], &m->X[3 * T[3]]));
    }
    double s = cbrt(volume / target);
    if (!(s > 0) || !isfinite(s)) return rk_fail(err, "RKPM sampling: the mesh has zero or non-finite volume");
    /* n[d] cells per axis tiling the box, of h[d] each: points at origin + i h[d], i = 0 .. n[d]-1. */
    long long n[3];
    double origin[3], h[3];
    for (int d = 0; d < 3; d++) {
        double extent = hi[d] - lo[d];
        /* ceil, not round: a thin part keeps its layers (one layer of points cannot see the
         * affine handles' through-thickness terms, and the reduced mass turns singular); the 1e-9
         * keeps an extent of exactly k spacings at k cells */
        n[d] = (long long)ceil(extent / s - 1e-9);
        if (n[d] < 1) n[d] = 1;
        h[d] = extent > 0 ? extent / (double)n[d] : s; /* a flat mesh (no volume) was refused above */
        origin[d] = lo[d] + 0.5 * h[d];
    }
    if ((double)n[0] * (double)n[1] * (double)n[2] > 4e18)
        return rk_fail(err, "RKPM sampling: a grid of spacing %g over the mesh's bounding box is too large", s);

    size_t cap = (target < (1 << 20) ? (size_t)target : (size_t)1 << 20) + 1024, count = 0;
    hit *hits = rk_calloc(cap, sizeof *hits, err);
    if (!hits) return -1;
    for (int t = 0; t < m->nt; t++) {
        const int *T = &m->tets[4 * t];
        const double *a = &m->X[3 * T[0]];
        double e[3][3], inv[3][3], tlo[3], thi[3];
        for (int c = 0; c < 3; c++)
            for (int d = 0; d < 3; d++) e[c][d] = m->X[3 * T[c + 1] + d] - a[d];
        inverse3(e, inv);
        for (int d = 0; d < 3; d++) {
            tlo[d] = thi[d] = a[d];
            for (int c = 1; c < 4; c++) {
                tlo[d] = fmin(tlo[d], m->X[3 * T[c] + d]);
                thi[d] = fmax(thi[d], m->X[3 * T[c] + d]);
            }
        }
        long long i0[3], i1[3];
        for (int d = 0; d < 3; d++) {
            double pad = 1e-9 * h[d];
            i0[d] = (long long)fmax(0.0, ceil((tlo[d] - pad - origin[d]) / h[d]));
            i1[d] = (long long)fmin((double)(n[d] - 1), floor((thi[d] + pad - origin[d]) / h[d]));
        }
        for (long long k = i0[2]; k <= i1[2]; k++)
            for (long long j = i0[1]; j <= i1[1]; j++)
                for (long long i = i0[0]; i <= i1[0]; i++) {
                    double r[3] = {origin[0] + (double)i * h[0] - a[0], origin[1] + (double)j * h[1] - a[1],
                                   origin[2] + (double)k * h[2] - a[2]};
                    double b[3], b0 = 1;
                    for (int c = 0; c < 3; c++) {
                        b[c] = inv[c][0] * r[0] + inv[c][1] * r[1] + inv[c][2] * r[2];
                        b0 -= b[c];
                    }
                    if (b0 < -INSIDE_TOL || b[0] < -INSIDE_TOL || b[1] < -INSIDE_TOL || b[2] < -INSIDE_TOL) continue;
                    if (count == cap) {
                        hit *grown = realloc(hits, 2 * cap * sizeof *hits);
                        if (!grown) {
                            free(hits);
                            return rk_fail(err, "RKPM sampling: out of memory");
                        }
                        hits = grown;
                        cap *= 2;
                    }
                    hits[count++] = (hit){i + n[0] * (j + n[1] * k), t};
                }
    }
    qsort(hits, count, sizeof *hits, cmp_hit);
    size_t kept = 0;
    for (size_t q = 0; q < count; q++)
        if (q == 0 || hits[q].cell != hits[q - 1].cell) hits[kept++] = hits[q];
    if (kept == 0) {
        free(hits);
        return rk_fail(err,
                       "RKPM sampling: no point of a grid of spacing %g (target %d points) fell inside the mesh "
                       "(volume %g); raise the target",
                       s, target, volume);
    }
    if (kept > (size_t)1 << 30) {
        free(hits);
        return rk_fail(err, "RKPM sampling: %zu points is too many", kept);
    }
    p->n = (int)kept;
    p->X = rk_calloc(3 * kept, sizeof(double), err);
    p->weight = rk_calloc(kept, sizeof(double), err);
    p->tet = rk_calloc(kept, sizeof(int), err);
    if (!p->X || !p->weight || !p->tet) {
        free(hits);
        rk_rkpm_points_free(p);
        return -1;
    }
    for (size_t q = 0; q < kept; q++) {
        long long c = hits[q].cell;
        long long idx[3] = {c % n[0], (c / n[0]) % n[1], c / (n[0] * n[1])};
        for (int d = 0; d < 3; d++) p->X[3 * q + d] = origin[d] + (double)idx[d] * h[d];
        p->weight[q] = h[0] * h[1] * h[2];
        p->tet[q] = hits[q].tet;
    }
    p->spacing = cbrt(h[0] * h[1] * h[2]);
    p->volume = volume;
    free(hits);
    return 0;
}
