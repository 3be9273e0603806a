/* Shared by the contact tests: one mesh of two boxes (object A at the origin, object B shifted),
 * each `size` with `cells` cells a side, B left out when two is 0. */
#ifndef RK_TEST_TWO_BOXES_H
#define RK_TEST_TWO_BOXES_H

#include <stdlib.h>
#include <string.h>

#include "mesh/mesh.h"

/* out: the mesh; first: the objects' first vertices (first[0] = 0, first[1] = B's, first[2] = nv). */
static int two_boxes(const double size[3], const int cells[3], const double shift[3], int two, rk_mesh *out,
                     int first[3], rk_error *err)
{
    rk_mesh a, b;
    memset(out, 0, sizeof *out);
    if (rk_mesh_box(size, cells, &a, err)) return -1;
    if (rk_mesh_box(size, cells, &b, err)) {
        rk_mesh_free(&a);
        return -1;
    }
    rk_mesh_transform(&b, 1, shift);
    int nb = two ? b.nv : 0, tb = two ? b.nt : 0;
    out->nv = a.nv + nb;
    out->nt = a.nt + tb;
    out->X = calloc(3 * (size_t)out->nv, sizeof(double));
    out->tets = calloc(4 * (size_t)out->nt, sizeof(int));
    if (out->X && out->tets) {
        memcpy(out->X, a.X, sizeof(double) * 3 * a.nv);
        memcpy(out->X + 3 * a.nv, b.X, sizeof(double) * 3 * nb);
        memcpy(out->tets, a.tets, sizeof(int) * 4 * a.nt);
        for (int i = 0; i < 4 * tb; i++) out->tets[4 * a.nt + i] = b.tets[i] + a.nv;
    }
    first[0] = 0, first[1] = a.nv, first[2] = out->nv;
    rk_mesh_free(&a), rk_mesh_free(&b);
    return out->X && out->tets ? 0 : rk_fail(err, "two boxes: out of memory");
}

#endif
