/* The prescribed vertices' motion of a step (fom_impl.h, rk_fom_advance_kinematics): with contact
 * they may only go as far as CCD allows, so the motion is made in moves, each as far as is safe
 * and each followed by a Newton solve that pushes the free vertices clear (rk_contact_advance).
 * Moving obstacles go to their targets inside the solves (their augmented Lagrangian). */
#include "fom/fom_impl.h"

#include <string.h>

#include "util/util.h"

typedef struct {
    rk_fom *s;
    rk_fom_solve_fn solve;
    void *ctx;
} kinematics;

/* What is left: the prescribed vertices' way to their targets at t (in work2, which the solve
 * reuses as scratch: recomputed on every call). */
static double *remaining(rk_fom *s, double t)
{
    rk_fom_impl *im = s->impl;
    double *dx = im->work2;
    memcpy(dx, s->x, sizeof(double) * (size_t)im->n);
    rk_fom_prescribe(s, t, dx);
    for (int i = 0; i < im->n; i++) dx[i] = im->prescribed_dof[i] ? dx[i] - s->x[i] : 0;
    return dx;
}

static double fraction(void *ctx, double t, rk_error *err)
{
    rk_fom *s = ((kinematics *)ctx)->s;
    double t0 = rk_now();
    double f = rk_fom_contact_ccd(s->impl, s->x, remaining(s, t), NULL, err);
    s->stats.seconds_contact += rk_now() - t0;
    return f;
}

static int move(void *ctx, double t, double f, rk_error *err)
{
    kinematics *k = ctx;
    rk_fom *s = k->s;
    if (f >= 1) rk_fom_prescribe(s, t, s->x); /* exactly on target */
    else {
        const double *dx = remaining(s, t);
        for (int i = 0; i < s->impl->n; i++) s->x[i] += f * dx[i];
    }
    return k->solve(s, k->ctx, err);
}

int rk_fom_advance_kinematics(rk_fom *s, double t, rk_fom_solve_fn solve, void *ctx, rk_error *err)
{
    if (!s->impl->has_contact) {
        rk_fom_prescribe(s, t, s->x);
        return solve(s, ctx, err);
    }
    kinematics k = {s, solve, ctx};
    return rk_contact_advance(&k, t, fraction, move, err);
}
