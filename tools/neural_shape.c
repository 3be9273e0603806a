/* romkit neural-dmd --objective: shape optimisation through the trained model (neural_shape.h). */
#include "neural_shape.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"

int neural_gamma(const char *opt, const char *text, const rk_family *f, double *gamma, rk_error *err)
{
    const char *p = text;
    double lo[RK_KOOPMAN_SHAPE_MAX], hi[RK_KOOPMAN_SHAPE_MAX];
    rk_family_range(f, lo, hi);
    for (int j = 0; j < f->g; j++) {
        char *end;
        gamma[j] = strtod(p, &end);
        if (end == p || !isfinite(gamma[j]) || (j + 1 < f->g ? *end != ',' : *end != '\0'))
            return rk_fail(err, "%s '%s': need %d comma-separated finite numbers (the family's shape code)", opt, text,
                           f->g);
        if (gamma[j] < lo[j] || gamma[j] > hi[j])
            return rk_fail(err, "%s '%s': value %d (%g) is outside the members' range [%g, %g]", opt, text, j, gamma[j],
                           lo[j], hi[j]);
        p = end + 1;
    }
    return 0;
}

int neural_shape_wanted(const neural_shape_args *a)
{
    return a->objective || a->lift;
}

/* "X0,Y0,Z0,X1,Y1,Z1": a box of rest positions, its corners in order. */
static int lift_box(const char *text, double *box, rk_error *err)
{
    char extra;
    if (!text || sscanf(text, "%lf,%lf,%lf,%lf,%lf,%lf%c", &box[0], &box[1], &box[2], &box[3], &box[4], &box[5],
                        &extra) != 6)
        return rk_fail(err, "--lift '%s': need X0,Y0,Z0,X1,Y1,Z1 (a box of rest positions, m)", text ? text : "");
    for (int a = 0; a < 3; a++)
        if (!isfinite(box[a]) || !isfinite(box[a + 3]) || box[a] > box[a + 3])
            return rk_fail(err, "--lift '%s': corner %c %g above %g (or not finite)", text, 'x' + a, box[a], box[a + 3]);
    return 0;
}

/* The vertices of rest positions X (nv) inside box, into *region (malloc'd); none is an error. */
static int region_of(const double *X, int nv, const double *box, const double *gamma, int **region, int *n,
                     rk_error *err)
{
    *n = 0;
    if (!(*region = rk_calloc((size_t)nv, sizeof(int), err))) return -1;
    for (int v = 0; v < nv; v++) {
        int in = 1;
        for (int a = 0; a < 3; a++) in &= X[3 * v + a] >= box[a] && X[3 * v + a] <= box[a + 3];
        if (in) (*region)[(*n)++] = v;
    }
    return *n ? 0 : rk_fail(err, "--lift: no vertex of the mesh at gamma[0] = %g lies in the box", gamma ? gamma[0] : 0);
}

/* "VERTEX,AXIS": a vertex index and x, y or z. */
static int objective(const char *text, int *vertex, int *axis, rk_error *err)
{
    char ax = 0, extra;
    long v;
    if (!text || sscanf(text, "%ld,%c%c", &v, &ax, &extra) != 2 || v < 0 || v > 1L << 30 || ax < 'x' || ax > 'z')
        return rk_fail(err, "--objective '%s': need VERTEX,AXIS (a vertex index and x, y or z)", text ? text : "");
    *vertex = (int)v;
    *axis = ax - 'x';
    return 0;
}

/* The mesh of a code and what the objective reads on it. */
typedef struct {
    const rk_family *f;
    int vertex, axis, built;
    rk_scene sc;
    rk_scene_sim sim;
    double *accel;
    int lift, nregion, *region; /* --lift: its box and the shape's vertices in it */
    double box[6];
    double fd[RK_KOOPMAN_SHAPE_MAX]; /* the difference steps when keys move in whole steps */
    char *text;                      /* the scene built (rk_family_shape_text), */
    int ready;                       /* and everything above made from it */
} shape_ctx;

static void shape_close(shape_ctx *c)
{
    if (c->built) {
        rk_scene_sim_free(&c->sim);
        rk_scene_free(&c->sc);
    }
    free(c->accel);
    free(c->region);
    free(c->text);
    c->accel = NULL;
    c->region = NULL;
    c->text = NULL;
    c->built = c->ready = 0;
}

static int family_shape(void *ctx, const double *gamma, rk_koopman_shape *s, rk_error *err)
{
    shape_ctx *c = ctx;
    /* keys in whole steps give one scene to many codes (a difference's two sides, most trial
     * steps): the scene, its load and region are reused while the scene's text is the same */
    char *text = rk_family_shape_text(c->f, gamma, err);
    if (!text) return -1;
    int same = c->ready && !strcmp(text, c->text);
    if (same) {
        free(text);
        *s = (rk_koopman_shape){c->sim.mesh.X, c->sim.mesh.nv, c->accel, 3 * c->vertex + c->axis, c->region, c->nregion, 1};
        return 0;
    }
    shape_close(c);
    c->text = text;
    if (rk_family_shape_scene(c->f, gamma, &c->sc, err)) return -1;
    if (rk_scene_build(&c->sc, &c->sim, err)) {
        rk_scene_free(&c->sc);
        return -1;
    }
    c->built = 1;
    int nv = c->sim.mesh.nv;
    if (!c->lift && c->vertex >= nv) return rk_fail(err, "--objective: vertex %d, the shape's mesh has %d", c->vertex, nv);
    if (c->lift && region_of(c->sim.mesh.X, nv, c->box, gamma, &c->region, &c->nregion, err)) return -1;
    if (!(c->accel = rk_calloc((size_t)3 * nv, sizeof(double), err))) return -1;
    rk_koopman_scene_accel(&c->sim, c->sim.options.gravity, c->sim.options.force, c->accel);
    if (rk_koopman_scene_pressure_accel(&c->sim, c->accel, err)) return -1; /* the members' load, as trained */
    *s = (rk_koopman_shape){c->sim.mesh.X, nv, c->accel, 3 * c->vertex + c->axis, c->region, c->nregion, 1};
    c->ready = 1;
    return 0;
}

/* The problem from the arguments; gamma: the start. */
static int problem(const neural_shape_args *a, const rk_family *f, shape_ctx *c, rk_koopman_shape_problem *p,
                   double *gamma, rk_error *err)
{
    long steps;
    memset(c, 0, sizeof *c);
    c->f = f;
    rk_koopman_shape_default(p);
    p->shape = family_shape;
    p->ctx = c;
    const char *opt = a->lift ? "--lift" : "--objective";
    if (!f->has_shape) return rk_fail(err, "%s: the family file has no \"shape\" (how a code maps to a mesh)", opt);
    if (a->lift) {
        c->lift = 1;
        if (lift_box(a->lift, c->box, err)) return -1;
    } else {
        if (objective(a->objective, &c->vertex, &c->axis, err)) return -1;
        if (!a->target || cli_real(a->target, -1e6, 1e6, &p->target))
            return rk_fail(err, "--target: a position in m is required with --objective, got '%s'", a->target ? a->target : "");
    }
    if (!a->steps || cli_whole(a->steps, 1, 1L << 40, &steps))
        return rk_fail(err, "--steps: a whole number of steps >= 1 is required with %s", opt);
    p->steps = steps;
    /* keys that move in whole steps make the mesh piecewise constant in the code: the difference
     * reaches across one step of the coarsest key in each code value (rk_koopman_shape_problem) */
    int stepped = 0;
    for (int j = 0; j < f->g; j++) {
        c->fd[j] = 0;
        for (int k = 0; k < f->nkeys; k++)
            if (f->keys[k].step > 0 && f->keys[k].per_gamma[j] != 0)
                c->fd[j] = fmax(c->fd[j], f->keys[k].step / fabs(f->keys[k].per_gamma[j])), stepped = 1;
    }
    double lo[RK_KOOPMAN_SHAPE_MAX], hi[RK_KOOPMAN_SHAPE_MAX];
    rk_family_range(f, lo, hi);
    if (stepped) {
        for (int j = 0; j < f->g; j++)
            if (!(c->fd[j] > 0)) c->fd[j] = p->epsilon * (hi[j] > lo[j] ? 0.5 * (hi[j] - lo[j]) : 1);
        p->fd_step = c->fd;
    }
    for (int j = 0; j < f->g; j++) gamma[j] = 0.5 * (lo[j] + hi[j]); /* default start: the middle of the range */
    return a->start ? neural_gamma("--gamma-start", a->start, f, gamma, err) : 0;
}

int neural_shape_check(const neural_shape_args *a, const rk_family *f, rk_error *err)
{
    shape_ctx c;
    rk_koopman_shape_problem p;
    rk_koopman_shape s;
    double gamma[RK_KOOPMAN_SHAPE_MAX];
    int rc = problem(a, f, &c, &p, gamma, err) || family_shape(&c, gamma, &s, err);
    if (!rc && c.sim.options.h != f->options.h)
        rc = rk_fail(err, "shape.scene: %s steps %g s, the family's members %g s", f->shape_scene, c.sim.options.h,
                     f->options.h);
    shape_close(&c);
    return rc ? -1 : 0;
}

/* --scene-out: the optimum's scene, for romkit fom there. */
static int write_scene(const char *path, const rk_family *f, const double *gamma, rk_error *err)
{
    char *text = rk_family_shape_text(f, gamma, err);
    if (!text) return -1;
    FILE *fp = fopen(path, "w");
    int rc = !fp || fputs(text, fp) < 0 || fputc('\n', fp) < 0;
    if (fp && fclose(fp)) rc = 1;
    free(text);
    return rc ? rk_fail(err, "--scene-out %s: cannot write it", path) : 0;
}

int neural_shape_optimize(const neural_shape_args *a, const rk_koopman_neural *nk, const rk_family *f, double *gamma,
                          cJSON *report, rk_error *err)
{
    shape_ctx c;
    rk_koopman_shape_problem p;
    rk_koopman_shape_report r;
    if (problem(a, f, &c, &p, gamma, err)) return -1;
    cJSON_AddItemToObject(report, "gamma_start", rk_json_array(gamma, f->g));
    p.nk = nk;
    int rc = c.lift ? rk_koopman_shape_maximize(&p, gamma, &r, err) : rk_koopman_shape_optimize(&p, gamma, &r, err);
    int nregion = c.nregion;
    shape_close(&c);
    if (rc) return rk_error_prefix(err, "shape optimisation");
    if (c.lift) {
        cJSON_AddStringToObject(report, "objective", "lift");
        cJSON_AddItemToObject(report, "box", rk_json_array(c.box, 6));
        cJSON_AddNumberToObject(report, "region_vertices", nregion);
        cJSON_AddNumberToObject(report, "value_start", r.history[0]);
        cJSON_AddItemToObject(report, "history", rk_json_array(r.history, r.iterations + 1));
    } else {
        cJSON_AddNumberToObject(report, "vertex", c.vertex);
        cJSON_AddNumberToObject(report, "axis", c.axis);
        cJSON_AddNumberToObject(report, "target", p.target);
    }
    cJSON_AddNumberToObject(report, "steps", (double)p.steps);
    cJSON_AddItemToObject(report, "gamma", rk_json_array(gamma, f->g));
    cJSON_AddNumberToObject(report, "value", r.value);
    cJSON_AddNumberToObject(report, "iterations", r.iterations);
    cJSON_AddNumberToObject(report, "evaluations", r.evaluations);
    cJSON_AddNumberToObject(report, "seconds", r.seconds);
    if (c.lift) {
        printf("lift optimisation: %d iterations (%d evaluations, %.2f s), mean y displacement of %d vertices after "
               "%lld steps:\n", r.iterations, r.evaluations, r.seconds, nregion, p.steps);
        for (int i = 0; i <= r.iterations; i++) printf("  iteration %d: %.6g m\n", i, r.history[i]);
        printf("  gamma");
        for (int j = 0; j < f->g; j++) printf(" %.6g", gamma[j]);
        printf(": predicted lift %.6g m (start %.6g m)\n", r.value, r.history[0]);
    } else {
        printf("shape optimisation: gamma %.6g after %d iterations (%d evaluations, %.2f s): vertex %d's %c after %lld "
               "steps %.6g m, target %.6g m\n", gamma[0], r.iterations, r.evaluations, r.seconds, c.vertex, 'x' + c.axis,
               p.steps, r.value, p.target);
    }
    return a->scene_out ? write_scene(a->scene_out, f, gamma, err) : 0;
}

/* A member's own mesh as the shape (its scene as built, its load as trained). */
typedef struct {
    const rk_family_member *m;
    const double *accel;
    const int *region;
    int nregion;
} member_ctx;

static int member_shape(void *ctx, const double *gamma, rk_koopman_shape *s, rk_error *err)
{
    const member_ctx *c = ctx;
    (void)gamma;
    (void)err;
    *s = (rk_koopman_shape){c->m->sim.mesh.X, c->m->sim.mesh.nv, c->accel, 0, c->region, c->nregion, 1};
    return 0;
}

int neural_shape_members(const neural_shape_args *a, const rk_koopman_neural *nk, const rk_family *f, cJSON *report,
                         int quiet, rk_error *err)
{
    shape_ctx c;
    rk_koopman_shape_problem p;
    double gamma[RK_KOOPMAN_SHAPE_MAX], worst = -1, worst_rel = -1;
    if (!a->lift) return 0;
    if (problem(a, f, &c, &p, gamma, err)) return -1;
    p.nk = nk;
    p.shape = member_shape;
    cJSON *arr = cJSON_AddArrayToObject(report, "members");
    for (int i = 0; i < f->nmembers; i++) {
        const rk_family_member *m = &f->member[i];
        int *region, n, nv = m->sim.mesh.nv;
        if (region_of(m->sim.mesh.X, nv, c.box, m->gamma, &region, &n, err)) {
            free(region);
            return rk_error_prefix(err, "members[%d]", i);
        }
        member_ctx mc = {m, m->run.accel, region, n};
        p.ctx = &mc;
        double model, full = 0;
        int rc = rk_koopman_shape_objective(&p, m->gamma, &model, err);
        /* the run's frames: u_{-1}, u_0, then one per step, so step N is frame N + 1 */
        if (!rc && p.steps + 2 > m->run.t.frames)
            rc = rk_fail(err, "%s has %d steps, the lift is at step %lld", m->snapshots, m->run.t.frames - 2, p.steps);
        for (int k = 0; !rc && k < n; k++) full += m->run.t.u[(size_t)3 * nv * (p.steps + 1) + 3 * region[k] + 1] / n;
        free(region);
        if (rc) return rk_error_prefix(err, "members[%d]", i);
        cJSON *o = cJSON_CreateObject();
        cJSON_AddItemToObject(o, "gamma", rk_json_array(m->gamma, f->g));
        cJSON_AddBoolToObject(o, "held_out", m->held_out);
        cJSON_AddNumberToObject(o, "lift_model", model);
        cJSON_AddNumberToObject(o, "lift_full_order", full);
        cJSON_AddItemToArray(arr, o);
        if (m->held_out) worst = fmax(worst, fabs(model - full)), worst_rel = fmax(worst_rel, fabs(model - full) / fabs(full));
        if (!quiet) printf("  member %d%s: lift %.6g m by the model, %.6g m at full order\n", i,
                           m->held_out ? " (held out)" : "", model, full);
    }
    if (worst >= 0) {
        cJSON_AddNumberToObject(report, "held_out_lift_error", worst);
        cJSON_AddNumberToObject(report, "held_out_lift_relative_error", worst_rel);
    } else {
        cJSON_AddNullToObject(report, "held_out_lift_error");
        cJSON_AddNullToObject(report, "held_out_lift_relative_error");
    }
    return 0;
}
