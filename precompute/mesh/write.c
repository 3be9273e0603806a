/* rk_mesh_write: dispatch by extension; .obj/.ply/.off/.stl get the boundary surface. */
#include <stdlib.h>

#include "mesh/mesh_impl.h"

int rk_mesh_validate_for_write(const char *path, const rk_mesh *m, rk_error *err)
{
    if (m->nv <= 0 || m->nt <= 0 || !m->X || !m->tets)
        return rk_fail(err, "%s: nothing to write (%d vertices, %d tets)", path, m->nv, m->nt);
    for (size_t i = 0; i < 4 * (size_t)m->nt; i++)
        if (m->tets[i] < 0 || m->tets[i] >= m->nv)
            return rk_fail(err, "%s: tet %zu references vertex %d of %d", path, i / 4, m->tets[i], m->nv);
    return 0;
}

/* The boundary with only the vertices it uses, renumbered. */
static int write_boundary(const char *path, const rk_mesh *m, const double *X, rk_error *err)
{
    rk_surface s = {0};
    int *remap = NULL;
    if (rk_mesh_boundary(m, &s.tris, &s.nf, err)) return rk_error_prefix(err, "%s", path);
    remap = rk_calloc((size_t)m->nv, sizeof *remap, err);
    s.X = rk_calloc((size_t)m->nv * 3, sizeof *s.X, err);
    int rc = -1;
    if (remap && s.X) {
        for (int i = 0; i < m->nv; i++) remap[i] = -1;
        for (size_t i = 0; i < 3 * (size_t)s.nf; i++) {
            int v = s.tris[i];
            if (remap[v] < 0) {
                for (int k = 0; k < 3; k++) s.X[3 * (size_t)s.nv + k] = X[3 * (size_t)v + k];
                remap[v] = s.nv++;
            }
            s.tris[i] = remap[v];
        }
        rc = rk_surface_write(path, &s, err);
    }
    free(remap);
    rk_surface_free(&s);
    return rc;
}

static int write_any(const char *path, const rk_mesh *m, const double *x, int binary, rk_error *err)
{
    if (rk_mesh_validate_for_write(path, m, err)) return -1;
    const double *X = x ? x : m->X;
    if (rk_path_has_ext(path, ".mesh")) return rk_write_medit(path, m, X, err);
    if (rk_path_has_ext(path, ".vtk")) return rk_write_vtk(path, m, X, binary, err);
    if (rk_path_has_ext(path, ".msh")) return rk_write_gmsh(path, m, X, binary, err);
    if (rk_path_has_ext(path, ".node") || rk_path_has_ext(path, ".ele")) return rk_write_tetgen(path, m, X, err);
    if (rk_path_has_ext(path, ".obj") || rk_path_has_ext(path, ".ply") || rk_path_has_ext(path, ".off") ||
        rk_path_has_ext(path, ".stl"))
        return write_boundary(path, m, X, err);
    return rk_fail(err, "%s: unknown output format (expected .mesh, .vtk, .msh, .node, .obj, .ply, .off or .stl)", path);
}

int rk_mesh_write(const char *path, const rk_mesh *m, const double *x, rk_error *err)
{
    return write_any(path, m, x, 0, err);
}

int rk_mesh_write_binary(const char *path, const rk_mesh *m, const double *x, rk_error *err)
{
    return write_any(path, m, x, 1, err);
}
