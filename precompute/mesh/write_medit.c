/* MEDIT .mesh writer (ASCII, 1-based, refs from tet_tag). */
#include "mesh/mesh_impl.h"
#include "util/util.h"

int rk_write_medit(const char *path, const rk_mesh *m, const double *X, rk_error *err)
{
    rk_atomic_file f;
    if (rk_atomic_open(&f, path, err)) return -1;
    FILE *fp = f.fp;
    fprintf(fp, "MeshVersionFormatted 2\nDimension 3\n\nVertices\n%d\n", m->nv);
    for (size_t i = 0; i < (size_t)m->nv; i++)
        fprintf(fp, "%.17g %.17g %.17g 0\n", X[3 * i], X[3 * i + 1], X[3 * i + 2]);
    fprintf(fp, "\nTetrahedra\n%d\n", m->nt);
    for (size_t t = 0; t < (size_t)m->nt; t++) {
        const int *v = m->tets + 4 * t;
        fprintf(fp, "%d %d %d %d %d\n", v[0] + 1, v[1] + 1, v[2] + 1, v[3] + 1, m->tet_tag ? m->tet_tag[t] : 0);
    }
    fprintf(fp, "\nEnd\n");
    return rk_atomic_commit(&f, err);
}
