/* Shape optimisation through the Koopman jump (koopman.h; koopman-dmd-log-linear paper, Sec. 7.4,
 * Fig. 16): the shape code of a gamma-conditioned neural DMD (Sec. 5) for which one value of the
 * frame N steps after rest reaches a target, by finite differences over gamma and Gauss-Newton. */
#include "koopman/koopman.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void rk_koopman_shape_default(rk_koopman_shape_problem *p)
{
    memset(p, 0, sizeof *p);
    p->tolerance = 1e-5;
    p->epsilon = 1e-4;
    p->max_iterations = 50;
}

int rk_koopman_shape_objective(const rk_koopman_shape_problem *p, const double *gamma, double *value, rk_error *err)
{
    rk_koopman_shape s;
    rk_koopman k;
    memset(&s, 0, sizeof s);
    if (!p || !p->nk || !p->shape || !gamma || p->steps < 1)
        return rk_fail(err, "shape optimisation: the objective needs a model, a shape function, gamma and steps >= 1");
    for (int c = 0; c < p->nk->g; c++)
        if (!isfinite(gamma[c])) return rk_fail(err, "shape optimisation: gamma[%d] is %g", c, gamma[c]);
    if (p->shape(p->ctx, gamma, &s, err)) return rk_error_prefix(err, "shape optimisation: the shape at gamma[0] = %g", gamma[0]);
    for (int i = 0; i < s.nregion; i++)
        if (!s.region || s.region[i] < 0 || s.region[i] >= s.nv || s.axis < 0 || s.axis > 2)
            return rk_fail(err, "shape optimisation: the shape at gamma[0] = %g has %d vertices: region vertex %d (%d), "
                           "axis %d", gamma[0], s.nv, i, s.region ? s.region[i] : -1, s.axis);
    if (!s.X || s.nv < 1 || (!s.nregion && (s.index < 0 || s.index >= 3 * s.nv)))
        return rk_fail(err, "shape optimisation: the shape at gamma[0] = %g has %d vertices and objective index %d", gamma[0],
                       s.nv, s.index);
    if (rk_koopman_neural_operator(p->nk, s.X, s.nv, gamma, &k, err)) return -1;
    double *z = rk_calloc((size_t)k.r, sizeof(double), err), *u = rk_calloc((size_t)k.n, sizeof(double), err);
    int rc = -1;
    /* from rest (u_{-1} = u_0 = 0: z = 0), N forced steps in closed form (Eq. 19, Eq. 25) */
    if (z && u && !rk_koopman_forced(&k, p->steps, s.accel, z, err)) {
        rk_koopman_positions(&k, z, u);
        *value = s.nregion ? 0 : s.X[s.index] + u[s.index];
        for (int i = 0; i < s.nregion; i++) *value += u[3 * s.region[i] + s.axis] / s.nregion;
        rc = isfinite(*value) ? 0 : rk_fail(err, "shape optimisation: the objective at gamma[0] = %g is %g", gamma[0], *value);
    }
    free(z);
    free(u);
    rk_koopman_free(&k);
    return rc;
}

static int check_problem(const rk_koopman_shape_problem *p, const double *gamma, rk_error *err)
{
    if (!p || !p->nk || p->nk->g < 1 || !p->shape || !gamma)
        return rk_fail(err, "shape optimisation: needs a model trained with a shape code (g >= 1), a shape function and "
                       "a start gamma");
    for (int c = 0; p->fd_step && c < p->nk->g; c++)
        if (!(p->fd_step[c] > 0) || !isfinite(p->fd_step[c]))
            return rk_fail(err, "shape optimisation: the difference step %d is %g", c, p->fd_step[c]);
    if (p->steps < 1 || !(p->tolerance > 0) || !(p->epsilon > 0) || p->max_iterations < 1)
        return rk_fail(err, "shape optimisation: bad settings (steps %lld, tolerance %g, epsilon %g, iterations %d)",
                       p->steps, p->tolerance, p->epsilon, p->max_iterations);
    if (!isfinite(p->target)) return rk_fail(err, "shape optimisation: the target is %g", p->target);
    for (int c = 0; c < p->nk->g; c++) {
        if (!isfinite(gamma[c])) return rk_fail(err, "shape optimisation: the start gamma[%d] is %g", c, gamma[c]);
        if (gamma[c] < p->nk->gamma_lo[c] || gamma[c] > p->nk->gamma_hi[c])
            return rk_fail(err, "shape optimisation: the start gamma[%d] = %g is outside the training range [%g, %g]", c,
                           gamma[c], p->nk->gamma_lo[c], p->nk->gamma_hi[c]);
    }
    return 0;
}

/* df/dgamma (g values) by central differences, step epsilon times each component's half-range
 * (or fd_step), one-sided where a side would leave the training range. */
static int gradient(const rk_koopman_shape_problem *p, double *gamma, double *grad, int *evals, rk_error *err)
{
    const rk_koopman_neural *nk = p->nk;
    for (int c = 0; c < nk->g; c++) {
        double keep = gamma[c], half = 0.5 * (nk->gamma_hi[c] - nk->gamma_lo[c]);
        double e = p->fd_step ? p->fd_step[c] : p->epsilon * (half > 0 ? half : 1), fp, fm;
        double hi = keep + e, lo = keep - e;
        if (hi > nk->gamma_hi[c] && lo >= nk->gamma_lo[c]) hi = keep;
        else if (lo < nk->gamma_lo[c] && hi <= nk->gamma_hi[c]) lo = keep;
        gamma[c] = hi;
        int rc = rk_koopman_shape_objective(p, gamma, &fp, err);
        gamma[c] = lo;
        if (!rc) rc = rk_koopman_shape_objective(p, gamma, &fm, err);
        gamma[c] = keep;
        if (rc) return -1;
        *evals += 2;
        grad[c] = (fp - fm) / (hi - lo);
    }
    return 0;
}

static void fill_report(rk_koopman_shape_report *report, int it, int evals, double f, double t0)
{
    if (!report) return;
    report->iterations = it;
    report->evaluations = evals;
    report->value = f;
    report->seconds = rk_now() - t0;
}

int rk_koopman_shape_optimize(const rk_koopman_shape_problem *p, double *gamma, rk_koopman_shape_report *report,
                              rk_error *err)
{
    if (check_problem(p, gamma, err)) return -1;
    const rk_koopman_neural *nk = p->nk;
    int g = nk->g, evals = 1, it = 0, rc = -1;
    double t0 = rk_now();
    double f, grad[RK_KOOPMAN_SHAPE_MAX], trial[RK_KOOPMAN_SHAPE_MAX];
    if (rk_koopman_shape_objective(p, gamma, &f, err)) return -1;
    while (fabs(f - p->target) > p->tolerance && it < p->max_iterations) {
        if (gradient(p, gamma, grad, &evals, err)) goto done;
        double gg = 0, res = f - p->target;
        for (int c = 0; c < g; c++) gg += grad[c] * grad[c];
        if (!(gg > 0)) {
            rk_fail(err, "shape optimisation: the objective does not change with gamma at gamma[0] = %g", gamma[0]);
            goto done;
        }
        /* Gauss-Newton on the residual: the minimum-norm step that zeroes its linearisation,
         * halved until the residual decreases, each trial clamped into the training range */
        double ft = f;
        int better = 0;
        for (double a = 1; a > 1e-6 && !better; a *= 0.5) {
            for (int c = 0; c < g; c++)
                trial[c] = fmin(nk->gamma_hi[c], fmax(nk->gamma_lo[c], gamma[c] - a * res * grad[c] / gg));
            if (rk_koopman_shape_objective(p, trial, &ft, err)) goto done;
            evals++;
            better = fabs(ft - p->target) < fabs(res);
        }
        it++;
        if (!better) break; /* stuck (at the range's edge, or at a minimum of |f - target| above tol) */
        memcpy(gamma, trial, sizeof(double) * g);
        f = ft;
    }
    if (fabs(f - p->target) > p->tolerance) {
        rk_fail(err, "shape optimisation: after %d iterations |f - target| = %g above the tolerance %g (f %g, target %g, "
                "gamma[0] %g, training range [%g, %g])", it, fabs(f - p->target), p->tolerance, f, p->target, gamma[0],
                nk->gamma_lo[0], nk->gamma_hi[0]);
    } else {
        rc = 0;
    }
done:
    fill_report(report, it, evals, f, t0);
    return rc;
}

int rk_koopman_shape_maximize(const rk_koopman_shape_problem *p, double *gamma, rk_koopman_shape_report *report,
                              rk_error *err)
{
    rk_koopman_shape_problem q = *p;
    q.target = 0; /* unused: check_problem wants it finite */
    if (check_problem(&q, gamma, err)) return -1;
    if (p->max_iterations >= RK_KOOPMAN_SHAPE_HISTORY)
        return rk_fail(err, "shape optimisation: %d iterations, at most %d", p->max_iterations,
                       RK_KOOPMAN_SHAPE_HISTORY - 1);
    const rk_koopman_neural *nk = p->nk;
    int g = nk->g, evals = 1, it = 0, rc = -1;
    double t0 = rk_now(), f, ft, grad[RK_KOOPMAN_SHAPE_MAX], trial[RK_KOOPMAN_SHAPE_MAX], half[RK_KOOPMAN_SHAPE_MAX];
    double step = 1; /* in half-range units: half the range */
    for (int c = 0; c < g; c++) half[c] = 0.5 * (nk->gamma_hi[c] - nk->gamma_lo[c]) > 0 ? 0.5 * (nk->gamma_hi[c] - nk->gamma_lo[c]) : 1;
    if (rk_koopman_shape_objective(p, gamma, &f, err)) return -1;
    if (report) report->history[0] = f;
    while (it < p->max_iterations) {
        if (gradient(p, gamma, grad, &evals, err)) goto done;
        /* the gradient in half-range units: d f / d (gamma_c / half_c) */
        double gn = 0;
        for (int c = 0; c < g; c++) gn += (grad[c] * half[c]) * (grad[c] * half[c]);
        gn = sqrt(gn);
        if (!(gn > 0)) break; /* flat: a stationary point */
        int better = 0;
        double moved = 0;
        for (; step > 1e-6 && !better; step *= 0.5) {
            double rise = 0; /* the gradient's prediction for the projected step */
            moved = 0;
            for (int c = 0; c < g; c++) {
                double x = fmin(nk->gamma_hi[c], fmax(nk->gamma_lo[c], gamma[c] + step * grad[c] * half[c] * half[c] / gn));
                rise += grad[c] * (x - gamma[c]);
                moved = fmax(moved, fabs(x - gamma[c]) / half[c]);
                trial[c] = x;
            }
            if (moved < 1e-6) break; /* the projection leaves nowhere to go */
            if (rk_koopman_shape_objective(p, trial, &ft, err)) goto done;
            evals++;
            better = ft > f + 1e-4 * rise;
        }
        if (!better) break;
        step *= 4; /* undo the loop's last halving, and double */
        if (step > 2) step = 2;
        memcpy(gamma, trial, sizeof(double) * g);
        f = ft;
        it++;
        if (report) report->history[it] = f;
        if (moved < 1e-6) break;
    }
    rc = 0;
done:
    fill_report(report, it, evals, f, t0);
    return rc;
}
