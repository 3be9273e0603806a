/* The adaptive linear ROM in the runtime (the adaptive-linear-rom-grassmann paper, Algorithms 1-4),
 * over the asset's stored vertices only and in fixed arena buffers. Before each step:
 *
 *   p = e(u)                          the quadratic decoder's encoder: Gauss-Newton on |g(p) - u|_M
 *   U = dg/dp (p)                     its Jacobian, Phi_k + sum_j Psi_kj p_j (Eq. 8)
 *   Phi_h = D P^T (P P^T + reg I)^-1  the last m steps' displacements D and codes P (Eq. 13)
 *   U_interp = Grassmann(Phi_h, U, lambda)   (Algorithm 4: thin QRs, the SVD of Q_Phi^T Q_U)
 *
 * then the reduced model's own Newton (step.c) in the incremental form x = x_ref + U_interp q
 * (Eq. 5-6), with M_r = U^T M U over the stored vertices' masses (the mesh's lumped mass gathered
 * onto them), C_r = a M_r, f_r = U^T f and the cubature elements' F = F(x_ref) + G_e q. The
 * prescribed vertices move to their targets in x_ref and their rows are zero, as in the
 * precompute's simulator (precompute/grassmann/alrom.c), which this reproduces when every vertex
 * is stored and the mass is lumped. Inner products are Euclidean over the stored rows. With a
 * CROM decoder (ALRH's decoder 1) the code is the encoder network's output and U the decoder
 * network's Jacobian at each stored vertex (forward mode), every vertex stored for the encoder. */
#include <math.h>
#include <string.h>

#include "runtime/loader_impl.h"

/* A QR diagonal below this fraction of the largest is rank loss, the precompute's rk_thin_q floor
 * (precompute/grassmann/interpolate.c: the history's missing directions are amplified round-off
 * above 1e-12, so the data decides only from well above it). */
#define RANK_TOL 1e-6
#define ENCODE_ITERATIONS 20
#define MAX_HISTORY 1000u

/* Pair (i, j), i <= j, row-major over r (the precompute's rk_quadratic_pairs layout). */
static int pair(int r, int i, int j)
{
    if (i > j) {
        int t = i;
        i = j;
        j = t;
    }
    return i * r - i * (i - 1) / 2 + (j - i);
}

/* ---- the loader ---- */

/* A CROM's chunks: CRMS's sizes (the encoder 3 nv -> .. -> r, the decoder r + 3 -> .. -> 3, 1 to
 * 64 layers of 1 to 4096 units), CRMX, CRMW (both networks' parameters and the scale), and the
 * buffers of the widest layer. */
static romrt_status crom_arrays(rt_loader *L, romrt_model *m)
{
    rt_alrom *al = &m->al;
    rombin_chunk c;
    int found, k;
    const uint32_t *sz;
    uint64_t count = 0, e_count = 0, d_count = 0;
    romrt_status st = rt_chunk(L, ROMBIN_CRMS, ROMBIN_TYPE_U32, 0, 1, &c, &found);
    const romrt_real *w;
    if (st) return st;
    sz = (const uint32_t *)(const void *)c.data;
    if (c.raw < 8 || sz[0] < 1 || sz[0] > 64 || sz[1] < 1 || sz[1] > 64 || c.raw != 4 * (4 + (uint64_t)sz[0] + sz[1]))
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_CRMS, "layer counts out of 1..64 or sizes missing");
    al->enc_layers = (int)sz[0];
    al->dec_layers = (int)sz[1];
    al->enc_sizes = sz + 2;
    al->dec_sizes = sz + 3 + al->enc_layers;
    if (al->enc_sizes[0] != 3 * (uint32_t)m->nv || al->enc_sizes[al->enc_layers] != (uint32_t)m->r ||
        al->dec_sizes[0] != (uint32_t)m->r + 3 || al->dec_sizes[al->dec_layers] != 3)
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_CRMS,
                       "the encoder must map every stored coordinate to r, the decoder r + 3 to 3");
    al->widest = 3 * m->nv;
    for (k = 0; k <= al->enc_layers + al->dec_layers + 1; k++) {
        uint32_t units = k <= al->enc_layers ? al->enc_sizes[k] : al->dec_sizes[k - al->enc_layers - 1];
        if (units < 1 || (units > 4096 && !(k == 0)))
            return rt_fail_n(L->err, ROMRT_E_LIMIT, ROMBIN_CRMS, "a layer of ", units, " units (1..4096)");
        if ((int)units > al->widest) al->widest = (int)units;
    }
    for (k = 0; k < al->enc_layers; k++) e_count += (uint64_t)al->enc_sizes[k + 1] * (al->enc_sizes[k] + 1);
    for (k = 0; k < al->dec_layers; k++) d_count += (uint64_t)al->dec_sizes[k + 1] * (al->dec_sizes[k] + 1);
    count = e_count + d_count + 1;
    if ((st = rt_reals(L, ROMBIN_CRMX, 3 * (uint64_t)m->nv, 1, &al->crom_x)) ||
        (st = rt_reals(L, ROMBIN_CRMW, count, 1, &w)))
        return st;
    al->enc_w = w;
    al->dec_w = w ? w + e_count : 0;
    al->u_scale = w ? (double)w[count - 1] : 1;
    rt_scratch_wide(L, (uint64_t)al->widest, &al->act[0]);
    rt_scratch_wide(L, (uint64_t)al->widest, &al->act[1]);
    rt_scratch_wide(L, (uint64_t)al->widest * (uint64_t)m->r, &al->tan[0]);
    rt_scratch_wide(L, (uint64_t)al->widest * (uint64_t)m->r, &al->tan[1]);
    return ROMRT_OK;
}

romrt_status rt_alrom_arrays(rt_loader *L, romrt_model *m)
{
    const uint32_t *head;
    const romrt_real *parm;
    rt_alrom *al = &m->al;
    uint64_t nv = (uint64_t)m->nv, r = (uint64_t)m->r, n = 3 * nv;
    romrt_status st;
    int k;
    if ((st = rt_u32s(L, ROMBIN_ALRH, ROMBIN_ALRH_COUNT, 0, &head))) return st;
    if (!head) { /* the rest without their header: a damaged asset, not a fixed-basis model */
        static const char *const rest[] = {ROMBIN_ALRP, ROMBIN_QDRV, ROMBIN_VMSS, ROMBIN_VLOD, ROMBIN_AMOV, ROMBIN_AMOT,
                                           ROMBIN_CRMS, ROMBIN_CRMX, ROMBIN_CRMW};
        rombin_chunk c;
        for (k = 0; k < (int)(sizeof rest / sizeof *rest); k++)
            if (rombin_find(&L->file, rest[k], &c))
                return rt_fail(L->err, ROMRT_E_MODEL, rest[k], "an adaptive linear ROM's chunk without its header ALRH");
        return ROMRT_OK;
    }
    for (k = ROMBIN_ALRH_DECODER + 1; k < ROMBIN_ALRH_COUNT; k++)
        if (head[k]) return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_ALRH, "reserved field ", (uint64_t)k, " is not 0");
    if (head[ROMBIN_ALRH_DECODER] > 1)
        return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_ALRH, "unknown decoder ", head[ROMBIN_ALRH_DECODER], "");
    if (head[ROMBIN_ALRH_HISTORY] < 1 || head[ROMBIN_ALRH_HISTORY] > MAX_HISTORY)
        return rt_fail_n(L->err, ROMRT_E_LIMIT, ROMBIN_ALRH, "history of ", head[ROMBIN_ALRH_HISTORY], " steps is not in 1..1000");
    if ((uint64_t)head[ROMBIN_ALRH_PAIRS] != r * (r + 1) / 2)
        return rt_fail_nn(L->err, ROMRT_E_MODEL, ROMBIN_ALRH, "names ", head[ROMBIN_ALRH_PAIRS],
                          " modal-derivative pairs; r gives ", r * (r + 1) / 2, "");
    if (head[ROMBIN_ALRH_MOTIONS] > ROMBIN_MAX_MOTIONS)
        return rt_fail_n(L->err, ROMRT_E_LIMIT, ROMBIN_ALRH, "prescribed motion count ", head[ROMBIN_ALRH_MOTIONS],
                         " is above 64");
    m->alrom = 1;
    al->decoder = (int)head[ROMBIN_ALRH_DECODER];
    al->m = (int)head[ROMBIN_ALRH_HISTORY];
    al->pairs = (int)head[ROMBIN_ALRH_PAIRS];
    al->nmotions = (int)head[ROMBIN_ALRH_MOTIONS];
    if ((st = rt_reals(L, ROMBIN_ALRP, ROMBIN_ALRP_COUNT, 1, &parm)) ||
        (!al->decoder && (st = rt_reals(L, ROMBIN_QDRV, n * (uint64_t)al->pairs, 1, &al->psi))) ||
        (al->decoder && (st = crom_arrays(L, m))) ||
        (st = rt_reals(L, ROMBIN_VMSS, nv, 1, &al->mass)) || (st = rt_reals(L, ROMBIN_VLOD, n, 1, &al->load)) ||
        (st = rt_u32s(L, ROMBIN_AMOV, nv, 1, &al->motion_of)) ||
        (st = rt_reals(L, ROMBIN_AMOT, (uint64_t)al->nmotions * ROMBIN_PIN_PARAMS, al->nmotions > 0, &al->motions)))
        return st;
    if (parm) {
        al->lambda = parm[ROMBIN_ALRP_LAMBDA];
        al->reg = parm[ROMBIN_ALRP_REG];
        al->damping = parm[ROMBIN_ALRP_DAMPING];
        for (k = ROMBIN_ALRP_DAMPING + 1; k < ROMBIN_ALRP_COUNT; k++)
            if (parm[k] != 0) return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_ALRP, "reserved value ", (uint64_t)k, " is not 0");
    }
    al->X0 = m->X;
    al->phi = m->rows;
    rt_scratch_wide(L, n, &al->u_t);
    rt_scratch_wide(L, n, &al->v);
    rt_scratch_wide(L, n, &al->u_prev);
    rt_scratch_wide(L, n, &al->v_prev);
    rt_scratch_wide(L, n, &al->u_ref);
    rt_scratch(L, n, &al->f_app);
    rt_scratch_wide(L, n * (uint64_t)(al->m + 1), &al->D);
    rt_scratch_wide(L, r * (uint64_t)(al->m + 1), &al->P);
    rt_scratch_wide(L, r * (uint64_t)(al->m + 1), &al->coef);
    rt_scratch(L, n, &al->x_ref);
    rt_scratch(L, n * r, &al->rows);
    rt_scratch(L, r * r, &al->M);
    rt_scratch(L, r * r, &al->C);
    rt_scratch(L, r, &al->f);
    rt_scratch(L, 9 * (uint64_t)m->ne, &al->Hd0);
    rt_scratch_wide(L, n * r, &al->U);
    rt_scratch_wide(L, n * r, &al->Q1);
    rt_scratch_wide(L, n * r, &al->Q2);
    rt_scratch_wide(L, n, &al->u);
    rt_scratch_wide(L, n, &al->res);
    if (!al->decoder) rt_scratch(L, n * r * r, &al->psi_full);
    rt_scratch_wide(L, 4 * r * r, &al->work);
    rt_scratch_wide(L, n, &al->u_new);
    rt_scratch_wide(L, n, &al->v_new);
    return ROMRT_OK;
}

romrt_status rt_alrom_contents(rt_loader *L, romrt_model *m)
{
    const rt_alrom *al = &m->al;
    double total = 0;
    int v, g;
    if (!m->alrom) return ROMRT_OK;
    if (m->skin || m->np || m->npins || m->ne < 1)
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_ALRH,
                       "an adaptive linear ROM needs cubature elements and dense rows, and holds its prescribed "
                       "vertices itself (no SKIN, IPNT or PINS)");
    for (v = 0; v < m->nv; v++)
        if (al->motion_of[v] != ROMBIN_NO_MOTION && al->motion_of[v] >= (uint32_t)al->nmotions)
            return rt_fail_nn(L->err, ROMRT_E_MODEL, ROMBIN_AMOV, "stored vertex ", (uint64_t)v, " names motion ",
                              al->motion_of[v], ", beyond AMOT");
    if (!L->arena) return ROMRT_OK; /* the values below live in the arena when converted */
    if (al->decoder && !(al->u_scale > 0))
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_CRMW, "the displacement scale must be positive");
    if (!al->decoder) {
        int r = m->r, i, k, j;
        for (i = 0; i < 3 * m->nv; i++)
            for (k = 0; k < r; k++)
                for (j = 0; j < r; j++)
                    al->psi_full[((size_t)i * (size_t)r + (size_t)k) * (size_t)r + (size_t)j] =
                        al->psi[(size_t)i * (size_t)al->pairs + (size_t)pair(r, k, j)];
    }
    if (!(al->lambda >= 0 && al->lambda <= 1) || !(al->reg >= 0) || !(al->damping >= 0))
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_ALRP, "lambda must be in [0, 1], the regularisation and damping >= 0");
    for (v = 0; v < m->nv; v++) {
        if (!(al->mass[v] >= 0)) return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_VMSS, "stored vertex ", (uint64_t)v, " has a negative mass");
        total += al->mass[v];
    }
    if (!(total > 0)) return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_VMSS, "the stored vertices carry no mass");
    for (g = 0; g < al->nmotions; g++) {
        const romrt_real *p = al->motions + ROMBIN_PIN_PARAMS * (size_t)g;
        if (!(p[0] == 0 || p[0] == 1 || p[0] == 2) || p[ROMBIN_PIN_PARAMS - 1] != 0)
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_AMOT, "motion ", (uint64_t)g, " has an unknown kind");
        if (p[0] == 1 && !(p[1] * p[1] + p[2] * p[2] + p[3] * p[3] > 0))
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_AMOT, "motion ", (uint64_t)g, " twists about a zero axis");
    }
    return ROMRT_OK;
}

/* ---- small dense helpers (rows: n x r, row i's r reals contiguous) ---- */

static int prescribed(const rt_alrom *al, int row) { return al->motion_of[row / 3] != ROMBIN_NO_MOTION; }

static void zero_prescribed_rows(const romrt_model *m, double *A)
{
    int i, n = 3 * m->nv;
    for (i = 0; i < n; i++)
        if (prescribed(&m->al, i)) memset(A + (size_t)i * (size_t)m->r, 0, sizeof(double) * (size_t)m->r);
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

/* p = e(u): the mass projection onto the linear part, then Gauss-Newton on |g(p) - u|_M^2 (the
 * precompute's quadratic encoder, precompute/grassmann/quadratic.c). Leaves J(p) in al->U. */
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

static romrt_status encode(romrt_model *m, romrt_error *err)
{
    rt_alrom *al = &m->al;
    double rhs[ROMRT_MAX_R];
    int r = m->r, it, k;
    romrt_status st;
    if (al->decoder) {
        crom_encode(m);
        return ROMRT_OK;
    }
    for (k = 0; k < r; k++) al->p[k] = 0;
    jacobian(m, al->p, al->U, 0, 0); /* the linear part, Phi */
    st = mass_lsq(m, al->U, al->u, al->p, al->work, err);
    for (it = 0; !st && it < ENCODE_ITERATIONS; it++) {
        double step = 0, size = 0;
        jacobian(m, al->p, al->U, al->u, al->res);
        if ((st = mass_lsq(m, al->U, al->res, rhs, al->work, err))) break;
        for (k = 0; k < r; k++) {
            al->p[k] += rhs[k];
            step = fabs(rhs[k]) > step ? fabs(rhs[k]) : step;
            size = fabs(al->p[k]) > size ? fabs(al->p[k]) : size;
        }
        if (step <= 1e-12 * (size > 0 ? size : 1)) break;
    }
    if (!st) jacobian(m, al->p, al->U, 0, 0);
    return st;
}

/* Q: orthonormal columns spanning A's (n x r; Q may be A), classical Gram-Schmidt run twice per
 * column (as stable as Householder for this purpose, and row by row over memory). -1 when a
 * column's remainder, R's diagonal, is below RANK_TOL of the largest: rank below r. */
static int thin_q(int n, int r, const double *A, double *Q)
{
    double d[ROMRT_MAX_R], big = 0, small = INFINITY;
    int i, j, k, pass;
    if (Q != A) memcpy(Q, A, sizeof(double) * (size_t)n * (size_t)r);
    for (j = 0; j < r; j++) {
        double norm2 = 0, norm;
        for (pass = 0; pass < 2 && j > 0; pass++) {
            for (k = 0; k < j; k++) d[k] = 0;
            for (i = 0; i < n; i++) {
                const double *Qi = Q + (size_t)i * (size_t)r;
                for (k = 0; k < j; k++) d[k] += Qi[k] * Qi[j];
            }
            for (i = 0; i < n; i++) {
                double *Qi = Q + (size_t)i * (size_t)r, s = Qi[j];
                for (k = 0; k < j; k++) s -= d[k] * Qi[k];
                Qi[j] = s;
            }
        }
        for (i = 0; i < n; i++) norm2 += Q[(size_t)i * (size_t)r + (size_t)j] * Q[(size_t)i * (size_t)r + (size_t)j];
        norm = sqrt(norm2);
        if (!(norm > 0) || !isfinite(norm)) return -1;
        big = norm > big ? norm : big;
        small = norm < small ? norm : small;
        for (i = 0; i < n; i++) Q[(size_t)i * (size_t)r + (size_t)j] /= norm;
    }
    return small > RANK_TOL * big ? 0 : -1;
}

/* The SVD of the r x r matrix M (column-major) by one-sided Jacobi: M W = V diag(s), W and V
 * orthogonal, s >= 0 (unsorted: every use here is column by column). M is overwritten. */
static void jacobi_svd(int r, double *M, double *W, double *V, double *s)
{
    int i, j, k, sweep, rotated = 1;
    for (k = 0; k < r * r; k++) W[k] = (double)(k % (r + 1) == 0);
    for (sweep = 0; sweep < 60 && rotated; sweep++) {
        rotated = 0;
        for (i = 0; i < r; i++)
            for (j = i + 1; j < r; j++) {
                double *a = M + (size_t)r * i, *b = M + (size_t)r * j, al = 0, be = 0, ga = 0, zeta, t, c, sn;
                for (k = 0; k < r; k++) {
                    al += a[k] * a[k];
                    be += b[k] * b[k];
                    ga += a[k] * b[k];
                }
                if (!(fabs(ga) > 1e-15 * sqrt(al * be))) continue;
                rotated = 1;
                zeta = (be - al) / (2 * ga);
                t = (zeta >= 0 ? 1 : -1) / (fabs(zeta) + sqrt(1 + zeta * zeta));
                c = 1 / sqrt(1 + t * t);
                sn = c * t;
                for (k = 0; k < r; k++) {
                    double x = a[k], y = b[k];
                    a[k] = c * x - sn * y;
                    b[k] = sn * x + c * y;
                    x = W[(size_t)r * i + k];
                    y = W[(size_t)r * j + k];
                    W[(size_t)r * i + k] = c * x - sn * y;
                    W[(size_t)r * j + k] = sn * x + c * y;
                }
            }
    }
    for (j = 0; j < r; j++) {
        double n2 = 0;
        for (k = 0; k < r; k++) n2 += M[(size_t)r * j + k] * M[(size_t)r * j + k];
        s[j] = sqrt(n2);
    }
    /* V = M W / s; a zero s (orthogonal directions) gets a unit vector clear of the other columns */
    for (j = 0; j < r; j++) {
        double *vj = V + (size_t)r * j;
        if (s[j] > RANK_TOL) {
            for (k = 0; k < r; k++) vj[k] = M[(size_t)r * j + k] / s[j];
            continue;
        }
        s[j] = 0;
        for (i = 0; i < r; i++) {
            double n2 = 0;
            int l;
            for (k = 0; k < r; k++) vj[k] = (double)(k == i);
            for (l = 0; l < r; l++) {
                double dot = 0;
                if (l == j || (l > j && s[l] <= RANK_TOL)) continue;
                for (k = 0; k < r; k++) dot += vj[k] * V[(size_t)r * l + k];
                for (k = 0; k < r; k++) vj[k] -= dot * V[(size_t)r * l + k];
            }
            for (k = 0; k < r; k++) n2 += vj[k] * vj[k];
            if (n2 > 0.25) {
                for (k = 0; k < r; k++) vj[k] /= sqrt(n2);
                break;
            }
        }
    }
}

/* Algorithm 4 from Q1 = Q_Phi and Q2 = Q_U (orthonormal): with Q1^T Q2 = V cos(Theta) W^T, the
 * geodesic point G = Q1 V cos(lambda Theta) + S sin(lambda Theta), S = (Q2 W - Q1 V cos Theta)
 * / sin Theta, written as G = Q1 V diag(a) + Q2 W diag(b), b = sin(lambda theta) / sin theta
 * (-> lambda as theta -> 0, where the spans share a direction), a = cos(lambda theta) - b cos theta.
 * Into out (n x r, not orthonormalised). */
static void geodesic(romrt_model *m, double *out)
{
    rt_alrom *al = &m->al;
    int r = m->r, n = 3 * m->nv, i, j, k;
    double *Mq = al->work, *W = Mq + (size_t)r * r, *V = W + (size_t)r * r, *A = V + (size_t)r * r, s[ROMRT_MAX_R];
    double a[ROMRT_MAX_R], b[ROMRT_MAX_R], lambda = al->lambda;
    for (k = 0; k < r * r; k++) Mq[k] = 0;
    for (i = 0; i < n; i++) { /* Mq = Q1^T Q2, column-major */
        const double *q1 = al->Q1 + (size_t)i * (size_t)r, *q2 = al->Q2 + (size_t)i * (size_t)r;
        for (j = 0; j < r; j++)
            for (k = 0; k < r; k++) Mq[k + (size_t)r * j] += q1[k] * q2[j];
    }
    jacobi_svd(r, Mq, W, V, s);
    for (j = 0; j < r; j++) {
        double c = s[j] < 1 ? s[j] : 1, sn = sqrt(1 - c * c), theta = atan2(sn, c);
        b[j] = theta > 1e-4 ? sin(lambda * theta) / sn : lambda * (1 + (1 - lambda * lambda) * theta * theta / 6);
        a[j] = cos(lambda * theta) - b[j] * c;
    }
    /* A = V diag(a) (r x r), Mq reused for W diag(b); out = Q1 A + Q2 (W diag b) */
    for (j = 0; j < r; j++)
        for (k = 0; k < r; k++) {
            A[k + (size_t)r * j] = V[k + (size_t)r * j] * a[j];
            Mq[k + (size_t)r * j] = W[k + (size_t)r * j] * b[j];
        }
    for (i = 0; i < n; i++) {
        const double *q1 = al->Q1 + (size_t)i * (size_t)r, *q2 = al->Q2 + (size_t)i * (size_t)r;
        double *o = out + (size_t)i * (size_t)r;
        for (j = 0; j < r; j++) {
            double acc = 0;
            for (k = 0; k < r; k++) acc += q1[k] * A[k + (size_t)r * j] + q2[k] * Mq[k + (size_t)r * j];
            o[j] = acc;
        }
    }
}

/* Phi_h = D P^T (P P^T + reg I)^-1 over the newest `count` ring entries (Eq. 13) into al->Q1; the
 * order of the entries does not matter to it. -1 when P P^T + reg I is not positive definite. */
static int history_basis(romrt_model *m, int count)
{
    rt_alrom *al = &m->al;
    int r = m->r, n = 3 * m->nv, slots = al->m + 1, e, i, j, k;
    double *A = al->work;
    for (k = 0; k < r * r; k++) A[k] = 0;
    for (e = 0; e < count; e++) {
        const double *p = al->P + (size_t)((al->head - e + slots) % slots) * (size_t)r;
        for (j = 0; j < r; j++)
            for (k = 0; k <= j; k++) A[k + (size_t)r * j] += p[k] * p[j];
    }
    for (k = 0; k < r; k++) A[k + (size_t)r * k] += al->reg;
    if (rt_cholesky_wide(r, A)) return -1;
    /* Phi_h = D C with C's row e = (A^-1 p_e)^T: count small solves, then one pass over the rows */
    for (e = 0; e < count; e++) {
        double *c = al->coef + (size_t)e * (size_t)r;
        memcpy(c, al->P + (size_t)((al->head - e + slots) % slots) * (size_t)r, sizeof(double) * (size_t)r);
        rt_cholesky_solve_wide(r, A, c);
    }
    for (i = 0; i < n * r; i++) al->Q1[i] = 0;
    for (e = 0; e < count; e++) {
        const double *d = al->D + (size_t)((al->head - e + slots) % slots) * (size_t)n, *c = al->coef + (size_t)e * (size_t)r;
        for (i = 0; i < n; i++) {
            double *Phi = al->Q1 + (size_t)i * (size_t)r, di = d[i];
            for (j = 0; j < r; j++) Phi[j] += di * c[j];
        }
    }
    return 0;
}

/* ---- a step ---- */

/* x_ref: where the step starts, the prescribed vertices moved to their targets at time t. */
static void place_prescribed(romrt_model *m, double t)
{
    rt_alrom *al = &m->al;
    int v, a, g;
    romrt_real R[ROMBIN_MAX_MOTIONS][9], shift[ROMBIN_MAX_MOTIONS][3];
    for (g = 0; g < al->nmotions; g++) {
        const romrt_real *p = al->motions + ROMBIN_PIN_PARAMS * (size_t)g;
        RT_PHYS(motion)((rk_motion_kind)(int)p[0], p + 1, p + 4, p[7], p + 8, t, R[g], shift[g]);
    }
    for (v = 0; v < m->nv; v++) {
        uint32_t g2 = al->motion_of[v];
        const romrt_real *X = al->X0 + 3 * (size_t)v;
        if (g2 == ROMBIN_NO_MOTION) continue;
        for (a = 0; a < 3; a++)
            al->u_ref[3 * v + a] = (double)R[g2][3 * a] * X[0] + (double)R[g2][3 * a + 1] * X[1] +
                                   (double)R[g2][3 * a + 2] * X[2] + shift[g2][a] - X[a];
    }
}

/* Each cubature element's F - I at x_ref, from its vertices' displacements. */
static void element_offsets(romrt_model *m)
{
    rt_alrom *al = &m->al;
    int e, k, a, b, c;
    for (e = 0; e < m->ne; e++) {
        const uint32_t *ev = m->elem + 5 * (size_t)e;
        const romrt_real *Dm = m->elem_real + 12 * (size_t)e;
        double u[12];
        for (k = 0; k < 4; k++)
            for (a = 0; a < 3; a++) u[3 * k + a] = al->u_ref[3 * ev[k] + a];
        for (a = 0; a < 3; a++)
            for (b = 0; b < 3; b++) {
                double s = 0;
                for (c = 0; c < 3; c++) s += (u[3 * (c + 1) + a] - u[a]) * Dm[3 * c + b];
                al->Hd0[9 * (size_t)e + 3 * a + b] = (romrt_real)s;
            }
    }
}

/* M_r = U^T diag(mass) U (full), f_r = U^T (f + f_app), C_r = a M_r; qtilde = M_r^-1 U^T M (x~ - x_ref). */
static romrt_status reduced_terms(romrt_model *m, const double *xtilde, romrt_error *err)
{
    rt_alrom *al = &m->al;
    int r = m->r, n = 3 * m->nv, i, j, k;
    romrt_real *b = m->qtilde;
    for (k = 0; k < r * r; k++) al->M[k] = 0;
    for (k = 0; k < r; k++) al->f[k] = b[k] = 0;
    for (i = 0; i < n; i++) {
        const romrt_real *Ui = al->rows + (size_t)i * (size_t)r;
        romrt_real w = al->mass[i / 3], fi = al->load[i] + al->f_app[i], wd = w * (romrt_real)(xtilde[i] - al->u_ref[i]);
        for (k = 0; k < r; k++) {
            romrt_real wk = w * Ui[k];
            al->f[k] += fi * Ui[k];
            b[k] += wd * Ui[k];
            for (j = k; j < r; j++) al->M[k + (size_t)r * j] += wk * Ui[j];
        }
    }
    for (j = 0; j < r; j++)
        for (k = 0; k < j; k++) al->M[j + (size_t)r * k] = al->M[k + (size_t)r * j];
    for (k = 0; k < r * r; k++) al->C[k] = al->damping * al->M[k];
    memcpy(m->H, al->M, sizeof(romrt_real) * (size_t)r * (size_t)r);
    if (rt_cholesky(r, m->H))
        return rt_fail(err, ROMRT_E_DIVERGED, ROMBIN_VMSS, "the step basis has no mass on some direction (U^T M U is singular)");
    rt_cholesky_solve(r, m->H, b);
    return ROMRT_OK;
}

romrt_status rt_alrom_begin(romrt_model *m, romrt_real *w_inertia, romrt_error *err)
{
    rt_alrom *al = &m->al;
    int n = 3 * m->nv, r = m->r, i, count, blended = 0, bdf2 = m->integrator == 1 && m->have_prev;
    romrt_real h = m->h;
    double *xtilde = al->res, *basis = al->Q2;
    romrt_status st;
    /* Algorithm 3, lines 3-6: the code of the state, the decoder's basis there, the history */
    memcpy(al->u, al->u_t, sizeof(double) * (size_t)n);
    if ((st = encode(m, err))) return st;
    zero_prescribed_rows(m, al->U);
    if (thin_q(n, r, al->U, al->Q2))
        return rt_fail(err, ROMRT_E_DIVERGED, ROMBIN_QDRV, "the decoder's basis lost rank at this state");
    memcpy(al->D + (size_t)al->head * (size_t)n, al->u, sizeof(double) * (size_t)n);
    memcpy(al->P + (size_t)al->head * (size_t)r, al->p, sizeof(double) * (size_t)r);
    count = al->count < al->m ? al->count + 1 : al->m;
    if (!history_basis(m, count)) { /* Phi_h in Q1, then the geodesic from it toward Q2 into U */
        zero_prescribed_rows(m, al->Q1);
        if (!thin_q(n, r, al->Q1, al->Q1)) {
            geodesic(m, al->U);
            blended = !thin_q(n, r, al->U, al->U);
        }
    }
    if (blended) basis = al->U;
    al->blended += blended;
    for (i = 0; i < n * r; i++) al->rows[i] = (romrt_real)basis[i];
    /* the step's reference: the start with the prescribed vertices at their targets */
    memcpy(al->u_ref, al->u_t, sizeof(double) * (size_t)n);
    place_prescribed(m, rt_clock(m, 1));
    for (i = 0; i < n; i++) al->x_ref[i] = (romrt_real)(al->X0[i] + al->u_ref[i]);
    element_offsets(m);
    for (i = 0; i < n; i++)
        xtilde[i] = bdf2 ? (4 * al->u_t[i] - al->u_prev[i]) / 3 + 2 * (double)h / 9 * (4 * al->v[i] - al->v_prev[i])
                         : al->u_t[i] + (double)h * al->v[i];
    *w_inertia = bdf2 ? RT_K(9.0) / (RT_K(4.0) * h * h) : 1 / (h * h);
    if ((st = reduced_terms(m, xtilde, err))) return st;
    m->C = al->damping > 0 ? al->C : 0;
    for (i = 0; i < r; i++) m->q[i] = m->v[i] = m->f_app[i] = 0;
    return ROMRT_OK;
}

romrt_status rt_alrom_commit(romrt_model *m, romrt_error *err)
{
    rt_alrom *al = &m->al;
    int n = 3 * m->nv, r = m->r, i, bdf2 = m->integrator == 1 && m->have_prev;
    double h = m->h, *u_new = al->u_new, *v_new = al->v_new;
    double top = 0;
    for (i = 0; i < n; i++) {
        const romrt_real *row = al->rows + (size_t)i * (size_t)r;
        double du = 0;
        int j;
        for (j = 0; j < r; j++) du += (double)row[j] * m->q[j];
        u_new[i] = al->u_ref[i] + du;
        v_new[i] = bdf2 ? (3 * u_new[i] - 4 * al->u_t[i] + al->u_prev[i]) / (2 * h) : (u_new[i] - al->u_t[i]) / h;
        if (!isfinite(u_new[i]) || !isfinite(v_new[i]) || !isfinite(u_new[i] + al->X0[i]))
            return rt_fail_n(err, ROMRT_E_DIVERGED, 0, "stored coordinate ", (uint64_t)i, " is not finite after the step");
        if (i < 3 * m->shown && fabs(u_new[i] + al->X0[i]) > top) top = fabs(u_new[i] + al->X0[i]);
    }
    memcpy(al->u_prev, al->u_t, sizeof(double) * (size_t)n);
    memcpy(al->v_prev, al->v, sizeof(double) * (size_t)n);
    memcpy(al->u_t, u_new, sizeof(double) * (size_t)n);
    memcpy(al->v, v_new, sizeof(double) * (size_t)n);
    memcpy(al->u_ref, u_new, sizeof(double) * (size_t)n);
    for (i = 0; i < n; i++) al->x_ref[i] = (romrt_real)(al->X0[i] + u_new[i]);
    al->head = (al->head + 1) % (al->m + 1);
    if (al->count < al->m) al->count++;
    for (i = 0; i < r; i++) m->q[i] = 0;
    m->x_bound = top;
    return ROMRT_OK;
}

void rt_alrom_abort(romrt_model *m)
{
    rt_alrom *al = &m->al;
    int n = 3 * m->nv, k;
    memcpy(al->u_ref, al->u_t, sizeof(double) * (size_t)n);
    for (k = 0; k < n; k++) al->x_ref[k] = (romrt_real)(al->X0[k] + al->u_t[k]);
    for (k = 0; k < m->r; k++) m->q[k] = 0;
}

void rt_alrom_reset(romrt_model *m)
{
    rt_alrom *al = &m->al;
    size_t n = 3 * (size_t)m->nv;
    memset(al->u_t, 0, sizeof(double) * n);
    memset(al->u_ref, 0, sizeof(double) * n);
    memcpy(al->x_ref, al->X0, sizeof(romrt_real) * n);
    memset(al->v, 0, sizeof(double) * n);
    memset(al->u_prev, 0, sizeof(double) * n);
    memset(al->v_prev, 0, sizeof(double) * n);
    memset(al->f_app, 0, sizeof(romrt_real) * n);
    memset(al->Hd0, 0, sizeof(romrt_real) * 9 * (size_t)m->ne);
    al->count = al->head = 0;
    al->blended = 0;
    /* until the first step, the decoder's linear part (orthonormalised by that step) */
    memcpy(al->rows, al->phi, sizeof(romrt_real) * n * (size_t)m->r);
    {
        size_t i;
        for (i = 0; i < n; i++)
            if (prescribed(al, (int)i)) memset(al->rows + i * (size_t)m->r, 0, sizeof(romrt_real) * (size_t)m->r);
    }
    m->X = al->x_ref;
    m->rows = al->rows;
    m->force_rows = al->rows;
    m->M = al->M;
    m->f = al->f;
    m->C = 0;
    /* positions are x_ref + rows q with q = 0 between steps and orthonormal rows within one */
    m->row_bound = m->r;
}

int rt_alrom_push(romrt_model *m, uint32_t v, const romrt_real f[3], int apply)
{
    romrt_real *fa = m->al.f_app + 3 * (size_t)v;
    int a;
    for (a = 0; a < 3; a++)
        if (!isfinite(fa[a] + f[a])) return -1;
    for (a = 0; a < 3 && apply; a++) fa[a] += f[a];
    return 0;
}

/* The state after the clock and have_prev (access.c): the ring's count and head, then as pairs
 * (rt_split: the state is double in either build) u_t, v, u_prev, v_prev, the ring's D and P,
 * then the applied forces (romrt_real, as the app gave them). */
int rt_alrom_state_size(const romrt_model *m)
{
    const rt_alrom *al = &m->al;
    int n = 3 * m->nv, slots = al->m + 1;
    return 2 + 2 * (4 * n + slots * (n + m->r)) + n;
}

static romrt_real *put(romrt_real *s, const double *x, size_t count)
{
    size_t i;
    for (i = 0; i < count; i++, s += 2) rt_split(x[i], s);
    return s;
}

static const romrt_real *take(const romrt_real *s, double *x, size_t count)
{
    size_t i;
    for (i = 0; i < count; i++, s += 2) x[i] = (double)s[0] + (double)s[1];
    return s;
}

void rt_alrom_get_state(const romrt_model *m, romrt_real *s)
{
    const rt_alrom *al = &m->al;
    size_t n = 3 * (size_t)m->nv, slots = (size_t)al->m + 1;
    *s++ = (romrt_real)al->count;
    *s++ = (romrt_real)al->head;
    s = put(s, al->u_t, n);
    s = put(s, al->v, n);
    s = put(s, al->u_prev, n);
    s = put(s, al->v_prev, n);
    s = put(s, al->D, slots * n);
    s = put(s, al->P, slots * (size_t)m->r);
    memcpy(s, al->f_app, sizeof(romrt_real) * n);
}

int rt_alrom_set_state(romrt_model *m, const romrt_real *s)
{
    rt_alrom *al = &m->al;
    size_t n = 3 * (size_t)m->nv, slots = (size_t)al->m + 1, k;
    romrt_real count = s[0], head = s[1];
    if (!(count >= 0 && count <= al->m && count == (romrt_real)(int)count) ||
        !(head >= 0 && head <= al->m && head == (romrt_real)(int)head))
        return -1;
    for (k = 0; k < n; k++) /* positions that would not be representable */
        if (!((double)s[2 + 2 * k] + al->X0[k] < 1e30 && (double)s[2 + 2 * k] + al->X0[k] > -1e30)) return -1;
    al->count = (int)count;
    al->head = (int)head;
    s += 2;
    s = take(s, al->u_t, n);
    s = take(s, al->v, n);
    s = take(s, al->u_prev, n);
    s = take(s, al->v_prev, n);
    s = take(s, al->D, slots * n);
    s = take(s, al->P, slots * (size_t)m->r);
    memcpy(al->f_app, s, sizeof(romrt_real) * n);
    rt_alrom_abort(m); /* x_ref and q from u_t */
    m->x_bound = 0;
    for (k = 0; k < 3 * (size_t)m->shown; k++)
        if (fabs((double)al->x_ref[k]) > m->x_bound) m->x_bound = fabs((double)al->x_ref[k]);
    return 0;
}
