/* The adaptive linear ROM's decoders (alrom_impl.h): the quadratic manifold's Jacobian and its
 * Gauss-Newton encoder, and a CROM's two networks (the encoder, and the decoder's Jacobian by forward
 * mode at each stored vertex), both in double in either build. */
#include <math.h>
#include <string.h>

#include "runtime/alrom_impl.h"

#define ENCODE_ITERATIONS 20

/* ---- small dense helpers (rows: n x r, row i's r reals contiguous) ---- */

void rt_alrom_zero_prescribed(const romrt_model *m, double *A)
{
    int i, n = 3 * m->nv;
    for (i = 0; i < n; i++)
        if (rt_alrom_prescribed(&m->al, i)) memset(A + (size_t)i * (size_t)m->r, 0, sizeof(double) * (size_t)m->r);
}

/* U = dg/dp, row i column k = Phi_ik + sum_j Psi_i,kj p_j (Psi_i the row's symmetric r x r
 * second-order term, expanded from QDRV's pairs at open); with res, also res_i = u_i - g_i(p),
 * g_i = Phi_i p + 1/2 sum_kj Psi_i,kj p_k p_j = Phi_i p + 1/2 p . (U_i - Phi_i): one pass for both. */
static void jacobian(const romrt_model *m, const double *p, double *U, const double *u, double *res)
{
    const rt_alrom *al = &m->al;
    int r = m->r, n = 3 * m->nv, i, k, j;
    for (i = 0; i < n; i++) {
        const romrt_real *phi = al->phi + (size_t)i * (size_t)r, *psi = al->psi_full + (size_t)i * (size_t)r * (size_t)r;
        double *Ui = U + (size_t)i * (size_t)r, lin = 0, quad = 0;
        for (k = 0; k < r; k++) {
            const romrt_real *row = psi + (size_t)k * (size_t)r;
            double s = 0;
            for (j = 0; j < r; j++) s += row[j] * p[j];
            Ui[k] = phi[k] + s;
            lin += phi[k] * p[k];
            quad += p[k] * s;
        }
        if (res) res[i] = u[i] - (lin + 0.5 * quad);
    }
}

/* x = (J^T W J + shift I)^-1 J^T W b over the stored rows, W their vertices' masses (the mass-norm
 * least squares of the encoder); A: r x r scratch. */
static romrt_status mass_lsq(const romrt_model *m, const double *J, const double *b, double *x, double *A,
                             romrt_error *err)
{
    const rt_alrom *al = &m->al;
    int r = m->r, n = 3 * m->nv, i, j, k;
    double scale = 0;
    for (k = 0; k < r * r; k++) A[k] = 0;
    for (k = 0; k < r; k++) x[k] = 0;
    for (i = 0; i < n; i++) {
        const double *Ji = J + (size_t)i * (size_t)r;
        double w = al->mass[i / 3], wb = w * b[i];
        if (w == 0) continue;
        for (k = 0; k < r; k++) {
            double wk = w * Ji[k];
            x[k] += wb * Ji[k];
            for (j = k; j < r; j++) A[k + (size_t)r * j] += wk * Ji[j]; /* upper */
        }
    }
    for (k = 0; k < r; k++) scale = A[k + (size_t)r * k] > scale ? A[k + (size_t)r * k] : scale;
    for (k = 0; k < r; k++) A[k + (size_t)r * k] += 1e-12 * scale; /* rigid or repeated columns */
    if (rt_cholesky_wide(r, A))
        return rt_fail_n(err, ROMRT_E_DIVERGED, ROMBIN_ALRH, "the decoder's Jacobian has rank below r = ", (uint64_t)r,
                         " (the encoder's mass least squares)");
    rt_cholesky_solve_wide(r, A, x);
    return ROMRT_OK;
}

/* |u - g(p)|_M^2 over the stored rows (their vertices' masses), with U = J(p) and res = u - g(p). */
static double misfit(const romrt_model *m, const double *p, double *U, double *res)
{
    const rt_alrom *al = &m->al;
    int i, n = 3 * m->nv;
    double f = 0;
    jacobian(m, p, U, al->u, res);
    for (i = 0; i < n; i++) f += (double)al->mass[i / 3] * res[i] * res[i];
    return f;
}

/* p = e(u): the mass projection onto the linear part, then Gauss-Newton on |g(p) - u|_M^2, each
 * step halved until it lowers the misfit (the precompute's quadratic encoder, precompute/grassmann/
 * quadratic.c: why). Leaves J(p) in al->U; al->Q1 and al->Q2 as scratch (the basis is built after). */
/* ---- a CROM decoder: networks z = W a + b, ELU on all layers but the last (precompute/neural) ---- */

static double elu(double z) { return z > 0 ? z : exp(z) - 1; }

/* The network of L layers with sizes and params (neural.h's layout) on one input x (sizes[0]
 * values): its output into out (sizes[L]); al->act as scratch. */
static void mlp_forward(rt_alrom *al, int L, const uint32_t *sizes, const romrt_real *w, const double *x, double *out)
{
    const double *in = x;
    int l, o, i;
    for (l = 0; l < L; l++) {
        int n_in = (int)sizes[l], n_out = (int)sizes[l + 1];
        double *z = l + 1 == L ? out : al->act[l % 2];
        const romrt_real *b = w + (size_t)n_out * (size_t)n_in;
        for (o = 0; o < n_out; o++) {
            const romrt_real *row = w + (size_t)o * (size_t)n_in;
            double s = b[o];
            for (i = 0; i < n_in; i++) s += row[i] * in[i];
            z[o] = l + 1 == L ? s : elu(s);
        }
        w = b + n_out;
        in = z;
    }
}

/* The decoder's output and its Jacobian in the first r inputs at x = [p, X_v] (forward mode, r
 * tangents): J (3 x r, row-major). */
static void mlp_jacobian(rt_alrom *al, int r, const double *x, double *J)
{
    int L = al->dec_layers, l, o, i, j;
    const uint32_t *sizes = al->dec_sizes;
    const romrt_real *w = al->dec_w;
    const double *in = x, *tin = 0;
    for (l = 0; l < L; l++) {
        int n_in = (int)sizes[l], n_out = (int)sizes[l + 1];
        double *z = al->act[l % 2], *t = l + 1 == L ? J : al->tan[l % 2];
        const romrt_real *b = w + (size_t)n_out * (size_t)n_in;
        for (o = 0; o < n_out; o++) {
            const romrt_real *row = w + (size_t)o * (size_t)n_in;
            double s = b[o], *to = t + (size_t)o * (size_t)r;
            for (i = 0; i < n_in; i++) s += row[i] * in[i];
            if (l == 0) /* the input's tangents are the identity on p */
                for (j = 0; j < r; j++) to[j] = row[j];
            else {
                for (j = 0; j < r; j++) to[j] = 0;
                for (i = 0; i < n_in; i++) {
                    const double *ti = tin + (size_t)i * (size_t)r;
                    double wi = row[i];
                    for (j = 0; j < r; j++) to[j] += wi * ti[j];
                }
            }
            if (l + 1 < L) { /* ELU and its derivative, exp(z) = a + 1 below 0 */
                double a = elu(s), d = s > 0 ? 1 : a + 1;
                z[o] = a;
                for (j = 0; j < r; j++) to[j] *= d;
            }
        }
        w = b + n_out;
        in = z;
        tin = t;
    }
}

/* p = e(u) by the encoder, and U: the decoder's Jacobian at every stored vertex (the precompute's
 * CROM, precompute/grassmann/crom.c: inputs scaled by u_scale, positions normalised). */
static void crom_encode(romrt_model *m)
{
    rt_alrom *al = &m->al;
    int n = 3 * m->nv, r = m->r, v, a, j;
    double x[ROMRT_MAX_R + 3], J[3 * ROMRT_MAX_R];
    for (j = 0; j < n; j++) al->res[j] = al->u[j] / al->u_scale;
    mlp_forward(al, al->enc_layers, al->enc_sizes, al->enc_w, al->res, al->p);
    memcpy(x, al->p, sizeof(double) * (size_t)r);
    for (v = 0; v < m->nv; v++) {
        for (a = 0; a < 3; a++) x[r + a] = al->crom_x[3 * v + a];
        mlp_jacobian(al, r, x, J);
        for (a = 0; a < 3; a++)
            for (j = 0; j < r; j++) al->U[((size_t)3 * v + a) * (size_t)r + j] = al->u_scale * J[a * r + j];
    }
}

romrt_status rt_alrom_encode(romrt_model *m, romrt_error *err)
{
    rt_alrom *al = &m->al;
    double rhs[ROMRT_MAX_R], ptry[ROMRT_MAX_R], f, ft, t, *Ut = al->Q1, *rt = al->Q2;
    int r = m->r, n = 3 * m->nv, it, k, h;
    romrt_status st;
    if (al->decoder) {
        crom_encode(m);
        return ROMRT_OK;
    }
    for (k = 0; k < r; k++) al->p[k] = 0;
    jacobian(m, al->p, al->U, 0, 0); /* the linear part, Phi */
    st = mass_lsq(m, al->U, al->u, al->p, al->work, err);
    f = st ? 0 : misfit(m, al->p, al->U, al->res);
    for (it = 0; !st && it < ENCODE_ITERATIONS; it++) {
        double step = 0, size = 0;
        if ((st = mass_lsq(m, al->U, al->res, rhs, al->work, err))) break;
        ft = INFINITY;
        for (h = 0, t = 1; h < 10; h++, t *= 0.5) {
            for (k = 0; k < r; k++) ptry[k] = al->p[k] + t * rhs[k];
            if ((ft = misfit(m, ptry, Ut, rt)) < f) break;
        }
        if (!(ft < f)) break;
        for (k = 0; k < r; k++) {
            double d = fabs(ptry[k] - al->p[k]);
            step = d > step ? d : step;
            al->p[k] = ptry[k];
            size = fabs(al->p[k]) > size ? fabs(al->p[k]) : size;
        }
        memcpy(al->U, Ut, sizeof(double) * (size_t)n * (size_t)r);
        memcpy(al->res, rt, sizeof(double) * (size_t)n);
        f = ft;
        if (step <= 1e-12 * (size > 0 ? size : 1)) break;
    }
    if (!st) jacobian(m, al->p, al->U, 0, 0);
    return st;
}

