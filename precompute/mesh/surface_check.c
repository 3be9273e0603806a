/* rk_surface_check: a surface that can bound a solid (see mesh.h). Edges are found by
 * sorting the 3 * nf half-edges by their vertex pair: a closed, edge-manifold, consistently
 * oriented surface has every pair exactly twice, once in each direction. */
#include <math.h>
#include <stdlib.h>

#include "mesh/mesh_impl.h"

#define INSIDE_OUT 1

typedef struct {
    int lo, hi;  /* vertex pair, lo < hi */
    int face;
    int forward; /* the face runs lo -> hi */
} half_edge;

static int by_edge(const void *a, const void *b)
{
    const half_edge *x = a, *y = b;
    if (x->lo != y->lo) return x->lo < y->lo ? -1 : 1;
    if (x->hi != y->hi) return x->hi < y->hi ? -1 : 1;
    return (x->face > y->face) - (x->face < y->face);
}

static int check_faces(const rk_surface *s, const char *what, rk_error *err)
{
    if (s->nv <= 0 || s->nf <= 0) return rk_fail(err, "%s: empty surface (%d vertices, %d faces)", what, s->nv, s->nf);
    for (int f = 0; f < s->nf; f++) {
        const int *t = s->tris + 3 * (size_t)f;
        for (int k = 0; k < 3; k++)
            if (t[k] < 0 || t[k] >= s->nv)
                return rk_fail(err, "%s: face %d references vertex %d, but there are %d vertices", what, f, t[k], s->nv);
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
            return rk_fail(err, "%s: face %d (%d %d %d) repeats a vertex", what, f, t[0], t[1], t[2]);
        for (int k = 0; k < 3; k++) {
            const double *p = s->X + 3 * (size_t)t[k];
            if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
                return rk_fail(err, "%s: vertex %d (of face %d) has a non-finite coordinate", what, t[k], f);
        }
    }
    return 0;
}

static int check_edges(const rk_surface *s, const char *what, rk_error *err)
{
    size_t n = 3 * (size_t)s->nf;
    half_edge *e = rk_calloc(n, sizeof *e, err);
    if (!e) return -1;
    for (int f = 0; f < s->nf; f++) {
        const int *t = s->tris + 3 * (size_t)f;
        for (int k = 0; k < 3; k++) {
            int a = t[k], b = t[(k + 1) % 3];
            e[3 * (size_t)f + k] = (half_edge){a < b ? a : b, a < b ? b : a, f, a < b};
        }
    }
    qsort(e, n, sizeof *e, by_edge);
    int rc = 0;
    for (size_t i = 0; i < n && rc == 0;) {
        size_t j = i + 1;
        while (j < n && e[j].lo == e[i].lo && e[j].hi == e[i].hi) j++;
        if (j - i == 1)
            rc = rk_fail(err, "%s: not closed: edge (%d, %d) of face %d belongs to no other face", what, e[i].lo, e[i].hi,
                         e[i].face);
        else if (j - i > 2)
            rc = rk_fail(err, "%s: not edge-manifold: edge (%d, %d) is shared by %zu faces (%d, %d, %d, ...)", what,
                         e[i].lo, e[i].hi, j - i, e[i].face, e[i + 1].face, e[i + 2].face);
        else if (e[i].forward == e[i + 1].forward)
            rc = rk_fail(err, "%s: inconsistently oriented: faces %d and %d both run along edge (%d, %d) from %d to %d",
                         what, e[i].face, e[i + 1].face, e[i].lo, e[i].hi, e[i].forward ? e[i].lo : e[i].hi,
                         e[i].forward ? e[i].hi : e[i].lo);
        i = j;
    }
    free(e);
    return rc;
}

/* 0: fine; INSIDE_OUT: fine except that the volume is negative; -1: anything else. */
static int check(const rk_surface *s, const char *what, rk_error *err)
{
    if (check_faces(s, what, err) || check_edges(s, what, err)) return -1;
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (int i = 0; i < 3 * s->nf; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], s->X[3 * (size_t)s->tris[i] + k]);
            hi[k] = fmax(hi[k], s->X[3 * (size_t)s->tris[i] + k]);
        }
    double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    double vol = rk_surface_volume(s), flat = 1e-12 * diag * diag * diag;
    if (fabs(vol) <= flat) return rk_fail(err, "%s: encloses no volume (%g)", what, vol);
    if (vol < 0) {
        rk_fail(err, "%s: inside out: the enclosed volume is negative (%g), the faces wind clockwise seen from outside",
                what, vol);
        return INSIDE_OUT;
    }
    return 0;
}

int rk_surface_check(const rk_surface *s, const char *what, rk_error *err)
{
    return check(s, what, err) ? -1 : 0;
}

int rk_surface_check_and_orient(rk_surface *s, const char *what, int *flipped, rk_error *err)
{
    if (flipped) *flipped = 0;
    int rc = check(s, what, err);
    if (rc != INSIDE_OUT) return rc;
    for (int f = 0; f < s->nf; f++) {
        int *t = s->tris + 3 * (size_t)f;
        int swap = t[1];
        t[1] = t[2];
        t[2] = swap;
    }
    if (flipped) *flipped = 1;
    rk_error_clear(err);
    return 0;
}
