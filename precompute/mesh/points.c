/* Point clouds: the vertices of a PLY file (Gaussian-splat PLYs included). */
#include <math.h>
#include <stdlib.h>

#include "mesh/mesh_impl.h"

int rk_points_load(const char *path, double **X, int *n, rk_error *err)
{
    return rk_points_load_tagged(path, X, n, NULL, err);
}

int rk_points_load_tagged(const char *path, double **X, int *n, int **tag, rk_error *err)
{
    rk_surface s;
    *X = NULL;
    *n = 0;
    if (!rk_path_has_ext(path, ".ply")) return rk_fail(err, "%s: point clouds are read from .ply files", path);
    if (rk_read_ply(path, &s, 0, tag, err)) return -1;
    for (int i = 0; i < 3 * s.nv; i++)
        if (!isfinite(s.X[i])) {
            rk_surface_free(&s);
            if (tag) {
                free(*tag);
                *tag = NULL;
            }
            return rk_fail(err, "%s: point %d has a non-finite coordinate", path, i / 3);
        }
    *X = s.X;
    *n = s.nv;
    free(s.tris);
    return 0;
}
