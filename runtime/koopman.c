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

/* e^x below e^RT_EXP_ZERO rounds to 0 in romrt_real (under half its smallest subnormal). */
#ifdef ROMRT_DOUBLE
#define RT_EXP_ZERO (-746.0)
#else
#define RT_EXP_ZERO (-105.0)
#endif

/* sin and cos of y / 2 for polar_power, which reads them only through s^2 and s c (a sign flip of
 * both changes nothing). In float, y is first reduced to [-pi, pi] in double (y - 2 pi k, exact
 * to the double rounding of y itself) and sinf / cosf take half of it: the powers are rounded to
 * float anyway, and the float functions cost half as much as sin / cos, which dominate a jump. */
static void half_angle(double y, double *s, double *c)
{
#ifdef ROMRT_DOUBLE
    *s = sin(0.5 * y), *c = cos(0.5 * y);
#else
    const double two_pi = 6.283185307179586476925;
    float h = (float)(0.5 * (y - two_pi * nearbyint(y / two_pi)));
    *s = sinf(h), *c = cosf(h);
#endif
}

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

/* log |l|, keeping its digits when |l| is near 1: log1p(|l|^2 - 1) / 2 with |l|^2 - 1 formed as
 * (|re| - 1)(|re| + 1) + im^2, whose first factor is exact for |re| in [0.5, 2] (Sterbenz), next to
 * -1 as next to 1. */
static double log_modulus(rt_complex l)
{
    double dr = fabs(l.re) - 1, q2 = dr * (2 + dr) + l.im * l.im;
    return fabs(q2) < 0.5 ? 0.5 * log1p(q2) : log(sqrt(l.re * l.re + l.im * l.im));
}

/* P = l^p and e = l^p - 1 for l = exp(lm + i th) (lm = log |l|, th = arg l), each to its own
 * relative precision: with x = p lm, y = p th, |l^p| = e^x. Away from the unit circle (|x| > 0.5)
 * P = e^x (cos y + i sin y) and e = P - 1 cannot cancel; near it, e = expm1(x) cos y - 2 sin^2(y/2)
 * + i e^x sin y keeps its digits as l^p nears 1, and P = 1 + e cannot cancel (|P| > 0.6). cos y
 * and sin y come from sin(y/2), cos(y/2) (half_angle): at most three libm calls (one for a positive real l)
 * whatever p, and none once |l^p| rounds to 0 in romrt_real (a decayed mode: P = 0, as the power
 * itself would round, and e = -1). For a real l (th = 0 or pi) the imaginary part is dropped: a
 * negative l at a fractional p takes the real part of the principal power (Sec. 5.2), exactly
 * (+-1)^p |l|^p at whole p. */
static void polar_power(double lm, double th, double p, int real, rt_complex *P, rt_complex *e)
{
    double x = p * lm, y, s, c, cy, sy;
    if (x < RT_EXP_ZERO) {
        P->re = P->im = e->im = 0, e->re = -1;
        return;
    }
    y = p * th, s = 0, c = 1;
    if (y != 0) half_angle(y, &s, &c); /* a positive real l turns by nothing */
    cy = 1 - 2 * s * s, sy = real ? 0 : 2 * s * c;
    if (fabs(x) > 0.5) {
        double ex = exp(x);
        P->re = ex * cy, P->im = ex * sy;
        e->re = P->re - 1, e->im = P->im;
    } else {
        double em = expm1(x);
        e->re = em * cy - 2 * s * s, e->im = (em + 1) * sy;
        P->re = e->re + 1, P->im = e->im;
    }
}

/* The blocks of one step of sigma training steps with damping mu: P = l^sigma for
 * l = (1 - mu) lambda (Sec. 7.2, then Eq. 21, so both hold per second of motion), and what a
 * forcing c held over the step adds, sum_{t=1}^{sigma} l^t c = l (l^sigma - 1) / (l - 1) c: for
 * whole sigma exactly sigma training steps with the impulse of Eq. 19 before each (at sigma = 1
 * both are l itself, as trained). Then each block's step factor m = P, as rounded to romrt_real
 * (the factor romrt_step applies), in the polar form romrt_jump powers: log |m|, arg m, and
 * 1 / (m - 1) (0 at m = 1, where the jump's sum is N). */
static void set_blocks(romrt_model *m)
{
    int j;
    double sigma = (double)m->dt_scale, keep = 1 - (double)m->damping;
    for (j = 0; j < m->r; j++) {
        rt_complex l, P, e, S, mu;
        l.re = keep * m->eig[2 * j], l.im = keep * m->eig[2 * j + 1];
        if ((l.re == 0 && l.im == 0) || sigma == 1) {
            P = S = l;
        } else {
            polar_power(log_modulus(l), atan2(l.im, l.re), sigma, l.im == 0, &P, &e);
            if (l.re == 1 && l.im == 0) {
                S.re = sigma, S.im = 0;
            } else {
                rt_complex d;
                d.re = l.re - 1, d.im = l.im;
                S = cmul(l, cdiv(e, d));
            }
        }
        m->lam_re[j] = (romrt_real)P.re;
        m->lam_im[j] = (romrt_real)P.im;
        m->sum_re[j] = (romrt_real)S.re;
        m->sum_im[j] = (romrt_real)S.im;
        mu.re = m->lam_re[j], mu.im = m->lam_im[j];
        m->jump_log[j] = mu.re == 0 && mu.im == 0 ? 0 : log_modulus(mu);
        m->jump_arg[j] = atan2(mu.im, mu.re);
        if (mu.re == 1 && mu.im == 0) {
            m->jump_inv_re[j] = m->jump_inv_im[j] = 0;
        } else {
            rt_complex one, d;
            one.re = 1, one.im = 0, d.re = mu.re - 1, d.im = mu.im;
            d = cdiv(one, d);
            m->jump_inv_re[j] = d.re, m->jump_inv_im[j] = d.im;
        }
    }
}

void rt_koopman_reset(romrt_model *m)
{
    memcpy(m->q, m->y0, sizeof(romrt_real) * (size_t)m->r);
}

/* Block j of v times the block [[a, b], [-b, a]] (a pair, from its first index) or a (a real one). */
static void block_mul(const romrt_model *m, int j, romrt_real a, romrt_real b, romrt_real *v)
{
    if (m->eig[2 * j + 1] == 0) {
        v[j] *= a;
    } else {
        romrt_real v0 = v[j], v1 = v[j + 1];
        v[j] = a * v0 + b * v1;
        v[j + 1] = -b * v0 + a * v1;
    }
}

/* y <- B y, blockwise. */
static void apply_blocks(const romrt_model *m, const romrt_real *lr, const romrt_real *li, romrt_real *y)
{
    int j;
    for (j = 0; j < m->r; j++)
        if (block_starts(m, j)) block_mul(m, j, lr[j], li[j], y);
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

/* A jump of N steps in closed form per block, at the cost of about one step whatever N (the
 * paper's Eq. 20 powers Lambda by repeated squaring, O(log N)): with the step factor
 * m = exp(lm + i th) (set_blocks), m^N and e = m^N - 1 come from polar_power at p = N, and the
 * forcing the N steps add, sum_{k<N} m^k c, has G = (m^N - 1) / (m - 1) = e / (m - 1) (G = N at
 * m = 1; G = 1 at m = 0, 0^0 = 1). e keeps its digits as m^N approaches 1 (expm1), and m - 1 is
 * exact near 1, so G is accurate for m next to 1. A negative real m takes its sign from N's
 * parity, exact for any N (N th would lose it once N passes 2^53). */
romrt_status romrt_jump(romrt_model *m, unsigned long steps, romrt_error *err)
{
    romrt_real y[ROMRT_MAX_R], c[ROMRT_MAX_R];
    romrt_status st = koopman_only(m, "romrt_jump: the asset has no Koopman operator (no KHED chunk)", err);
    double N = (double)steps;
    int j;
    if (st || steps == 0) return st;
    forcing(m, c); /* c: what one step's forcing adds */
    memcpy(y, m->q, sizeof(romrt_real) * (size_t)m->r);
    for (j = 0; j < m->r; j++) {
        rt_complex P, G;
        int real = m->eig[2 * j + 1] == 0; /* a 1 x 1 block, as block_mul reads it */
        if (!block_starts(m, j)) continue; /* a pair's second: its first holds the block */
        if (steps == 1 || (real && m->lam_re[j] == 0)) { /* one step is the step; 0^N = 0, 0^0 = 1 */
            P.re = steps == 1 ? m->lam_re[j] : 0, P.im = steps == 1 ? m->lam_im[j] : 0;
            G.re = 1, G.im = 0;
        } else {
            rt_complex e;
            if (real && m->lam_re[j] < 0) { /* |m|^N (-1)^N */
                polar_power(m->jump_log[j], 0, N, 1, &P, &e);
                if (steps & 1) P.re = -P.re, e.re = P.re - 1;
            } else {
                polar_power(m->jump_log[j], m->jump_arg[j], N, real, &P, &e);
            }
            if (real && m->lam_re[j] == 1) {
                G.re = N, G.im = 0;
            } else {
                rt_complex inv;
                inv.re = m->jump_inv_re[j], inv.im = m->jump_inv_im[j];
                G = cmul(e, inv);
            }
        }
        /* y_N = m^N y + G c */
        block_mul(m, j, (romrt_real)P.re, (romrt_real)P.im, y);
        block_mul(m, j, (romrt_real)G.re, (romrt_real)G.im, c);
    }
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
