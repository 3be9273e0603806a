/* One time step: backward Euler or BDF2 (solver.h) through the incremental potential, prescribed
 * vertices moved to their targets at t + h first. */
#include "fom/fom_impl.h"

#include "util/util.h"

#include <math.h>
#include <string.h>

static int check_state(const rk_fom *s, rk_error *err)
{
    for (int i = 0; i < s->impl->n; i++) {
        if (!isfinite(s->x[i])) return rk_fail(err, "position of vertex %d is not finite", i / 3);
        if (!isfinite(s->v[i])) return rk_fail(err, "velocity of vertex %d is not finite", i / 3);
    }
    return 0;
}

typedef struct {
    const rk_fom_terms *T;
    int converged;
    rk_fom_newton_fn newton;  /* NULL: the full-order Newton */
    void *newton_ctx;
} step_solve;

/* Newton on the step's potential from where s->x is now. */
static int solve_step(rk_fom *s, void *ctx, rk_error *err)
{
    step_solve *c = ctx;
    double tol = s->opt.newton_tol * s->opt.h;
    if (c->newton) return c->newton(c->newton_ctx, s, c->T, tol, &c->converged, err);
    return rk_fom_newton(s, c->T, tol, &c->converged, err);
}

static int step(rk_fom *s, rk_fom_newton_fn newton, void *newton_ctx, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    rk_stepper *st = &im->stepper;
    double h = s->opt.h;
    if (check_state(s, err)) return -1;
    if (!newton && im->og)
        return rk_fail(err, "opt.obstacle_progress: the moving obstacles need a solver that moves them "
                            "(rk_fom_step_with)");
    rk_stepper_predict(st, s->x, s->v);
    int friction = im->has_contact && s->opt.contact.friction > 0;
    rk_fom_terms T = {.w_inertia = st->w_inertia, .xtilde = st->xtilde, .w_damping = 1.0 / h, .xt = st->xt,
                      .load = 1.0, .friction = friction};
    /* friction's normal forces and tangents lagged at x_t for the first solve */
    if (friction && (rk_fom_friction_start(im, st->xt, err) || rk_fom_friction_lag(im, st->xt, err)))
        return -1;
    /* Start Newton from the predictor when nothing is in the way (the obstacles where they are),
     * else from x_t; the prescribed vertices and the obstacles then move to their targets at t + h. */
    int start_predicted = 1;
    if (im->has_contact) {
        for (int i = 0; i < im->n; i++) im->work2[i] = st->xtilde[i] - st->xt[i];
        double t0 = rk_now();
        double alpha = rk_fom_contact_ccd(im, st->xt, im->work2, NULL, err);
        s->stats.seconds_contact += rk_now() - t0;
        if (alpha < 0) return -1;
        start_predicted = alpha >= 1;
    }
    memcpy(s->x, start_predicted ? st->xtilde : st->xt, sizeof(double) * (size_t)im->n);
    rk_fom_obstacle_targets(s, s->t + h);
    rk_fom_pressure_at(s, s->t + h); /* keyed chambers: their pressure at the step's end, as the loads act there */
    step_solve c = {&T, 1, newton, newton_ctx};
    if (rk_fom_advance_kinematics(s, s->t + h, solve_step, &c, err)) return -1;
    /* then lagged again at the solution and solved again, until a solve has nothing left to do */
    for (int k = 1; friction && k < s->opt.contact.friction_iterations; k++) {
        long before = s->stats.newton_iterations;
        if (rk_fom_friction_lag(im, s->x, err) || solve_step(s, &c, err)) return -1;
        if (s->stats.newton_iterations - before <= 1) break;
    }
    if (!c.converged) s->stats.unconverged_steps++;
    rk_stepper_finish(st, s->x, s->v);
    if (check_state(s, err)) return -1;
    s->t += h;
    if (im->has_contact) im->contact.stats.steps++;
    return 0;
}

int rk_fom_step(rk_fom *s, rk_error *err)
{
    return rk_fom_step_with(s, NULL, NULL, err);
}

int rk_fom_step_with(rk_fom *s, rk_fom_newton_fn newton, void *ctx, rk_error *err)
{
    double t0 = rk_now();
    long number = s->stats.steps + 1;
    int rc = step(s, newton, ctx, err);
    s->stats.seconds_total += rk_now() - t0;
    rk_fom_sync_stats(s);
    if (rc) return rk_error_prefix(err, "step %ld (t = %g s)", number, s->t + s->opt.h);
    s->stats.steps = number;
    return 0;
}

void rk_fom_set_state(rk_fom *s, const double *x, const double *v, const double *x_prev, const double *v_prev,
                      double t)
{
    rk_fom_impl *im = s->impl;
    memcpy(s->x, x, sizeof(double) * (size_t)im->n);
    memcpy(s->v, v, sizeof(double) * (size_t)im->n);
    s->t = t;
    rk_stepper_forget(&im->stepper);
    if (x_prev && v_prev) {
        memcpy(im->stepper.x_prev, x_prev, sizeof(double) * (size_t)im->n);
        memcpy(im->stepper.v_prev, v_prev, sizeof(double) * (size_t)im->n);
        im->stepper.have_prev = 1;
    }
    if (im->has_contact) rk_contact_set_time(&im->contact, t);
}

void rk_fom_set_force(rk_fom *s, const double *force)
{
    rk_fom_impl *im = s->impl;
    for (int v = 0; v < s->fem->nv; v++)
        for (int i = 0; i < 3; i++) im->f_ext[3 * v + i] = s->fem->vertex_mass[v] * s->opt.gravity[i];
    if (force)
        memcpy(im->force, force, sizeof(double) * (size_t)im->n);
    else
        memset(im->force, 0, sizeof(double) * (size_t)im->n);
    for (int i = 0; i < im->n; i++) im->f_ext[i] += im->force[i];
    s->opt.force = im->force;
}

void rk_fom_set_pressure(rk_fom *s, const double *pressure)
{
    for (int k = 0; k < s->opt.nchambers; k++) s->impl->chambers[k].pressure = pressure[k], s->impl->chambers[k].nkeys = 0;
}

void rk_fom_pressure_at(rk_fom *s, double t)
{
    for (int k = 0; k < s->opt.nchambers; k++) {
        rk_chamber *c = &s->impl->chambers[k];
        if (c->nkeys) c->pressure = rk_chamber_pressure_at(c, t);
    }
}
