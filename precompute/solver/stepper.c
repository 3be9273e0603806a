/* Backward Euler and BDF2 around the incremental potential (solver.h; adaptive-subspace paper,
 * Eq. 3 and footnote 9): the prediction x~ and weight 1/(alpha h^2) of each step, where Newton
 * starts, and the velocity update with the history BDF2 keeps. */
#include "solver/solver.h"

#include <stdlib.h>
#include <string.h>

int rk_stepper_init(rk_stepper *s, int n, rk_integrator integrator, double h, rk_error *err)
{
    memset(s, 0, sizeof *s);
    if (integrator != RK_BACKWARD_EULER && integrator != RK_BDF2)
        return rk_fail(err, "unknown integrator %d", (int)integrator);
    s->n = n;
    s->integrator = integrator;
    s->h = h;
    double **vecs[] = {&s->xt, &s->xtilde, &s->x_prev, &s->v_prev, &s->scratch};
    for (size_t k = 0; k < sizeof vecs / sizeof vecs[0]; k++)
        if (!(*vecs[k] = rk_calloc((size_t)(n > 0 ? n : 1), sizeof(double), err))) {
            rk_stepper_free(s);
            return -1;
        }
    return 0;
}

void rk_stepper_free(rk_stepper *s)
{
    free(s->xt), free(s->xtilde), free(s->x_prev), free(s->v_prev), free(s->scratch);
    memset(s, 0, sizeof *s);
}

void rk_stepper_forget(rk_stepper *s)
{
    s->have_prev = 0;
}

void rk_stepper_predict(rk_stepper *s, const double *x, const double *v)
{
    double h = s->h;
    memcpy(s->xt, x, (size_t)s->n * sizeof(double));
    if (s->integrator == RK_BDF2 && s->have_prev) {
        for (int i = 0; i < s->n; i++)
            s->xtilde[i] = (4 * x[i] - s->x_prev[i]) / 3 + 2 * h / 9 * (4 * v[i] - s->v_prev[i]);
        s->w_inertia = 9.0 / (4.0 * h * h); /* alpha = 4/9 */
    } else {
        for (int i = 0; i < s->n; i++) s->xtilde[i] = x[i] + h * v[i];
        s->w_inertia = 1.0 / (h * h);
    }
}

void rk_stepper_start(rk_stepper *s, const rk_newton_problem *p, double *x)
{
    double *d = s->scratch;
    for (int i = 0; i < s->n; i++) d[i] = s->xtilde[i] - s->xt[i];
    int reachable = !p->max_step || p->max_step(p->ctx, s->xt, d) >= 1.0;
    memcpy(x, reachable ? s->xtilde : s->xt, (size_t)s->n * sizeof(double));
}

void rk_stepper_finish(rk_stepper *s, const double *x, double *v)
{
    double h = s->h;
    int bdf2 = s->integrator == RK_BDF2 && s->have_prev;
    for (int i = 0; i < s->n; i++) {
        double v_old = v[i];
        v[i] = bdf2 ? (3 * x[i] - 4 * s->xt[i] + s->x_prev[i]) / (2 * h) : (x[i] - s->xt[i]) / h;
        s->x_prev[i] = s->xt[i];
        s->v_prev[i] = v_old;
    }
    s->have_prev = 1;
}
