/* rk_koopman_track (koopman.h): a target trajectory followed frame by frame with the control of
 * Sec. 7.3, receding horizon. Nothing here is a second solver: each frame is one
 * rk_koopman_control problem and one rk_koopman_forced step. */
#include "koopman/koopman.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int check_track(const rk_koopman *k, const rk_koopman_track_problem *p, rk_error *err)
{
    if (p->frames < 2) return rk_fail(err, "%d goal frames: at least 2 (the start and one step)", p->frames);
    if (p->horizon < 1) return rk_fail(err, "horizon %d: at least 1 step", p->horizon);
    if (p->m < 1 || !p->index || !p->goal) return rk_fail(err, "no values to follow");
    for (size_t i = 0; i < (size_t)p->m * p->frames; i++)
        if (!isfinite(p->goal[i]))
            return rk_fail(err, "goal of value %d at frame %zu is not finite", p->index[i % p->m], i / p->m);
    return 0; /* the rest (indices, inputs, callback) is rk_koopman_control's to check */
}

/* a = accel + sum_j C_j a_j(u): the total acceleration during one step. */
static int total_accel(const rk_koopman *k, const rk_koopman_track_problem *p, const double *C, const double *u,
                       double *aj, double *a, rk_error *err)
{
    for (int i = 0; i < k->n; i++) a[i] = p->accel ? p->accel[i] : 0;
    for (int j = 0; j < p->inputs; j++) {
        memset(aj, 0, sizeof(double) * (size_t)k->n);
        if (p->input_field(p->ctx, u, j, aj)) return rk_fail(err, "input field %d: the callback failed", j);
        for (int i = 0; i < k->n; i++) a[i] += C[j] * aj[i];
    }
    return 0;
}

int rk_koopman_track(const rk_koopman *k, const rk_koopman_track_problem *p, double *C, double *u, rk_error *err)
{
    if (check_track(k, p, err)) return rk_error_prefix(err, "Koopman tracking");
    int n = k->n, r = k->r, T = p->frames, rc = -1;
    rk_koopman_target *tg = rk_calloc((size_t)p->m, sizeof *tg, err);
    double *z = rk_calloc((size_t)2 * r, sizeof(double), err), *zf = z ? z + r : NULL;
    double *buf = rk_calloc((size_t)3 * n, sizeof(double), err), *uf = buf, *aj = buf ? buf + n : NULL,
           *a = buf ? buf + 2 * n : NULL;
    if (!tg || !z || !buf) goto done;
    if (p->z0) memcpy(z, p->z0, sizeof(double) * (size_t)r);
    if (u) rk_koopman_positions(k, z, u);
    for (int t = 0; t + 1 < T; t++) {
        int H = p->horizon < T - 1 - t ? p->horizon : T - 1 - t, g = t + H;
        for (int i = 0; i < p->m; i++) tg[i] = (rk_koopman_target){p->index[i], p->goal[(size_t)p->m * g + i]};
        rk_koopman_control_problem cp;
        rk_koopman_control_default(&cp);
        cp.steps = H;
        cp.z0 = z;
        cp.accel = p->accel;
        cp.inputs = p->inputs;
        cp.input_field = p->input_field;
        cp.ctx = p->ctx;
        cp.targets = tg;
        cp.ntargets = p->m;
        cp.nonnegative = p->nonnegative;
        cp.regularize = p->regularize;
        cp.iterations = p->iterations;
        double *Ct = C + (size_t)p->inputs * t;
        if (rk_koopman_control(k, &cp, Ct, NULL, zf, err)) {
            rk_error_prefix(err, "frame %d", t);
            goto done;
        }
        /* the inputs act as the solve assumed them: their fields at the predicted goal frame */
        rk_koopman_positions(k, zf, uf);
        if (total_accel(k, p, Ct, uf, aj, a, err) || rk_koopman_forced(k, 1, a, z, err)) {
            rk_error_prefix(err, "frame %d", t);
            goto done;
        }
        if (u) rk_koopman_positions(k, z, u + (size_t)n * (t + 1));
    }
    rc = 0;
done:
    free(tg);
    free(z);
    free(buf);
    return rc ? rk_error_prefix(err, "Koopman tracking") : 0;
}
