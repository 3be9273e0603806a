/* rk_scene_control (pipeline.h): the Koopman control of Sec. 7.3 on a scene, from the command line's
 * point of view. The inputs are forces on named vertex groups; the operator is trained on the
 * entry's trajectories plus one run per input (a linear model answers a push it never saw with
 * whatever its fit happens to say: test_pipeline_koopman_control.c); the target is followed by
 * rk_koopman_track; the full-order model is then run under the same inputs, as Fig. 15 does. */
#include "pipeline/pipeline.h"
#include "pipeline/control.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/util.h"

/* The inputs' groups as vertex lists. */
typedef struct {
    const rk_scene_sim *sim;
    const rk_control_options *o;
    int *verts[RK_ASSET_MAX_GROUPS], count[RK_ASSET_MAX_GROUPS];
    double mass[RK_ASSET_MAX_GROUPS];
} groups;

static void groups_free(groups *g)
{
    for (int i = 0; i < RK_ASSET_MAX_GROUPS; i++) free(g->verts[i]);
}

static int groups_init(const rk_scene_sim *sim, const rk_rom_entry *e, const rk_control_options *o, groups *g,
                       rk_error *err)
{
    g->sim = sim; /* g zeroed by the caller, so that a partial init frees cleanly */
    g->o = o;
    int nv = sim->mesh.nv;
    double slack = 1e-9 * rk_points_diagonal(sim->mesh.X, nv); /* as the asset's groups select */
    for (int q = 0; q < e->asset.ngroups; q++) {
        if (!(g->verts[q] = rk_calloc((size_t)nv, sizeof(int), err))) return -1;
        for (int v = 0; v < nv; v++)
            if (rk_box_contains(&e->asset.groups[q].box, &sim->mesh.X[3 * v], slack)) {
                g->verts[q][g->count[q]++] = v;
                g->mass[q] += sim->fem.vertex_mass[v];
            }
        if (!g->count[q]) return rk_fail(err, "group \"%s\": its box holds no vertex", e->asset.groups[q].name);
    }
    return 0;
}

/* a += C times input j's acceleration field: C / M_group along the axis on the group's vertices
 * (force m_v C / M_group on vertex v, C newtons in all). */
static void add_field(const groups *g, int j, double C, double *a)
{
    const rk_control_input *in = &g->o->input[j];
    for (int q = 0; q < g->count[in->group]; q++) a[3 * g->verts[in->group][q] + in->axis] += C / g->mass[in->group];
}

static int input_field(void *ctx, const double *u, int j, double *a)
{
    (void)u; /* a force of fixed direction: A does not depend on the state */
    add_field(ctx, j, 1, a);
    return 0;
}

/* force = the scene's loads + sum_j C_j (input j's forces); C NULL: the loads alone. */
static void forces(const groups *g, const double *C, double *force)
{
    const rk_scene_sim *sim = g->sim;
    int n3 = 3 * sim->mesh.nv;
    for (int i = 0; i < n3; i++) force[i] = 0;
    for (int j = 0; C && j < g->o->ninputs; j++) add_field(g, j, C[j], force); /* accelerations first */
    for (int i = 0; i < n3; i++)
        force[i] = force[i] * sim->fem.vertex_mass[i / 3] + (sim->options.force ? sim->options.force[i] : 0);
}

/* The training runs (the entry's trajectories, then one per input holding its train force) and the fit. */
static int train(const groups *g, const rk_rom_entry *e, rk_koopman *k, rk_control_result *out, rk_error *err)
{
    const rk_scene_sim *sim = g->sim;
    const rk_control_options *o = g->o;
    const rk_koopman_entry *ko = rk_koopman_of(e);
    int nvar = ko->ntraj ? ko->ntraj : 1, ntraj = nvar + o->ninputs, n3 = 3 * sim->mesh.nv, rc = -1;
    rk_koopman_run *runs = rk_calloc((size_t)ntraj, sizeof *runs, err);
    rk_koopman_trajectory *t = rk_calloc((size_t)ntraj, sizeof *t, err);
    double *f = rk_calloc((size_t)n3, sizeof(double), err), *C = rk_calloc((size_t)o->ninputs, sizeof(double), err);
    double t0 = rk_now();
    if (!runs || !t || !f || !C) goto done;
    for (int i = 0; i < ntraj; i++) {
        rk_scene_sim s = *sim; /* a shallow copy with its own load */
        if (i >= nvar) {
            int j = i - nvar, q = o->input[j].group;
            double gn = sqrt(sim->options.gravity[0] * sim->options.gravity[0] +
                             sim->options.gravity[1] * sim->options.gravity[1] +
                             sim->options.gravity[2] * sim->options.gravity[2]);
            memset(C, 0, sizeof(double) * (size_t)o->ninputs);
            C[j] = o->train_force > 0 ? o->train_force : g->mass[q] * (gn > 0 ? gn : 9.81);
            forces(g, C, f);
            s.options.force = f;
        }
        if (rk_koopman_scene_run(&s, i < nvar && ko->ntraj ? &ko->traj[i] : NULL, &runs[i], err)) {
            rk_error_prefix(err, i < nvar ? "trajectory %d" : "training run of input %d", i < nvar ? i : i - nvar);
            goto done;
        }
        t[i] = runs[i].t;
    }
    out->trajectories = ntraj;
    out->seconds_training = rk_now() - t0;
    t0 = rk_now();
    if (rk_koopman_fit(t, ntraj, n3, &ko->fit, k, err)) goto done;
    out->seconds_fit = rk_now() - t0;
    out->rank = k->r;
    for (int j = 0; j < k->r; j++) out->max_abs_eigenvalue = fmax(out->max_abs_eigenvalue, hypot(k->lambda_re[j], k->lambda_im[j]));
    rc = 0;
done:
    for (int i = 0; runs && i < ntraj; i++) rk_koopman_run_free(&runs[i]);
    free(runs);
    free(t);
    free(f);
    free(C);
    return rc;
}

/* The followed values (3 per vertex of each followed group, a vertex once) and their goals. */
static int follow_values(const groups *g, const double *target, int T, int **index, double **goal, int *m,
                         rk_error *err)
{
    const rk_control_options *o = g->o;
    int nv = g->sim->mesh.nv;
    unsigned char *in = rk_calloc((size_t)nv, 1, err);
    if (!in) return -1;
    for (int q = 0; q < (o->nfollow ? o->nfollow : o->ninputs); q++) {
        int grp = o->nfollow ? o->follow[q] : o->input[q].group;
        for (int v = 0; v < g->count[grp]; v++) in[g->verts[grp][v]] = 1;
    }
    *m = 0;
    for (int v = 0; v < nv; v++) *m += 3 * in[v];
    *index = rk_calloc((size_t)*m, sizeof(int), err);
    *goal = rk_calloc((size_t)*m * T, sizeof(double), err);
    if (*index && *goal) {
        for (int v = 0, i = 0; v < nv; v++)
            for (int c = 0; in[v] && c < 3; c++) (*index)[i++] = 3 * v + c;
        for (int t = 0; t < T; t++)
            for (int i = 0; i < *m; i++) (*goal)[(size_t)*m * t + i] = target[(size_t)3 * nv * t + (*index)[i]];
    }
    free(in);
    return *index && *goal ? 0 : -1;
}

/* The solve: rk_koopman_track from the scene's start under its gravity and loads. */
static int solve(const groups *g, const rk_koopman *k, const double *target, int T, rk_control_result *out,
                 rk_error *err)
{
    const rk_scene_sim *sim = g->sim;
    int n3 = 3 * sim->mesh.nv, rc = -1, *index = NULL;
    double *goal = NULL, t0 = rk_now();
    double *accel = rk_calloc((size_t)n3 * 3, sizeof(double), err), *u0 = accel + n3, *u_prev = u0 + n3;
    double *z0 = rk_calloc((size_t)k->r, sizeof(double), err);
    if (!accel || !z0 || follow_values(g, target, T, &index, &goal, &out->follow_values, err)) goto done;
    rk_koopman_scene_accel(sim, sim->options.gravity, sim->options.force, accel);
    rk_koopman_frame_before(sim, sim->options.velocity0, u_prev); /* as the training runs start */
    rk_koopman_lift(k, u0, u_prev, z0);
    rk_koopman_track_problem p = {.frames = T, .horizon = g->o->horizon, .m = out->follow_values, .index = index,
                                  .goal = goal, .z0 = z0, .accel = accel, .inputs = g->o->ninputs,
                                  .input_field = input_field, .ctx = (void *)g, .nonnegative = g->o->nonnegative,
                                  .regularize = g->o->regularize,
                                  .iterations = 1}; /* A does not depend on the state: one solve is exact */
    rc = rk_koopman_track(k, &p, out->C, out->u_model, err);
    out->seconds_solve = rk_now() - t0;
done:
    free(accel);
    free(z0);
    free(index);
    free(goal);
    return rc;
}

typedef struct {
    const groups *g;
    rk_control_result *out;
    double *force;
} replay;

/* After step s: keep the frame, then set the forces of step s + 1 (inputs C_s). */
static int replay_frame(void *ctx, int step, rk_fom *fom, double seconds, rk_error *err)
{
    replay *r = ctx;
    int n3 = 3 * r->g->sim->mesh.nv;
    for (int i = 0; i < n3; i++) r->out->u_fom[(size_t)n3 * step + i] = fom->x[i] - r->g->sim->mesh.X[i];
    if (step + 1 < r->out->T) {
        forces(r->g, r->out->C + (size_t)r->out->inputs * step, r->force);
        rk_fom_set_force(fom, r->force);
    }
    return 0;
}

static int full_order(const groups *g, rk_control_result *out, rk_error *err)
{
    rk_scene_sim s = *g->sim;
    s.steps = out->T - 1;
    replay r = {g, out, rk_calloc((size_t)3 * s.mesh.nv, sizeof(double), err)};
    double t0 = rk_now();
    int rc = r.force ? rk_scene_fom_run(&s, NULL, "full-order run under the inputs", replay_frame, &r, NULL, err) : -1;
    out->seconds_fom = rk_now() - t0;
    free(r.force);
    return rc;
}

void rk_control_result_free(rk_control_result *r)
{
    free(r->C);
    free(r->u_model);
    free(r->u_fom);
    memset(r, 0, sizeof *r);
}

int rk_scene_control(const rk_scene_sim *sim, const rk_rom_entry *e, const rk_control_options *o,
                     const double *target, int T, rk_control_result *out, rk_error *err)
{
    memset(out, 0, sizeof *out);
    if (!rk_koopman_of(e)) return rk_fail(err, "%s has no koopman section: control needs a Koopman operator", e->path);
    if (rk_koopman_of(e)->project)
        return rk_fail(err, "%s.koopman.project: control works on full displacements; remove \"project\"", e->path);
    if (o->ninputs < 1 || o->ninputs > RK_CONTROL_MAX_INPUTS)
        return rk_fail(err, "%d inputs: between 1 and %d", o->ninputs, RK_CONTROL_MAX_INPUTS);
    if (T < 2) return rk_fail(err, "the target has %d frames: at least 2", T);
    for (int j = 0; j < o->ninputs; j++)
        if (o->input[j].group < 0 || o->input[j].group >= e->asset.ngroups || o->input[j].axis < 0 || o->input[j].axis > 2)
            return rk_fail(err, "input %d: no such group or axis", j);
    groups g;
    rk_koopman k;
    memset(&k, 0, sizeof k);
    memset(&g, 0, sizeof g);
    int rc = -1, n3 = 3 * sim->mesh.nv;
    out->T = T;
    out->inputs = o->ninputs;
    out->C = rk_calloc((size_t)o->ninputs * (T - 1), sizeof(double), err);
    out->u_model = rk_calloc((size_t)n3 * T, sizeof(double), err);
    out->u_fom = rk_calloc((size_t)n3 * T, sizeof(double), err);
    if (out->C && out->u_model && out->u_fom && !groups_init(sim, e, o, &g, err))
        rc = train(&g, e, &k, out, err) || solve(&g, &k, target, T, out, err) || full_order(&g, out, err) ? -1 : 0;
    groups_free(&g);
    rk_koopman_free(&k);
    if (rc) rk_control_result_free(out);
    return rc ? rk_error_prefix(err, "control") : 0;
}
