/* A point cloud's Gaussian splats moved by the reduced simulator (pipeline.h, rk_scene_splats_*): F at
 * each splat from the skinning weights as the mesh-free integration forms it, the splats deformed and
 * written by the one 3DGS writer (rk_splats_write). */
#include "pipeline/pipeline.h"
#include "pipeline/method_fixed.h"

#include <stdlib.h>
#include <string.h>

#include "util/util.h"

int rk_scene_splats_open(const rk_scene *scene, const rk_scene_sim *sim, const rk_scene_rom *R, int k,
                         rk_scene_splats *o, rk_error *err)
{
    memset(o, 0, sizeof *o);
    if (k < 0 || k >= scene->nobjects || scene->objects[k].shape != RK_SHAPE_POINTS || !sim->object_points)
        return rk_fail(err, "%s: objects[%d] is not a point cloud: it has no splats", scene->path, k);
    const rk_scene_object *obj = &scene->objects[k];
    o->object = k;
    o->v0 = sim->object_first_vertex[k];
    o->scale = obj->scale;
    int n = sim->object_points[k];
    if (rk_splats_read(obj->file, &o->splats, err)) return rk_error_prefix(err, "objects[%d]", k);
    if (!o->splats.has_splat_attributes || o->splats.n != n) {
        rk_fail(err, "%s: %s", obj->file,
                o->splats.has_splat_attributes ? "its splat count is not the object's point count"
                                               : "a plain point cloud (no scale, rot, opacity, f_dc): no splats to move");
        rk_scene_splats_free(o);
        return -1;
    }
    int r = R->model.r;
    o->x = rk_calloc(3 * (size_t)n, sizeof(double), err);
    o->F = rk_calloc(9 * (size_t)n, sizeof(double), err);
    o->G = rk_calloc(9 * (size_t)r, sizeof(double), err);
    if (!o->x || !o->F || !o->G || rk_scene_object_weights(&R->basis, k, sim->mesh.X + 3 * (size_t)o->v0, n, &o->points, err)) {
        rk_scene_splats_free(o);
        return rk_error_prefix(err, "objects[%d] splats", k);
    }
    if (12 * o->points.H != r) {
        rk_scene_splats_free(o);
        return rk_fail(err, "objects[%d] splats: %d weights do not make the model's %d coordinates", k, R->basis.m, r);
    }
    return 0;
}

int rk_scene_splats_write(rk_scene_splats *o, const rk_scene_rom *R, const double *q, const double *x,
                          const char *path, rk_error *err)
{
    int n = o->points.n, r = R->model.r;
    memcpy(o->x, x + 3 * (size_t)o->v0, 3 * (size_t)n * sizeof(double));
    for (int i = 0; i < n; i++) {
        double *F = o->F + 9 * (size_t)i;
        rk_skin_points_G(&o->points, i, o->G);
        for (int a = 0; a < 9; a++) {
            const double *row = o->G + (size_t)r * a;
            double v = a % 4 == 0 ? 1.0 : 0.0;
            for (int j = 0; j < r; j++) v += row[j] * q[j];
            F[a] = o->scale * v; /* the file's covariances are in its own units: world = scale x file */
        }
    }
    return rk_splats_write(path, &o->splats, o->x, o->F, err);
}

void rk_scene_splats_free(rk_scene_splats *o)
{
    rk_splats_free(&o->splats);
    rk_skin_points_free(&o->points);
    free(o->x);
    free(o->F);
    free(o->G);
    memset(o, 0, sizeof *o);
}
