/* The adaptive linear ROM's decoders (alrom_impl.h): the quadratic manifold's Jacobian and its
 * Gauss-Newton encoder, and a CROM's two networks (the encoder, and the decoder's Jacobian by forward
 * mode at each stored vertex), both in double in either build. */
#include <math.h>
#include <string.h>

#include "runtime/alrom_impl.h"

/* ---- small dense helpers (rows: n x r, row i's r reals contiguous) ---- */

void rt_alrom_zero_prescribed(const romrt_model *m, double *A)
{
    int i, n = 3 * m->nv;
    for (i = 0; i < n; i++)
        if (rt_alrom_prescribed(&m->al, i)) memset(A + (size_t)i * (size_t)m->r, 0, sizeof(double) * (size_t)m->r);
}

/* Row i of U = dg/dp at al->p: column k = Phi_ik + sum_j Psi_i,kj p_j, from QDRV's packed pairs
 * (k <= j) in order: each pair adds to column k and, off the diagonal, to column j (half the
 * reads of the expanded r x r matrix; this pass is the step's largest). */
void rt_alrom_jacobian_row(const romrt_model *m, int i, double *Ui)
{
    const rt_alrom *al = &m->al;
    int r = m->r, k, j;
    const romrt_real *phi = al->phi + (size_t)i * (size_t)r, *psi = al->psi + (size_t)i * (size_t)al->pairs;
    const double *p = al->p;
    for (k = 0; k < r; k++) Ui[k] = phi[k];
    for (k = 0; k < r; k++) {
        /* column k's sum in four partial sums, and row k's additions apart: one loop doing both
         * was a chain of dependent adds (perf: a seventh of the step) */
        double pk = p[k], s[4] = {0, 0, 0, 0};
        int len = r - k;
        for (j = 1; j < len; j++) Ui[k + j] += (double)psi[j] * pk;
        for (j = 0; j + 3 < len; j += 4) {
            s[0] += (double)psi[j] * p[k + j];
            s[1] += (double)psi[j + 1] * p[k + j + 1];
            s[2] += (double)psi[j + 2] * p[k + j + 2];
            s[3] += (double)psi[j + 3] * p[k + j + 3];
        }
        for (; j < len; j++) s[j % 4] += (double)psi[j] * p[k + j];
        Ui[k] += (s[0] + s[1]) + (s[2] + s[3]);
        psi += len;
    }
}

/* Rows 3v, 3v + 1, 3v + 2 of U at al->p into J (r x 4, J[4 k + a] row 3v + a's column k, lane 3
 * zero): the same sums as rt_alrom_jacobian_row, r + 2 pairs - r = 256 multiply-adds a row at
 * r = 16 (the Jacobian's needed count, each pair read once for both columns it adds to), three rows
 * side by side. A row at a time left each pair's two additions in short loops of r - k (one to 15)
 * and chains of dependent adds: 2 G multiply-adds a second, a sixth of the step (perf, issue 33);
 * three rows in lanes make every addition independent of the next but the row sums, which keep
 * two partial sums each. */
void rt_alrom_jacobian_vertex(const romrt_model *m, int v, double *J)
{
    const rt_alrom *al = &m->al;
    int r = m->r, P = al->pairs, k, j, q;
    const romrt_real *phi = al->phi + (size_t)3 * (size_t)v * (size_t)r, *s0 = al->psi + (size_t)3 * (size_t)v * (size_t)P,
                     *s1 = s0 + P, *s2 = s1 + P;
    const double *p = al->p;
    for (k = 0; k < r; k++) {
        J[4 * k] = phi[k];
        J[4 * k + 1] = phi[r + k];
        J[4 * k + 2] = phi[2 * r + k];
        J[4 * k + 3] = 0;
    }
    for (k = 0, q = 0; k < r; k++) {
        double pk = p[k], a0 = (double)s0[q] * pk, a1 = (double)s1[q] * pk, a2 = (double)s2[q] * pk, b0 = 0, b1 = 0, b2 = 0;
        for (j = k + 1, q++; j < r; j++, q++) {
            double x0 = s0[q], x1 = s1[q], x2 = s2[q], pj = p[j], *Jj = J + 4 * j;
            Jj[0] += x0 * pk;
            Jj[1] += x1 * pk;
            Jj[2] += x2 * pk;
            b0 += x0 * pj, b1 += x1 * pj, b2 += x2 * pj;
            if (++j == r) {
                q++;
                break;
            }
            q++;
            x0 = s0[q], x1 = s1[q], x2 = s2[q], pj = p[j], Jj = J + 4 * j;
            Jj[0] += x0 * pk;
            Jj[1] += x1 * pk;
            Jj[2] += x2 * pk;
            a0 += x0 * pj, a1 += x1 * pj, a2 += x2 * pj;
        }
        J[4 * k] += a0 + b0;
        J[4 * k + 1] += a1 + b1;
        J[4 * k + 2] += a2 + b2;
    }
}

/* ---- the quadratic decoder's encoder, in r-space ----
 *
 * g(p) = B c(p) with B = [Phi | Psi's pairs] (n x R, R = r + pairs, QDRV's order) and c(p) = (p, the
 * pairs' p_k p_j, halved on the diagonal); its Jacobian J(p) = B C(p), C's column k = e_k + sum_j
 * p_j e_(r + pair(k, j)). So the encoder's mass least squares over the stored rows needs only the
 * Gram B^T W B (formed once at open) and B^T W u (one pass over the rows a step): J^T W J =
 * C^T (B^T W B) C, J^T W (u - g) = C^T (B^T W u - B^T W B c), and a trial code's change of the
 * misfit |u - g|_W^2 is -2 dc . B^T W (u - g) + dc^T B^T W B dc, dc = c(p + d) - c(p) (issue 33:
 * the encoder was 65% of the step, 10 to 20 passes of n r^2 over the rows for its Jacobians and
 * misfits; now one of n R and r-space work independent of the mesh). Same iterates as the
 * precompute's encoder (precompute/grassmann/quadratic.c), whose misfits it computes exactly. */

void rt_alrom_gram(romrt_model *m)
{
    rt_alrom *al = &m->al;
    int r = m->r, P = al->pairs, R = r + P, n = 3 * m->nv, i, a, b;
    double *G = al->gram, *F = al->gram_free, *WF = al->gram_wfree, *row = al->ext;
    for (i = 0; i < R * R; i++) G[i] = F[i] = WF[i] = 0;
    for (a = 0; a < R; a++) al->load_c[a] = 0;
    for (i = 0; i < n; i++) {
        double w = al->mass[i / 3];
        int is_free = !rt_alrom_prescribed(al, i);
        for (a = 0; a < r; a++) row[a] = al->phi[(size_t)i * (size_t)r + (size_t)a];
        for (a = 0; a < P; a++) row[r + a] = al->psi[(size_t)i * (size_t)P + (size_t)a];
        for (a = 0; a < R && is_free; a++) al->load_c[a] += (double)al->load[i] * row[a];
        for (b = 0; b < R; b++) {
            double wb = w * row[b], xb = row[b], *Gb = G + (size_t)R * (size_t)b, *Fb = F + (size_t)R * (size_t)b,
                   *Wb = WF + (size_t)R * (size_t)b;
            if (xb == 0) continue; /* the rigid modes' pairs are zero */
            for (a = 0; a <= b; a++) Gb[a] += wb * row[a];
            for (a = 0; a <= b && is_free; a++) {
                Fb[a] += xb * row[a];
                Wb[a] += wb * row[a];
            }
        }
    }
    for (b = 0; b < R; b++)
        for (a = 0; a < b; a++) {
            G[b + (size_t)R * a] = G[a + (size_t)R * b];
            F[b + (size_t)R * a] = F[a + (size_t)R * b];
            WF[b + (size_t)R * a] = WF[a + (size_t)R * b];
        }
}

void rt_alrom_used(romrt_model *m)
{
    rt_alrom *al = &m->al;
    int v, k, e, i;
    al->s_of = al->sv + m->nv;
    for (v = 0; v < m->nv; v++) al->s_of[v] = ROMBIN_NO_MOTION;
    for (e = 0; e < m->ne; e++)
        for (k = 0; k < 4; k++) al->s_of[m->elem[5 * (size_t)e + (size_t)k]] = 0;
    for (k = 0; k < m->ncontacts; k++) al->s_of[m->contacts[2 * (size_t)k]] = 0;
    for (v = 0, al->ns = 0; v < m->nv; v++)
        if (al->s_of[v] != ROMBIN_NO_MOTION) {
            al->s_of[v] = (uint32_t)al->ns;
            al->sv[al->ns++] = (uint32_t)v;
        }
    al->ns_base = al->ns; /* then the collision vertices not among them, used while a collider or the
                           * collision surface is (rt_alrom_begin) */
    for (k = 0; k < m->ncv; k++)
        if (al->s_of[m->cv[k]] == ROMBIN_NO_MOTION) {
            al->s_of[m->cv[k]] = (uint32_t)al->ns;
            al->sv[al->ns++] = m->cv[k];
        }
    al->ns_on = al->ns_base;
    al->b_sum = al->x0_max = 0; /* the bounds of rt_alrom_bound */
    for (i = 0; i < 3 * m->nv; i++) {
        double s = 0;
        for (k = 0; k < m->r; k++) s += fabs((double)al->phi[(size_t)i * (size_t)m->r + (size_t)k]);
        for (k = 0; k < al->pairs; k++) s += fabs((double)al->psi[(size_t)i * (size_t)al->pairs + (size_t)k]);
        if (s > al->b_sum) al->b_sum = s;
        if (i < 3 * m->shown && fabs((double)al->X0[i]) > al->x0_max) al->x0_max = fabs((double)al->X0[i]);
    }
}

double rt_alrom_b_dot(const romrt_model *m, int i, const double *c)
{
    const rt_alrom *al = &m->al;
    int r = m->r, P = al->pairs, a;
    const romrt_real *phi = al->phi + (size_t)i * (size_t)r, *psi = al->psi + (size_t)i * (size_t)P;
    double s = 0;
    for (a = 0; a < r; a++) s += (double)phi[a] * c[a];
    for (a = 0; a < P; a++) s += (double)psi[a] * c[r + a];
    return s;
}

void rt_alrom_gram_times(int R, const double *G, const double *v, double *out)
{
    int a, b;
    for (a = 0; a < R; a++) out[a] = 0;
    for (b = 0; b < R; b++) {
        const double *Gb = G + (size_t)R * (size_t)b;
        double vb = v[b];
        if (vb == 0) continue;
        for (a = 0; a < R; a++) out[a] += Gb[a] * vb;
    }
}

void rt_alrom_c_apply(const romrt_model *m, const double *p, const double *v, double *out)
{
    int r = m->r, k, j;
    for (k = 0; k < r; k++) {
        out[k] = v[k];
        for (j = 0; j < r; j++) out[k] += p[j] * v[r + rt_alrom_pair(r, k, j)];
    }
}

/* out = base + sum_i w_i col_i over R rows (base NULL: 0), each row's terms added in order. */
static void combine(int R, const double *base, int terms, const double *const *col, const double *w, double *out)
{
    int a, i;
    /* 8 rows at a time summed in registers: axpys over out in memory loaded and stored it once a
     * term (the encoder's largest cost) */
    for (a = 0; a + 8 <= R; a += 8) {
        double c0 = 0, c1 = 0, c2 = 0, c3 = 0, c4 = 0, c5 = 0, c6 = 0, c7 = 0;
        if (base) {
            const double *b = base + a;
            c0 = b[0], c1 = b[1], c2 = b[2], c3 = b[3], c4 = b[4], c5 = b[5], c6 = b[6], c7 = b[7];
        }
        for (i = 0; i < terms; i++) {
            const double *Sj = col[i] + a, x = w[i];
            c0 += x * Sj[0];
            c1 += x * Sj[1];
            c2 += x * Sj[2];
            c3 += x * Sj[3];
            c4 += x * Sj[4];
            c5 += x * Sj[5];
            c6 += x * Sj[6];
            c7 += x * Sj[7];
        }
        out[a] = c0, out[a + 1] = c1, out[a + 2] = c2, out[a + 3] = c3;
        out[a + 4] = c4, out[a + 5] = c5, out[a + 6] = c6, out[a + 7] = c7;
    }
    for (; a < R; a++) {
        double x = base ? base[a] : 0;
        for (i = 0; i < terms; i++) x += w[i] * col[i][a];
        out[a] = x;
    }
}

void rt_alrom_s_c(const romrt_model *m, const double *S, const double *p, double *SC)
{
    int r = m->r, R = r + m->al.pairs, k, j;
    const double *col[ROMRT_MAX_R];
    double w[ROMRT_MAX_R];
    for (k = 0; k < r; k++) { /* SC column k = S e_k + sum_j p_j S e_(r + pair(k, j)) */
        int terms = 0;
        for (j = 0; j < r; j++)
            if (p[j] != 0) {
                col[terms] = S + (size_t)R * (size_t)(r + rt_alrom_pair(r, k, j));
                w[terms++] = p[j];
            }
        combine(R, S + (size_t)R * (size_t)k, terms, col, w, SC + (size_t)R * (size_t)k);
    }
}

void rt_alrom_c_gram(const romrt_model *m, const double *S, const double *p, double *out)
{
    const rt_alrom *al = &m->al;
    int r = m->r, R = r + al->pairs, l;
    double *SC = al->gram_c;
    rt_alrom_s_c(m, S, p, SC);
    for (l = 0; l < r; l++) /* C^T (S C): column l */
        rt_alrom_c_apply(m, p, SC + (size_t)R * (size_t)l, out + (size_t)r * (size_t)l);
}

/* dc = c(p + d) - c(p), the pairs as d_k p_j + p_k d_j + d_k d_j (no cancellation for a small d). */
static void code_change(int r, const double *p, const double *d, double *dc)
{
    int k, j, q = r;
    for (k = 0; k < r; k++) dc[k] = d[k];
    for (k = 0; k < r; k++)
        for (j = k; j < r; j++, q++) {
            double x = d[k] * p[j] + p[k] * d[j] + d[k] * d[j];
            dc[q] = k == j ? 0.5 * x : x;
        }
}

/* x = (C^T G C + 1e-12 max diag I)^-1 C^T gres at p (the mass least squares of the misfit's
 * residual, whose B^T W is gres); A: r x r scratch. */
static romrt_status code_step(romrt_model *m, const double *p, const double *gres, double *x, double *A, romrt_error *err)
{
    int r = m->r, k;
    double scale = 0;
    rt_alrom_c_gram(m, m->al.gram, p, A);
    rt_alrom_c_apply(m, p, gres, x);
    for (k = 0; k < r; k++) scale = A[k + (size_t)r * k] > scale ? A[k + (size_t)r * k] : scale;
    for (k = 0; k < r; k++) A[k + (size_t)r * k] += 1e-12 * scale; /* rigid or repeated columns */
    if (rt_cholesky_wide(r, A))
        return rt_fail_n(err, ROMRT_E_DIVERGED, ROMBIN_ALRH, "the decoder's Jacobian has rank below r = ", (uint64_t)r,
                         " (the encoder's mass least squares)");
    rt_cholesky_solve_wide(r, A, x);
    return ROMRT_OK;
}

/* p = e(u): the mass projection onto the linear part (a step from 0, where c = 0 and the residual
 * is u), then Gauss-Newton on |g(p) - u|_W^2, each step halved until it lowers the misfit (the
 * precompute's quadratic encoder: why). */
static romrt_status quadratic_encode(romrt_model *m, romrt_error *err)
{
    rt_alrom *al = &m->al;
    int r = m->r, P = al->pairs, R = r + P, i, a, it, k, h;
    double *gres = al->ext, *dc = gres + R, *Gdc = dc + R, *zero = Gdc + R, d[ROMRT_MAX_R], step_p[ROMRT_MAX_R],
           ptry[ROMRT_MAX_R];
    romrt_status st;
    /* gres = B^T W u = (B^T W B)_free c + B^T W u over the prescribed rows (u's free part is B c:
     * alrom.c), no pass over the free rows */
    rt_alrom_gram_times(R, al->gram_wfree, al->c, gres);
    /* c is the ring's newest entry this step (rt_alrom_step_basis): its W_F c kept for the history */
    memcpy(al->wdb + (size_t)al->head * (size_t)R, gres, sizeof(double) * (size_t)R);
    for (a = 0; a < R; a++) zero[a] = 0;
    for (i = 0; i < 3 * al->npv; i++) { /* the prescribed rows, ascending as pv */
        int row = 3 * (int)al->pv[i / 3] + i % 3;
        double wu = al->mass[row / 3] * al->u[row];
        const romrt_real *phi = al->phi + (size_t)row * (size_t)r, *psi = al->psi + (size_t)row * (size_t)P;
        if (wu == 0) continue;
        for (a = 0; a < r; a++) gres[a] += wu * phi[a];
        for (a = 0; a < P; a++) gres[r + a] += wu * psi[a];
    }
    if ((st = code_step(m, zero, gres, al->p, al->work, err))) return st;
    for (k = 0; k < r; k++) d[k] = al->p[k];
    code_change(r, zero, d, dc); /* gres -= G c(p) */
    rt_alrom_gram_times(R, al->gram, dc, Gdc);
    for (a = 0; a < R; a++) gres[a] -= Gdc[a];
    for (it = 0; it < al->encoder_iterations; it++) { /* (ALRH: 20 unless the asset says fewer) */
        double step = 0, size = 0, t, change = INFINITY;
        if ((st = code_step(m, al->p, gres, step_p, al->work, err))) return st;
        for (h = 0, t = 1; h < 10; h++, t *= 0.5) {
            for (k = 0; k < r; k++) {
                ptry[k] = al->p[k] + t * step_p[k];
                d[k] = ptry[k] - al->p[k];
            }
            code_change(r, al->p, d, dc);
            rt_alrom_gram_times(R, al->gram, dc, Gdc);
            change = 0;
            for (a = 0; a < R; a++) change += dc[a] * (Gdc[a] - 2 * gres[a]);
            if (change < 0) break;
        }
        if (!(change < 0)) break;
        for (k = 0; k < r; k++) {
            step = fabs(d[k]) > step ? fabs(d[k]) : step;
            al->p[k] = ptry[k];
            size = fabs(ptry[k]) > size ? fabs(ptry[k]) : size;
        }
        for (a = 0; a < R; a++) gres[a] -= Gdc[a];
        if (step <= 1e-12 * (size > 0 ? size : 1)) break;
    }
    return ROMRT_OK; /* U's rows where used (rt_alrom_jacobian_row) */
}

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
    if (m->al.decoder) {
        crom_encode(m);
        return ROMRT_OK;
    }
    return quadratic_encode(m, err);
}
