/* A mesh-free entry's integration points (pipeline.h, rk_scene_mesh_free_points): where the
 * elastic energy and the mass are integrated (freeform paper Eq. 22), each with its volume, its
 * material and the skinning weights with their gradients (Eq. 21) from the basis's RKPM kernels,
 * object by object (an object's points carry only its own handles' weights). */
#include "pipeline/pipeline.h"

#include <stdlib.h>
#include <string.h>

#include "util/util.h"

static int sample(const rk_scene_object *obj, const rk_object_view *ov, const rk_mesh_free_options *o,
                  rk_rkpm_points *pts, rk_error *err)
{
    if (obj->shape == RK_SHAPE_POINTS) {
        if (o->sampling != RK_SAMPLING_CLOUD)
            return rk_fail(err, "a point cloud has no inside to sample a grid or random points in; mesh_free.sampling "
                           "must be cloud");
        return rk_rkpm_sample_cloud(ov->mesh.X, ov->points, o->points, pts, err);
    }
    switch (o->sampling) {
    case RK_SAMPLING_GRID: return rk_rkpm_sample_mesh(&ov->mesh, o->points, pts, err);
    case RK_SAMPLING_RANDOM: return rk_rkpm_sample_mesh_random(&ov->mesh, o->points, o->seed, pts, err);
    case RK_SAMPLING_CLOUD: /* the mesh's vertices as a point cloud sampled from it: no tet used */
        return rk_rkpm_sample_cloud(ov->mesh.X, ov->mesh.nv, o->points, pts, err);
    }
    return rk_fail(err, "unknown mesh_free.sampling");
}

/* Object k's points appended to P (its columns from handle h0 on, through its own basis part). */
static int add_object(const rk_scene *scene, const rk_scene_sim *sim, const rk_mesh_free_options *o,
                      const rk_basis *part, int h0, int k, rk_skin_points *P, rk_error *err)
{
    rk_object_view ov;
    rk_rkpm_points pts;
    if (rk_scene_object_view(sim, k, &ov, err)) return -1;
    int rc = sample(&scene->objects[k], &ov, o, &pts, err);
    free(ov.mesh.tets);
    if (rc) return rk_error_prefix(err, "objects[%d]", k);
    int n = pts.n, Hk = part->m, at = P->n, total = at + n, H = P->H;
    double *W = rk_calloc((size_t)n * Hk, sizeof(double), err), *dW = rk_calloc(3 * (size_t)n * Hk, sizeof(double), err);
    double *X = realloc(P->X, sizeof(double) * 3 * (size_t)total);
    if (X) P->X = X;
    double *vol = realloc(P->volume, sizeof(double) * (size_t)total);
    if (vol) P->volume = vol;
    double *dens = realloc(P->density, sizeof(double) * (size_t)total);
    if (dens) P->density = dens;
    rk_material_model *model = realloc(P->model, sizeof *model * (size_t)total);
    if (model) P->model = model;
    double *mu = realloc(P->mu, sizeof(double) * (size_t)total);
    if (mu) P->mu = mu;
    double *lambda = realloc(P->lambda, sizeof(double) * (size_t)total);
    if (lambda) P->lambda = lambda;
    int damped = 0;
    rc = -1;
    if (!W || !dW || !X || !vol || !dens || !model || !mu || !lambda)
        rk_fail(err, "out of memory for %d integration points", total);
    else if (!rk_rkpm_interpolate(part->rkpm, pts.X, n, part->C, Hk, W, dW, &damped, err)) {
        double sum = 0;
        for (int i = 0; i < n; i++) sum += pts.weight[i];
        for (int i = 0; i < n; i++) {
            int p = at + i;
            memcpy(P->X + 3 * (size_t)p, pts.X + 3 * (size_t)i, 3 * sizeof(double));
            /* the given volume, shared as the sampling shared its estimate */
            P->volume[p] = o->volume > 0 ? pts.weight[i] * o->volume / sum : pts.weight[i];
            rk_material mat = rk_scene_material_at(&scene->objects[k], pts.X + 3 * (size_t)i);
            P->model[p] = mat.model;
            P->density[p] = mat.density;
            rk_lame(mat.young, mat.poisson, &P->mu[p], &P->lambda[p]);
        }
        P->n = total; /* then the weights, in the grown (total x H) layout */
        rc = 0;
    }
    if (!rc) {
        double *Wn = rk_calloc((size_t)total * H, sizeof(double), err), *dWn = rk_calloc(3 * (size_t)total * H, sizeof(double), err);
        if (!Wn || !dWn) rc = -1;
        else {
            for (int j = 0; j < H; j++) {
                for (int i = 0; i < at; i++) {
                    Wn[(size_t)i + (size_t)total * j] = P->W[(size_t)i + (size_t)at * j];
                    for (int b = 0; b < 3; b++) dWn[3 * (size_t)i + b + 3 * (size_t)total * j] = P->dW[3 * (size_t)i + b + 3 * (size_t)at * j];
                }
            }
            for (int j = 0; j < Hk; j++)
                for (int i = 0; i < n; i++) {
                    Wn[(size_t)(at + i) + (size_t)total * (h0 + j)] = W[(size_t)i + (size_t)n * j];
                    for (int b = 0; b < 3; b++)
                        dWn[3 * (size_t)(at + i) + b + 3 * (size_t)total * (h0 + j)] = dW[3 * (size_t)i + b + 3 * (size_t)n * j];
                }
            free(P->W);
            free(P->dW);
            P->W = Wn;
            P->dW = dWn;
            Wn = dWn = NULL;
        }
        free(Wn);
        free(dWn);
    }
    free(W);
    free(dW);
    rk_rkpm_points_free(&pts);
    return rc ? rk_error_prefix(err, "objects[%d]", k) : 0;
}

int rk_scene_mesh_free_points(const rk_scene *scene, const rk_scene_sim *sim, const rk_mesh_free_options *o,
                              const rk_basis *b, rk_skin_points *P, rk_error *err)
{
    memset(P, 0, sizeof *P);
    if (b->type != RK_BASIS_RKPM_SKINNING || (!b->nparts && (!b->rkpm || !b->C)))
        return rk_fail(err, "mesh-free integration needs an rkpm_skinning basis (weights with gradients anywhere)");
    P->H = b->m;
    for (int k = 0; k < scene->nobjects; k++) {
        const rk_basis *part = b->nparts ? &b->part[k] : b;
        if (add_object(scene, sim, o, part, b->nparts ? b->part_handle[k] : 0, k, P, err)) {
            rk_skin_points_free(P);
            return rk_error_prefix(err, "mesh-free integration points");
        }
    }
    return 0;
}
