/* rom.koopman: training runs of the scene and the fit on them (scene_koopman.h). */
#include "koopman/scene_koopman.h"

#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fom/fom.h"
#include "scene/json_get.h"
#include "util/timer.h"

static const cJSON *koopman_entry(const cJSON *rom, int index, char *path, size_t size)
{
    const cJSON *e = cJSON_IsArray(rom) ? cJSON_GetArrayItem(rom, index) : rom;
    snprintf(path, size, cJSON_IsArray(rom) ? "rom[%d].koopman" : "rom.koopman", index);
    return cJSON_IsObject(e) ? cJSON_GetObjectItemCaseSensitive(e, "koopman") : NULL;
}

int rk_koopman_scene_present(const cJSON *rom, int index)
{
    char path[64];
    return rom && koopman_entry(rom, index, path, sizeof path) != NULL;
}

int rk_koopman_scene_options_parse(const cJSON *rom, int index, const char *file, double h,
                                   rk_koopman_scene_options *o, rk_error *err)
{
    rk_json_ctx c = {file, err};
    char path[64], tpath[96];
    memset(o, 0, sizeof *o);
    rk_koopman_default_options(&o->fit);
    o->fit.h = h;
    const cJSON *k = rom ? koopman_entry(rom, index, path, sizeof path) : NULL;
    if (!k) return rk_fail(err, "%s: the rom entry has no koopman section", file);
    if (!cJSON_IsObject(k)) return rk_json_fail(&c, path, "must be an object");
    static const char *const keys[] = {"rank", "energy", "clamp", "project", "trajectories", NULL};
    if (rk_json_check_keys(&c, k, path, keys) || rk_json_whole(&c, k, path, "rank", 0, 4096, &o->fit.rank) /* 0: by energy */ ||
        rk_json_number(&c, k, path, "energy", 0, &o->fit.energy) || rk_json_bool(&c, k, path, "clamp", &o->fit.clamp) ||
        rk_json_bool(&c, k, path, "project", &o->project))
        return -1;
    if (!(o->fit.energy > 0 && o->fit.energy <= 1))
        return rk_json_fail(&c, path, "energy must be in (0, 1], got %g", o->fit.energy);
    const cJSON *list = rk_json_child(k, path, "trajectories", tpath, sizeof tpath);
    if (!list) return 0;
    if (!cJSON_IsArray(list) || cJSON_GetArraySize(list) < 1 || cJSON_GetArraySize(list) > RK_KOOPMAN_MAX_TRAJECTORIES)
        return rk_json_fail(&c, tpath, "must be a list of 1 to %d trajectories", RK_KOOPMAN_MAX_TRAJECTORIES);
    static const char *const tkeys[] = {"gravity", "velocity", "load_scale", NULL};
    o->ntraj = cJSON_GetArraySize(list);
    for (int i = 0; i < o->ntraj; i++) {
        const cJSON *t = cJSON_GetArrayItem(list, i);
        rk_koopman_variation *v = &o->traj[i];
        char p[128];
        snprintf(p, sizeof p, "%s[%d]", tpath, i);
        if (!cJSON_IsObject(t)) return rk_json_fail(&c, p, "must be an object");
        v->load_scale = 1;
        v->has_gravity = cJSON_HasObjectItem(t, "gravity");
        v->has_velocity = cJSON_HasObjectItem(t, "velocity");
        if (rk_json_check_keys(&c, t, p, tkeys) || rk_json_vector(&c, t, p, "gravity", 0, 3, v->gravity) ||
            rk_json_vector(&c, t, p, "velocity", 0, 3, v->velocity) ||
            rk_json_number(&c, t, p, "load_scale", 0, &v->load_scale))
            return -1;
    }
    return 0;
}

void rk_koopman_run_free(rk_koopman_run *r)
{
    free(r->u);
    free(r->accel);
    memset(r, 0, sizeof *r);
}

void rk_koopman_scene_accel(const rk_scene_sim *sim, const double gravity[3], const double *force, double *accel)
{
    for (int p = 0; p < sim->mesh.nv; p++)
        for (int a = 0; a < 3; a++) {
            int i = 3 * p + a;
            accel[i] = gravity[a] + (force ? force[i] / sim->fem.vertex_mass[p] : 0);
        }
}

void rk_koopman_frame_before(const rk_scene_sim *sim, const double *vel, double *u_prev)
{
    for (int i = 0; i < 3 * sim->mesh.nv; i++) u_prev[i] = vel ? -sim->options.h * vel[i] : 0;
}

/* A run of T steps under gravity, loads `force` (N, or NULL) and initial velocities `vel` (or
 * NULL): its arrays, the acceleration (gravity plus each load over its vertex's lumped mass) and
 * the frame before the start, u_{-1} = -h v_0 (u_0 = 0 is left to the caller). */
static int run_start(const rk_scene_sim *sim, const double gravity[3], const double *force, const double *vel, int T,
                     rk_koopman_run *out, rk_error *err)
{
    int nv = sim->mesh.nv, n3 = 3 * nv;
    memset(out, 0, sizeof *out);
    out->u = rk_calloc((size_t)n3 * (T + 2), sizeof(double), err);
    out->accel = rk_calloc((size_t)n3, sizeof(double), err);
    if (!out->u || !out->accel) {
        rk_koopman_run_free(out);
        return -1;
    }
    rk_koopman_scene_accel(sim, gravity, force, out->accel);
    rk_koopman_frame_before(sim, vel, out->u);
    out->t = (rk_koopman_trajectory){out->u, T + 2, out->accel};
    return 0;
}

int rk_koopman_scene_run(const rk_scene_sim *sim, const rk_koopman_variation *v, rk_koopman_run *out, rk_error *err)
{
    memset(out, 0, sizeof *out);
    if (sim->options.is_static) return rk_fail(err, "Koopman: the scene is a static solve; DMD learns dynamics");
    int n3 = 3 * sim->mesh.nv, steps = sim->steps;
    rk_fom_options opt = sim->options;
    double *force = rk_calloc((size_t)n3, sizeof(double), err), *vel = rk_calloc((size_t)n3, sizeof(double), err);
    if (!force || !vel) goto fail;
    if (v && v->has_gravity) memcpy(opt.gravity, v->gravity, sizeof opt.gravity);
    for (int i = 0; i < n3; i++) {
        force[i] = sim->options.force ? sim->options.force[i] * (v ? v->load_scale : 1) : 0;
        vel[i] = v && v->has_velocity ? v->velocity[i % 3] : sim->options.velocity0 ? sim->options.velocity0[i] : 0;
    }
    opt.force = force;
    opt.velocity0 = vel;
    if (run_start(sim, opt.gravity, force, vel, steps, out, err)) goto fail;
    rk_fom fom;
    if (rk_fom_init(&fom, &sim->fem, &opt, err)) goto fail;
    /* the simulator holds prescribed vertices at their targets from the start */
    for (int i = 0; i < n3; i++) out->u[n3 + i] = fom.x[i] - sim->mesh.X[i];
    for (int s = 0; s < steps; s++) {
        if (rk_fom_step(&fom, err)) {
            rk_fom_free(&fom);
            goto fail;
        }
        for (int i = 0; i < n3; i++) out->u[(size_t)(s + 2) * n3 + i] = fom.x[i] - sim->mesh.X[i];
        rk_progress("Koopman training run", s + 1, steps);
    }
    rk_progress_done("Koopman training run");
    rk_fom_free(&fom);
    free(force);
    free(vel);
    return 0;
fail:
    free(force);
    free(vel);
    rk_koopman_run_free(out);
    return rk_error_prefix(err, "Koopman training run");
}

int rk_koopman_scene_run_frames(const rk_scene_sim *sim, const double *frames, int T, rk_koopman_run *out,
                                rk_error *err)
{
    if (run_start(sim, sim->options.gravity, sim->options.force, sim->options.velocity0, T, out, err)) return -1;
    memcpy(out->u + 2 * (size_t)3 * sim->mesh.nv, frames, sizeof(double) * 3 * sim->mesh.nv * T);
    return 0;
}

static int as_written(const rk_koopman_variation *v)
{
    return !v || (!v->has_gravity && !v->has_velocity && v->load_scale == 1);
}

/* P_out = U, P_in = (U^T M U)^-1 U^T M: the mass-orthogonal projection onto the basis. */
static int projection(const rk_scene_sim *sim, const rk_basis *b, double **P_in, double **P_out, rk_error *err)
{
    int n = 3 * sim->mesh.nv, d = b->r, rc = -1;
    rk_sparse M;
    memset(&M, 0, sizeof M);
    double *MU = rk_calloc((size_t)n * d, sizeof(double), err), *G = rk_calloc((size_t)d * d, sizeof(double), err);
    *P_in = rk_calloc((size_t)n * d, sizeof(double), err);
    *P_out = rk_calloc((size_t)n * d, sizeof(double), err);
    if (!MU || !G || !*P_in || !*P_out || rk_sparse_alloc_pattern(&sim->fem, &M, err)) goto done;
    rk_fem_add_mass(&sim->fem, sim->options.lumped_mass, 1.0, &M);
    for (int j = 0; j < d; j++) rk_sparse_mul(&M, b->U + (size_t)n * j, MU + (size_t)n * j);
    memcpy(*P_out, b->U, sizeof(double) * n * d);
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, d, d, n, 1.0, b->U, n, MU, n, 0.0, G, d);
    for (int j = 0; j < d; j++)
        for (int i = 0; i < n; i++) (*P_in)[(size_t)d * i + j] = MU[(size_t)n * j + i];
    int info = LAPACKE_dposv(LAPACK_COL_MAJOR, 'U', d, n, G, d, *P_in, d);
    if (info != 0) {
        rk_fail(err, "the basis's mass Gram matrix is singular (LAPACK dposv info %d): its columns are dependent", info);
        goto done;
    }
    rc = 0;
done:
    rk_sparse_free(&M);
    free(MU);
    free(G);
    return rc;
}

int rk_koopman_scene_fit(const rk_scene_sim *sim, const rk_koopman_scene_options *o, const rk_basis *basis,
                         const double *frames, int T, rk_koopman *k, rk_koopman_scene_info *info, rk_error *err)
{
    memset(k, 0, sizeof *k);
    memset(info, 0, sizeof *info);
    int ntraj = o->ntraj ? o->ntraj : 1, rc = -1;
    rk_koopman_run *runs = rk_calloc((size_t)ntraj, sizeof *runs, err);
    rk_koopman_trajectory *t = rk_calloc((size_t)ntraj, sizeof *t, err);
    double *P_in = NULL, *P_out = NULL;
    if (!runs || !t) goto done;
    double t0 = rk_now();
    for (int i = 0; i < ntraj; i++) {
        const rk_koopman_variation *v = o->ntraj ? &o->traj[i] : NULL;
        info->reused |= frames && as_written(v);
        if (frames && as_written(v) ? rk_koopman_scene_run_frames(sim, frames, T, &runs[i], err)
                                    : rk_koopman_scene_run(sim, v, &runs[i], err)) {
            rk_error_prefix(err, "trajectory %d", i);
            goto done;
        }
        t[i] = runs[i].t;
        info->frames += t[i].frames;
    }
    info->trajectories = ntraj;
    info->seconds_fom = rk_now() - t0;
    t0 = rk_now();
    if (basis) {
        if (projection(sim, basis, &P_in, &P_out, err) ||
            rk_koopman_fit_projected(t, ntraj, 3 * sim->mesh.nv, P_in, P_out, basis->r, &o->fit, k, err))
            goto done;
        info->projected = 1;
    } else if (rk_koopman_fit(t, ntraj, 3 * sim->mesh.nv, &o->fit, k, err)) {
        goto done;
    }
    info->seconds_fit = rk_now() - t0;
    rc = 0;
done:
    for (int i = 0; runs && i < ntraj; i++) rk_koopman_run_free(&runs[i]);
    free(runs);
    free(t);
    free(P_in);
    free(P_out);
    return rc;
}

int rk_koopman_scene_build(const rk_scene *scene, const rk_scene_sim *sim, int index, const rk_basis_options *bo,
                           const double *frames, int T, rk_koopman *k, rk_koopman_scene_info *info, rk_error *err)
{
    rk_koopman_scene_options ko;
    rk_basis b;
    rk_scene_basis_info bi;
    double *own = NULL, seconds_basis = 0;
    int have_basis = 0, rc = -1;
    memset(k, 0, sizeof *k);
    memset(info, 0, sizeof *info);
    if (rk_koopman_scene_options_parse(scene->rom, index, scene->path, sim->options.h, &ko, err)) return -1;
    if (ko.project) {
        double t0 = rk_now();
        if (!frames && rk_basis_needs_frames(bo)) {
            if (rk_scene_training_frames(sim, &own, &T, err)) goto done;
            frames = own;
        }
        if (rk_scene_basis_build_frames(scene, bo, frames, T, &b, &bi, err)) goto done;
        have_basis = 1;
        seconds_basis = rk_now() - t0;
    }
    rc = rk_koopman_scene_fit(sim, &ko, have_basis ? &b : NULL, frames, T, k, info, err);
    if (!rc && have_basis) {
        info->basis_type = b.type;
        info->basis_columns = b.r;
        info->seconds_basis = seconds_basis;
    }
done:
    free(own);
    if (have_basis) {
        rk_basis_free(&b);
        rk_scene_basis_info_free(&bi);
    }
    return rc;
}
