/* Legacy VTK writer (ParaView): ASCII or BINARY (big-endian, as the format requires). */
#include "mesh/mesh_impl.h"
#include "util/util.h"

int rk_write_vtk(const char *path, const rk_mesh *m, const double *X, int binary, rk_error *err)
{
    if (m->nt > INT32_MAX / 5) return rk_fail(err, "%s: too many tets for a VTK cell list", path);
    rk_atomic_file f;
    if (rk_atomic_open(&f, path, err)) return -1;
    FILE *fp = f.fp;
    fprintf(fp, "# vtk DataFile Version 3.0\nromkit tet mesh\n%s\nDATASET UNSTRUCTURED_GRID\n",
            binary ? "BINARY" : "ASCII");
    fprintf(fp, "POINTS %d double\n", m->nv);
    for (size_t i = 0; i < 3 * (size_t)m->nv; i += 3) {
        if (binary)
            for (int k = 0; k < 3; k++) rk_put_f64(fp, X[i + k], 1);
        else fprintf(fp, "%.17g %.17g %.17g\n", X[i], X[i + 1], X[i + 2]);
    }
    fprintf(fp, "%sCELLS %d %d\n", binary ? "\n" : "", m->nt, 5 * m->nt);
    for (size_t t = 0; t < (size_t)m->nt; t++) {
        const int *v = m->tets + 4 * t;
        if (binary) {
            rk_put_i32(fp, 4, 1);
            for (int k = 0; k < 4; k++) rk_put_i32(fp, v[k], 1);
        } else {
            fprintf(fp, "4 %d %d %d %d\n", v[0], v[1], v[2], v[3]);
        }
    }
    fprintf(fp, "%sCELL_TYPES %d\n", binary ? "\n" : "", m->nt);
    for (int t = 0; t < m->nt; t++) {
        if (binary) rk_put_i32(fp, 10, 1);
        else fputs("10\n", fp);
    }
    if (m->tet_tag) {
        fprintf(fp, "%sCELL_DATA %d\nSCALARS tag int 1\nLOOKUP_TABLE default\n", binary ? "\n" : "", m->nt);
        for (int t = 0; t < m->nt; t++) {
            if (binary) rk_put_i32(fp, m->tet_tag[t], 1);
            else fprintf(fp, "%d\n", m->tet_tag[t]);
        }
    }
    if (binary) fputc('\n', fp);
    return rk_atomic_commit(&f, err);
}
