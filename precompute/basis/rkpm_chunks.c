/* Integration points in spatial chunks, and the kernels covering each point of a chunk: the
 * traversal both assembly passes share (rkpm_assemble.c). */
#include "basis/rkpm_chunks_impl.h"
#include "util/util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Chunk cell edge, in units of the median kernel radius: small enough that the kernels covering
 * a chunk are not many more than those covering each of its points (the dense blocks stay
 * mostly non-zero), large enough that a chunk has tens of points for the BLAS products. */
#define CHUNK_CELL_RADII 1.5
#define CHUNK_MAX_POINTS 256

void rkpm_chunks_free(rkpm_chunks *c)
{
    rkpm_grid_free(&c->grid);
    free(c->pts);
    free(c->cand);
    free(c->used);
    free(c->U);
    free(c->cover_start);
    free(c->cover);
    memset(c, 0, sizeof *c);
}

int rkpm_chunks_init(rkpm_chunks *c, const rk_rkpm *k, const double *X, int n, rk_error *err)
{
    memset(c, 0, sizeof *c);
    c->k = k;
    c->X = X;
    c->n = n;
    double *r = rk_calloc((size_t)k->K, sizeof *r, err);
    if (!r) return -1;
    memcpy(r, k->radius, (size_t)k->K * sizeof *r);
    qsort(r, (size_t)k->K, sizeof *r, rk_cmp_double);
    double cell = CHUNK_CELL_RADII * r[k->K / 2];
    free(r);
    int cap = k->max_support;
    c->pts = rk_calloc(CHUNK_MAX_POINTS, sizeof(int), err);
    c->cand = rk_calloc((size_t)k->K, sizeof(int), err);
    c->used = rk_calloc((size_t)k->K, sizeof(int), err);
    c->U = rk_calloc((size_t)k->K, sizeof(int), err);
    c->cover_start = rk_calloc(CHUNK_MAX_POINTS + 1, sizeof(int), err);
    c->cover = rk_calloc((size_t)CHUNK_MAX_POINTS * (size_t)cap, sizeof(int), err);
    if (!c->pts || !c->cand || !c->used || !c->U || !c->cover_start || !c->cover ||
        rkpm_grid_build(&c->grid, X, n, cell, err)) {
        rkpm_chunks_free(c);
        return -1;
    }
    c->max_points = CHUNK_MAX_POINTS;
    return 0;
}

/* Squared distance from p to the box [lo, hi]. */
static double box_dist2(const double *p, const double lo[3], const double hi[3])
{
    double s = 0;
    for (int d = 0; d < 3; d++) {
        double e = p[d] < lo[d] ? lo[d] - p[d] : p[d] > hi[d] ? p[d] - hi[d] : 0;
        s += e * e;
    }
    return s;
}

/* Collects the kernels whose support meets the box [lo, hi] (each kernel is met once). */
typedef struct {
    const rk_rkpm *k;
    const double *lo, *hi;
    int *cand, count;
} candidate_list;

static int add_candidate(int l, void *ctx)
{
    candidate_list *c = ctx;
    if (box_dist2(&c->k->centers[3 * l], c->lo, c->hi) < c->k->support[l] * c->k->support[l]) c->cand[c->count++] = l;
    return 0;
}

int rkpm_chunks_next(rkpm_chunks *c, rk_error *err)
{
    const rk_rkpm_grid *g = &c->grid;
    const rk_rkpm *k = c->k;
    int ncell = g->dim[0] * g->dim[1] * g->dim[2];
    while (c->cell < ncell && c->offset >= g->start[c->cell + 1] - g->start[c->cell]) {
        c->cell++;
        c->offset = 0;
    }
    if (c->cell >= ncell) {
        c->cell = c->offset = 0;
        return 0;
    }
    int first = g->start[c->cell] + c->offset, avail = g->start[c->cell + 1] - first;
    c->np = avail < c->max_points ? avail : c->max_points;
    c->offset += c->np;
    double lo[3], hi[3];
    for (int t = 0; t < c->np; t++) {
        int i = g->item[first + t];
        c->pts[t] = i;
        for (int d = 0; d < 3; d++) {
            double x = c->X[3 * i + d];
            lo[d] = t == 0 ? x : fmin(lo[d], x);
            hi[d] = t == 0 ? x : fmax(hi[d], x);
        }
    }
    /* Candidates: kernels whose support meets the chunk's bounding box, ascending. */
    double qlo[3], qhi[3];
    for (int d = 0; d < 3; d++) qlo[d] = lo[d] - k->max_support_radius, qhi[d] = hi[d] + k->max_support_radius;
    candidate_list cl = {k, lo, hi, c->cand, 0};
    rkpm_grid_visit(&k->hash, qlo, qhi, add_candidate, &cl);
    int ncand = cl.count;
    qsort(c->cand, (size_t)ncand, sizeof(int), rkpm_cmp_int);
    /* Each point's covering kernels (as candidate positions for now). */
    memset(c->used, 0, (size_t)ncand * sizeof(int));
    int pos = 0, cap = k->max_support;
    for (int t = 0; t < c->np; t++) {
        const double *x = &c->X[3 * c->pts[t]];
        c->cover_start[t] = pos;
        for (int a = 0; a < ncand; a++) {
            const double *p = &k->centers[3 * c->cand[a]];
            double e0 = x[0] - p[0], e1 = x[1] - p[1], e2 = x[2] - p[2];
            double R = k->support[c->cand[a]];
            if (e0 * e0 + e1 * e1 + e2 * e2 >= R * R) continue;
            if (pos - c->cover_start[t] == cap)
                return rk_fail(err, "point %d at (%g, %g, %g) is covered by more than %d kernels", c->pts[t], x[0], x[1],
                               x[2], cap);
            c->cover[pos++] = a;
            c->used[a] = 1;
        }
    }
    c->cover_start[c->np] = pos;
    /* U: the candidates that cover some point, ascending; cover entries become positions in U. */
    c->u = 0;
    for (int a = 0; a < ncand; a++)
        if (c->used[a]) {
            c->U[c->u] = c->cand[a];
            c->used[a] = c->u++;
        }
    for (int q = 0; q < pos; q++) c->cover[q] = c->used[c->cover[q]];
    return 1;
}
