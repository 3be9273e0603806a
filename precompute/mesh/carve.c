/* rk_mesh_carve: voids cut out of a mesh (a pneumatic chamber's cavity, koopman-dmd-log-linear
 * paper Sec. 7.3): the tets whose centroid lies in a box go, and so do the vertices only they used
 * (rk_mesh_check), so the void's walls become boundary faces of the mesh. */
#include <string.h>

#include "mesh/mesh_impl.h"

int rk_mesh_carve(rk_mesh *m, const rk_box *boxes, int nboxes, rk_error *err)
{
    if (nboxes == 0) return 0;
    int kept = 0;
    for (int t = 0; t < m->nt; t++) {
        double c[3] = {0, 0, 0};
        for (int k = 0; k < 4; k++)
            for (int i = 0; i < 3; i++) c[i] += 0.25 * m->X[3 * m->tets[4 * t + k] + i];
        int inside = 0;
        for (int b = 0; b < nboxes && !inside; b++) inside = rk_box_contains(&boxes[b], c, 0);
        if (inside) continue;
        memmove(&m->tets[4 * kept], &m->tets[4 * t], 4 * sizeof(int));
        if (m->tet_tag) m->tet_tag[kept] = m->tet_tag[t];
        kept++;
    }
    if (kept == 0) return rk_fail(err, "the voids hold every tet");
    m->nt = kept;
    return rk_mesh_check(m, "carved mesh", RK_MESH_DROP_FLAT, NULL, err);
}
