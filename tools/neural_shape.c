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
    for (int j = 0; j < f->g; j++) {
        char *end;
        gamma[j] = strtod(p, &end);
        if (end == p || !isfinite(gamma[j]) || (j + 1 < f->g ? *end != ',' : *end != '\0'))
            return rk_fail(err, "%s '%s': need %d comma-separated finite numbers (the family's shape code)", opt, text,
                           f->g);
        double lo = INFINITY, hi = -INFINITY;
        for (int i = 0; i < f->nmembers; i++) lo = fmin(lo, f->member[i].gamma[j]), hi = fmax(hi, f->member[i].gamma[j]);
        if (gamma[j] < lo || gamma[j] > hi)
            return rk_fail(err, "%s '%s': value %d (%g) is outside the members' range [%g, %g]", opt, text, j, gamma[j],
                           lo, hi);
        p = end + 1;
    }
    return 0;
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
} shape_ctx;

static void shape_close(shape_ctx *c)
{
    if (c->built) {
        rk_scene_sim_free(&c->sim);
        rk_scene_free(&c->sc);
    }
    free(c->accel);
    c->accel = NULL;
    c->built = 0;
}

static int family_shape(void *ctx, const double *gamma, rk_koopman_shape *s, rk_error *err)
{
    shape_ctx *c = ctx;
    shape_close(c);
    if (rk_family_shape_scene(c->f, gamma, &c->sc, err)) return -1;
    if (rk_scene_build(&c->sc, &c->sim, err)) {
        rk_scene_free(&c->sc);
        return -1;
    }
    c->built = 1;
    int nv = c->sim.mesh.nv;
    if (c->vertex >= nv) return rk_fail(err, "--objective: vertex %d, the shape's mesh has %d", c->vertex, nv);
    if (!(c->accel = rk_calloc((size_t)3 * nv, sizeof(double), err))) return -1;
    rk_koopman_scene_accel(&c->sim, c->sim.options.gravity, c->sim.options.force, c->accel);
    *s = (rk_koopman_shape){c->sim.mesh.X, nv, c->accel, 3 * c->vertex + c->axis};
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
    if (!f->has_shape) return rk_fail(err, "--objective: the family file has no \"shape\" (how a code maps to a mesh)");
    if (objective(a->objective, &c->vertex, &c->axis, err)) return -1;
    if (!a->target || cli_real(a->target, -1e6, 1e6, &p->target))
        return rk_fail(err, "--target: a position in m is required with --objective, got '%s'", a->target ? a->target : "");
    if (!a->steps || cli_whole(a->steps, 1, 1L << 40, &steps))
        return rk_fail(err, "--steps: a whole number of steps >= 1 is required with --objective");
    p->steps = steps;
    for (int j = 0; j < f->g; j++) { /* default start: the middle of the members' range */
        double lo = INFINITY, hi = -INFINITY;
        for (int i = 0; i < f->nmembers; i++) lo = fmin(lo, f->member[i].gamma[j]), hi = fmax(hi, f->member[i].gamma[j]);
        gamma[j] = 0.5 * (lo + hi);
    }
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

int neural_shape_optimize(const neural_shape_args *a, const rk_koopman_neural *nk, const rk_family *f, double *gamma,
                          cJSON *report, rk_error *err)
{
    shape_ctx c;
    rk_koopman_shape_problem p;
    rk_koopman_shape_report r;
    if (problem(a, f, &c, &p, gamma, err)) return -1;
    cJSON_AddItemToObject(report, "gamma_start", rk_json_array(gamma, f->g));
    p.nk = nk;
    int rc = rk_koopman_shape_optimize(&p, gamma, &r, err);
    shape_close(&c);
    if (rc) return rk_error_prefix(err, "shape optimisation");
    cJSON_AddNumberToObject(report, "vertex", c.vertex);
    cJSON_AddNumberToObject(report, "axis", c.axis);
    cJSON_AddNumberToObject(report, "steps", (double)p.steps);
    cJSON_AddNumberToObject(report, "target", p.target);
    cJSON_AddItemToObject(report, "gamma", rk_json_array(gamma, f->g));
    cJSON_AddNumberToObject(report, "value", r.value);
    cJSON_AddNumberToObject(report, "iterations", r.iterations);
    cJSON_AddNumberToObject(report, "evaluations", r.evaluations);
    cJSON_AddNumberToObject(report, "seconds", r.seconds);
    printf("shape optimisation: gamma %.6g after %d iterations (%d evaluations, %.2f s): vertex %d's %c after %lld steps "
           "%.6g m, target %.6g m\n", gamma[0], r.iterations, r.evaluations, r.seconds, c.vertex, 'x' + c.axis,
           p.steps, r.value, p.target);
    return 0;
}
