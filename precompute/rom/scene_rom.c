/* A scene's reduced model: basis (precompute/basis), exact quadrature, and when asked a trained
 * cubature in its place; with the reasons each size is what it is. */
#include "rom/scene_rom.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/json_get.h"
#include "util/timer.h"

int rk_rom_entries(const cJSON *rom)
{
    if (!rom) return 0;
    return cJSON_IsArray(rom) ? cJSON_GetArraySize(rom) : 1;
}

static int parse_cubature(const rk_json_ctx *c, const cJSON *e, const char *path, rk_rom_options *o)
{
    char cpath[128];
    const cJSON *cub = rk_json_child(e, path, "cubature", cpath, sizeof cpath);
    rk_cubature_default_options(&o->cub);
    o->cubature = cub != NULL;
    if (!cub) return 0;
    if (!cJSON_IsObject(cub)) return rk_json_fail(c, cpath, "must be an object");
    static const char *const keys[] = {"tolerance", "max_points", "poses", "sample", NULL};
    if (rk_json_check_keys(c, cub, cpath, keys)) return -1;
    double tol = o->cub.tolerance;
    if (rk_json_number(c, cub, cpath, "tolerance", 0, &tol) ||
        rk_json_whole(c, cub, cpath, "max_points", 0, 1e7, &o->cub.max_points) ||
        rk_json_whole(c, cub, cpath, "poses", 1, 10000, &o->cub.poses) ||
        rk_json_whole(c, cub, cpath, "sample", 0, 1e7, &o->cub.sample))
        return -1;
    if (!(tol > 0 && tol < 1)) return rk_json_fail(c, cpath, "tolerance must be in (0, 1), got %g", tol);
    o->cub.tolerance = tol;
    return 0;
}

static int parse_reference(const rk_json_ctx *c, const cJSON *e, const char *path, rk_rom_options *o)
{
    char rpath[128];
    const cJSON *ref = rk_json_child(e, path, "reference", rpath, sizeof rpath);
    o->reference_nmse = NAN;
    o->reference_source[0] = 0;
    if (!ref) return 0;
    static const char *const keys[] = {"normalized_mse", "source", NULL};
    if (!cJSON_IsObject(ref)) return rk_json_fail(c, rpath, "must be an object");
    if (rk_json_check_keys(c, ref, rpath, keys) || rk_json_number(c, ref, rpath, "normalized_mse", 1, &o->reference_nmse))
        return -1;
    const char *src = NULL;
    if (rk_json_string(c, ref, rpath, "source", 0, &src)) return -1;
    if (src) snprintf(o->reference_source, sizeof o->reference_source, "%s", src);
    return 0;
}

int rk_rom_options_parse(const cJSON *rom, int index, const char *file, rk_rom_options *o, rk_error *err)
{
    memset(o, 0, sizeof *o);
    if (rk_basis_options_parse(rom, index, file, &o->basis, err)) return -1;
    rk_json_ctx c = {file, err};
    char path[64];
    const cJSON *e = cJSON_IsArray(rom) ? cJSON_GetArrayItem(rom, index) : rom;
    snprintf(path, sizeof path, cJSON_IsArray(rom) ? "rom[%d]" : "rom", index);
    if (parse_cubature(&c, e, path, o) || parse_reference(&c, e, path, o)) return -1;
    const char *name = NULL;
    if (rk_json_string(&c, e, path, "name", 0, &name)) return -1;
    if (name && (!*name || strlen(name) >= sizeof o->name))
        return rk_json_fail(&c, path, "name must have 1 to %zu characters", sizeof o->name - 1);
    if (name) {
        snprintf(o->name, sizeof o->name, "%s", name);
    } else {
        const char *type = rk_basis_type_name(o->basis.type);
        if (o->basis.size) snprintf(o->name, sizeof o->name, "%s-%d%s", type, o->basis.size, o->cubature ? "-cubature" : "");
        else snprintf(o->name, sizeof o->name, "%s-tol%g%s", type, o->basis.tolerance, o->cubature ? "-cubature" : "");
    }
    return 0;
}

static void explain_basis(const rk_rom_options *o, rk_scene_rom *R)
{
    const rk_scene_basis_info *in = &R->basis_info;
    const char *unit = R->basis.W ? "weights" : "columns";
    int size = R->basis.W ? R->basis.m - 1 : R->basis.r;
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
    for (int t = 0; t < T; t++)
        if (rk_rom_project(&R->model, &M, R->basis.U, ndof, NULL, frames + (size_t)ndof * t, q + (size_t)r * t, err)) {
            free(q);
            q = NULL;
            break;
        }
    rk_sparse_free(&M);
    return q;
}

static int train_cubature(const rk_scene_sim *sim, const rk_rom_options *o, const double *frames, int T,
                          rk_scene_rom *R, rk_error *err)
{
    double t0 = rk_now();
    double *q = frames ? reduced_frames(sim, R, frames, T, err) : NULL;
    if (frames && !q) return -1;
    rk_cubature_set set;
    int rc = rk_cubature_train(&R->model.quad, R->model.M, R->model.mass, q, frames ? T : 0, &o->cub, &set,
                               &R->cubature_poses, err);
    free(q);
    if (rc) return rk_error_prefix(err, "cubature training");
    rk_quadrature cub;
    if (rk_quadrature_elements(&sim->fem, R->basis.U, R->basis.r, set.count, set.index, set.weight, &cub, err)) {
        rk_cubature_set_free(&set);
        return -1;
    }
    rk_quadrature_free(&R->model.quad);
    R->model.quad = cub;
    R->cubature_points = set.count;
    R->cubature_error = set.relative_error;
    R->cubature_reached = set.reached;
    if (set.reached)
        snprintf(R->cubature_reason, sizeof R->cubature_reason, "rom.cubature.tolerance %g: %d of %d elements "
                 "reproduce the reduced forces of %d training poses to %.3g", o->cub.tolerance, set.count,
                 sim->mesh.nt, R->cubature_poses, set.relative_error);
    else
        snprintf(R->cubature_reason, sizeof R->cubature_reason, "%s: stopped at %d of %d elements with force error "
                 "%.3g, above rom.cubature.tolerance %g",
                 o->cub.max_points && set.count >= o->cub.max_points ? "rom.cubature.max_points" : "no further element helped",
                 set.count, sim->mesh.nt, set.relative_error, o->cub.tolerance);
    rk_cubature_set_free(&set);
    R->seconds_cubature = rk_now() - t0;
    return 0;
}

int rk_scene_rom_build(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_options *o,
                       const double *frames, int T, rk_scene_rom *R, rk_error *err)
{
    memset(R, 0, sizeof *R);
    R->cubature_error = NAN;
    double t0 = rk_now();
    if (rk_scene_basis_build_frames(scene, &o->basis, frames, T, &R->basis, &R->basis_info, err))
        return rk_error_prefix(err, "%s", o->name);
    R->seconds_basis = rk_now() - t0;
    explain_basis(o, R);
    if (R->basis.n != sim->mesh.nv) {
        rk_scene_rom_free(R);
        return rk_fail(err, "%s: the reduced simulator needs a mesh (the basis has %d points, the mesh %d vertices)",
                       o->name, R->basis.n, sim->mesh.nv);
    }
    rk_quadrature exact;
    if (rk_quadrature_elements(&sim->fem, R->basis.U, R->basis.r, sim->mesh.nt, NULL, NULL, &exact, err) ||
        rk_rom_model_init(&R->model, &sim->fem, &sim->options, R->basis.U, R->basis.r, &exact, err)) {
        rk_basis_free(&R->basis);
        rk_scene_basis_info_free(&R->basis_info);
        return rk_error_prefix(err, "%s", o->name);
    }
    snprintf(R->cubature_reason, sizeof R->cubature_reason, "no rom.cubature: exact integration over all %d elements",
             sim->mesh.nt);
    if (o->cubature && train_cubature(sim, o, frames, T, R, err)) {
        rk_scene_rom_free(R);
        return rk_error_prefix(err, "%s", o->name);
    }
    return 0;
}

void rk_scene_rom_free(rk_scene_rom *R)
{
    rk_rom_model_free(&R->model);
    rk_basis_free(&R->basis);
    rk_scene_basis_info_free(&R->basis_info);
}
