/* rk_basis_join: one skinning basis per object, side by side (basis.h). */
#include "basis/basis.h"

#include <stdlib.h>
#include <string.h>

#include "util/util.h"

int rk_basis_join(rk_basis *parts, int nparts, const int *first_vertex, const double *X, int nv, rk_basis *out,
                  rk_error *err)
{
    memset(out, 0, sizeof *out);
    out->nparts = nparts;
    out->part = parts;
    out->part_vertex = rk_calloc((size_t)nparts + 1, sizeof(int), err);
    out->part_handle = rk_calloc((size_t)nparts + 1, sizeof(int), err);
    if (!out->part_vertex || !out->part_handle) goto fail;
    for (int k = 0; k < nparts; k++) {
        if (!parts[k].W || parts[k].n != first_vertex[k + 1] - first_vertex[k]) {
            rk_fail(err, "joining bases: part %d is not a skinning basis over its object's %d vertices", k,
                    first_vertex[k + 1] - first_vertex[k]);
            goto fail;
        }
        out->part_vertex[k] = first_vertex[k];
        out->part_handle[k + 1] = out->part_handle[k] + parts[k].m;
        out->nvalues += parts[k].nvalues;
        out->nzero += parts[k].nzero;
        out->damped_points += parts[k].damped_points;
    }
    out->part_vertex[nparts] = first_vertex[nparts];
    int H = out->part_handle[nparts];
    out->type = parts[0].type;
    out->n = nv;
    out->m = H;
    out->r = 12 * H;
    out->W = rk_calloc((size_t)nv * H, sizeof(double), err);
    out->U = rk_calloc(3 * (size_t)nv * out->r, sizeof(double), err);
    out->values = rk_calloc((size_t)out->nvalues + 1, sizeof(double), err);
    if (!out->W || !out->U || !out->values) goto fail;
    for (int k = 0, at = 0; k < nparts; k++) {
        const rk_basis *p = &parts[k];
        for (int j = 0; j < p->m; j++)
            for (int i = 0; i < p->n; i++)
                out->W[(size_t)(first_vertex[k] + i) + (size_t)nv * (out->part_handle[k] + j)] = p->W[(size_t)i + (size_t)p->n * j];
        memcpy(out->values + at, p->values, sizeof(double) * p->nvalues);
        at += p->nvalues;
    }
    rk_skinning_to_U(out->W, nv, H, X, out->U);
    return 0;
fail:
    rk_basis_free(out);
    return -1;
}
