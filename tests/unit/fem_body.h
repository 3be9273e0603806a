/* Test fixture shared by the fem and fom tests: a mesh with one material everywhere, built into
 * an rk_fem. */
#ifndef RK_TEST_FEM_BODY_H
#define RK_TEST_FEM_BODY_H

#include <stdlib.h>

#include "fem/fem.h"

typedef struct {
    rk_mesh m;
    rk_fem f;
} fem_body;

/* rk_fem_init over b->m (already filled) with `mat` on every element. */
static inline int fem_body_init(fem_body *b, rk_material mat, rk_error *err)
{
    rk_material *mats = calloc((size_t)b->m.nt, sizeof *mats);
    if (!mats) return rk_fail(err, "out of memory");
    for (int t = 0; t < b->m.nt; t++) mats[t] = mat;
    int rc = rk_fem_init(&b->f, &b->m, mats, err);
    free(mats);
    return rc;
}

/* The box [0, size] of cells hexahedra (6 tets each), one material. */
static inline int fem_body_box(fem_body *b, double sx, double sy, double sz, int nx, int ny, int nz,
                               rk_material mat, rk_error *err)
{
    double size[3] = {sx, sy, sz};
    int cells[3] = {nx, ny, nz};
    if (rk_mesh_box(size, cells, &b->m, err)) return -1;
    return fem_body_init(b, mat, err);
}

/* Flags (nv bytes) of the vertices with x below `x`: the clamped end of a cantilever. */
static inline unsigned char *fem_body_fix_x_below(const fem_body *b, double x)
{
    unsigned char *fixed = calloc((size_t)b->m.nv, 1);
    for (int v = 0; v < b->m.nv; v++) fixed[v] = b->m.X[3 * v] < x;
    return fixed;
}

static inline void fem_body_free(fem_body *b)
{
    rk_fem_free(&b->f);
    rk_mesh_free(&b->m);
}

#endif
