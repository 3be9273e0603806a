/* rk_scene_control (pipeline.h): the Koopman control of Sec. 7.3 on a scene, from the command line's
 * point of view. The inputs are forces on named vertex groups or chambers' pressures; the operator is trained on the
 * entry's trajectories plus one run per input (a linear model answers a push it never saw with
 * whatever its fit happens to say: test_pipeline_koopman_control.c); the target is followed by
 * rk_koopman_track; the full-order model is then run under the same inputs, as Fig. 15 does. */
#include "pipeline/pipeline.h"
#include "pipeline/control.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/util.h"

/* The inputs' groups as vertex lists, each pressure input's chamber (index into the scene's), and
 * scratch for a pressure field (positions, forces). */
typedef struct {
    const rk_scene_sim *sim;
    const rk_control_options *o;
    int *verts[RK_ASSET_MAX_GROUPS], count[RK_ASSET_MAX_GROUPS];
    double mass[RK_ASSET_MAX_GROUPS];
    int chamber[RK_CONTROL_MAX_INPUTS];  /* -1: a force input */
    int pressures;                       /* pressure inputs */
    double *x, *f;                       /* 3 nv each */
    double *trained[RK_CONTROL_MAX_INPUTS]; /* a pressure input's field per pascal (m/s^2 / Pa) where its
                                             * training run ended: the one forcing the fit has seen */
} groups;

static void groups_free(groups *g)
{
    for (int i = 0; i < RK_ASSET_MAX_GROUPS; i++) free(g->verts[i]);
    for (int j = 0; j < RK_CONTROL_MAX_INPUTS; j++) free(g->trained[j]);
    free(g->x);
    free(g->f);
}

/* Pressure inputs: their chambers by name; none of the scene's chambers pressurised (the solve
 * starts every chamber from 0). */
static int chambers_init(const rk_scene_sim *sim, const rk_control_options *o, groups *g, rk_error *err)
{
    const rk_fom_options *opt = &sim->options;
    for (int j = 0; j < o->ninputs; j++) {
        g->chamber[j] = -1;
        if (!o->input[j].chamber[0]) continue;
        for (int c = 0; c < opt->nchambers && g->chamber[j] < 0; c++)
            if (!strcmp(sim->chamber_name[c], o->input[j].chamber)) g->chamber[j] = c;
        if (g->chamber[j] < 0)
            return rk_fail(err, "input %d: the scene has no chamber \"%s\" (%d named)", j, o->input[j].chamber,
                           opt->nchambers);
        g->pressures++;
    }
    for (int c = 0; c < opt->nchambers; c++)
        if (opt->chambers[c].pressure != 0 || opt->chambers[c].nkeys)
            return rk_fail(err, "chamber \"%s\" holds %g Pa (or a schedule) in the scene: control solves the chambers' "
                           "pressures from 0 (set it to 0)", sim->chamber_name[c], opt->chambers[c].pressure);
    if (g->pressures && !(o->train_pressure > 0))
        return rk_fail(err, "a pressure input needs a training pressure (Pa, > 0)");
    if (g->pressures && !o->nfollow)
        return rk_fail(err, "a pressure input has no group to follow: name the followed groups");
    int n3 = 3 * sim->mesh.nv;
    g->x = rk_calloc((size_t)n3, sizeof(double), err);
    g->f = rk_calloc((size_t)n3, sizeof(double), err);
    return g->x && g->f ? 0 : -1;
}

/* A(X) for pressure input j: the force of 1 Pa on its chamber's walls at displacements u (NULL:
 * rest) into g->f. */
static void unit_pressure_force(const groups *g, int j, const double *u)
{
    const rk_scene_sim *sim = g->sim;
    int n3 = 3 * sim->mesh.nv;
    rk_chamber c = sim->options.chambers[g->chamber[j]];
    c.pressure = 1;
    for (int i = 0; i < n3; i++) g->x[i] = sim->mesh.X[i] + (u ? u[i] : 0), g->f[i] = 0;
    rk_chamber_force(&c, g->x, 1.0, g->f);
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

/* a += C times input j's acceleration field at displacements u (NULL: rest): a force input's is
 * C / M_group along the axis on the group's vertices (force m_v C / M_group on vertex v, C newtons
 * in all). A pressure input's is C A(X) / m_v, the force of C pascals on the chamber's walls where
 * they are at u over each vertex's mass, once trained taken along the trained field alone: its
 * mass-weighted projection on it. Why: the fit has seen the pressure push one way only (its training
 * run's), and a linear model answers a forcing it never saw with whatever its fit happens to say (on
 * examples/scenes/finger_pneumatic.json the rest walls' field, 1e5 Pa, threw the tip 125 m where the
 * run moved it 2.4 mm); what A(X) then says is how much of that push a pascal makes where the walls
 * are (they stretch: more area, more force). */
static void add_field(const groups *g, int j, double C, const double *u, double *a)
{
    const rk_control_input *in = &g->o->input[j];
    const rk_scene_sim *sim = g->sim;
    int n3 = 3 * sim->mesh.nv;
    if (g->chamber[j] >= 0) {
        unit_pressure_force(g, j, u);
        const double *T = g->trained[j];
        if (!T) {
            for (int i = 0; i < n3; i++)
                if (g->f[i] != 0) a[i] += C * g->f[i] / sim->fem.vertex_mass[i / 3];
            return;
        }
        double fa = 0, aa = 0; /* <a(X), T>_M / <T, T>_M with a(X) = f / m: sum f T over sum m T T */
        for (int i = 0; i < n3; i++) fa += g->f[i] * T[i], aa += sim->fem.vertex_mass[i / 3] * T[i] * T[i];
        for (int i = 0; aa > 0 && i < n3; i++) a[i] += C * fa / aa * T[i];
        return;
    }
    for (int q = 0; q < g->count[in->group]; q++) a[3 * g->verts[in->group][q] + in->axis] += C / g->mass[in->group];
}

static int input_field(void *ctx, const double *u, int j, double *a)
{
    /* a force of fixed direction does not depend on the state; a pressure's A(X) does (Sec. 7.3: it
     * is evaluated at the predicted final state, and the solve repeated) */
    add_field(ctx, j, 1, u, a);
    return 0;
}

/* force = the scene's loads + sum_j C_j (input j's forces; a pressure input's as its force on the rest
 * walls, unless follower: then it is left to the chambers, rk_fom_set_pressure); C NULL: the loads. */
static void forces(const groups *g, const double *C, int follower, double *force)
{
    const rk_scene_sim *sim = g->sim;
    int n3 = 3 * sim->mesh.nv;
    for (int i = 0; i < n3; i++) force[i] = 0;
    for (int j = 0; C && j < g->o->ninputs; j++)
        if (!(follower && g->chamber[j] >= 0)) add_field(g, j, C[j], NULL, force); /* accelerations first */
    for (int i = 0; i < n3; i++)
        force[i] = force[i] * sim->fem.vertex_mass[i / 3] + (sim->options.force ? sim->options.force[i] : 0);
}

/* P (the scene's chambers) = sum of the pressure inputs' C_j on each. */
static void pressures(const groups *g, const double *C, double *P)
{
    for (int c = 0; c < g->sim->options.nchambers; c++) P[c] = 0;
    for (int j = 0; j < g->o->ninputs; j++)
        if (g->chamber[j] >= 0) P[g->chamber[j]] += C[j];
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
        int j = i - nvar, pressure = i >= nvar && g->chamber[j] >= 0;
        if (i >= nvar && !pressure) {
            int q = o->input[j].group;
            double gn = sqrt(sim->options.gravity[0] * sim->options.gravity[0] +
                             sim->options.gravity[1] * sim->options.gravity[1] +
                             sim->options.gravity[2] * sim->options.gravity[2]);
            memset(C, 0, sizeof(double) * (size_t)o->ninputs);
            C[j] = o->train_force > 0 ? o->train_force : g->mass[q] * (gn > 0 ? gn : 9.81);
            forces(g, C, 0, f);
            s.options.force = f;
        }
        rk_chamber *held = NULL;
        if (pressure) { /* the chamber held at the training pressure, a follower load as the replay's */
            if (!(held = rk_calloc((size_t)sim->options.nchambers, sizeof *held, err))) goto done;
            memcpy(held, sim->options.chambers, sizeof *held * (size_t)sim->options.nchambers);
            held[g->chamber[j]].pressure = o->train_pressure;
            s.options.chambers = held;
        }
        int failed = rk_koopman_scene_run(&s, i < nvar && ko->ntraj ? &ko->traj[i] : NULL, &runs[i], err);
        free(held);
        if (failed) {
            rk_error_prefix(err, i < nvar ? "trajectory %d" : "training run of input %d", i < nvar ? i : j);
            goto done;
        }
        if (pressure) { /* the fit's forcing: the pressure's field where the run ends (Sec. 7.3's
                         * quasi-static assumption: a constant force at the final state) */
            double *field = rk_calloc((size_t)n3, sizeof(double), err);
            if (!field) goto done;
            add_field(g, j, 1, runs[i].u + (size_t)n3 * (runs[i].t.frames - 1), field); /* before it is trained */
            for (int v = 0; v < n3; v++) runs[i].accel[v] += o->train_pressure * field[v];
            ((groups *)g)->trained[j] = field;
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
                                  /* forces: A does not depend on the state, one solve is exact;
                                   * pressures: the paper's 5 (Sec. 7.3) */
                                  .iterations = g->pressures ? 5 : 1};
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
    double *force, *pressure;
} replay;

/* After step s: keep the frame, then set the forces of step s + 1 (inputs C_s). */
static int replay_frame(void *ctx, int step, rk_fom *fom, double seconds, rk_error *err)
{
    replay *r = ctx;
    int n3 = 3 * r->g->sim->mesh.nv;
    for (int i = 0; i < n3; i++) r->out->u_fom[(size_t)n3 * step + i] = fom->x[i] - r->g->sim->mesh.X[i];
    if (step + 1 < r->out->T) {
        const double *C = r->out->C + (size_t)r->out->inputs * step;
        forces(r->g, C, 1, r->force);
        rk_fom_set_force(fom, r->force);
        pressures(r->g, C, r->pressure);
        rk_fom_set_pressure(fom, r->pressure);
    }
    return 0;
}

static int full_order(const groups *g, rk_control_result *out, rk_error *err)
{
    rk_scene_sim s = *g->sim;
    s.steps = out->T - 1;
    replay r = {g, out, rk_calloc((size_t)3 * s.mesh.nv, sizeof(double), err),
                rk_calloc((size_t)s.options.nchambers + 1, sizeof(double), err)};
    double t0 = rk_now();
    int rc = r.force && r.pressure
                 ? rk_scene_fom_run(&s, NULL, "full-order run under the inputs", replay_frame, &r, NULL, err)
                 : -1;
    out->seconds_fom = rk_now() - t0;
    free(r.force);
    free(r.pressure);
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
        if (!o->input[j].chamber[0] && (o->input[j].group < 0 || o->input[j].group >= e->asset.ngroups ||
                                        o->input[j].axis < 0 || o->input[j].axis > 2))
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
    if (out->C && out->u_model && out->u_fom && !groups_init(sim, e, o, &g, err) && !chambers_init(sim, o, &g, err))
        rc = train(&g, e, &k, out, err) || solve(&g, &k, target, T, out, err) || full_order(&g, out, err) ? -1 : 0;
    groups_free(&g);
    rk_koopman_free(&k);
    if (rc) rk_control_result_free(out);
    return rc ? rk_error_prefix(err, "control") : 0;
}
