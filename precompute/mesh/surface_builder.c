/* Surfaces built a vertex and a polygon at a time (OBJ, OFF, PLY), or from loose triangle corners
 * welded where they coincide (STL, glTF). */
#include <stdlib.h>
#include <string.h>

#include "mesh/mesh_impl.h"

int rk_sb_vertex(rk_surface_builder *b, const double p[3], rk_error *err)
{
    if (b->s.nv >= RK_MESH_MAX_COUNT) return rk_fail(err, "too many vertices (more than %d)", RK_MESH_MAX_COUNT);
    if (rk_grow(&b->s.X, &b->vcap, 3 * ((size_t)b->s.nv + 1), sizeof(double), err)) return -1;
    for (int k = 0; k < 3; k++) b->s.X[3 * (size_t)b->s.nv + k] = p[k];
    b->s.nv++;
    return 0;
}

int rk_sb_polygon(rk_surface_builder *b, const int *idx, int n, rk_error *err)
{
    if (n < 3) return rk_fail(err, "a face needs at least 3 vertices, got %d", n);
    if (b->s.nf > RK_MESH_MAX_COUNT - (n - 2)) return rk_fail(err, "too many faces (more than %d)", RK_MESH_MAX_COUNT);
    if (rk_grow(&b->s.tris, &b->fcap, 3 * ((size_t)b->s.nf + (size_t)(n - 2)), sizeof(int), err)) return -1;
    /* Fan around the first vertex: exact for convex polygons, which is what exporters write. */
    for (int k = 1; k + 1 < n; k++) {
        int *t = b->s.tris + 3 * (size_t)b->s.nf;
        t[0] = idx[0];
        t[1] = idx[k];
        t[2] = idx[k + 1];
        b->s.nf++;
    }
    return 0;
}

typedef struct {
    double p[3];
    int corner;
} corner_point;

static int by_position(const void *a, const void *b)
{
    const double *p = ((const corner_point *)a)->p, *q = ((const corner_point *)b)->p;
    for (int k = 0; k < 3; k++)
        if (p[k] != q[k]) return p[k] < q[k] ? -1 : 1;
    return 0;
}

int rk_surface_weld(const double *corners, int nf, rk_surface *s, rk_error *err)
{
    size_t nc = 3 * (size_t)nf;
    corner_point *cp = rk_calloc(nc, sizeof *cp, err);
    s->tris = rk_calloc(nc, sizeof *s->tris, err);
    s->X = rk_calloc(nc * 3, sizeof *s->X, err);
    if (!cp || !s->tris || !s->X) {
        free(cp);
        return -1;
    }
    for (size_t c = 0; c < nc; c++) {
        memcpy(cp[c].p, corners + 3 * c, sizeof cp[c].p);
        cp[c].corner = (int)c;
    }
    qsort(cp, nc, sizeof *cp, by_position);
    int nv = 0;
    for (size_t c = 0; c < nc; c++) {
        if (c == 0 || by_position(&cp[c - 1], &cp[c]) != 0) memcpy(s->X + 3 * (size_t)nv++, cp[c].p, sizeof cp[c].p);
        s->tris[cp[c].corner] = nv - 1;
    }
    s->nv = nv;
    s->nf = nf;
    free(cp);
    return 0;
}
