/* A mesh-free entry's integration points (pipeline.h, rk_scene_mesh_free_points): where the
 * elastic energy and the mass are integrated (freeform paper Eq. 22), each with its volume, its
 * material and the skinning weights with their gradients (Eq. 21) from the basis's RKPM kernels. */
#include "pipeline/pipeline.h"

#include <stdlib.h>
#include <string.h>

#include "util/util.h"

/* The object a mesh vertex belongs to. */
static int object_of_vertex(const rk_scene_sim *sim, int nobjects, int v)
{
    int k = 0;
    while (k + 1 < nobjects && v >= sim->object_first_vertex[k + 1]) k++;
    return k;
}

static int object_of_tet(const rk_scene_sim *sim, int nobjects, int t)
{
    int k = 0;
    while (k + 1 < nobjects && t >= sim->object_first_tet[k + 1]) k++;
    return k;
}

static int sample(const rk_scene *scene, const rk_scene_sim *sim, const rk_mesh_free_options *o, rk_rkpm_points *pts,
                  rk_error *err)
{
    const rk_scene_object *obj = &scene->objects[0];
    if (obj->shape == RK_SHAPE_POINTS) {
        if (o->sampling != RK_SAMPLING_CLOUD)
            return rk_fail(err, "objects[0] is a point cloud: it has no inside to sample a grid or random points in; "
                           "mesh_free.sampling must be cloud");
        return rk_rkpm_sample_cloud(sim->mesh.X, sim->cloud_points, o->points, pts, err);
    }
    switch (o->sampling) {
    case RK_SAMPLING_GRID: return rk_rkpm_sample_mesh(&sim->mesh, o->points, pts, err);
    case RK_SAMPLING_RANDOM: return rk_rkpm_sample_mesh_random(&sim->mesh, o->points, o->seed, pts, err);
    case RK_SAMPLING_CLOUD: /* the mesh's vertices as a point cloud sampled from it: no tet used */
        return rk_rkpm_sample_cloud(sim->mesh.X, sim->mesh.nv, o->points, pts, err);
    }
    return rk_fail(err, "unknown mesh_free.sampling");
}

int rk_scene_mesh_free_points(const rk_scene *scene, const rk_scene_sim *sim, const rk_mesh_free_options *o,
                              const rk_basis *b, rk_skin_points *P, rk_error *err)
{
    memset(P, 0, sizeof *P);
    if (b->type != RK_BASIS_RKPM_SKINNING || !b->rkpm || !b->C)
        return rk_fail(err, "mesh-free integration needs an rkpm_skinning basis (weights with gradients anywhere)");
    rk_rkpm_points pts;
    if (sample(scene, sim, o, &pts, err)) return rk_error_prefix(err, "mesh-free integration points");
    int n = pts.n, H = b->m;
    P->n = n;
    P->H = H;
    P->X = pts.X;
    P->volume = pts.weight;
    pts.X = NULL;
    pts.weight = NULL;
    P->W = rk_calloc((size_t)n * H, sizeof(double), err);
    P->dW = rk_calloc(3 * (size_t)n * H, sizeof(double), err);
    P->density = rk_calloc((size_t)n, sizeof(double), err);
    P->model = rk_calloc((size_t)n, sizeof *P->model, err);
    P->mu = rk_calloc((size_t)n, sizeof(double), err);
    P->lambda = rk_calloc((size_t)n, sizeof(double), err);
    int damped = 0, rc = -1;
    if (!P->W || !P->dW || !P->density || !P->model || !P->mu || !P->lambda) goto out;
    if (rk_rkpm_interpolate(b->rkpm, P->X, n, b->C, H, P->W, P->dW, &damped, err)) goto out;
    if (o->volume > 0) { /* the given volume, shared as the sampling shared its estimate */
        double sum = 0;
        for (int i = 0; i < n; i++) sum += P->volume[i];
        for (int i = 0; i < n; i++) P->volume[i] *= o->volume / sum;
    }
    for (int i = 0; i < n; i++) {
        int k = pts.tet ? object_of_tet(sim, scene->nobjects, pts.tet[i])
                        : object_of_vertex(sim, scene->nobjects, pts.source ? pts.source[i] : 0);
        rk_material mat = rk_scene_material_at(&scene->objects[k], P->X + 3 * (size_t)i);
        P->model[i] = mat.model;
        P->density[i] = mat.density;
        rk_lame(mat.young, mat.poisson, &P->mu[i], &P->lambda[i]);
    }
    rc = 0;
out:
    rk_rkpm_points_free(&pts);
    if (rc) {
        rk_skin_points_free(P);
        rk_error_prefix(err, "mesh-free integration points");
    }
    return rc;
}
