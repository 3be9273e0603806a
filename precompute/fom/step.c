/* One time step: backward Euler or BDF2 (paper Eq. 3 and footnote 9) through the incremental
 * potential, prescribed vertices moved to their targets at t + h first. */
#include "fom/impl.h"

#include "util/timer.h"

#include <math.h>
#include <string.h>

/* Predictor x~ and inertia weight 1/(alpha h^2) of the step from s->x, s->v. */
static double predict(const rk_fom *s, double *xtilde)
{
    const rk_fom_impl *im = s->impl;
    double h = s->opt.h;
    if (s->opt.integrator == RK_BDF2 && im->have_prev) {
        for (int i = 0; i < im->n; i++)
            xtilde[i] = (4 * s->x[i] - im->x_prev[i]) / 3 + 2 * h / 9 * (4 * s->v[i] - im->v_prev[i]);
        return 9.0 / (4.0 * h * h); /* alpha = 4/9 */
    }
    for (int i = 0; i < im->n; i++) xtilde[i] = s->x[i] + h * s->v[i];
    return 1.0 / (h * h);
}

static int check_state(const rk_fom *s, rk_error *err)
{
    for (int i = 0; i < s->impl->n; i++) {
        if (!isfinite(s->x[i])) return rk_fail(err, "position of vertex %d is not finite", i / 3);
        if (!isfinite(s->v[i])) return rk_fail(err, "velocity of vertex %d is not finite", i / 3);
    }
    return 0;
}

static int step(rk_fom *s, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    int n = im->n;
    double h = s->opt.h;
    if (check_state(s, err)) return -1;
    int bdf2 = s->opt.integrator == RK_BDF2 && im->have_prev;
    rk_fom_terms T = {0};
    T.w_inertia = predict(s, im->xtilde);
    T.xtilde = im->xtilde;
    T.w_damping = 1.0 / h;
    T.xt = im->xt;
    T.load = 1.0;
    memcpy(im->xt, s->x, (size_t)n * sizeof(double));

    /* Start Newton from the predictor when it keeps clear of the planes, else from x_t. */
    for (int i = 0; i < n; i++) im->d[i] = im->xtilde[i] - im->xt[i];
    if (!s->opt.obstacles.count || rk_planes_max_step(&s->opt.obstacles, s->fem->nv, im->xt, im->d) >= 1.0)
        memcpy(s->x, im->xtilde, (size_t)n * sizeof(double));
    rk_fom_prescribe(s, s->t + h, s->x);
    if (rk_fom_check_planes(s, s->x, err)) return -1;

    int converged;
    if (rk_fom_newton(s, &T, s->opt.newton_tol * h, &converged, err)) return -1;
    if (!converged) s->stats.unconverged_steps++;

    /* v_{t+1}; x_{t-1}, v_{t-1} <- x_t, v_t for the next BDF2 step. */
    for (int i = 0; i < n; i++) {
        double v_old = s->v[i];
        s->v[i] = bdf2 ? (3 * s->x[i] - 4 * im->xt[i] + im->x_prev[i]) / (2 * h) : (s->x[i] - im->xt[i]) / h;
        im->x_prev[i] = im->xt[i];
        im->v_prev[i] = v_old;
    }
    im->have_prev = 1;
    if (check_state(s, err)) return -1;
    s->t += h;
    return 0;
}

int rk_fom_step(rk_fom *s, rk_error *err)
{
    double t0 = rk_now();
    long number = s->stats.steps + 1;
    int rc = step(s, err);
    s->stats.seconds_total += rk_now() - t0;
    if (rc) return rk_error_prefix(err, "step %ld (t = %g s)", number, s->t + s->opt.h);
    s->stats.steps = number;
    return 0;
}
