/* Control by fast time stepping (koopman.h; koopman-dmd-log-linear paper, Sec. 7.3, Eq. 25): the
 * summed propagator in closed form, the forced N-step map, and the iterated least-squares solve
 * for the inputs. */
#include "koopman/koopman.h"

#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* log|l| for a real l != 0: through log1p near |l| = 1, where |l| - 1 is exact (Sterbenz). */
static double log_abs(double l)
{
    double dl = fabs(l) - 1;
    return fabs(dl) < 0.5 ? log1p(dl) : log(fabs(l));
}

/* sum_{t=1}^N l^t for a real l != 1: l (l^N - 1) / (l - 1), with l^N - 1 = expm1(N log l) for
 * l > 0 so that l near 1 keeps its digits. */
static double real_power_sum(double l, long long N)
{
    if (l == 0) return 0;
    double Nln = (double)N * log_abs(l);
    /* l < 0: l^N = (-1)^N |l|^N; for odd N, l^N - 1 = -(|l|^N + 1) has no cancellation */
    double m1 = l < 0 && N % 2 ? -exp(Nln) - 1 : expm1(Nln);
    return l * m1 / (l - 1);
}

void rk_koopman_power_sum(double re, double im, long long N, double *s_re, double *s_im)
{
    *s_re = *s_im = 0;
    if (N <= 0) return;
    if (im == 0) {
        *s_re = re == 1 ? (double)N : real_power_sum(re, N);
        return;
    }
    /* L = log lambda = log|lambda| + i arg lambda, with |lambda|^2 - 1 = dr (2 + dr) + im^2 formed
     * without cancellation (dr = re - 1 exact near 1). lambda^N - 1 = expm1(N L), in complex
     * arithmetic: expm1(x) cos y - 2 sin^2(y / 2) + i e^x sin y. */
    double dr = re - 1, q2 = dr * (2 + dr) + im * im, y = atan2(im, re);
    double x = fabs(q2) < 0.5 ? 0.5 * log1p(q2) : log(hypot(re, im));
    double Nx = (double)N * x, Ny = (double)N * y, sh = sin(0.5 * Ny);
    double nr = expm1(Nx) * cos(Ny) - 2 * sh * sh, ni = exp(Nx) * sin(Ny);
    /* q = (lambda^N - 1) / (lambda - 1), then s = lambda q */
    double den = dr * dr + im * im, qr = (nr * dr + ni * im) / den, qi = (ni * dr - nr * im) / den;
    *s_re = re * qr - im * qi;
    *s_im = re * qi + im * qr;
}

void rk_koopman_summed_propagator(const rk_koopman *k, long long N, double *y)
{
    for (int j = 0; j < k->r; j++) {
        double sr, si;
        if (k->block[j] == 1) {
            rk_koopman_power_sum(k->lambda_re[j], 0, N, &sr, &si);
            y[j] *= sr;
        } else if (k->block[j] == 2) {
            /* B = a I + b J with J = [[0, 1], [-1, 0]], J^2 = -I: the pair's block is the complex
             * number a + ib, and so is every sum of its powers. */
            rk_koopman_power_sum(k->lambda_re[j], k->lambda_im[j], N, &sr, &si);
            double y0 = y[j], y1 = y[j + 1];
            y[j] = sr * y0 + si * y1;
            y[j + 1] = -si * y0 + sr * y1;
        }
    }
}

/* z <- W S_N W^-1 z with w (r) as scratch. */
static void summed_apply(const rk_koopman *k, long long N, double *z, double *w)
{
    int r = k->r;
    cblas_dgemv(CblasColMajor, CblasNoTrans, r, r, 1.0, k->Winv, r, z, 1, 0.0, w, 1);
    rk_koopman_summed_propagator(k, N, w);
    cblas_dgemv(CblasColMajor, CblasNoTrans, r, r, 1.0, k->W, r, w, 1, 0.0, z, 1);
}

int rk_koopman_summed_apply(const rk_koopman *k, long long N, double *z, rk_error *err)
{
    double *w = rk_calloc((size_t)k->r, sizeof(double), err);
    if (!w) return -1;
    summed_apply(k, N, z, w);
    free(w);
    return 0;
}

/* g += sum_{t=1}^N K'^t g(a) and z <- K'^N z + g: g (r) and w (r) are scratch, g zero on entry. */
static void forced(const rk_koopman *k, long long N, const double *a, double *z, double *g, double *w)
{
    if (a) {
        rk_koopman_impulse(k, a, g); /* Eq. 19: g = U_r^T [0; beta P_in a h^2] */
        summed_apply(k, N, g, w);
    }
    rk_koopman_advance(k, z, N, 1, 0);
    for (int i = 0; i < k->r; i++) z[i] += g[i];
}

int rk_koopman_forced(const rk_koopman *k, long long N, const double *a, double *z, rk_error *err)
{
    if (N < 0) return rk_fail(err, "Koopman forced map: %lld steps; N must not be negative", N);
    double *g = rk_calloc((size_t)2 * k->r, sizeof(double), err);
    if (!g) return -1;
    forced(k, N, a, z, g, g + k->r);
    free(g);
    return 0;
}

void rk_koopman_control_default(rk_koopman_control_problem *p)
{
    memset(p, 0, sizeof *p);
    p->iterations = 5;
}

static int all_finite(const double *x, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(x[i])) return 0;
    return 1;
}

static int check_problem(const rk_koopman *k, const rk_koopman_control_problem *p, rk_error *err)
{
    if (!k || k->r < 1 || !k->W || !k->Winv || !k->block)
        return rk_fail(err, "the Koopman operator is empty (not fitted?)");
    if (p->inputs < 1) return rk_fail(err, "%d inputs: at least one input field is needed", p->inputs);
    if (p->steps < 1) return rk_fail(err, "%lld steps: N must be at least 1", p->steps);
    if (!p->input_field) return rk_fail(err, "no input_field callback to evaluate the %d input fields", p->inputs);
    if (p->ntargets < 1 || !p->targets)
        return rk_fail(err, "no targets: name at least one (value index, goal) for the final frame");
    if (p->iterations < 1) return rk_fail(err, "%d iterations: at least 1 (the paper uses 5)", p->iterations);
    if (!(p->regularize >= 0) || !isfinite(p->regularize))
        return rk_fail(err, "regularization %g: must be finite and >= 0", p->regularize);
    if (!(p->velocity_weight >= 0) || !isfinite(p->velocity_weight))
        return rk_fail(err, "velocity weight %g: must be finite and >= 0", p->velocity_weight);
    for (int t = 0; t < p->ntargets; t++) {
        if (p->targets[t].index < 0 || p->targets[t].index >= k->n)
            return rk_fail(err, "target %d: value index %d is outside 0..%d", t, p->targets[t].index, k->n - 1);
        if (!isfinite(p->targets[t].goal)) return rk_fail(err, "target %d: goal %g is not finite", t, p->targets[t].goal);
    }
    if (p->z0 && !all_finite(p->z0, k->r)) return rk_fail(err, "the start state z0 is not finite");
    if (p->accel && !all_finite(p->accel, k->n)) return rk_fail(err, "the constant acceleration is not finite");
    return 0;
}

/* Scratch for one solve. */
typedef struct {
    int m;            /* rows: targets, then velocity rows */
    int nvel;
    double *zfree;    /* r: the final state with C = 0 */
    double *zN;       /* r: the final state under the current C */
    double *Z;        /* r x k: the final state's response to each input field (C_j = 1) */
    double *g, *w;    /* r scratch */
    double *u, *v;    /* n: values and velocities of one reduced state */
    double *ufree, *vfree, *ucur, *a;
    double *A, *b;    /* m x k, m: the system */
} control_ws;

static void ws_free(control_ws *s)
{
    double *all[] = {s->zfree, s->zN, s->Z, s->g, s->u, s->ufree, s->A};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++) free(all[i]);
}

static int ws_alloc(const rk_koopman *k, const rk_koopman_control_problem *p, control_ws *s, rk_error *err)
{
    int r = k->r, n = k->n, kk = p->inputs;
    memset(s, 0, sizeof *s);
    s->nvel = p->velocity_weight > 0 ? (p->velocity_all ? n : p->ntargets) : 0;
    s->m = p->ntargets + s->nvel;
    s->zfree = rk_calloc((size_t)r, sizeof(double), err);
    s->zN = rk_calloc((size_t)r, sizeof(double), err);
    s->Z = rk_calloc((size_t)r * kk, sizeof(double), err);
    s->g = rk_calloc((size_t)2 * r, sizeof(double), err);
    s->u = rk_calloc((size_t)4 * n, sizeof(double), err);
    s->ufree = rk_calloc((size_t)2 * n, sizeof(double), err);
    s->A = rk_calloc((size_t)s->m * (kk + 1), sizeof(double), err);
    if (!s->zfree || !s->zN || !s->Z || !s->g || !s->u || !s->ufree || !s->A) {
        ws_free(s);
        return -1;
    }
    s->w = s->g + r;
    s->v = s->u + n;
    s->ucur = s->u + 2 * n;
    s->a = s->u + 3 * n;
    s->vfree = s->ufree + n;
    s->b = s->A + (size_t)s->m * kk;
    return 0;
}

/* The n values and n velocities (u_N - u_{N-1}: the velocity part of X = U_r z) of z. */
static void state_values(const rk_koopman *k, const double *z, double *u, double *v)
{
    rk_koopman_positions(k, z, u);
    rk_koopman_velocities(k, z, v);
}

/* Rows of the state (u, v) that the system reads: target values, then weighted velocities. */
static void rows_of(const rk_koopman_control_problem *p, const control_ws *s, const double *u, const double *v,
                    double *out)
{
    for (int t = 0; t < p->ntargets; t++) out[t] = u[p->targets[t].index];
    for (int i = 0; i < s->nvel; i++)
        out[p->ntargets + i] = p->velocity_weight * v[p->velocity_all ? i : p->targets[i].index];
}

/* zfree = the final state with C = 0 (z0 and the constant acceleration only); its rows go into
 * the right-hand side: b = goals - rows(zfree), velocity rows 0 - rows(zfree). */
static void free_state(const rk_koopman *k, const rk_koopman_control_problem *p, control_ws *s)
{
    if (p->z0) memcpy(s->zfree, p->z0, sizeof(double) * (size_t)k->r);
    memset(s->g, 0, sizeof(double) * (size_t)k->r);
    forced(k, p->steps, p->accel, s->zfree, s->g, s->w);
    state_values(k, s->zfree, s->ufree, s->vfree);
    rows_of(p, s, s->ufree, s->vfree, s->b);
    for (int i = 0; i < s->m; i++) s->b[i] = (i < p->ntargets ? p->targets[i].goal : 0) - s->b[i];
    memcpy(s->ucur, s->ufree, sizeof(double) * (size_t)k->n);
}

/* Column j of the system: input field j evaluated at s->ucur, pushed through Eq. 25
 * (Z_j = sum_{t=1}^N K'^t g(a_j)), read at the rows. */
static int input_column(const rk_koopman *k, const rk_koopman_control_problem *p, int j, control_ws *s,
                        rk_error *err)
{
    int n = k->n, r = k->r;
    double *Zj = s->Z + (size_t)r * j;
    memset(s->a, 0, sizeof(double) * (size_t)n);
    if (p->input_field(p->ctx, s->ucur, j, s->a) != 0) return rk_fail(err, "input field %d: the callback failed", j);
    for (int i = 0; i < n; i++)
        if (!isfinite(s->a[i])) return rk_fail(err, "input field %d: acceleration of value %d is not finite", j, i);
    memset(Zj, 0, sizeof(double) * (size_t)r);
    rk_koopman_impulse(k, s->a, Zj);
    summed_apply(k, p->steps, Zj, s->w);
    state_values(k, Zj, s->u, s->v);
    rows_of(p, s, s->u, s->v, s->A + (size_t)s->m * j);
    if (!all_finite(s->A + (size_t)s->m * j, s->m))
        return rk_fail(err, "input field %d: its response over %lld steps is not finite (an eigenvalue above 1 in "
                       "magnitude overflows: fit with clamp, or fewer steps)", j, p->steps);
    return 0;
}

/* C from the system, regularised as asked; residual = |A C - b| (the misfit alone, without the
 * Tikhonov term). */
static int solve(const rk_koopman_control_problem *p, control_ws *s, double *C, double *residual, rk_error *err)
{
    int m = s->m, kk = p->inputs;
    if (rk_lstsq_tikhonov(m, kk, s->A, s->b, p->regularize, p->nonnegative, C, NULL, err)) return -1;
    double sum = 0;
    for (int i = 0; i < m; i++) {
        double e = -s->b[i];
        for (int j = 0; j < kk; j++) e += s->A[(size_t)m * j + i] * C[j];
        sum += e * e;
    }
    *residual = sqrt(sum);
    return all_finite(C, kk) ? 0 : rk_fail(err, "the solve gave non-finite inputs");
}

/* zN = zfree + Z C, and its values become the estimate A is evaluated at next. */
static void predict(const rk_koopman *k, const rk_koopman_control_problem *p, control_ws *s, const double *C)
{
    memcpy(s->zN, s->zfree, sizeof(double) * (size_t)k->r);
    cblas_dgemv(CblasColMajor, CblasNoTrans, k->r, p->inputs, 1.0, s->Z, k->r, C, 1, 1.0, s->zN, 1);
    rk_koopman_positions(k, s->zN, s->ucur);
}

int rk_koopman_control(const rk_koopman *k, const rk_koopman_control_problem *p, double *C, double *residual,
                       double *z_final, rk_error *err)
{
    control_ws s;
    if (check_problem(k, p, err) || ws_alloc(k, p, &s, err)) return rk_error_prefix(err, "Koopman control");
    int rc = -1;
    free_state(k, p, &s);
    if (!all_finite(s.b, s.m)) {
        rk_fail(err, "the unforced final state over %lld steps is not finite (an eigenvalue above 1 in magnitude "
                "overflows: fit with clamp, or fewer steps)", p->steps);
        goto done;
    }
    for (int it = 0; it < p->iterations; it++) {
        double res;
        for (int j = 0; j < p->inputs; j++)
            if (input_column(k, p, j, &s, err)) goto done;
        if (solve(p, &s, C, &res, err)) goto done;
        if (residual) residual[it] = res;
        predict(k, p, &s, C);
    }
    if (z_final) memcpy(z_final, s.zN, sizeof(double) * (size_t)k->r);
    rc = 0;
done:
    ws_free(&s);
    return rc ? rk_error_prefix(err, "Koopman control") : 0;
}
