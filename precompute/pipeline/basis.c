/* A basis for a scene (pipeline.h): constraints from its prescribed boxes, per-element or
 * per-point materials, and full-order training frames from its own simulation when POD or a
 * tolerance asks for them. */
#include "pipeline/pipeline.h"
#include "pipeline/method_fixed.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/util.h"

/* Largest basis tried when only a tolerance is given (columns, or weights for skinning). */
static int default_max(rk_basis_type t)
{
    return t == RK_BASIS_MODES || t == RK_BASIS_POD ? 64 : 32;
}

/* Kernels for a point cloud's own points: at most one per RK_CLOUD_POINTS_PER_KERNEL of them. On a
 * sparse cloud (armadillo_4k's 1,180 vertices) the default 1,000 kernels would put one on almost
 * every point, each covering only its neighbours, and the weights turn rough: the hanging
 * armadillo's error against full order was 2.1x the mesh path's at 1,000 kernels, 1.3x at 393 (one
 * per 3 points), 1.1x at 236 (one per 5), where pulling at its farthest points lost (1.98x, 2.4x):
 * examples/scenes/armadillo_*.json, make paper-table. */
#define RK_CLOUD_POINTS_PER_KERNEL 3
static int cloud_kernels(int kernels, int points, rk_scene_basis_info *info)
{
    int cap = points / RK_CLOUD_POINTS_PER_KERNEL;
    int k = kernels < cap ? kernels : cap < 4 ? 4 : cap;
    info->kernels = k;
    return k;
}

static double lame_sum(const rk_material *m)
{
    double mu, lambda;
    rk_lame(m->young, m->poisson, &mu, &lambda);
    return lambda + 4 * mu; /* Prop. 1 */
}

unsigned char *rk_scene_fixed_vertices(const rk_scene_sim *sim, rk_error *err)
{
    unsigned char *fixed = rk_calloc((size_t)sim->mesh.nv, 1, err);
    if (!fixed) return NULL;
    for (int g = 0; g < sim->options.nprescribed; g++)
        for (int k = 0; k < sim->options.prescribed[g].count && sim->options.prescribed[g].kind == RK_MOTION_FIXED; k++)
            fixed[sim->options.prescribed[g].verts[k]] = 1;
    return fixed;
}

int rk_scene_moving_group(const rk_scene_sim *sim, rk_error *err)
{
    int found = -1;
    for (int g = 0; g < sim->options.nprescribed; g++)
        if (sim->options.prescribed[g].kind != RK_MOTION_FIXED) {
            if (found >= 0)
                return rk_fail(err, "clamp \"lifted\" holds one moving group exactly, and the scene has several (%d and "
                               "%d among its prescribed groups): use clamp \"dirichlet\" (their penalty)", found, g);
            found = g;
        }
    if (found < 0)
        return rk_fail(err, "clamp \"lifted\" needs a moving group to lift, and the scene has none: use clamp "
                       "\"dirichlet\"");
    return found;
}

unsigned char *rk_scene_moving_vertices(const rk_scene_sim *sim, rk_error *err)
{
    int g = rk_scene_moving_group(sim, err);
    if (g < 0) return NULL;
    unsigned char *moving = rk_calloc((size_t)sim->mesh.nv, 1, err);
    if (!moving) return NULL;
    for (int k = 0; k < sim->options.prescribed[g].count; k++) moving[sim->options.prescribed[g].verts[k]] = 1;
    return moving;
}

/* The RKPM skinning eigenmodes of object k alone: integration points from its tets (a grid), its
 * vertices taken as a cloud (from_vertices), or a point cloud's own points; the weights at all its
 * vertices, clamped to its fixed ones (fixed: the scene's flags, or NULL for none) when it has
 * tets. Not yet for a cloud (its own points, or a mesh's vertices taken as one): there the
 * integration points are the cloud's points, the fixed ones included, and a mask that is 0 with
 * zero gradient at them hides the strain of a hinge just past the clamp from every point (the
 * beam of test_pipeline_meshfree_beam, vertices as the cloud, m = 16: 236% / 290% / 134% of beam
 * theory at 525 / 3,321 / 10,309 points; an 80,000-point check sees 8-12x the energy). Such a
 * cloud keeps free weights and the penalty (71% / 78% / 88% there). A null-space constraint on the
 * nodal values instead (sum_k phi_k(X_v) c_k = 0 at every fixed point, Eq. 15 solved densely in
 * that space: the weights keep their gradient at the fixed points) held them to 1e-17 but locked
 * the kernels by the clamp: 29% / 55% / 60%. A cloud clamp needs a better-integrated boundary
 * (smoothed nodal integration, or integration points that are not the cloud's own). */
static int rkpm_object(const rk_scene *scene, const rk_scene_sim *sim, const rk_basis_options *o, int m, int k,
                       const unsigned char *fixed, rk_basis *b, rk_scene_basis_info *info, rk_error *err)
{
    rk_object_view ov;
    if (rk_scene_object_view(sim, k, &ov, err)) return -1;
    const rk_scene_object *obj = &scene->objects[k];
    int cloud = obj->shape == RK_SHAPE_POINTS, rc = -1;
    rk_rkpm_points pts;
    int sampled = cloud ? rk_rkpm_sample_cloud(ov.mesh.X, ov.points, o->integration_points, &pts, err)
                  : o->from_vertices ? rk_rkpm_sample_cloud(ov.mesh.X, ov.mesh.nv, o->integration_points, &pts, err)
                                     : rk_rkpm_sample_mesh(&ov.mesh, o->integration_points, &pts, err);
    if (sampled) {
        free(ov.mesh.tets);
        return -1;
    }
    double *coef = rk_calloc((size_t)pts.n, sizeof(double), err);
    if (coef) {
        for (int i = 0; i < pts.n; i++) {
            rk_material mat = rk_scene_sample_material(scene, sim, k, &pts, i);
            coef[i] = lame_sum(&mat);
        }
        int kernels = cloud || o->from_vertices ? cloud_kernels(o->kernels, pts.n, info) : o->kernels;
        int clamp = fixed && !cloud && !o->from_vertices;
        if (o->clamp_lifted) {
            unsigned char *moving = rk_scene_moving_vertices(sim, err);
            rc = !moving ? -1
                 : cloud || o->from_vertices
                     ? rk_fail(err, "clamp \"lifted\" needs the object's tets (not a point cloud, nor its vertices as one)")
                     : rk_basis_rkpm_skinning_lifted(&pts, coef, kernels, m, ov.mesh.X, ov.mesh.nv, fixed + ov.v0,
                                                     moving + ov.v0, ov.mesh.tets, ov.mesh.nt, b, &info->rkpm, err);
            free(moving);
        } else
            rc = rk_basis_rkpm_skinning(&pts, coef, kernels, m, ov.mesh.X, ov.mesh.nv, clamp ? fixed + ov.v0 : NULL,
                                        ov.mesh.tets, ov.mesh.nt, b, &info->rkpm, err);
    }
    info->integration_points += pts.n;
    free(coef);
    free(ov.mesh.tets);
    rk_rkpm_points_free(&pts);
    return rc ? rk_error_prefix(err, "objects[%d]", k) : 0;
}

/* The scene's RKPM skinning basis: one object's, or each object's own side by side (rk_basis_join:
 * a disconnected body has no single constant weight). */
static int rkpm_scene(const rk_scene *scene, const rk_scene_sim *sim, const rk_basis_options *o, int m,
                      const unsigned char *fixed, rk_basis *b, rk_scene_basis_info *info, rk_error *err)
{
    int n = scene->nobjects;
    if (n == 1) return rkpm_object(scene, sim, o, m, 0, fixed, b, info, err);
    if (o->clamp_lifted)
        return rk_fail(err, "clamp \"lifted\": one object only for now (the scene has %d)", n);
    rk_basis *parts = rk_calloc((size_t)n, sizeof *parts, err);
    if (!parts) return -1;
    for (int k = 0; k < n; k++)
        if (rkpm_object(scene, sim, o, m, k, fixed, &parts[k], info, err)) {
            for (int i = 0; i < k; i++) rk_basis_free(&parts[i]);
            free(parts);
            return -1;
        }
    return rk_basis_join(parts, n, sim->object_first_vertex, sim->mesh.X, sim->mesh.nv, b, err);
}

/* The RKPM skinning basis of a scene with point clouds (meshes beside them, each object its own). */
static int rkpm_on_points(const rk_scene *scene, const rk_scene_sim *sim, const rk_basis_options *o, rk_basis *b,
                          rk_scene_basis_info *info, rk_error *err)
{
    if (o->type != RK_BASIS_RKPM_SKINNING)
        return rk_fail(err, "%s: the scene holds a point cloud: only basis rkpm_skinning works without "
                       "a mesh, not %s", scene->path, rk_basis_type_name(o->type));
    if (o->size == 0)
        return rk_fail(err, "%s: rom.tolerance needs full-order frames, and a point cloud has no mesh "
                       "to simulate: give rom.size", scene->path);
    if (!sim) return rk_fail(err, "%s: a point cloud's basis needs the built scene", scene->path);
    unsigned char *fixed = o->clamp_penalty ? NULL : rk_scene_fixed_vertices(sim, err);
    if (!o->clamp_penalty && !fixed) return -1;
    int rc = rkpm_scene(scene, sim, o, o->size, fixed, b, info, err);
    free(fixed);
    info->vertices = sim->mesh.nv;
    info->X = rk_calloc(3 * (size_t)sim->mesh.nv, sizeof(double), err);
    if (!info->X) rc = -1;
    else memcpy(info->X, sim->mesh.X, sizeof(double) * 3 * sim->mesh.nv);
    return rc;
}

/* The basis of one size (columns, or weights m for skinning). */
static int build_sized(const rk_scene *scene, const rk_scene_sim *sim, const rk_basis_options *o, const unsigned char *fixed,
                       int size, const double *D, int T, const rk_sparse *M, rk_basis *b,
                       rk_scene_basis_info *info, rk_error *err)
{
    int lumped = sim->options.lumped_mass;
    switch (o->type) {
    case RK_BASIS_MODES: return rk_basis_modes(&sim->fem, fixed, lumped, size, b, err);
    case RK_BASIS_MODAL_DERIVATIVES:
        return rk_basis_modal_derivatives(&sim->fem, fixed, lumped, size, o->modes, b, err);
    /* the clamp (issue 37): skinning weights vanish on the fixed region unless rom.clamp is "penalty" */
    case RK_BASIS_SKINNING:
        return scene->nobjects > 1 ? rk_basis_skinning_objects(&sim->fem, o->clamp_penalty ? NULL : fixed, lumped, size,
                                                               sim->object_first_vertex, scene->nobjects, b, err)
                                   : rk_basis_skinning(&sim->fem, o->clamp_penalty ? NULL : fixed, lumped, size, b, err);
    case RK_BASIS_RKPM_SKINNING: return rkpm_scene(scene, sim, o, size, o->clamp_penalty ? NULL : fixed, b, info, err);
    case RK_BASIS_POD: {
        int max_r = size < T ? size : T;
        if (o->size && o->size > T)
            return rk_fail(err, "POD: size %d is more than the %d full-order frames the scene runs",
                           o->size, T);
        return rk_basis_pod(D, sim->mesh.nv, T, M, max_r, o->tolerance, b, err);
    }
    }
    return rk_fail(err, "unknown basis type");
}

/* Smallest prefix meeting the tolerance (POD chose its own size already). */
static int meet_tolerance(const rk_basis_options *o, rk_basis *b, const double *D, int T,
                          const rk_sparse *M, rk_scene_basis_info *info, rk_error *err)
{
    if (b->nparts && o->tolerance > 0)
        return rk_fail(err, "rom.tolerance: a scene of several objects takes rom.size (each object gets that many weights)");
    int group = b->W ? 12 : 1, ng = b->r / group;
    double *e = rk_calloc((size_t)ng, sizeof(double), err);
    if (!e || rk_projection_errors(b->U, 3 * b->n, b->r, group, D, T, M, e, err)) { free(e); return -1; }
    int g = 0;
    if (o->tolerance > 0 && o->type != RK_BASIS_POD) {
        while (g < ng - 1 && e[g] > o->tolerance) g++;
        info->projection_error_below = g > 0 ? e[g - 1] : NAN;
        if (e[g] > o->tolerance) {
            double best = e[ng - 1];
            free(e);
            return rk_fail(err, "tolerance %g not met: the largest %s basis tried (%d columns) still "
                           "misses the full-order frames by %.3g (relative); raise rom.size or the "
                           "tolerance", o->tolerance, rk_basis_type_name(o->type), b->r, best);
        }
        rk_basis_truncate(b, (g + 1) * group);
    } else {
        g = ng - 1;
        info->projection_error_below = g > 0 ? e[g - 1] : NAN;
    }
    info->projection_error = e[g];
    free(e);
    return 0;
}

int rk_scene_basis(const rk_scene *scene, const rk_scene_sim *sim, const rk_basis_options *o, const double *frames,
                   int T_given, rk_basis *b, rk_scene_basis_info *info, rk_error *err)
{
    memset(info, 0, sizeof *info);
    memset(b, 0, sizeof *b);
    info->projection_error = info->projection_error_below = NAN;
    info->kernels = o->type == RK_BASIS_RKPM_SKINNING ? o->kernels : 0; /* (a cloud's: cloud_kernels) */
    double t0 = rk_now();
    if (rk_scene_clouds(scene) > 0) {
        int rc = rkpm_on_points(scene, sim, o, b, info, err);
        info->seconds_basis = rk_now() - t0;
        return rc;
    }
    if (!sim) return rk_fail(err, "%s: a basis of a mesh needs the built scene", scene->path);
    int rc = -1, T = 0;
    double *D = NULL;
    unsigned char *fixed = rk_scene_fixed_vertices(sim, err);
    rk_sparse M = {0};
    if (!fixed) goto out;
    int need_frames = rk_basis_needs_frames(o);
    if (need_frames) {
        double t = rk_now();
        if (frames) T = T_given;
        else if (rk_scene_training_frames(sim, &D, &T, err)) goto out;
        info->seconds_fom = frames ? 0 : rk_now() - t;
        info->fom_frames = T;
        if (rk_sparse_alloc_pattern(&sim->fem, &M, err)) goto out;
        rk_fem_add_mass(&sim->fem, sim->options.lumped_mass, 1.0, &M);
    }
    int size = o->size ? o->size : default_max(o->type);
    double t = rk_now();
    const double *frames_used = frames ? frames : D;
    if (build_sized(scene, sim, o, fixed, size, frames_used, T, &M, b, info, err)) goto out;
    info->seconds_basis = rk_now() - t;
    if (need_frames && meet_tolerance(o, b, frames_used, T, &M, info, err)) goto out;
    info->vertices = sim->mesh.nv;
    info->tets = sim->mesh.nt;
    info->X = rk_calloc(3 * (size_t)sim->mesh.nv, sizeof(double), err);
    if (!info->X) goto out;
    memcpy(info->X, sim->mesh.X, sizeof(double) * 3 * sim->mesh.nv);
    rc = 0;
out:
    if (rc) rk_basis_free(b);
    free(D);
    free(fixed);
    rk_sparse_free(&M);
    return rc;
}

void rk_scene_basis_info_free(rk_scene_basis_info *info)
{
    free(info->X);
    info->X = NULL;
}
