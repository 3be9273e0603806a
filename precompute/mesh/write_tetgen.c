/* TetGen writer: PATH.node and PATH.ele (0-based; tet_tag as the region attribute). */
#include "mesh/mesh_impl.h"
#include "util/util.h"

int rk_write_tetgen(const char *path, const rk_mesh *m, const double *X, rk_error *err)
{
    char node_path[4096], ele_path[4096];
    if (rk_path_with_ext(path, ".node", node_path, sizeof node_path, err) ||
        rk_path_with_ext(path, ".ele", ele_path, sizeof ele_path, err))
        return -1;
    rk_atomic_file node, ele;
    if (rk_atomic_open(&node, node_path, err)) return -1;
    if (rk_atomic_open(&ele, ele_path, err)) {
        rk_atomic_abort(&node);
        return -1;
    }
    fprintf(node.fp, "%d 3 0 0\n", m->nv);
    for (size_t i = 0; i < (size_t)m->nv; i++)
        fprintf(node.fp, "%zu %.17g %.17g %.17g\n", i, X[3 * i], X[3 * i + 1], X[3 * i + 2]);
    fprintf(ele.fp, "%d 4 %d\n", m->nt, m->tet_tag ? 1 : 0);
    for (size_t t = 0; t < (size_t)m->nt; t++) {
        const int *v = m->tets + 4 * t;
        fprintf(ele.fp, "%zu %d %d %d %d", t, v[0], v[1], v[2], v[3]);
        if (m->tet_tag) fprintf(ele.fp, " %d", m->tet_tag[t]);
        fputc('\n', ele.fp);
    }
    fprintf(node.fp, "# written by romkit\n");
    fprintf(ele.fp, "# written by romkit\n");
    if (rk_atomic_commit(&node, err)) {
        rk_atomic_abort(&ele);
        return -1;
    }
    return rk_atomic_commit(&ele, err);
}
