/* A mesh-free entry's integration points (pipeline.h, rk_scene_mesh_free_points): where the
 * elastic energy and the mass are integrated (freeform paper Eq. 22), each with its volume, its
 * material and the skinning weights with their gradients (Eq. 21) from the basis's RKPM kernels,
 * object by object (an object's points carry only its own handles' weights). */
#include "pipeline/pipeline.h"
#include "pipeline/method_fixed.h"

#include <stdlib.h>
#include <string.h>

#include "util/util.h"

static int sample(const rk_scene_object *obj, const rk_object_view *ov, const rk_mesh_free_options *o,
                  rk_rkpm_points *pts, rk_error *err)
{
    if (obj->shape == RK_SHAPE_POINTS) { /* (its own points whatever a scene with meshes samples them by) */
        if (o->sampling_given && o->sampling != RK_SAMPLING_CLOUD)
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

/* Basis b's weights and gradients at the n points X (3n) of object k into P's rows at .. at + n - 1:
 * the object's own handles' columns (part k's, from part_handle[k] on, for several objects); the
 * other objects' columns stay 0. */
static int object_weights(const rk_basis *b, int k, const double *X, int n, int at, rk_skin_points *P, rk_error *err)
{
    const rk_basis *part = b->nparts ? &b->part[k] : b;
    int Hk = part->m, h0 = b->nparts ? b->part_handle[k] : 0, damped = 0;
    double *W = rk_calloc((size_t)n * Hk, sizeof(double), err), *dW = rk_calloc(3 * (size_t)n * Hk, sizeof(double), err);
    int rc = !W || !dW || rk_rkpm_interpolate(part->rkpm, X, n, part->C, Hk, W, dW, &damped, err) ? -1 : 0;
    for (int i = 0; !rc && i < n; i++)
        for (int j = 0; j < Hk; j++) {
            size_t p = (size_t)at + i;
            P->W[p + (size_t)P->n * (h0 + j)] = W[(size_t)i + (size_t)n * j];
            for (int c = 0; c < 3; c++)
                P->dW[3 * p + c + 3 * (size_t)P->n * (h0 + j)] = dW[3 * (size_t)i + c + 3 * (size_t)n * j];
        }
    free(W);
    free(dW);
    return rc;
}

/* Object k's n sampled points into P from row `at` on: position, volume, material, and its own
 * handles' weights and gradients. */
static int fill_object(const rk_scene *scene, const rk_scene_sim *sim, const rk_mesh_free_options *o, const rk_basis *b,
                       int k, const rk_rkpm_points *pts, int at, rk_skin_points *P, rk_error *err)
{
    int n = pts->n;
    if (object_weights(b, k, pts->X, n, at, P, err)) return -1;
    double sum = 0;
    for (int i = 0; i < n; i++) sum += pts->weight[i];
    for (int i = 0; i < n; i++) {
        int p = at + i;
        memcpy(P->X + 3 * (size_t)p, pts->X + 3 * (size_t)i, 3 * sizeof(double));
        /* the given volume, shared as the sampling shared its estimate */
        P->volume[p] = o->volume > 0 ? pts->weight[i] * o->volume / sum : pts->weight[i];
        rk_material mat = rk_scene_sample_material(scene, sim, k, pts, i);
        P->model[p] = mat.model;
        P->density[p] = mat.density;
        rk_lame(mat.young, mat.poisson, &P->mu[p], &P->lambda[p]);
    }
    return 0;
}

static int rkpm_basis(const rk_basis *b)
{
    return b->type == RK_BASIS_RKPM_SKINNING && (b->nparts || (b->rkpm && b->C));
}

int rk_scene_object_weights(const rk_basis *b, int k, const double *X, int n, rk_skin_points *P, rk_error *err)
{
    memset(P, 0, sizeof *P);
    if (!rkpm_basis(b) || (b->nparts && (k < 0 || k >= b->nparts)) || (!b->nparts && k != 0) || n < 1)
        return rk_fail(err, "weights at %d points of object %d: needs an rkpm_skinning basis over that object", n, k);
    P->n = n;
    P->H = b->m;
    P->X = rk_calloc(3 * (size_t)n, sizeof(double), err);
    P->W = rk_calloc((size_t)n * P->H, sizeof(double), err);
    P->dW = rk_calloc(3 * (size_t)n * P->H, sizeof(double), err);
    if (!P->X || !P->W || !P->dW || object_weights(b, k, X, n, 0, P, err)) {
        rk_skin_points_free(P);
        return -1;
    }
    memcpy(P->X, X, 3 * (size_t)n * sizeof(double));
    return 0;
}

int rk_scene_mesh_free_points(const rk_scene *scene, const rk_scene_sim *sim, const rk_mesh_free_options *o,
                              const rk_basis *b, rk_skin_points *P, rk_error *err)
{
    memset(P, 0, sizeof *P);
    if (!rkpm_basis(b))
        return rk_fail(err, "mesh-free integration needs an rkpm_skinning basis (weights with gradients anywhere)");
    int nobj = scene->nobjects, rc = -1, sampled = 0;
    rk_rkpm_points *pts = rk_calloc((size_t)nobj, sizeof *pts, err);
    if (!pts) return -1;
    for (; sampled < nobj; sampled++) { /* every object's points first, then one allocation */
        rk_object_view ov;
        if (rk_scene_object_view(sim, sampled, &ov, err)) goto out;
        int bad = sample(&scene->objects[sampled], &ov, o, &pts[sampled], err);
        free(ov.mesh.tets);
        if (bad) {
            rk_error_prefix(err, "objects[%d]", sampled);
            goto out;
        }
        P->n += pts[sampled].n;
    }
    size_t n = (size_t)P->n;
    P->H = b->m;
    P->X = rk_calloc(3 * n, sizeof(double), err);
    P->W = rk_calloc(n * P->H, sizeof(double), err);
    P->dW = rk_calloc(3 * n * P->H, sizeof(double), err);
    P->volume = rk_calloc(n, sizeof(double), err);
    P->density = rk_calloc(n, sizeof(double), err);
    P->model = rk_calloc(n, sizeof *P->model, err);
    P->mu = rk_calloc(n, sizeof(double), err);
    P->lambda = rk_calloc(n, sizeof(double), err);
    if (!P->X || !P->W || !P->dW || !P->volume || !P->density || !P->model || !P->mu || !P->lambda) goto out;
    for (int k = 0, at = 0; k < nobj; at += pts[k].n, k++)
        if (fill_object(scene, sim, o, b, k, &pts[k], at, P, err)) {
            rk_error_prefix(err, "objects[%d]", k);
            goto out;
        }
    rc = 0;
out:
    for (int k = 0; k < sampled; k++) rk_rkpm_points_free(&pts[k]);
    free(pts);
    if (rc) {
        rk_skin_points_free(P);
        rk_error_prefix(err, "mesh-free integration points");
    }
    return rc;
}
