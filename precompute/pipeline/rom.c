/* A scene's reduced model (pipeline.h): basis (precompute/basis), exact quadrature, and when asked
 * a trained cubature in its place; with the reasons each size is what it is. */
#include "pipeline/pipeline.h"
#include "pipeline/method_fixed.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/util.h"

static void explain_basis(const rk_rom_entry *o, rk_scene_rom *R)
{
    const rk_scene_basis_info *in = &R->basis_info;
    const char *unit = R->basis.W ? "weights" : "columns";
    int size = R->basis.W ? R->basis.m - 1 - (R->basis.lift_handle != 0) : R->basis.r; /* (m: not the lift) */
    if (o->basis.tolerance > 0 && isfinite(in->projection_error_below))
        snprintf(R->basis_reason, sizeof R->basis_reason,
                 "rom.tolerance %g: %d %s miss the full-order frames by %.3g, one fewer by %.3g", o->basis.tolerance,
                 size, unit, in->projection_error, in->projection_error_below);
    else if (o->basis.tolerance > 0)
        snprintf(R->basis_reason, sizeof R->basis_reason, "rom.tolerance %g: the smallest basis (%d %s) already "
                 "misses the full-order frames by only %.3g", o->basis.tolerance, size, unit, in->projection_error);
    else
        snprintf(R->basis_reason, sizeof R->basis_reason, "rom.size %d", o->basis.size);
}

/* Reduced coordinates of the full-order frames (r x T), for the cubature's training poses. */
static double *reduced_frames(const rk_scene_sim *sim, const rk_scene_rom *R, const double *frames, int T,
                              rk_error *err)
{
    int r = R->basis.r, ndof = 3 * sim->mesh.nv;
    double *q = rk_calloc((size_t)r * (T > 0 ? T : 1), sizeof(double), err);
    rk_sparse M = {0};
    if (!q || rk_sparse_alloc_pattern(&sim->fem, &M, err)) {
        free(q);
        return NULL;
    }
    rk_fem_add_mass(&sim->fem, sim->options.lumped_mass, 1.0, &M);
    rk_fem_add_point_mass(&sim->fem, 1.0, &M);
    for (int t = 0; t < T; t++)
        if (rk_rom_project(&R->model, &M, R->basis.U, ndof, NULL, frames + (size_t)ndof * t, q + (size_t)r * t, err)) {
            free(q);
            q = NULL;
            break;
        }
    rk_sparse_free(&M);
    return q;
}

/* Without full-order frames (a point cloud), the cubature's snapshot poses come from the scene run
 * with the exact reduced model itself: r x *T coordinates, the steps it took (it stops early at a
 * step that fails, keeping what it has). */
static double *reduced_training_run(const rk_scene_sim *sim, rk_scene_rom *R, int *T, rk_error *err)
{
    int r = R->model.r, steps = sim->steps > 0 ? sim->steps : 1;
    double *q = rk_calloc((size_t)r * steps, sizeof(double), err);
    rk_rom s;
    *T = 0;
    if (!q || rk_rom_init(&s, &R->model, NULL, NULL, err)) {
        free(q);
        return NULL;
    }
    rk_error ignored = {{0}};
    while (*T < steps && !rk_rom_step(&s, &ignored)) {
        memcpy(q + (size_t)r * *T, s.q, sizeof(double) * r);
        ++*T;
        rk_progress("cubature training run", *T, steps);
    }
    rk_rom_free(&s);
    return q;
}

/* A copy of a given set (g), or the set trained on the frames (or random poses). */
static int cubature_set(const rk_scene_sim *sim, const rk_rom_entry *o, const double *frames, int T,
                        const rk_scene_rom_given *g, rk_scene_rom *R, rk_cubature_set *set, rk_error *err)
{
    if (g && g->cubature) {
        const rk_cubature_set *c = g->cubature;
        *set = *c;
        set->index = rk_calloc(c->count > 0 ? c->count : 1, sizeof(int), err);
        set->weight = rk_calloc(c->count > 0 ? c->count : 1, sizeof(double), err);
        if (!set->index || !set->weight) {
            rk_cubature_set_free(set);
            return -1;
        }
        memcpy(set->index, c->index, sizeof(int) * c->count);
        memcpy(set->weight, c->weight, sizeof(double) * c->count);
        R->cubature_poses = g->cubature_poses;
        return 0;
    }
    double *q = frames ? reduced_frames(sim, R, frames, T, err) : NULL;
    if (frames && !q) return -1;
    if (!frames && sim->cloud_points) {
        q = reduced_training_run(sim, R, &T, err);
        if (!q) return -1;
        frames = q; /* (only its presence is read below) */
    }
    int rc = rk_cubature_train(&R->model.quad, R->model.M, R->model.mass, q, frames ? T : 0, &o->cub, set,
                               &R->cubature_poses, err);
    free(q);
    return rc ? rk_error_prefix(err, "cubature training") : 0;
}

static int train_cubature(const rk_scene_sim *sim, const rk_rom_entry *o, const double *frames, int T,
                          const rk_scene_rom_given *g, rk_scene_rom *R, rk_error *err)
{
    double t0 = rk_now();
    rk_cubature_set set = {0};
    if (cubature_set(sim, o, frames, T, g, R, &set, err)) return -1;
    int candidates = R->points.n ? R->points.n : sim->mesh.nt;
    if (g && g->cubature && (set.count < 1 || set.count > candidates)) {
        rk_cubature_set_free(&set);
        return rk_fail(err, "the cubature given has %d points, not 1..%d", set.count, candidates);
    }
    for (int i = 0; g && g->cubature && i < set.count; i++)
        if (set.index[i] < 0 || set.index[i] >= candidates || !(set.weight[i] > 0)) {
            rk_fail(err, "the cubature given: point %d (element %d, weight %g) is not an element of this scene with a "
                    "positive weight", i, set.index[i], set.weight[i]);
            rk_cubature_set_free(&set);
            return -1;
        }
    rk_quadrature cub;
    int made = R->points.n ? rk_quadrature_points(&R->points, set.count, set.index, set.weight, &cub, err)
                           : rk_quadrature_elements(&sim->fem, R->basis.U, R->basis.r, set.count, set.index, set.weight,
                                                    &cub, err);
    if (made) {
        rk_cubature_set_free(&set);
        return -1;
    }
    rk_quadrature_free(&R->model.quad);
    R->model.quad = cub;
    R->cubature_points = set.count;
    R->cubature_error = set.relative_error;
    R->cubature_reached = set.reached;
    const char *what = R->points.n ? "integration points" : "elements";
    if (set.reached && set.greedy_count > set.count)
        snprintf(R->cubature_reason, sizeof R->cubature_reason, "rom.cubature.tolerance %g: %d of %d %s "
                 "(pruned from the greedy selection's %d) reproduce the reduced forces of %d training poses to %.3g",
                 o->cub.tolerance, set.count, candidates, what, set.greedy_count, R->cubature_poses, set.relative_error);
    else if (set.reached)
        snprintf(R->cubature_reason, sizeof R->cubature_reason, "rom.cubature.tolerance %g: %d of %d %s "
                 "reproduce the reduced forces of %d training poses to %.3g", o->cub.tolerance, set.count,
                 candidates, what, R->cubature_poses, set.relative_error);
    else
        snprintf(R->cubature_reason, sizeof R->cubature_reason, "%s: stopped at %d of %d %s with force error "
                 "%.3g, above rom.cubature.tolerance %g",
                 o->cub.max_points && set.count >= o->cub.max_points ? "rom.cubature.max_points" : "no further point helped",
                 set.count, candidates, what, set.relative_error, o->cub.tolerance);
    R->cubature_set = set; /* kept: romkit cubature writes it */
    R->seconds_cubature = rk_now() - t0;
    return 0;
}

/* RKPM weights exist anywhere: the shown surfaces' vertices of a scene with a cage get them at
 * their own points, object by object (R->embedded_W, nv x m). */
static int embedded_weights(const rk_scene_sim *sim, rk_scene_rom *R, rk_error *err)
{
    int nv = sim->embedded.nv, m = R->basis.m;
    R->embedded_W = rk_calloc((size_t)nv * m, sizeof(double), err);
    if (!R->embedded_W) return -1;
    for (int k = 0; sim->embedded_first[k] < nv; k++) {
        int first = sim->embedded_first[k], n = sim->embedded_first[k + 1] - first;
        rk_skin_points at;
        if (n == 0) continue;
        if (rk_scene_object_weights(&R->basis, R->basis.nparts ? k : 0, sim->embedded.X + 3 * (size_t)first, n, &at, err))
            return -1;
        for (int j = 0; j < m; j++) memcpy(R->embedded_W + (size_t)nv * j + first, at.W + (size_t)n * j, sizeof(double) * n);
        rk_skin_points_free(&at);
    }
    return 0;
}

/* A given basis (U alone) copied into R->basis, checked against the entry and the scene. */
static int given_basis(const rk_scene_sim *sim, const rk_rom_entry *o, const rk_basis *b, rk_scene_rom *R, rk_error *err)
{
    if (b->type != o->basis.type || b->W || b->nparts || b->rkpm)
        return rk_fail(err, "the basis given is a %s basis%s; the entry's is %s, and only modes, modal_derivatives "
                       "and pod bases are taken from a file", rk_basis_type_name(b->type), b->W ? " with weights" : "",
                       rk_basis_type_name(o->basis.type));
    if (b->n != sim->mesh.nv || b->r < 1)
        return rk_fail(err, "the basis given has %d vertices and %d columns; the scene has %d vertices", b->n, b->r,
                       sim->mesh.nv);
    R->basis.type = b->type;
    R->basis.n = b->n;
    R->basis.r = b->r;
    R->basis.U = rk_calloc((size_t)3 * b->n * b->r, sizeof(double), err);
    if (!R->basis.U) return -1;
    memcpy(R->basis.U, b->U, sizeof(double) * 3 * (size_t)b->n * b->r);
    R->basis_info.vertices = sim->mesh.nv;
    R->basis_info.tets = sim->mesh.nt;
    R->basis_info.projection_error = R->basis_info.projection_error_below = NAN;
    snprintf(R->basis_reason, sizeof R->basis_reason, "the basis given (a basis step's file, %d columns)", b->r);
    return 0;
}

int rk_scene_rom_build(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *o, const double *frames,
                       int T, rk_scene_rom *R, rk_error *err)
{
    return rk_scene_rom_build_given(scene, sim, o, frames, T, NULL, R, err);
}

int rk_scene_rom_build_given(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *o,
                             const double *frames, int T, const rk_scene_rom_given *g, rk_scene_rom *R, rk_error *err)
{
    memset(R, 0, sizeof *R);
    R->cubature_error = NAN;
    double t0 = rk_now();
    if (g && g->basis) {
        if (given_basis(sim, o, g->basis, R, err)) {
            rk_scene_rom_free(R);
            return rk_error_prefix(err, "%s", o->name);
        }
    } else {
        if (rk_scene_basis(scene, sim, &o->basis, frames, T, &R->basis, &R->basis_info, err))
            return rk_error_prefix(err, "%s", o->name);
        explain_basis(o, R);
    }
    R->seconds_basis = rk_now() - t0;
    if (R->basis.n != sim->mesh.nv) {
        rk_scene_rom_free(R);
        return rk_fail(err, "%s: the reduced simulator needs a mesh (the basis has %d points, the mesh %d vertices)",
                       o->name, R->basis.n, sim->mesh.nv);
    }
    rk_quadrature exact;
    rk_fom_options opt = sim->options; /* the entry's own penalty on prescribed vertices */
    opt.pin_stiffness = o->pin_stiffness;
    if (R->basis.lift_handle) { /* the moving group rides on the lifting handle, not on the penalty */
        int group = rk_scene_moving_group(sim, err);
        if (group < 0) {
            rk_scene_rom_free(R);
            return rk_error_prefix(err, "%s", o->name);
        }
        opt.lift_group = group + 1;
        opt.lift_handle = R->basis.lift_handle;
    }
    int mesh_free = rk_scene_mesh_free(scene, o);
    rk_mesh_free_options mfo = o->mesh_free;
    if ((mesh_free && (rk_scene_mesh_free_points(scene, sim, &mfo, &R->basis, &R->points, err) ||
                       rk_quadrature_points(&R->points, R->points.n, NULL, NULL, &exact, err))) ||
        (!mesh_free && rk_quadrature_elements(&sim->fem, R->basis.U, R->basis.r, sim->mesh.nt, NULL, NULL, &exact, err)) ||
        rk_rom_model_init(&R->model, &sim->fem, &opt, R->basis.U, R->basis.r, &exact,
                          mesh_free ? &R->points : NULL, err) ||
        /* the app's shapes meet the surface's triangles, as the asset's runtime meets them */
        (o->asset.colliders == RK_COLLIDERS_SURFACE && rk_rom_contact_for_colliders(&R->model, &sim->fem, err))) {
        rk_scene_rom_free(R);
        return rk_error_prefix(err, "%s", o->name);
    }
    if (mesh_free && sim->cloud_points && scene->nobjects == 1) {
        /* the weights' gradients at the cloud's points, for F at each splat (GRAD) */
        rk_skin_points at;
        if (rk_scene_object_weights(&R->basis, 0, sim->mesh.X, sim->cloud_points, &at, err)) {
            rk_scene_rom_free(R);
            return rk_error_prefix(err, "%s: weight gradients at the cloud's points", o->name);
        }
        R->cloud_grad = at.dW; /* (3 n x H, as GRAD stores them) */
        at.dW = NULL;
        rk_skin_points_free(&at);
        R->splat_file = scene->objects[0].file;
    }
    if (R->basis.type == RK_BASIS_RKPM_SKINNING && sim->embedded.nv && embedded_weights(sim, R, err)) {
        rk_scene_rom_free(R);
        return rk_error_prefix(err, "%s: weights at the shown surfaces' vertices", o->name);
    }
    if (mesh_free)
        snprintf(R->cubature_reason, sizeof R->cubature_reason, "no rom.cubature: exact integration over all %d "
                 "mesh-free integration points", R->points.n);
    else
        snprintf(R->cubature_reason, sizeof R->cubature_reason, "no rom.cubature: exact integration over all %d elements",
                 sim->mesh.nt);
    if (o->cubature && train_cubature(sim, o, frames, T, g, R, err)) {
        rk_scene_rom_free(R);
        return rk_error_prefix(err, "%s", o->name);
    }
    if (rk_scene_rom_volume(scene, sim, o, R, err)) {
        rk_scene_rom_free(R);
        return -1;
    }
    return 0;
}

int rk_scene_mesh_free(const rk_scene *scene, const rk_rom_entry *o)
{
    return o->mesh_free.enabled || rk_scene_clouds(scene) > 0;
}

void rk_scene_rom_free(rk_scene_rom *R)
{
    rk_rom_model_free(&R->model);
    rk_skin_points_free(&R->points);
    free(R->cloud_grad);
    R->cloud_grad = NULL;
    free(R->embedded_W);
    R->embedded_W = NULL;
    rk_basis_free(&R->basis);
    rk_scene_basis_info_free(&R->basis_info);
    rk_cubature_set_free(&R->cubature_set);
}

rk_asset_rom rk_scene_asset_rom(const rk_scene_sim *sim, const rk_scene_rom *R)
{
    int skinning = R->basis.type == RK_BASIS_SKINNING || R->basis.type == RK_BASIS_RKPM_SKINNING;
    int cloud = R->points.n && sim->fem.nt == 0; /* a point cloud: its points are the mesh's first vertices */
    return (rk_asset_rom){&sim->mesh, &sim->fem, R->basis.U, &R->model, skinning ? R->basis.r / 12 : 0,
                          R->points.n ? &R->points : NULL, cloud ? sim->cloud_points : 0, cloud ? R->cloud_grad : NULL,
                          cloud ? R->splat_file : NULL, NULL, sim->embedded.nv ? &sim->embedded : NULL,
                          R->embedded_W, NULL};
}
