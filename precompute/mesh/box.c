/* rk_mesh_box: a structured box of hexahedral cells, each split into 6 tets (Kuhn /
 * Freudenthal split). Every tet of a cell runs along the cell's main diagonal, from the
 * (0,0,0) corner to (1,1,1), stepping one axis at a time in one of the 6 axis orders. Each
 * cell face is then cut along the diagonal from its lowest to its highest corner, the same
 * cut the neighbour sharing the face makes: the mesh is conforming. */
#include <math.h>
#include <stdint.h>

#include "mesh/mesh_impl.h"

int rk_mesh_box(const double size[3], const int cells[3], rk_mesh *m, rk_error *err)
{
    *m = (rk_mesh){0};
    for (int k = 0; k < 3; k++) {
        if (!(size[k] > 0) || !isfinite(size[k])) return rk_fail(err, "box: size %g is not positive", size[k]);
        if (cells[k] < 1) return rk_fail(err, "box: %d cells along an axis (need at least 1)", cells[k]);
    }
    int64_t nx = cells[0], ny = cells[1], nz = cells[2];
    int64_t nv = (nx + 1) * (ny + 1) * (nz + 1), nt = 6 * nx * ny * nz; /* each factor < 2^31: no overflow */
    if (nv > RK_MESH_MAX_COUNT || nt > RK_MESH_MAX_COUNT)
        return rk_fail(err, "box: %d x %d x %d cells is too many", cells[0], cells[1], cells[2]);
    m->X = rk_calloc((size_t)nv * 3, sizeof *m->X, err);
    m->tets = rk_calloc((size_t)nt * 4, sizeof *m->tets, err);
    if (!m->X || !m->tets) {
        rk_mesh_free(m);
        return -1;
    }
    m->nv = (int)nv;
    m->nt = (int)nt;
    for (int64_t k = 0, v = 0; k <= nz; k++)
        for (int64_t j = 0; j <= ny; j++)
            for (int64_t i = 0; i <= nx; i++, v++) {
                m->X[3 * v + 0] = size[0] * (double)i / (double)nx;
                m->X[3 * v + 1] = size[1] * (double)j / (double)ny;
                m->X[3 * v + 2] = size[2] * (double)k / (double)nz;
            }
    /* Axis orders; the odd permutations would be negatively oriented, so their last two
     * vertices are swapped (flag 1). */
    static const int order[6][4] = {{0, 1, 2, 0}, {1, 2, 0, 0}, {2, 0, 1, 0}, {0, 2, 1, 1}, {2, 1, 0, 1}, {1, 0, 2, 1}};
    const int64_t step[3] = {1, nx + 1, (nx + 1) * (ny + 1)};
    int *t = m->tets;
    for (int64_t k = 0; k < nz; k++)
        for (int64_t j = 0; j < ny; j++)
            for (int64_t i = 0; i < nx; i++) {
                int64_t base = i * step[0] + j * step[1] + k * step[2];
                for (int p = 0; p < 6; p++) {
                    int64_t v1 = base + step[order[p][0]], v2 = v1 + step[order[p][1]], v3 = v2 + step[order[p][2]];
                    t[0] = (int)base;
                    t[1] = (int)v1;
                    t[2] = (int)(order[p][3] ? v3 : v2);
                    t[3] = (int)(order[p][3] ? v2 : v3);
                    t += 4;
                }
            }
    return 0;
}
