/* Koopman assets (formats/ROMBIN.md "Koopman chunks"): a linear operator in real eigen-
 * coordinates y, one 1 x 1 block per real eigenvalue and one 2 x 2 block per complex pair. A
 * pair's block acts on (y_j, y_{j+1}) as multiplication of w = y_j - i y_{j+1} by lambda, so
 * every block is stepped, powered and summed as one complex number (a real one has im = 0). */
#include <math.h>
#include <string.h>

#include "runtime/loader_impl.h"

typedef struct {
    double re, im;
} rt_complex;

static rt_complex cmul(rt_complex a, rt_complex b)
{
    rt_complex c;
    c.re = a.re * b.re - a.im * b.im;
    c.im = a.re * b.im + a.im * b.re;
    return c;
}

/* Block j's factor: the first of a pair, or a real one (the pair's second is skipped). */
static int block_starts(const romrt_model *m, int j) { return !(j > 0 && m->eig[2 * j + 1] < 0); }

static rt_complex cdiv(rt_complex a, rt_complex b)
{
    rt_complex c;
    double d = b.re * b.re + b.im * b.im;
    c.re = (a.re * b.re + a.im * b.im) / d;
    c.im = (a.im * b.re - a.re * b.im) / d;
    return c;
}

/* lambda^sigma - 1, keeping its digits when lambda^sigma is near 1 (expm1, log1p); a negative
 * real lambda at a fractional sigma takes the real part of the principal power (the imaginary
 * part is projected out, Sec. 5.2), exactly (+-1)^sigma |lambda|^sigma at whole sigma. */
static rt_complex power_minus_one(rt_complex l, double sigma)
{
    rt_complex e;
    double dr = l.re - 1, q2 = dr * (2 + dr) + l.im * l.im; /* |l|^2 - 1 without cancellation */
    double x = sigma * (fabs(q2) < 0.5 ? 0.5 * log1p(q2) : log(sqrt(l.re * l.re + l.im * l.im)));
    double y = sigma * atan2(l.im, l.re), half = sin(0.5 * y);
    e.re = expm1(x) * cos(y) - 2 * half * half;
    e.im = l.im == 0 ? 0 : exp(x) * sin(y);
    return e;
}

/* The blocks of one step of sigma training steps with damping mu: P = l^sigma for
 * l = (1 - mu) lambda (Sec. 7.2, then Eq. 21, so both hold per second of motion), and what a
 * forcing c held over the step adds, sum_{t=1}^{sigma} l^t c = l (l^sigma - 1) / (l - 1) c: for
 * whole sigma exactly sigma training steps with the impulse of Eq. 19 before each. */
static void set_blocks(romrt_model *m)
{
    int j;
    double sigma = (double)m->dt_scale, keep = 1 - (double)m->damping;
    for (j = 0; j < m->r; j++) {
        rt_complex l, e, S;
        l.re = keep * m->eig[2 * j], l.im = keep * m->eig[2 * j + 1];
        if (l.re == 0 && l.im == 0) {
            m->lam_re[j] = m->lam_im[j] = m->sum_re[j] = m->sum_im[j] = 0;
            continue;
        }
        e = power_minus_one(l, sigma);
        if (l.re == 1 && l.im == 0) {
            S.re = sigma, S.im = 0;
        } else {
            rt_complex d;
            d.re = l.re - 1, d.im = l.im;
            S = cmul(l, cdiv(e, d));
        }
        m->lam_re[j] = (romrt_real)(e.re + 1);
        m->lam_im[j] = (romrt_real)e.im;
        m->sum_re[j] = (romrt_real)S.re;
        m->sum_im[j] = (romrt_real)S.im;
    }
}

void rt_koopman_reset(romrt_model *m)
{
    memcpy(m->q, m->y0, sizeof(romrt_real) * (size_t)m->r);
}

/* y <- B y, blockwise. */
static void apply_blocks(const romrt_model *m, const romrt_real *lr, const romrt_real *li, romrt_real *y)
{
    int j;
    for (j = 0; j < m->r; j++) {
        if (!block_starts(m, j)) continue;
        if (m->eig[2 * j + 1] == 0) {
            y[j] *= lr[j];
        } else {
            romrt_real a = lr[j], b = li[j], y0 = y[j], y1 = y[j + 1];
            y[j] = a * y0 + b * y1;
            y[j + 1] = -b * y0 + a * y1;
        }
    }
}

static int finite_all(const romrt_real *a, int n)
{
    int i;
    for (i = 0; i < n; i++)
        if (!isfinite(a[i])) return 0;
    return 1;
}

/* The impulse of the forcing over one training step, h_data^2 c (Eq. 19), then what it adds
 * over one step of the current size (the summed blocks). */
static void forcing(const romrt_model *m, romrt_real *c)
{
    int j;
    romrt_real s = m->h_data * m->h_data;
    for (j = 0; j < m->r; j++) c[j] = s * (m->accel[j] + m->f_app[j]);
    apply_blocks(m, m->sum_re, m->sum_im, c);
}

romrt_status rt_koopman_step(romrt_model *m, romrt_error *err)
{
    romrt_real y[ROMRT_MAX_R], c[ROMRT_MAX_R];
    int j;
    forcing(m, c);
    memcpy(y, m->q, sizeof(romrt_real) * (size_t)m->r);
    apply_blocks(m, m->lam_re, m->lam_im, y);
    for (j = 0; j < m->r; j++) y[j] += c[j];
    if (!finite_all(y, m->r) || !rt_showable(m, y))
        return rt_fail(err, ROMRT_E_DIVERGED, 0, "the Koopman state overflowed (an eigenvalue above 1: bake with clamp)");
    memcpy(m->q, y, sizeof(romrt_real) * (size_t)m->r);
    memset(&m->last, 0, sizeof m->last);
    m->last.converged = 1;
    rt_clock_advance(m, 1);
    return ROMRT_OK;
}

static romrt_status koopman_only(const romrt_model *m, const char *what, romrt_error *err)
{
    if (!m) return rt_fail(err, ROMRT_E_ARGUMENT, 0, "no model (NULL)");
    if (m->kind != ROMRT_KIND_KOOPMAN)
        return rt_fail(err, ROMRT_E_UNSUPPORTED, 0, what);
    return ROMRT_OK;
}

/* P = lambda^n and S = sum_{k=1}^n lambda^k by binary powering from the top bit:
 * doubling n: S <- S + P S, P <- P^2; adding one: P <- P lambda, S <- S + P. */
static void power_and_sum(rt_complex lambda, unsigned long n, rt_complex *P, rt_complex *S)
{
    unsigned long bit = 1;
    P->re = 1, P->im = 0, S->re = 0, S->im = 0;
    while (bit <= n / 2) bit <<= 1;
    for (; bit; bit >>= 1) {
        rt_complex PS = cmul(*P, *S);
        S->re += PS.re, S->im += PS.im;
        *P = cmul(*P, *P);
        if (n & bit) {
            *P = cmul(*P, lambda);
            S->re += P->re, S->im += P->im;
        }
    }
}

romrt_status romrt_jump(romrt_model *m, unsigned long steps, romrt_error *err)
{
    romrt_real y[ROMRT_MAX_R], c[ROMRT_MAX_R], pr[ROMRT_MAX_R], pi[ROMRT_MAX_R], sr[ROMRT_MAX_R], si[ROMRT_MAX_R];
    romrt_status st = koopman_only(m, "romrt_jump: the asset has no Koopman operator (no KHED chunk)", err);
    int j;
    if (st) return st;
    memset(pr, 0, sizeof pr), memset(pi, 0, sizeof pi), memset(sr, 0, sizeof sr), memset(si, 0, sizeof si);
    for (j = 0; j < m->r; j++) {
        rt_complex lambda, P, S;
        lambda.re = m->lam_re[j], lambda.im = m->lam_im[j];
        power_and_sum(lambda, steps, &P, &S);
        /* sum_{k=0}^{N-1} P^k = 1 + S - P^N multiplies each step's forcing */
        pr[j] = (romrt_real)P.re, pi[j] = (romrt_real)P.im;
        sr[j] = (romrt_real)(1 + S.re - P.re), si[j] = (romrt_real)(S.im - P.im);
    }
    /* y_N = P^N y + sum_{k=0}^{N-1} P^k c, c the forcing one step adds */
    forcing(m, c);
    memcpy(y, m->q, sizeof(romrt_real) * (size_t)m->r);
    apply_blocks(m, pr, pi, y);
    apply_blocks(m, sr, si, c);
    for (j = 0; j < m->r; j++) y[j] += c[j];
    if (!finite_all(y, m->r) || !rt_showable(m, y))
        return rt_fail(err, ROMRT_E_DIVERGED, 0, "the Koopman state overflowed over the jump (an eigenvalue above 1)");
    memcpy(m->q, y, sizeof(romrt_real) * (size_t)m->r);
    rt_clock_advance(m, steps);
    memset(&m->last, 0, sizeof m->last);
    m->last.converged = 1;
    return ROMRT_OK;
}

romrt_status romrt_set_time_step(romrt_model *m, romrt_real h, romrt_error *err)
{
    romrt_status st = koopman_only(m, "romrt_set_time_step: a reduced model's time step is baked in; only a "
                                      "Koopman asset rescales it", err);
    if (st) return st;
    if (!(h > 0) || !isfinite(h)) return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_set_time_step: h must be positive and finite");
    rt_clock_rebase(m); /* the steps so far were of the old h */
    m->dt_scale = h / m->h_data;
    m->h = h;
    set_blocks(m);
    return ROMRT_OK;
}

romrt_status romrt_set_damping(romrt_model *m, romrt_real mu, romrt_error *err)
{
    romrt_status st = koopman_only(m, "romrt_set_damping: only a Koopman asset's eigenvalues can be edited", err);
    if (st) return st;
    if (!(mu >= 0 && mu < 1)) return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_set_damping: mu must be in [0, 1)");
    m->damping = mu;
    set_blocks(m);
    return ROMRT_OK;
}

/* --- opening: KHED and KPRM, the arrays, then the eigenvalue structure --- */

romrt_status rt_koopman_sizes(rt_loader *L, romrt_model *m)
{
    const uint32_t *head;
    rombin_chunk c;
    int found, k;
    romrt_status st = rt_head(L, ROMBIN_KHED, ROMBIN_KHED_COUNT, ROMBIN_KHED_TRAJECTORIES + 1, ROMBIN_KHED_R,
                              ROMBIN_KHED_VERTICES, ROMBIN_KHED_SHOWN, &head);
    if (st) return st;
    if (head[ROMBIN_KHED_GROUPS] > ROMRT_MAX_GROUPS)
        return rt_fail(L->err, ROMRT_E_LIMIT, ROMBIN_KHED, "group count above the runtime's limits");
    m->kind = ROMRT_KIND_KOOPMAN;
    m->r = (int)head[ROMBIN_KHED_R];
    m->nv = (int)head[ROMBIN_KHED_VERTICES];
    m->shown = (int)head[ROMBIN_KHED_SHOWN];
    m->ngroups = (int)head[ROMBIN_KHED_GROUPS];
    if ((st = rt_chunk(L, ROMBIN_KPRM, ROMBIN_TYPE_REAL, ROMBIN_KPRM_COUNT, 1, &c, &found))) return st;
    for (k = 0; k < ROMBIN_KPRM_COUNT; k++) {
        double p = rt_real_at(L, &c, (uint64_t)k);
        if (k == ROMBIN_KPRM_H ? !(p > 0 && p < 1e30) : p != 0)
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_KPRM, "value ", (uint64_t)k,
                             k == ROMBIN_KPRM_H ? " (the time step) is not positive and finite" : " (reserved) is not 0");
        if (k == ROMBIN_KPRM_H) m->h = m->h_data = (romrt_real)p;
    }
    m->dt_scale = 1;
    m->damping = 0;
    return ROMRT_OK;
}

romrt_status rt_koopman_arrays(rt_loader *L, romrt_model *m)
{
    uint64_t r = (uint64_t)m->r, nv = (uint64_t)m->nv;
    romrt_status st;
    if ((st = rt_reals(L, ROMBIN_KEIG, 2 * r, 1, &m->eig)) || (st = rt_reals(L, ROMBIN_VERT, 3 * nv, 1, &m->X)) ||
        (st = rt_reals(L, ROMBIN_KOUT, 3 * nv * r, 1, &m->rows)) ||
        (st = rt_reals(L, ROMBIN_KIMP, 3 * nv * r, 1, &m->force_rows)) ||
        (st = rt_reals(L, ROMBIN_KACC, r, 1, &m->accel)) || (st = rt_reals(L, ROMBIN_KINI, r, 1, &m->y0)))
        return st;
    return rt_load_groups_and_surface(L, m);
}

/* The blocks: a complex pair is (a, b > 0) followed by its conjugate; |lambda| < 10. */
romrt_status rt_koopman_contents(rt_loader *L, romrt_model *m)
{
    romrt_status st = rt_check_groups_and_surface(L, m);
    int j;
    if (st || !L->arena) return st; /* KEIG's values live in the arena when converted */
    for (j = 0; j < m->r;) {
        romrt_real a = m->eig[2 * j], b = m->eig[2 * j + 1];
        if (!(a * a + b * b < 100))
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_KEIG, "eigenvalue ", (uint64_t)j, " has |lambda| >= 10");
        if (b < 0)
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_KEIG, "eigenvalue ", (uint64_t)j,
                             " is a conjugate without its pair before it");
        if (b > 0 && !(j + 1 < m->r && m->eig[2 * j + 2] == a && m->eig[2 * j + 3] == -b))
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_KEIG, "eigenvalue ", (uint64_t)j,
                             " is complex but not followed by its conjugate");
        j += b > 0 ? 2 : 1;
    }
    set_blocks(m);
    rt_koopman_reset(m);
    return ROMRT_OK;
}
