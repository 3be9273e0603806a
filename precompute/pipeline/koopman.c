/* rom.koopman: training runs of the scene, the fit on them, and what an asset of the operator
 * needs (pipeline.h). */
#include "pipeline/pipeline.h"
#include "pipeline/method_fixed.h"
#include "pipeline/method_koopman.h"

#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/util.h"

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

int rk_koopman_scene_pressure_accel(const rk_scene_sim *sim, double *accel, rk_error *err)
{
    int n3 = 3 * sim->mesh.nv, pressed = 0;
    for (int c = 0; c < sim->options.nchambers; c++) {
        if (sim->options.chambers[c].nkeys)
            return rk_fail(err, "chamber %d follows a pressure schedule: only a pressure held constant from t = 0 is a "
                           "constant load", c);
        pressed |= sim->options.chambers[c].pressure != 0;
    }
    if (!pressed) return 0;
    if (sim->options.is_static) return rk_fail(err, "the scene is a static solve; DMD learns dynamics");
    rk_fom_options opt = sim->options; /* the pressure alone: gravity and loads stay raw impulses */
    memset(opt.gravity, 0, sizeof opt.gravity);
    opt.force = NULL;
    opt.velocity0 = NULL;
    rk_fom fom;
    if (rk_fom_init(&fom, &sim->fem, &opt, err)) return rk_error_prefix(err, "the chambers' load");
    int rc = rk_fom_step(&fom, err); /* one step from rest: u_1 */
    double h2 = sim->options.h * sim->options.h;
    for (int i = 0; !rc && i < n3; i++) accel[i] += (fom.x[i] - sim->mesh.X[i]) / h2;
    rk_fom_free(&fom);
    return rc ? rk_error_prefix(err, "the chambers' load") : 0;
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

typedef struct {
    const rk_scene_sim *sim;
    rk_koopman_run *out;
} recording;

/* u_0 (step 0: the simulator holds prescribed vertices at their targets from the start), then one
 * displacement frame per step. */
static int record(void *ctx, int step, rk_fom *fom, double seconds, rk_error *err)
{
    const recording *r = ctx;
    int n3 = 3 * r->sim->mesh.nv;
    for (int i = 0; i < n3; i++) r->out->u[(size_t)(step + 1) * n3 + i] = fom->x[i] - r->sim->mesh.X[i];
    return 0;
}

/* What trajectory v runs under: opt (sim's options) with v's gravity, force (3 nv: every load
 * times load_scale) and vel (3 nv: v's velocity, else the scene's) in arrays of the caller's. */
static void variation(const rk_scene_sim *sim, const rk_koopman_variation *v, rk_fom_options *opt, double *force,
                      double *vel)
{
    *opt = sim->options;
    if (v && v->has_gravity) memcpy(opt->gravity, v->gravity, sizeof opt->gravity);
    for (int i = 0; i < 3 * sim->mesh.nv; i++) {
        force[i] = sim->options.force ? sim->options.force[i] * (v ? v->load_scale : 1) : 0;
        vel[i] = v && v->has_velocity ? v->velocity[i % 3] : sim->options.velocity0 ? sim->options.velocity0[i] : 0;
    }
    opt->force = force;
    opt->velocity0 = vel;
}

int rk_koopman_scene_vary(rk_scene_sim *sim, const rk_koopman_variation *v, rk_error *err)
{
    int n3 = 3 * sim->mesh.nv;
    double *force = rk_calloc((size_t)n3, sizeof(double), err), *vel = rk_calloc((size_t)n3, sizeof(double), err);
    if (!force || !vel) {
        free(force);
        free(vel);
        return -1;
    }
    rk_fom_options opt;
    variation(sim, v, &opt, force, vel);
    free(sim->options.force);
    free(sim->options.velocity0);
    sim->options = opt;
    return 0;
}

int rk_koopman_scene_run(const rk_scene_sim *sim, const rk_koopman_variation *v, rk_koopman_run *out, rk_error *err)
{
    memset(out, 0, sizeof *out);
    if (sim->options.is_static) return rk_fail(err, "Koopman: the scene is a static solve; DMD learns dynamics");
    int n3 = 3 * sim->mesh.nv, rc = -1;
    rk_fom_options opt;
    double *force = rk_calloc((size_t)n3, sizeof(double), err), *vel = rk_calloc((size_t)n3, sizeof(double), err);
    if (force && vel) {
        variation(sim, v, &opt, force, vel);
        recording r = {sim, out};
        rc = run_start(sim, opt.gravity, force, vel, sim->steps, out, err) ||
                     rk_scene_fom_run(sim, &opt, "Koopman training run", record, &r, NULL, err)
                 ? -1
                 : 0;
    }
    free(force);
    free(vel);
    if (rc) rk_koopman_run_free(out);
    return rc;
}

int rk_koopman_scene_run_file(const rk_scene_sim *sim, const rk_koopman_variation *v, const char *file,
                              rk_koopman_run *out, rk_error *err)
{
    memset(out, 0, sizeof *out);
    if (sim->options.is_static) return rk_fail(err, "Koopman: the scene is a static solve; DMD learns dynamics");
    int nv = sim->mesh.nv, n3 = 3 * nv, T = sim->steps, ndim, rc = -1;
    long shape[4];
    rk_fom_options opt;
    double *force = rk_calloc((size_t)n3, sizeof(double), err), *vel = rk_calloc((size_t)n3, sizeof(double), err);
    double *x = NULL;
    if (!force || !vel || rk_npy_read(file, &x, &ndim, shape, err)) goto done;
    if (ndim != 3 || shape[0] != T + 1 || shape[1] != nv || shape[2] != 3) {
        rk_fail(err, "%s: a trajectory of this scene is %d x %d x 3 (romkit fom --trajectory --snapshots)", file, T + 1, nv);
        goto done;
    }
    variation(sim, v, &opt, force, vel);
    if (run_start(sim, opt.gravity, force, vel, T, out, err)) goto done;
    /* as record() keeps them: u_s = x_s - X after the frame before */
    for (int t = 0; t <= T; t++)
        for (int i = 0; i < n3; i++) out->u[(size_t)(t + 1) * n3 + i] = x[(size_t)t * n3 + i] - sim->mesh.X[i];
    rc = 0;
done:
    free(x);
    free(force);
    free(vel);
    if (rc) rk_koopman_run_free(out);
    return rc;
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

int rk_koopman_scene_fit(const rk_scene_sim *sim, const rk_koopman_entry *o, const rk_basis *basis,
                         const double *frames, int T, rk_koopman *k, rk_koopman_scene_info *info, rk_error *err)
{
    return rk_koopman_scene_fit_from(sim, o, basis, frames, T, NULL, k, info, err);
}

int rk_koopman_scene_fit_from(const rk_scene_sim *sim, const rk_koopman_entry *o, const rk_basis *basis,
                              const double *frames, int T, const char *const *files, rk_koopman *k,
                              rk_koopman_scene_info *info, rk_error *err)
{
    memset(k, 0, sizeof *k);
    memset(info, 0, sizeof *info);
    /* the fit takes each run's forcing as a constant acceleration (gravity, loads): a chamber's
     * pressure, a follower load, is not one; romkit control takes chambers as inputs instead */
    for (int c = 0; c < sim->options.nchambers; c++)
        if (sim->options.chambers[c].pressure != 0 || sim->options.chambers[c].nkeys)
            return rk_fail(err, "Koopman: chamber %d holds a pressure, which the fit does not model as a forcing (romkit "
                           "control takes chambers as inputs); set it to 0", c);
    int ntraj = o->ntraj ? o->ntraj : 1, rc = -1;
    rk_koopman_run *runs = rk_calloc((size_t)ntraj, sizeof *runs, err);
    rk_koopman_trajectory *t = rk_calloc((size_t)ntraj, sizeof *t, err);
    double *P_in = NULL, *P_out = NULL;
    if (!runs || !t) goto done;
    double t0 = rk_now();
    for (int i = 0; i < ntraj; i++) {
        const rk_koopman_variation *v = o->ntraj ? &o->traj[i] : NULL;
        info->reused |= frames && as_written(v);
        int rc_run = frames && as_written(v) ? rk_koopman_scene_run_frames(sim, frames, T, &runs[i], err)
                     : files             ? rk_koopman_scene_run_file(sim, v, files[i], &runs[i], err)
                                         : rk_koopman_scene_run(sim, v, &runs[i], err);
        if (rc_run) {
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

void rk_scene_koopman_free(rk_scene_koopman *p)
{
    rk_koopman_free(&p->k);
    free(p->accel);
    free(p->u0);
    free(p->u_prev);
    free(p->tris);
    memset(p, 0, sizeof *p);
}

/* What the asset shows and steps along: the boundary, the scene's forcing, the training start. */
int rk_scene_koopman_geometry(const rk_scene_sim *sim, rk_scene_koopman *p, rk_error *err)
{
    int nv = sim->mesh.nv;
    p->accel = rk_calloc((size_t)3 * nv, sizeof(double), err);
    p->u0 = rk_calloc((size_t)3 * nv, sizeof(double), err);
    p->u_prev = rk_calloc((size_t)3 * nv, sizeof(double), err);
    if (!p->accel || !p->u0 || !p->u_prev) return -1;
    rk_koopman_scene_accel(sim, sim->options.gravity, sim->options.force, p->accel);
    rk_koopman_frame_before(sim, sim->options.velocity0, p->u_prev);
    if (rk_mesh_boundary(&sim->mesh, &p->tris, &p->ntris, err)) return -1;
    p->geometry = (rk_koopman_geometry){.nv = nv, .X = sim->mesh.X, .vertex_mass = sim->fem.vertex_mass,
                                        .tris = p->tris, .ntris = p->ntris, .accel = p->accel, .u0 = p->u0,
                                        .u_prev = p->u_prev, .source_tets = sim->mesh.nt,
                                        .trajectories = p->info.trajectories};
    return 0;
}

int rk_scene_koopman_build(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e,
                           const double *frames, int T, rk_scene_koopman *out, rk_error *err)
{
    return rk_scene_koopman_build_from(scene, sim, e, frames, T, NULL, out, err);
}

int rk_scene_koopman_build_from(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e,
                                const double *frames, int T, const char *const *files, rk_scene_koopman *out,
                                rk_error *err)
{
    rk_basis b;
    rk_scene_basis_info bi;
    double *own = NULL, seconds_basis = 0;
    int have_basis = 0, rc = -1;
    memset(out, 0, sizeof *out);
    const rk_koopman_entry *ko = rk_koopman_of(e);
    if (!ko) return rk_fail(err, "%s: %s has no koopman section", scene->path, e->path);
    if (ko->project) {
        double t0 = rk_now();
        if (!frames && rk_basis_needs_frames(&e->basis)) {
            if (rk_scene_training_frames(sim, &own, &T, err)) goto done;
            frames = own;
        }
        if (rk_scene_basis(scene, sim, &e->basis, frames, T, &b, &bi, err)) goto done;
        have_basis = 1;
        seconds_basis = rk_now() - t0;
    }
    rc = rk_koopman_scene_fit_from(sim, ko, have_basis ? &b : NULL, frames, T, files, &out->k, &out->info, err);
    if (!rc && have_basis) {
        out->info.basis_type = b.type;
        out->info.basis_columns = b.r;
        out->info.seconds_basis = seconds_basis;
    }
    if (!rc) rc = rk_scene_koopman_geometry(sim, out, err);
done:
    free(own);
    if (have_basis) {
        rk_basis_free(&b);
        rk_scene_basis_info_free(&bi);
    }
    if (rc) rk_scene_koopman_free(out);
    return rc;
}

cJSON *rk_koopman_report(const rk_koopman *k)
{
    cJSON *j = cJSON_CreateObject(), *eig = cJSON_CreateArray();
    for (int i = 0; i < k->r; i++) {
        double pair[2] = {k->lambda_re[i], k->lambda_im[i]};
        cJSON_AddItemToArray(eig, rk_json_array(pair, 2));
    }
    cJSON_AddNumberToObject(j, "rank", k->r);
    cJSON_AddNumberToObject(j, "max_abs_eigenvalue", rk_max_abs_eigenvalue(k->lambda_re, k->lambda_im, k->r));
    cJSON_AddItemToObject(j, "eigenvalues", eig);
    cJSON_AddItemToObject(j, "residuals", rk_json_array(k->residual, k->r));
    cJSON_AddNumberToObject(j, "clamped", k->clamped);
    cJSON_AddBoolToObject(j, "data_grows", k->data_grows);
    cJSON_AddNumberToObject(j, "stabilized", k->stabilized);
    cJSON_AddNumberToObject(j, "stabilize_shift", k->stabilize_shift);
    cJSON_AddNumberToObject(j, "max_abs_eigenvalue_before_refit",
                            k->stabilized ? k->stabilize_top : rk_max_abs_eigenvalue(k->lambda_re, k->lambda_im, k->r));
    cJSON_AddItemToObject(j, "step_residual", rk_json_array(k->step_residual, 2));
    cJSON_AddItemToObject(j, "singular_values", rk_json_array(k->singular, k->nsingular < 200 ? k->nsingular : 200));
    cJSON_AddNumberToObject(j, "observables", k->d);
    cJSON_AddNumberToObject(j, "h", k->h);
    return j;
}
