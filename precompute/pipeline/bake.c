/* A rom entry end to end into an asset (pipeline.h, rk_scene_bake: its method's bake), and the bake
 * that methods fixed and koopman share (method.h, rk_method_bake_models): the full-order run when
 * something trains on it, the reduced model, the Koopman operator, the bake and the report. */
#include "pipeline/method.h"
#include "pipeline/method_fixed.h"
#include "pipeline/method_koopman.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "formats/rombin_read.h"
#include "util/util.h"

void rk_asset_report(cJSON *a, const unsigned char *data, size_t bytes, const rk_asset_summary *sum)
{
    cJSON_AddNumberToObject(a, "bytes", (double)bytes);
    cJSON_AddNumberToObject(a, "stored_vertices", sum->vertices);
    cJSON_AddNumberToObject(a, "shown_vertices", sum->shown);
    cJSON_AddNumberToObject(a, "triangles", sum->triangles);
    cJSON_AddNumberToObject(a, "contacts", sum->contacts);
    cJSON_AddNumberToObject(a, "groups", sum->groups);
    rombin_file f;
    rombin_error e;
    if (rombin_open(&f, data, bytes, NULL, &e) != ROMBIN_OK) return;
    cJSON_AddStringToObject(a, "precision", f.real_type == ROMBIN_REAL_F32 ? "float32" : "float64");
    cJSON *chunks = cJSON_AddArrayToObject(a, "chunks");
    for (unsigned i = 0; i < f.count; i++) {
        rombin_chunk ch;
        rombin_chunk_get(&f, i, &ch);
        cJSON *j = cJSON_CreateObject();
        cJSON_AddStringToObject(j, "id", ch.id);
        cJSON_AddNumberToObject(j, "stored", (double)ch.stored);
        cJSON_AddNumberToObject(j, "raw", (double)ch.raw);
        cJSON_AddBoolToObject(j, "deflate", ch.compression == ROMBIN_COMP_DEFLATE);
        cJSON_AddItemToArray(chunks, j);
    }
}

/* The report's reduced-model keys: basis.* and cubature.*. */
static void add_rom_report(cJSON *root, const rk_scene_rom *R, int training_frames, const char *trained_on)
{
    cJSON *b = cJSON_AddObjectToObject(root, "basis");
    cJSON_AddNumberToObject(b, "training_frames", training_frames);
    cJSON_AddStringToObject(b, "trained_on", trained_on);
    cJSON_AddStringToObject(b, "type", rk_basis_type_name(R->basis.type));
    cJSON_AddNumberToObject(b, "size", R->basis.W ? R->basis.m : R->basis.r);
    cJSON_AddNumberToObject(b, "columns", R->basis.r);
    cJSON_AddItemToObject(b, R->basis.type == RK_BASIS_POD ? "singular_values" : "eigenvalues",
                          rk_json_array(R->basis.values, R->basis.nvalues));
    cJSON_AddStringToObject(b, "bound_by", R->basis_reason);
    cJSON *c = cJSON_AddObjectToObject(root, "cubature");
    cJSON_AddNumberToObject(c, "elements", R->model.quad.count);
    if (isfinite(R->cubature_error)) cJSON_AddNumberToObject(c, "relative_error", R->cubature_error);
    else cJSON_AddNullToObject(c, "relative_error");
    cJSON_AddStringToObject(c, "bound_by", R->cubature_reason);
    if (R->points.n) { /* mesh-free: where the energy and the mass were integrated */
        cJSON *mf = cJSON_AddObjectToObject(root, "mesh_free");
        double volume = 0;
        for (int i = 0; i < R->points.n; i++) volume += R->points.volume[i];
        cJSON_AddNumberToObject(mf, "integration_points", R->points.n);
        cJSON_AddNumberToObject(mf, "volume", volume);
        cJSON_AddNumberToObject(mf, "mass", R->model.mass);
    }
}

/* The report's "training" object for a Koopman operator fitted on the scene's runs. */
static void add_koopman_training(cJSON *root, const rk_koopman_scene_info *info)
{
    cJSON *tj = cJSON_AddObjectToObject(root, "training");
    cJSON_AddNumberToObject(tj, "trajectories", info->trajectories);
    cJSON_AddNumberToObject(tj, "frames", info->frames);
    cJSON_AddBoolToObject(tj, "projected", info->projected);
}

/* The report's "cage" object: the cage made (mesh.cage) and the surface embedded in it. */
static void add_cage_report(cJSON *root, const rk_scene_sim *sim)
{
    cJSON *c = cJSON_AddObjectToObject(root, "cage");
    cJSON_AddNumberToObject(c, "tets", sim->mesh.nt);
    cJSON_AddNumberToObject(c, "vertices", sim->mesh.nv);
    cJSON_AddNumberToObject(c, "simplified_triangles", sim->cage.triangles);
    cJSON_AddNumberToObject(c, "simplify_error", sim->cage.simplify_error);
    cJSON_AddNumberToObject(c, "max_offset", sim->cage.max_offset);
    cJSON_AddNumberToObject(c, "surface_vertices", sim->embedded.nv);
    cJSON_AddNumberToObject(c, "surface_triangles", sim->embedded.nf);
    cJSON_AddNumberToObject(c, "outside", sim->embedded_outside);
    cJSON_AddNumberToObject(c, "worst_distance", sim->embedded_worst);
}

/* The report's Koopman keys: koopman.* and the training it had. */
static void add_koopman_report(cJSON *root, const rk_scene_koopman *K)
{
    cJSON_AddItemToObject(root, "koopman", rk_koopman_report(&K->k));
    add_koopman_training(root, &K->info);
}

/* What the INFO chunk says: enough to tell where an asset came from, nothing time-dependent. */
static char *info_text(const rk_scene *scene, const rk_rom_entry *e, const rk_scene_rom *R, const rk_scene_koopman *K)
{
    cJSON *j = cJSON_CreateObject();
    const char *slash = strrchr(scene->path, '/');
    cJSON_AddStringToObject(j, "scene", slash ? slash + 1 : scene->path);
    if (R) {
        cJSON_AddStringToObject(j, "method", e->name);
        cJSON_AddStringToObject(j, "basis", rk_basis_type_name(R->basis.type));
        cJSON_AddNumberToObject(j, "columns", R->basis.r);
        cJSON_AddNumberToObject(j, "cubature_elements", R->model.quad.count);
    } else {
        cJSON_AddStringToObject(j, "method", "koopman");
        cJSON_AddNumberToObject(j, "rank", K->k.r);
        cJSON_AddNumberToObject(j, "trajectories", K->info.trajectories);
    }
    char *text = cJSON_PrintUnformatted(j);
    cJSON_Delete(j);
    return text;
}

typedef struct {
    rk_scene_sim sim;
    int have_sim, have_rom, have_koopman;
    double *own_frames;
    int training_frames;        /* frames the basis and the cubature trained on (0: none) */
    const char *trained_on;     /* where they came from, for the report */
    rk_scene_rom R;
    rk_scene_koopman K;
} bake_state;

static void state_free(bake_state *s)
{
    if (s->have_koopman) rk_scene_koopman_free(&s->K);
    if (s->have_rom) rk_scene_rom_free(&s->R);
    if (s->have_sim) rk_scene_sim_free(&s->sim);
    free(s->own_frames);
}

/* The given snapshots as displacement frames after each step (*D, 3 nv x steps). */
static int given_frames(const rk_bake_request *req, const rk_scene_sim *sim, double **D, int *T, rk_error *err)
{
    const long *shape = req->snapshot_shape;
    int n3 = 3 * sim->mesh.nv;
    if (req->snapshot_dims != 3 || shape[1] != sim->mesh.nv || shape[2] != 3 || shape[0] != sim->steps + 1)
        return rk_fail(err, "expected this scene's full-order frames, %d x %d x 3 (romkit fom --snapshots), got %ld%s%ld%s%ld",
                       sim->steps + 1, sim->mesh.nv, shape[0], req->snapshot_dims > 1 ? " x " : "",
                       req->snapshot_dims > 1 ? shape[1] : 0L, req->snapshot_dims > 2 ? " x " : "",
                       req->snapshot_dims > 2 ? shape[2] : 0L);
    *T = sim->steps;
    *D = rk_calloc((size_t)n3 * (*T > 0 ? *T : 1), sizeof(double), err);
    if (!*D) return -1;
    for (int t = 0; t < *T; t++)
        for (int i = 0; i < n3; i++)
            (*D)[(size_t)n3 * t + i] = req->snapshots[(size_t)n3 * (t + 1) + i] - sim->mesh.X[i];
    return 0;
}

int rk_scene_entry_frames(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e,
                          const rk_bake_request *req, double **D, int *T, const char **trained_on, rk_error *err)
{
    *D = NULL;
    *T = 0;
    *trained_on = "nothing (no data-driven part)";
    if (req->snapshots) {
        if (given_frames(req, sim, D, T, err)) return -1;
        *trained_on = "the snapshots given (--snapshots)";
        return 0;
    }
    int koopman = rk_koopman_of(e) != NULL, reduced = !koopman || e->cubature;
    int cubature = e->cubature && !req->cubature, basis = rk_basis_needs_frames(&e->basis) && !req->basis;
    /* a point cloud has no full order: its cubature trains on random poses alone. An entry that
     * lists its training runs trains on them, as romkit compare trains it (a POD of the scene's
     * own run would be fitted to the very motion it is tested on) */
    if (reduced && !sim->cloud_points && (cubature || basis)) {
        if (req->ntraining_runs && req->ntraining_runs != e->ntraining)
            return rk_fail(err, "%d training run files given for %s's %d training runs", req->ntraining_runs, e->path,
                           e->ntraining);
        if (e->ntraining ? rk_scene_training_set_from(scene, sim, e, req->ntraining_runs ? req->training_runs : NULL,
                                                      D, T, err)
                         : rk_scene_training_frames(sim, D, T, err))
            return -1;
        *trained_on = e->ntraining ? "the entry's training list" : "the scene's own full-order run";
    } else if (reduced && sim->cloud_points && e->cubature)
        *trained_on = "random poses (a point cloud has no full order)";
    return 0;
}

/* The models of entry e: the reduced one unless it is a Koopman-only entry, the operator when it
 * has a koopman section; the scene's full-order run once, when something trains on it. */
static int build_models(const rk_scene *scene, const rk_rom_entry *e, const rk_bake_request *req, bake_state *s,
                        rk_error *err)
{
    if (rk_scene_build(scene, &s->sim, err)) return -1;
    s->have_sim = 1;
    int T = 0;
    if (rk_scene_entry_frames(scene, &s->sim, e, req, &s->own_frames, &T, &s->trained_on, err)) return -1;
    const double *frames = s->own_frames;
    int koopman = rk_koopman_of(e) != NULL, reduced = !koopman || e->cubature;
    s->training_frames = frames ? T : 0;
    if (reduced) {
        rk_scene_rom_given g = {req->basis, req->cubature, req->cubature_poses};
        if (rk_scene_rom_build_given(scene, &s->sim, e, frames, T, &g, &s->R, err)) return -1;
        s->have_rom = 1;
    }
    if (koopman) {
        const rk_koopman_entry *ko = rk_koopman_of(e);
        int ntraj = ko->ntraj ? ko->ntraj : 1;
        if (req->ntrajectory_runs && req->ntrajectory_runs != ntraj)
            return rk_fail(err, "%d trajectory files given for %s's %d trajectories", req->ntrajectory_runs, e->path, ntraj);
        if (rk_scene_koopman_build_from(scene, &s->sim, e, frames, T, req->ntrajectory_runs ? req->trajectory_runs : NULL,
                                        &s->K, err))
            return -1;
        s->have_koopman = 1;
    }
    return 0;
}

/* The reduced model of s (and its Koopman operator beside it, if any) into out. */
static int bake_reduced(const rk_scene *scene, const rk_rom_entry *e, const rk_asset_options *ao, bake_state *s,
                        rk_baked *out, rk_error *err)
{
    rk_asset_summary sum = {0};
    rombin_writer w;
    rombin_writer_init(&w, ao->real_type, ao->compress);
    char *info = info_text(scene, e, &s->R, &s->K);
    rk_asset_rom source = rk_scene_asset_rom(&s->sim, &s->R);
    double *v0 = NULL, v0_residual = 0;
    int rc = rk_scene_rom_velocity0(&s->sim, &s->R, &v0, &v0_residual, err);
    source.velocity0 = v0;
    int moving = v0 != NULL;
    rc = rc || rk_asset_bake(&source, s->have_koopman ? &s->K.k : NULL, &s->K.geometry, ao, info, &w, &sum, err) ||
         rombin_serialize(&w, &out->data, &out->bytes, err);
    free(v0);
    free(info);
    rombin_writer_free(&w);
    if (rc) return -1;
    out->report = cJSON_CreateObject();
    add_rom_report(out->report, &s->R, s->training_frames, s->trained_on);
    if (s->have_koopman) add_koopman_report(out->report, &s->K);
    rk_asset_report(cJSON_AddObjectToObject(out->report, "asset"), out->data, out->bytes, &sum);
    snprintf(out->summary, sizeof out->summary, "%s, r = %d, %d cubature elements, %d of %d vertices stored "
             "(%d shown), %zu bytes", e->name, s->R.model.r, s->R.model.quad.count, sum.vertices, s->sim.mesh.nv + s->sim.embedded.nv,
             sum.shown, out->bytes);
    if (s->sim.embedded.nv) /* the shown vertices are the surface's, the rest the cage's */
        snprintf(out->summary + strlen(out->summary), sizeof out->summary - strlen(out->summary),
                 "\n  the surface (%d vertices, %d triangles) embedded in a cage of %d tets and %d vertices; %d surface "
                 "vertices outside it", s->sim.embedded.nv, s->sim.embedded.nf, s->sim.mesh.nt, s->sim.mesh.nv,
                 s->sim.embedded_outside);
    /* a cubature that stopped above its tolerance makes every force of the free run that far off:
     * said where the user looks, not only in the report */
    if (s->R.model.quad.count > 0 && !s->R.cubature_reached && isfinite(s->R.cubature_error))
        snprintf(out->summary + strlen(out->summary), sizeof out->summary - strlen(out->summary),
                 "\n  warning: the cubature missed its tolerance (%s)", s->R.cubature_reason);
    if (s->R.volume_warning[0])
        snprintf(out->summary + strlen(out->summary), sizeof out->summary - strlen(out->summary),
                 "\n  warning: %s", s->R.volume_warning);
    /* the objects' initial velocities are baked (VEL0) as compare starts its free run; a basis that
     * cannot hold them starts the runtime slower than the scene says: said, not silent */
    if (moving)
        snprintf(out->summary + strlen(out->summary), sizeof out->summary - strlen(out->summary),
                 "\n  moving at t = 0: the initial velocities baked (VEL0; residual of their projection %.2g)", v0_residual);
    if (moving && v0_residual > 1e-3)
        snprintf(out->summary + strlen(out->summary), sizeof out->summary - strlen(out->summary),
                 "\n  warning: the basis holds the initial velocities only to %.1f%% (M-norm residual %.3g)",
                 100 * (1 - v0_residual), v0_residual);
    if (s->have_koopman)
        snprintf(out->summary + strlen(out->summary), sizeof out->summary - strlen(out->summary),
                 "\n  and a Koopman operator of rank %d beside it (romkit run --koopman, romrt_open_kind)", s->K.k.r);
    return 0;
}

int rk_bake_koopman(const rk_koopman *k, const rk_koopman_geometry *g, const rk_asset_options *ao, const char *info,
                    rk_baked *out, rk_error *err)
{
    memset(out, 0, sizeof *out);
    rk_asset_summary sum = {0};
    if (rk_asset_koopman_serialized(k, g, ao, info, &sum, &out->data, &out->bytes, err)) return -1;
    out->report = cJSON_CreateObject();
    cJSON_AddItemToObject(out->report, "koopman", rk_koopman_report(k));
    rk_asset_report(cJSON_AddObjectToObject(out->report, "asset"), out->data, out->bytes, &sum);
    /* a refit (fit.c, stabilize) says how many eigenvalues it moved inside and what that cost the fit */
    char refit[200] = "";
    if (k->stabilized)
        snprintf(refit, sizeof refit, " (stable refit: %d outside up to %.6f, eigenvalues moved by at most %.2e, "
                 "one-step residual %.3e -> %.3e)", k->stabilized, k->stabilize_top, k->stabilize_shift,
                 k->step_residual[0], k->step_residual[1]);
    snprintf(out->summary, sizeof out->summary, "Koopman operator, rank %d over %d observables, max |lambda| %.9f%s%s, "
             "%d of %d vertices stored (%d shown), %zu bytes", k->r, k->d,
             rk_max_abs_eigenvalue(k->lambda_re, k->lambda_im, k->r), k->clamped ? " (clamped)" : "", refit,
             sum.vertices, g->nv, sum.shown, out->bytes);
    return 0;
}

int rk_scene_bake(const rk_scene *scene, const rk_rom_entry *e, const rk_bake_request *req, rk_baked *out,
                  rk_error *err)
{
    memset(out, 0, sizeof *out);
    rk_asset_options ao = e->asset;
    if (req->has_real_type) ao.real_type = req->real_type;
    if (req->compress) ao.compress = 1;
    return e->method->bake(scene, e, req, &ao, out, err);
}

int rk_method_bake_models(const rk_scene *scene, const rk_rom_entry *e, const rk_bake_request *req,
                          const rk_asset_options *aop, rk_baked *out, rk_error *err)
{
    double t0 = rk_now();
    rk_asset_options ao = *aop;
    bake_state s;
    memset(&s, 0, sizeof s);
    int rc = build_models(scene, e, req, &s, err);
    if (!rc && s.have_rom) {
        rc = bake_reduced(scene, e, &ao, &s, out, err);
    } else if (!rc) {
        char *info = info_text(scene, e, NULL, &s.K);
        rc = rk_bake_koopman(&s.K.k, &s.K.geometry, &ao, info, out, err);
        free(info);
        if (!rc && s.K.info.projected) {
            cJSON *bj = cJSON_AddObjectToObject(out->report, "basis");
            cJSON_AddStringToObject(bj, "type", rk_basis_type_name(s.K.info.basis_type));
            cJSON_AddNumberToObject(bj, "size", s.K.info.basis_columns);
        }
        if (!rc) add_koopman_training(out->report, &s.K.info);
    }
    if (!rc) {
        cJSON_AddNumberToObject(out->report, "vertices", s.sim.mesh.nv);
        cJSON_AddNumberToObject(out->report, "tets", s.sim.mesh.nt);
        if (s.sim.embedded.nv) add_cage_report(out->report, &s.sim);
        cJSON *sj = cJSON_AddObjectToObject(out->report, "seconds");
        if (s.have_rom) {
            cJSON_AddNumberToObject(sj, "basis", s.R.seconds_basis);
            cJSON_AddNumberToObject(sj, "cubature", s.R.seconds_cubature);
        } else {
            cJSON_AddNumberToObject(sj, "fom", s.K.info.seconds_fom);
            cJSON_AddNumberToObject(sj, "basis", s.K.info.seconds_basis);
            cJSON_AddNumberToObject(sj, "fit", s.K.info.seconds_fit);
        }
        cJSON_AddNumberToObject(sj, "total", rk_now() - t0);
    }
    state_free(&s);
    if (rc) rk_baked_free(out);
    return rc;
}

void rk_baked_free(rk_baked *b)
{
    free(b->data);
    cJSON_Delete(b->report);
    memset(b, 0, sizeof *b);
}
