/* Loading by extension: tet meshes (then rk_mesh_check) and surfaces. */
#include <stdlib.h>

#include "mesh/mesh_impl.h"

int rk_path_is_surface(const char *path)
{
    return rk_path_has_ext(path, ".obj") || rk_path_has_ext(path, ".off") || rk_path_has_ext(path, ".stl") ||
           rk_path_has_ext(path, ".ply") || rk_path_has_ext(path, ".gltf") || rk_path_has_ext(path, ".glb");
}

/* A file without region information gets tet_tag = NULL. */
static void drop_zero_tags(rk_mesh *m)
{
    if (!m->tet_tag) return;
    for (int t = 0; t < m->nt; t++)
        if (m->tet_tag[t] != 0) return;
    free(m->tet_tag);
    m->tet_tag = NULL;
}

int rk_mesh_load(const char *path, rk_mesh_flat_policy flat, rk_mesh *m, rk_mesh_report *rep, rk_error *err)
{
    int rc;
    *m = (rk_mesh){0};
    if (rk_path_has_ext(path, ".msh")) rc = rk_read_gmsh(path, m, err);
    else if (rk_path_has_ext(path, ".mesh")) rc = rk_read_medit(path, m, err);
    else if (rk_path_has_ext(path, ".node") || rk_path_has_ext(path, ".ele")) rc = rk_read_tetgen(path, m, err);
    else if (rk_path_has_ext(path, ".vtk")) rc = rk_read_vtk(path, m, err);
    else if (rk_path_is_surface(path))
        return rk_fail(err, "%s: is a surface mesh, not a tet mesh (tetrahedralize it: romkit mesh IN -o OUT)", path);
    else return rk_fail(err, "%s: unknown tet mesh format (expected .msh, .mesh, .node/.ele or .vtk)", path);
    if (rc == 0) {
        drop_zero_tags(m);
        rc = rk_mesh_check(m, path, flat, rep, err);
    }
    if (rc) rk_mesh_free(m);
    return rc;
}

void rk_mesh_free(rk_mesh *m)
{
    free(m->X);
    free(m->tets);
    free(m->tet_tag);
    free(m->ghost);
    *m = (rk_mesh){0};
}

int rk_surface_load(const char *path, rk_surface *s, rk_error *err)
{
    int rc;
    *s = (rk_surface){0};
    if (rk_path_has_ext(path, ".obj")) rc = rk_read_obj(path, s, err);
    else if (rk_path_has_ext(path, ".off")) rc = rk_read_off(path, s, err);
    else if (rk_path_has_ext(path, ".stl")) rc = rk_read_stl(path, s, err);
    else if (rk_path_has_ext(path, ".ply")) rc = rk_read_ply(path, s, 1, NULL, err);
    else if (rk_path_has_ext(path, ".gltf") || rk_path_has_ext(path, ".glb")) rc = rk_read_gltf(path, s, err);
    else return rk_fail(err, "%s: unknown surface format (expected .obj, .off, .stl, .ply, .gltf or .glb)", path);
    if (rc == 0 && s->nf == 0) rc = rk_fail(err, "%s: no faces", path);
    for (int i = 0; rc == 0 && i < 3 * s->nf; i++)
        if (s->tris[i] < 0 || s->tris[i] >= s->nv)
            rc = rk_fail(err, "%s: face %d references vertex %d, but there are %d vertices", path, i / 3, s->tris[i], s->nv);
    if (rc) rk_surface_free(s);
    return rc;
}

void rk_surface_free(rk_surface *s)
{
    free(s->X);
    free(s->tris);
    *s = (rk_surface){0};
}
