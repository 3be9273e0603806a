/* The reduced time step and static solve (rom.h): the full-order step (fom/step.c) on q. */
#include "rom/rom_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/util.h"

int rk_rom_init(rk_rom *s, rk_rom_model *m, const double *q0, const double *v0, rk_error *err)
{
    memset(s, 0, sizeof *s);
    int r = m->r;
    s->model = m;
    /* the model's contact without a former simulator's app obstacles (rk_rom_free drops them) */
    if ((m->has_contact || m->colliders_contact) && m->contact.nobstacles > m->contact.scene_obstacles &&
        rk_contact_set_app_obstacles(&m->contact, NULL, 0, err))
        return -1;
    s->q = rk_calloc((size_t)r, sizeof(double), err);
    s->v = rk_calloc((size_t)r, sizeof(double), err);
    s->work = rk_calloc((size_t)r * (RK_ROM_WORK_VECTORS + r), sizeof(double), err);
    /* collision-vertex scratch always: an app may add colliders to any model */
    size_t n3 = 3 * (size_t)m->nv + 1;
    s->x = rk_calloc(n3, sizeof(double), err);
    s->dx = rk_calloc(n3, sizeof(double), err);
    s->gx = rk_calloc(n3, sizeof(double), err);
    s->xs = rk_calloc(n3, sizeof(double), err);
    s->xl = rk_calloc(n3, sizeof(double), err);
    s->jb = rk_calloc(12 * (size_t)r, sizeof(double), err);
    /* obstacle scratch for the scene's and, on a collision surface, the app's (collider_obstacles.c) */
    size_t onv = m->has_contact || m->colliders_contact
                     ? (size_t)m->contact.onv + (m->surface ? RK_COLLIDER_MAX_VERTICES * RK_MAX_COLLIDERS : 0)
                     : 0;
    s->odx = rk_calloc(3 * onv + 1, sizeof(double), err);
    s->ogx = rk_calloc(3 * onv + 1, sizeof(double), err);
    if (!s->q || !s->v || !s->work || !s->x || !s->dx || !s->gx || !s->xs || !s->xl || !s->jb || !s->odx || !s->ogx ||
        rk_stepper_init(&s->stepper, r, m->integrator, m->h, err)) {
        rk_rom_free(s);
        return -1;
    }
    for (int i = 0; i < r; i++)
        if ((q0 && !isfinite(q0[i])) || (v0 && !isfinite(v0[i]))) {
            rk_rom_free(s);
            return rk_fail(err, "reduced start: coordinate %d is not finite", i);
        }
    rk_rom_reset(s, q0, v0, 0.0);
    if (m->has_contact) {
        int crossings = rk_rom_contact_intersections(s, s->q, err);
        if (crossings != 0) {
            rk_rom_free(s);
            return crossings < 0 ? -1 : rk_fail(err, "reduced start: the surface intersects an obstacle, another "
                                                "object or itself (%d crossings or points behind a plane)", crossings);
        }
    }
    return 0;
}

/* A projected state's (or velocity's) lifted coordinates set to `to`, the others as the projection
 * with those given would have them (lift_fix: -P_ff^-1 P_fL times the change). */
static void lift_set(const rk_rom_model *m, double *q, const double to[12])
{
    int r = m->r;
    double *ql = q + 12 * (size_t)(m->lift_handle - 1), d[12];
    for (int c = 0; c < 12; c++) d[c] = to[c] - ql[c];
    for (int c = 0; c < 12; c++)
        for (int i = 0; i < r; i++) q[i] += m->lift_fix[i + (size_t)r * c] * d[c]; /* (0 in the lifted rows) */
    memcpy(ql, to, sizeof d);
}

void rk_rom_reset(rk_rom *s, const double *q, const double *v, double t)
{
    int r = s->model->r;
    for (int i = 0; i < r; i++) {
        s->q[i] = q ? q[i] : 0;
        s->v[i] = v ? v[i] : 0;
    }
    s->t = t;
    if (s->model->lift_handle) {
        /* the lifted coordinates to their values at t, and their velocity to the backward
         * difference a free run has there (0 at the start) */
        const rk_rom_model *m = s->model;
        double now[12], before[12], rate[12];
        int moving = t >= m->h * (1 - 1e-9);
        rk_rom_lift_values(m, t, now);
        rk_rom_lift_values(m, moving ? t - m->h : t, before);
        for (int c = 0; c < 12; c++) rate[c] = (now[c] - before[c]) / m->h;
        lift_set(m, s->q, now);
        lift_set(m, s->v, rate);
    }
    rk_stepper_forget(&s->stepper);
    if (rk_rom_contact_on(s->model)) rk_contact_set_time(&s->model->contact, t);
}

int rk_rom_realign(rk_rom *s, const double *q, const double *v, double t, double *reached, rk_error *err)
{
    int r = s->model->r;
    double alpha = 1, *target = s->work + RK_ROM_WORK_TMP2 * (size_t)r; /* scratch */
    memcpy(target, q, sizeof(double) * (size_t)r);
    if (rk_rom_contact_on(s->model)) {
        rk_contact_set_time(&s->model->contact, t);
        double *dq = s->work + RK_ROM_WORK_TMP * (size_t)r;
        for (int i = 0; i < r; i++) dq[i] = q[i] - s->q[i];
        alpha = rk_rom_contact_max_step(s, s->q, dq, NAN, err);
        if (alpha < 0) return -1;
        for (int i = 0; i < r; i++) target[i] = s->q[i] + alpha * dq[i];
    }
    rk_rom_reset(s, target, v, t);
    *reached = alpha;
    return 0;
}

void rk_rom_free(rk_rom *s)
{
    rk_rom_model *m = s->model;
    rk_error ignored;
    /* the app's obstacles leave the model's contact (out of memory they stay, and the next
     * rk_rom_init drops them) */
    if (m && (m->has_contact || m->colliders_contact) && m->contact.nobstacles > m->contact.scene_obstacles)
        rk_contact_set_app_obstacles(&m->contact, NULL, 0, &ignored);
    free(s->q);
    free(s->v);
    rk_stepper_free(&s->stepper);
    free(s->work);
    free(s->x), free(s->dx), free(s->gx), free(s->xs), free(s->xl), free(s->jb), free(s->odx), free(s->ogx);
    rk_contact_set_free(&s->pairs);
    memset(s, 0, sizeof *s);
}

static int check_state(const rk_rom *s, rk_error *err)
{
    for (int i = 0; i < s->model->r; i++)
        if (!isfinite(s->q[i]) || !isfinite(s->v[i]))
            return rk_fail(err, "reduced coordinate %d is not finite", i);
    return 0;
}

typedef struct {
    rk_rom *s;
    const rk_rom_terms *T;
    int converged;
} step_solve;

static int moving_planes(const rk_contact *c)
{
    for (int k = 0; k < c->nobstacles; k++)
        if (c->obstacles[k].kind == RK_OBSTACLE_PLANE && c->obstacles[k].motion != RK_MOTION_FIXED) return 1;
    return 0;
}

/* The obstacles' motion to t allows this much of itself from here (the subspace holds still). */
static double obstacle_fraction(void *ctx, double t, rk_error *err)
{
    rk_rom *s = ((step_solve *)ctx)->s;
    return rk_rom_contact_max_step(s, s->q, NULL, t, err);
}

static int move_and_solve(void *ctx, double t, double fraction, rk_error *err)
{
    step_solve *c = ctx;
    if (rk_rom_contact_on(c->s->model)) rk_contact_move_obstacles(&c->s->model->contact, t, fraction);
    return rk_rom_newton(c->s, c->T, c->s->model->newton_tol, &c->converged, err);
}

typedef struct {
    rk_rom *s;
    rk_rom_terms T;
    double *pin;               /* T.pin_b */
    double last_lambda;        /* the previous increment's load fraction */
} static_ctx;

/* One load increment: forces at lambda, the pins' targets and the obstacles at lambda times the
 * end time (a new attempt of the load stepping starts the obstacles over). */
static int increment(void *ctx, double lambda, double *q, int *converged, rk_error *err)
{
    static_ctx *c = ctx;
    rk_rom_model *m = c->s->model;
    if (rk_rom_contact_on(m) && lambda <= c->last_lambda) rk_contact_set_time(&m->contact, 0);
    c->last_lambda = lambda;
    c->T.load = lambda;
    rk_rom_pin_target(m, lambda * m->static_time, c->pin);
    rk_rom_lift(m, lambda * m->static_time, c->s->q);
    step_solve sv = {c->s, &c->T, 1};
    int rc = rk_rom_contact_on(m) ? rk_contact_advance(&sv, lambda * m->static_time, obstacle_fraction, move_and_solve, err)
                            : move_and_solve(&sv, 0, 1, err);
    *converged = sv.converged;
    return rc;
}

/* Equilibrium at the end time (steps h), by the solver's load stepping; an equilibrium not reached
 * even so is kept and counted as unconverged. */
static int static_solve(rk_rom *s, rk_error *err)
{
    int r = s->model->r;
    /* reg: a tiny inertia (1/s^2) on the Hessian only: free rigid modes stay solvable */
    double *pin = s->work + RK_ROM_WORK_PIN * (size_t)r;
    static_ctx c = {.s = s, .T = {.reg = 1e-10, .pin_b = pin}, .pin = pin};
    int converged;
    if (rk_load_stepping(r, s->q, increment, &c, &converged, NULL, err)) return -1;
    if (converged) memset(s->v, 0, sizeof(double) * r);
    else s->stats.unconverged_steps++;
    return 0;
}

static int dynamic_step(rk_rom *s, rk_error *err)
{
    rk_rom_model *m = s->model;
    rk_stepper *st = &s->stepper;
    double *pin = s->work + RK_ROM_WORK_PIN * (size_t)m->r;
    rk_stepper_predict(st, s->q, s->v);
    int friction = (m->has_contact || s->ncolliders) && m->contact_options.friction > 0;
    rk_rom_terms T = {.w_inertia = st->w_inertia, .qtilde = st->xtilde, .w_damping = 1.0 / m->h, .qt = st->xt,
                      .load = 1.0, .pin_b = pin, .friction = friction};
    /* friction lagged at q_t for the first solve (as the full-order step) */
    if (friction && (rk_rom_friction_start(s, st->xt, err) || rk_rom_friction_lag(s, st->xt, err))) return -1;
    rk_rom_pin_target(m, s->t + m->h, pin);
    rk_rom_problem_ctx ctx = {.s = s, .T = &T};
    rk_newton_problem p;
    rk_rom_problem(&ctx, &p);
    rk_stepper_start(st, &p, s->q);
    if (ctx.failure.msg[0]) {
        *err = ctx.failure;
        return -1;
    }
    rk_rom_lift(m, s->t + m->h, s->q); /* the moving group where it is due, before Newton moves the rest */
    step_solve c = {s, &T, 1};
    /* the app's colliders to where it put them, the body pushed ahead of them in the same solve */
    if (rk_rom_colliders_pending(s) && rk_rom_colliders_solve(s, &T, &c.converged, err)) return -1;
    s->colliders_behind = rk_rom_colliders_pending(s);
    /* the scene's obstacles to where they are at the step's end: with the body in one solve
     * (obstacle_solve.c), or in safe moves when a plane moves (the runtime's planes are static) */
    int behind = 0;
    int on = rk_rom_contact_on(m);
    if (on && !moving_planes(&m->contact) ? rk_rom_obstacles_solve(s, &T, s->t + m->h, &c.converged, &behind, err)
        : on ? rk_contact_advance(&c, s->t + m->h, obstacle_fraction, move_and_solve, err)
                         : move_and_solve(&c, s->t + m->h, 1, err))
        return -1;
    s->colliders_behind |= behind;
    if (m->surface) rk_rom_collider_obstacles_arrived(s);
    /* then lagged again at the solution and solved again, the obstacles where they are, until a
     * solve has nothing left to do */
    for (int k = 1; friction && k < m->contact_options.friction_iterations; k++) {
        long before = s->stats.newton_iterations;
        if (rk_rom_friction_lag(s, s->q, err) || rk_rom_newton(s, &T, m->newton_tol, &c.converged, err)) return -1;
        if (s->stats.newton_iterations - before <= 1) break;
    }
    if (!c.converged) s->stats.unconverged_steps++;
    rk_stepper_finish(st, s->q, s->v);
    s->t += m->h;
    return 0;
}

int rk_rom_step(rk_rom *s, rk_error *err)
{
    double t0 = rk_now();
    long number = s->stats.steps + 1;
    int rc = check_state(s, err);
    if (!rc) rc = s->model->is_static ? static_solve(s, err) : dynamic_step(s, err);
    if (!rc) rc = check_state(s, err);
    s->stats.seconds_total += rk_now() - t0;
    if (rc) return rk_error_prefix(err, "reduced step %ld (t = %g s)", number, s->t + s->model->h);
    s->stats.steps = number;
    return 0;
}
