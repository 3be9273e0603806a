/* The adaptive linear ROM's step basis (alrom_impl.h, the paper's Algorithm 3, lines 3-6): the
 * history basis (Eq. 13), thin QRs, the SVD of Q_Phi^T Q_U and the Grassmann geodesic point at
 * lambda (Algorithm 4), in double in either build.
 *
 * All of it in r-space but for three passes over the stored rows (issue 33: thin QRs by Gram-
 * Schmidt, the history basis and the geodesic were 60% of the step once the encoder was in
 * r-space, nine passes of n r^2 and more): the history basis is Phi_h = D C + U G (history.c's
 * ridge: C's row e = (P P^T + (rho + reg) I)^-1 p_e, G = rho (..)^-1), so every inner product the
 * algorithm takes is one of the small Grams U^T U, D^T U (a pass each) and D^T D (one new row a
 * step, kept between steps); each thin QR is the Cholesky factor R of its Gram (Q = A R^-1: the
 * same Q and R as Gram-Schmidt in exact arithmetic, and R's diagonal its rank test), the geodesic
 * point is Q_Phi A + Q_U B, and the step basis D E_d + U E_u is formed in one last pass. The
 * Grams of well-conditioned bases (U: the decoder's Jacobian; Phi_h: held to U by the ridge) lose
 * nothing a step's float rows keep. Inner products are Euclidean over the free stored rows (the
 * prescribed rows are zero in every basis).
 *
 * What a step costs with the quadratic decoder, in multiply-adds (r = 16, pairs = r (r + 1) / 2 =
 * 136, R = r + pairs = 152, a history of m = 20; issue 33 asks each part to approach what it needs):
 *   encoder (alrom_decoder.c)  a Gauss-Newton iteration C^T G C: G C(p) R (r + 1) r = 41k, C^T (.)
 *                              r^2 (r + 1) = 4k, a trial's misfit R^2 = 23k; about 4 iterations a
 *                              step on the armadillo (counted): 0.28 M, all in r- and K-space.
 *   basis (this file)          U^T U = C^T F C 45k; the newest entry's F c, W_F c 2 R^2 = 46k; the
 *                              ridge's F w 23k; D^T U m r^2 = 5k; Phi_h's Grams m^2 r + m r^2 = 11k
 *                              (it was m^2 r^2 = 102k, a sum over entry pairs); QRs, SVD and the
 *                              geodesic O(r^3), about 50k: 0.18 M, none of it per vertex.
 *   rows (form_used)           C_s = sum_e c_e E_d[e] + C(p) E_u and W_F C_s: W_F C(p) 41k,
 *                              (W_F C(p)) E_u R r^2 = 39k, the entries 2 m R r = 97k; then per used
 *                              row the Jacobian's 2 pairs - r = 256 (each packed pair read once
 *                              for the two columns it adds to: the r + r^2 = 272 the issue counts,
 *                              less the symmetry) and the blend [D_i, U_i] E (m + r) r = 576 (in
 *                              the build's precision, float's 4 lanes): 832
 *                              a row, 0.72 M at the 288 used vertices of a 210-element cubature.
 *                              The blend's m r is the history's (Eq. 13 over the m stored entries);
 *                              a row of D E_d costs no less through the decoder (B_i C_D E_d is
 *                              R r), so 832 is what this basis needs a row, not a loss.
 *   G_e (potential.c)          27 r = 432 (and 9 r subtractions) an element, 91k at 210; their own
 *                              Newton work is PCA's (F = F(x_ref) + G_e q adds 9 a point).
 * Against PCA's step (its Newton alone, 3 iterations over the same 210 elements) these parts are
 * the adaptive step's excess: about 1.3 M multiply-adds a step, none of it per stored vertex
 * but the used rows; with a basis cadence K (alrom.c) all of it but the terms once in K steps. */
#include <math.h>
#include <string.h>

#include "runtime/alrom_impl.h"

/* ---- small column-major r x r helpers (R upper triangular, rt_cholesky_wide's layout) ---- */

/* R = the Cholesky factor of the Gram S (r x r, copied), -1 when R's smallest diagonal is below
 * RT_ALROM_RANK_TOL of its largest (the columns' rank is below r: Gram-Schmidt's test). */
static int gram_factor(int r, const double *S, double *R)
{
    double big = 0, small = INFINITY;
    int k;
    memcpy(R, S, sizeof(double) * (size_t)r * (size_t)r);
    if (rt_cholesky_wide(r, R)) return -1;
    for (k = 0; k < r; k++) {
        double d = R[k + (size_t)r * k];
        big = d > big ? d : big;
        small = d < small ? d : small;
    }
    return small > RT_ALROM_RANK_TOL * big ? 0 : -1;
}

/* X := X R^-1 (X: rows x r, column-major with leading dimension rows). */
static void solve_right(int r, int rows, const double *R, double *X)
{
    int i, j, k;
    for (j = 0; j < r; j++) {
        double *xj = X + (size_t)rows * j, d = R[j + (size_t)r * j];
        for (k = 0; k < j; k++) {
            const double *xk = X + (size_t)rows * k;
            double rkj = R[k + (size_t)r * j];
            for (i = 0; i < rows; i++) xj[i] -= xk[i] * rkj;
        }
        for (i = 0; i < rows; i++) xj[i] /= d;
    }
}

/* X := R^-1 X (X: r x r), back substitution column by column. */
static void solve_left(int r, const double *R, double *X)
{
    int i, j, k;
    for (j = 0; j < r; j++) {
        double *x = X + (size_t)r * j;
        for (i = r - 1; i >= 0; i--) {
            double s = x[i];
            for (k = i + 1; k < r; k++) s -= R[i + (size_t)r * k] * x[k];
            x[i] = s / R[i + (size_t)r * i];
        }
    }
}

/* X := R^-T X (X: r x r), forward substitution column by column. */
static void solve_left_t(int r, const double *R, double *X)
{
    int i, j, k;
    for (j = 0; j < r; j++) {
        double *x = X + (size_t)r * j;
        for (i = 0; i < r; i++) {
            double s = x[i];
            for (k = 0; k < i; k++) s -= R[k + (size_t)r * i] * x[k];
            x[i] = s / R[i + (size_t)r * i];
        }
    }
}

/* C = op(A) B (+ C when add), r x r, op(A) = A or A^T. */
static void mul(int r, const double *A, int transpose, const double *B, double *C, int add)
{
    int i, j, k;
    for (j = 0; j < r; j++)
        for (i = 0; i < r; i++) {
            double s = add ? C[i + (size_t)r * j] : 0;
            for (k = 0; k < r; k++)
                s += (transpose ? A[k + (size_t)r * i] : A[i + (size_t)r * k]) * B[k + (size_t)r * j];
            C[i + (size_t)r * j] = s;
        }
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
        if (s[j] > RT_ALROM_RANK_TOL) {
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
                if (l == j || (l > j && s[l] <= RT_ALROM_RANK_TOL)) continue;
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

/* ---- the history's Grams ---- */

/* The ring's entry e (0 the newest) and its slot. */
static int slot_of(const rt_alrom *al, int e) { return (al->head - e + al->m + 1) % (al->m + 1); }

/* d_a . d_b over the free stored rows. */
static double entry_dot(const romrt_model *m, int a, int b)
{
    const rt_alrom *al = &m->al;
    size_t n = 3 * (size_t)m->nv, i;
    const double *x = al->D + (size_t)a * n, *y = al->D + (size_t)b * n;
    double s = 0;
    for (i = 0; i < n; i++)
        if (!rt_alrom_prescribed(al, (int)i)) s += x[i] * y[i];
    return s;
}

/* al->dd (slots x slots): the newest entry's inner products with the `count` held, or all of them
 * after a reset or a restored state (dd_valid 0); each value is one fixed sum, so a restored run
 * steps as the original did. With the quadratic decoder also the entries' al->db. */
static void history_gram(romrt_model *m, int count)
{
    rt_alrom *al = &m->al;
    int slots = al->m + 1, e, f, first = al->dd_valid ? 0 : count - 1, R = m->r + al->pairs, k;
    for (e = 0; e <= first && !al->decoder; e++) { /* d_e = B c_e: B^T d_e = F c_e, B^T W d_e = W_F c_e
                                                    * (the newest's formed by the encoder) */
        size_t s = (size_t)slot_of(al, e) * (size_t)R;
        rt_alrom_gram_times(R, al->gram_free, al->D + s, al->db + s);
        if (e > 0) rt_alrom_gram_times(R, al->gram_wfree, al->D + s, al->wdb + s);
    }
    for (e = 0; e <= first; e++)
        for (f = e; f < count; f++) {
            int a = slot_of(al, e), b = slot_of(al, f);
            double d = 0;
            if (al->decoder) d = entry_dot(m, a, b);
            else
                for (k = 0; k < R; k++) d += al->D[(size_t)a * (size_t)R + (size_t)k] * al->db[(size_t)b * (size_t)R + (size_t)k];
            al->dd[a + (size_t)slots * b] = al->dd[b + (size_t)slots * a] = d;
        }
    al->dd_valid = 1;
}

/* The history's ridge in units of tr(P P^T) over the newest `count` ring entries, the
 * precompute's history_ridge (precompute/grassmann/alrom.c: why): at least the asset's ridge and
 * h |v| |u| / (budget sum_k |u_k|^2) over the free stored dofs (u the newest entry); -1 at rest
 * (the decoder's basis alone). */
static double history_ridge(const romrt_model *m, int count)
{
    const rt_alrom *al = &m->al;
    double uu, vv = 0, dd = 0, rate;
    int i, e, slots = al->m + 1;
    if (!al->decoder) { /* v's free part is B w */
        int R = m->r + al->pairs;
        rt_alrom_gram_times(R, al->gram_free, al->w, al->ext);
        for (i = 0; i < R; i++) vv += al->w[i] * al->ext[i];
    }
    for (i = 0; i < 3 * m->nv && al->decoder; i++)
        if (!rt_alrom_prescribed(al, i)) vv += al->v[i] * al->v[i];
    for (e = 0; e < count; e++) dd += al->dd[(size_t)(slots + 1) * (size_t)slot_of(al, e)];
    uu = al->dd[(size_t)(slots + 1) * (size_t)al->head];
    if (!(dd > 0)) return -1;
    if (!(al->budget > 0)) return (double)al->ridge;
    rate = (double)m->h * sqrt(vv * uu) / ((double)al->budget * dd);
    return rate > (double)al->ridge ? rate : (double)al->ridge;
}

/* The small matrices of a step (al->small, r x r each, column-major). */
enum { S_UU, S_HH, S_HU, K_DU, G_RHO, R_U, R_H, M_Q, W_SVD, V_SVD, A_H, A_U, G_3, T_1, E_U, SMALL_COUNT };

static double *small(const rt_alrom *al, int r, int which) { return al->small + (size_t)which * (size_t)r * (size_t)r; }

/* The history basis Phi_h = D C + U G (Eq. 13 with history.c's ridge toward U) in Grams: C's rows
 * into al->coef, G = rho (P P^T + (rho + reg) I)^-1, and with K = (D C)^T U (al->du: D^T U):
 * Phi_h^T U = K + G U^T U, Phi_h^T Phi_h = C^T (D^T D) C + K G + G K^T + G U^T U G. -1 when
 * P P^T + (rho + reg) I is not positive definite. */
static int history_basis(romrt_model *m, int count, double ridge)
{
    rt_alrom *al = &m->al;
    int r = m->r, slots = al->m + 1, e, f, i, j, k;
    double *A = al->work, *G = small(al, r, G_RHO), *K = small(al, r, K_DU), *Suu = small(al, r, S_UU),
           *Shh = small(al, r, S_HH), *Shu = small(al, r, S_HU), *T = small(al, r, T_1), trace = 0, rho;
    for (k = 0; k < r * r; k++) A[k] = 0;
    for (e = 0; e < count; e++) {
        const double *p = al->P + (size_t)slot_of(al, e) * (size_t)r;
        for (j = 0; j < r; j++)
            for (k = 0; k <= j; k++) A[k + (size_t)r * j] += p[k] * p[j];
    }
    for (k = 0; k < r; k++) trace += A[k + (size_t)r * k];
    rho = ridge > 0 ? ridge * trace : 0;
    for (k = 0; k < r; k++) A[k + (size_t)r * k] += rho + (double)al->reg;
    if (rt_cholesky_wide(r, A)) return -1;
    for (j = 0; j < r; j++) { /* G = rho A^-1 (symmetric), column by column */
        double *g = G + (size_t)r * j;
        for (k = 0; k < r; k++) g[k] = k == j && rho > 0 ? rho : 0;
        if (rho > 0) rt_cholesky_solve_wide(r, A, g);
    }
    for (e = 0; e < count; e++) {
        double *c = al->coef + (size_t)e * (size_t)r;
        memcpy(c, al->P + (size_t)slot_of(al, e) * (size_t)r, sizeof(double) * (size_t)r);
        rt_cholesky_solve_wide(r, A, c);
    }
    /* K = sum_e c_e (d_e^T U) */
    for (k = 0; k < r * r; k++) K[k] = 0;
    for (e = 0; e < count; e++) {
        const double *c = al->coef + (size_t)e * (size_t)r, *du = al->du + (size_t)e * (size_t)r;
        for (j = 0; j < r; j++)
            for (k = 0; k < r; k++) K[k + (size_t)r * j] += c[k] * du[j];
    }
    /* Phi_h^T U = K + G U^T U */
    memcpy(Shu, K, sizeof(double) * (size_t)r * (size_t)r);
    mul(r, G, 0, Suu, Shu, 1);
    /* Phi_h^T Phi_h = C^T (D^T D) C + K G + (K G)^T + G (U^T U) G */
    for (k = 0; k < r * r; k++) Shh[k] = 0;
    for (e = 0; e < count; e++) { /* += c_e t_e^T, t_e = sum_f (d_e . d_f) c_f: m^2 r + m r^2, not m^2 r^2 */
        const double *ce = al->coef + (size_t)e * (size_t)r;
        double t[ROMRT_MAX_R];
        for (j = 0; j < r; j++) t[j] = 0;
        for (f = 0; f < count; f++) {
            const double *cf = al->coef + (size_t)f * (size_t)r;
            double w = al->dd[slot_of(al, e) + (size_t)slots * (size_t)slot_of(al, f)];
            for (j = 0; j < r; j++) t[j] += w * cf[j];
        }
        for (j = 0; j < r; j++)
            for (i = 0; i < r; i++) Shh[i + (size_t)r * j] += ce[i] * t[j];
    }
    mul(r, K, 0, G, T, 0); /* T = K G */
    for (j = 0; j < r; j++)
        for (i = 0; i < r; i++) Shh[i + (size_t)r * j] += T[i + (size_t)r * j] + T[j + (size_t)r * i];
    mul(r, G, 0, Suu, T, 0);
    mul(r, T, 0, G, Shh, 1);
    return 0;
}

/* Algorithm 4 from Q1 = Phi_h R_h^-1 and Q2 = U R_u^-1 (orthonormal): with Q1^T Q2 = V cos(Theta)
 * W^T, the geodesic point G = Q1 V cos(lambda Theta) + S sin(lambda Theta), S = (Q2 W - Q1 V cos
 * Theta) / sin Theta, written as G = Q1 V diag(a) + Q2 W diag(b), b = sin(lambda theta) / sin theta
 * (-> lambda as theta -> 0, where the spans share a direction), a = cos(lambda theta) - b cos theta:
 * G = Phi_h A_h + U A_u, then orthonormalised by the Cholesky factor of its Gram G^T G (the
 * identity up to rounding). -1 when that Gram lost rank. */
static int geodesic(romrt_model *m)
{
    rt_alrom *al = &m->al;
    int r = m->r, i, j;
    double *Mq = small(al, r, M_Q), *W = small(al, r, W_SVD), *V = small(al, r, V_SVD), *Ah = small(al, r, A_H),
           *Au = small(al, r, A_U), *G3 = small(al, r, G_3), *T = small(al, r, T_1), *Rh = small(al, r, R_H),
           *Ru = small(al, r, R_U), s[ROMRT_MAX_R], a[ROMRT_MAX_R], b[ROMRT_MAX_R], lambda = al->lambda;
    /* Mq = Q1^T Q2 = R_h^-T (Phi_h^T U) R_u^-1, column-major */
    memcpy(Mq, small(al, r, S_HU), sizeof(double) * (size_t)r * (size_t)r);
    solve_right(r, r, Ru, Mq);
    solve_left_t(r, Rh, Mq);
    jacobi_svd(r, Mq, W, V, s);
    for (j = 0; j < r; j++) {
        double c = s[j] < 1 ? s[j] : 1, sn = sqrt(1 - c * c), theta = atan2(sn, c);
        b[j] = theta > 1e-4 ? sin(lambda * theta) / sn : lambda * (1 + (1 - lambda * lambda) * theta * theta / 6);
        a[j] = cos(lambda * theta) - b[j] * c;
    }
    /* A_h = R_h^-1 V diag(a), A_u = R_u^-1 W diag(b) */
    memcpy(Ah, V, sizeof(double) * (size_t)r * (size_t)r);
    memcpy(Au, W, sizeof(double) * (size_t)r * (size_t)r);
    solve_left(r, Rh, Ah);
    solve_left(r, Ru, Au);
    for (j = 0; j < r; j++)
        for (i = 0; i < r; i++) {
            Ah[i + (size_t)r * j] *= a[j];
            Au[i + (size_t)r * j] *= b[j];
        }
    /* G^T G = A_h^T Shh A_h + A_h^T Shu A_u + (..)^T + A_u^T Suu A_u */
    mul(r, small(al, r, S_HU), 0, Au, T, 0);
    mul(r, Ah, 1, T, G3, 0);
    for (j = 0; j < r; j++)
        for (i = 0; i <= j; i++) {
            double x = G3[i + (size_t)r * j] + G3[j + (size_t)r * i];
            G3[i + (size_t)r * j] = G3[j + (size_t)r * i] = x;
        }
    mul(r, small(al, r, S_HH), 0, Ah, T, 0);
    mul(r, Ah, 1, T, G3, 1);
    mul(r, small(al, r, S_UU), 0, Au, T, 0);
    mul(r, Au, 1, T, G3, 1);
    if (gram_factor(r, G3, T)) return -1;
    solve_right(r, r, T, Ah);
    solve_right(r, r, T, Au);
    return 0;
}

/* The step's rows: D E_d + U E_u over the free stored rows (E_d's row e into al->coef's), zero on
 * the prescribed; count 0: U E_u alone. The quadratic decoder's U rows are formed here, the only
 * place they are used. */
static void form_rows(romrt_model *m, int count, const double *Eu)
{
    rt_alrom *al = &m->al;
    int r = m->r, n = 3 * m->nv, i, j, k, e;
    double acc[ROMRT_MAX_R], Urow[ROMRT_MAX_R];
    for (i = 0; i < n; i++) {
        romrt_real *row = al->rows + (size_t)i * (size_t)r;
        const double *Ui = Urow;
        if (rt_alrom_prescribed(al, i)) {
            for (j = 0; j < r; j++) row[j] = 0;
            continue;
        }
        if (al->decoder) Ui = al->U + (size_t)i * (size_t)r;
        else rt_alrom_jacobian_row(m, i, Urow);
        for (j = 0; j < r; j++) acc[j] = 0;
        for (e = 0; e < count; e++) {
            double de = al->D[(size_t)slot_of(al, e) * (size_t)n + (size_t)i];
            const double *c = al->coef + (size_t)e * (size_t)r;
            for (j = 0; j < r; j++) acc[j] += de * c[j];
        }
        for (j = 0; j < r; j++) {
            const double *ej = Eu + (size_t)r * j;
            double s = acc[j];
            for (k = 0; k < r; k++) s += Ui[k] * ej[k];
            row[j] = (romrt_real)s;
        }
    }
}

/* acc = z^T Z (Z: T x r, row-major) with each column's sum kept in a register, 8 columns at a
 * time: the axpys over an acc in memory loaded and stored it once per term (perf: half of
 * form_used). Each column's terms are added in the same order as by the axpys. In the build's
 * precision, as the rows are kept (issue 33): float's four SSE lanes rather than double's two, the
 * largest per-row product of the step; a row is within 6e-7 of B C_s's (double: as before, bit for
 * bit), the free runs move by 1e-6 of their error. */
static void row_times(int T, int r, const romrt_real *z, const romrt_real *Z, romrt_real *acc)
{
    int j = 0, t;
    for (; j + 8 <= r; j += 8) {
        romrt_real a0 = 0, a1 = 0, a2 = 0, a3 = 0, a4 = 0, a5 = 0, a6 = 0, a7 = 0;
        const romrt_real *Zt = Z + j;
        for (t = 0; t < T; t++, Zt += r) {
            romrt_real x = z[t];
            a0 += x * Zt[0];
            a1 += x * Zt[1];
            a2 += x * Zt[2];
            a3 += x * Zt[3];
            a4 += x * Zt[4];
            a5 += x * Zt[5];
            a6 += x * Zt[6];
            a7 += x * Zt[7];
        }
        acc[j] = a0, acc[j + 1] = a1, acc[j + 2] = a2, acc[j + 3] = a3;
        acc[j + 4] = a4, acc[j + 5] = a5, acc[j + 6] = a6, acc[j + 7] = a7;
    }
    for (; j < r; j++) {
        romrt_real a = 0;
        for (t = 0; t < T; t++) a += z[t] * Z[(size_t)t * (size_t)r + (size_t)j];
        acc[j] = a;
    }
}

/* The quadratic decoder's step basis U = B C_s, C_s = sum_e c_e E_d's row e + C(p) E_u (R x r, into
 * al->cs), W_F C_s into al->wcs (from the entries' W_F c_e and W_F C(p): no R x R x r product), and
 * U's rows at the used vertices only (al->sv), from the Jacobian's rows and the ring's entries
 * there; the other rows are never read by a step (rt_alrom_used). */
static void form_used(romrt_model *m, int count, const double *Eu)
{
    rt_alrom *al = &m->al;
    int r = m->r, R = r + al->pairs, i, j, k, e, l, q, slot;
    double *WC = al->gram_c, *EuT = al->coef + (size_t)count * (size_t)r;
    romrt_real *z = al->zr + (size_t)(al->m + 1 + r) * (size_t)r; /* (al->zr's tail) */
    const double *p = al->p;
    /* C(p) E_u: rows 0..r-1 E_u, pair (k, j)'s row p_j E_u[k, :] + p_k E_u[j, :] (k < j), p_k E_u[k, :] */
    for (l = 0; l < r; l++) {
        double *cl = al->cs + (size_t)R * (size_t)l;
        const double *el = Eu + (size_t)r * (size_t)l;
        for (k = 0; k < r; k++) cl[k] = el[k];
        for (k = 0, q = r; k < r; k++)
            for (j = k; j < r; j++, q++) cl[q] = k == j ? p[k] * el[k] : p[j] * el[k] + p[k] * el[j];
    }
    rt_alrom_s_c(m, al->gram_wfree, p, WC); /* W_F C(p) (R x r) */
    for (l = 0; l < r; l++) { /* W_F C(p) E_u */
        double *wl = al->wcs + (size_t)R * (size_t)l;
        const double *el = Eu + (size_t)r * (size_t)l;
        for (i = 0; i < R; i++) wl[i] = 0;
        for (k = 0; k < r; k++)
            for (i = 0; i < R; i++) wl[i] += WC[(size_t)R * (size_t)k + (size_t)i] * el[k];
    }
    for (e = 0; e < count; e++) { /* + c_e E_d[e, :], W_F c_e E_d[e, :] */
        const double *ce = al->D + (size_t)slot_of(al, e) * (size_t)R, *we = al->wdb + (size_t)slot_of(al, e) * (size_t)R,
                     *ed = al->coef + (size_t)e * (size_t)r;
        for (l = 0; l < r; l++) {
            double *cl = al->cs + (size_t)R * (size_t)l, *wl = al->wcs + (size_t)R * (size_t)l, x = ed[l];
            for (i = 0; i < R; i++) {
                cl[i] += ce[i] * x;
                wl[i] += we[i] * x;
            }
        }
    }
    /* Z = [E_d; E_u^T] (count + r rows of r, E_d's rows already in al->coef), and each used row's
     * z = [its ring entries, newest first; its Jacobian row]: the row is z^T Z */
    for (i = 0; i < r; i++) /* E_u's rows contiguous */
        for (j = 0; j < r; j++) EuT[(size_t)r * (size_t)i + (size_t)j] = Eu[(size_t)r * (size_t)j + (size_t)i];
    for (i = 0; i < (count + r) * r; i++) al->zr[i] = (romrt_real)al->coef[i];
    for (k = 0; k < al->ns_on; k++) {
        int a, v = (int)al->sv[k];
        double J[4 * ROMRT_MAX_R];
        if (al->motion_of[v] == ROMBIN_NO_MOTION) rt_alrom_jacobian_vertex(m, v, J); /* (prescribed: zero rows) */
        for (a = 0; a < 3; a++) {
            int row_i = 3 * v + a;
            romrt_real *row = al->rows + (size_t)row_i * (size_t)r;
            if (rt_alrom_prescribed(al, row_i)) {
                for (j = 0; j < r; j++) row[j] = 0;
                continue;
            }
            for (j = 0; j < r; j++) z[count + j] = (romrt_real)J[4 * j + a];
            for (e = 0, slot = al->head; e < count; e++, slot = slot ? slot - 1 : al->m) /* slot_of(al, e) */
                z[e] = (romrt_real)*rt_alrom_ds(al, slot, 3 * k + a);
            row_times(count + r, r, z, al->zr, row);
        }
    }
}

romrt_status rt_alrom_step_basis(romrt_model *m, romrt_error *err)
{
    rt_alrom *al = &m->al;
    int n = 3 * m->nv, r = m->r, i, j, k, e, count, blended = 0;
    double *Suu = small(al, r, S_UU), *Ru = small(al, r, R_U), *Eu = small(al, r, E_U), ridge;
    romrt_status st;
    rt_alrom_copy_held(m, al->u, al->u_t);
    RT_PROF_BEGIN(RT_PROF_ALROM_ENCODE);
    st = rt_alrom_encode(m, err);
    RT_PROF_END(RT_PROF_ALROM_ENCODE);
    if (st) return st;
    if (!al->decoder) rt_alrom_c_gram(m, al->gram_free, al->p, Suu); /* U^T U = C^T (B^T B) C */
    else {
        rt_alrom_zero_prescribed(m, al->U);
        for (k = 0; k < r * r; k++) Suu[k] = 0;
        for (i = 0; i < n; i++) { /* U^T U (upper) */
            const double *Ui = al->U + (size_t)i * (size_t)r;
            for (j = 0; j < r; j++)
                for (k = 0; k <= j; k++) Suu[k + (size_t)r * j] += Ui[k] * Ui[j];
        }
        for (j = 0; j < r; j++)
            for (k = 0; k < j; k++) Suu[j + (size_t)r * k] = Suu[k + (size_t)r * j];
    }
    if (gram_factor(r, Suu, Ru))
        return rt_fail(err, ROMRT_E_DIVERGED, ROMBIN_QDRV, "the decoder's basis lost rank at this state");
    if (al->decoder) memcpy(al->D + (size_t)al->head * (size_t)n, al->u, sizeof(double) * (size_t)n);
    else { /* the entry's K-space coordinates, and its values on the used rows */
        int R = r + al->pairs;
        memcpy(al->D + (size_t)al->head * (size_t)R, al->c, sizeof(double) * (size_t)R);
        for (k = 0; k < al->ns_on; k++)
            for (j = 0; j < 3; j++) *rt_alrom_ds(al, al->head, 3 * k + j) = al->u[3 * al->sv[k] + (uint32_t)j];
    }
    memcpy(al->P + (size_t)al->head * (size_t)r, al->p, sizeof(double) * (size_t)r);
    count = al->count < al->m ? al->count + 1 : al->m;
    history_gram(m, count);
    ridge = history_ridge(m, count);
    /* a history of one state is no motion yet (and at rest there is none) */
    if (count >= 2 && ridge >= 0) {
        for (e = 0; e < count && !al->decoder; e++) /* D^T U = (D^T B) C(p) */
            rt_alrom_c_apply(m, al->p, al->db + (size_t)slot_of(al, e) * (size_t)(r + al->pairs), al->du + (size_t)e * (size_t)r);
        for (k = 0; k < count * r && al->decoder; k++) al->du[k] = 0;
        for (i = 0; i < n && al->decoder; i++) { /* D^T U over the free rows (U's prescribed rows are zero) */
            const double *Ui = al->U + (size_t)i * (size_t)r;
            for (e = 0; e < count; e++) {
                double de = al->D[(size_t)slot_of(al, e) * (size_t)n + (size_t)i], *du = al->du + (size_t)e * (size_t)r;
                if (de != 0)
                    for (j = 0; j < r; j++) du[j] += de * Ui[j];
            }
        }
        blended = !history_basis(m, count, ridge) && !gram_factor(r, small(al, r, S_HH), small(al, r, R_H)) &&
                  !geodesic(m);
    }
    if (blended) { /* rows = Phi_h A_h + U A_u = D (C A_h) + U (G A_h + A_u) */
        double *Ah = small(al, r, A_H), *Ed = al->work;
        for (e = 0; e < count; e++) { /* E_d's row e = c_e^T A_h, over coef's row e */
            double *c = al->coef + (size_t)e * (size_t)r;
            for (j = 0; j < r; j++) {
                double s = 0;
                for (k = 0; k < r; k++) s += c[k] * Ah[k + (size_t)r * j];
                Ed[j] = s;
            }
            memcpy(c, Ed, sizeof(double) * (size_t)r);
        }
        memcpy(Eu, small(al, r, A_U), sizeof(double) * (size_t)r * (size_t)r);
        mul(r, small(al, r, G_RHO), 0, Ah, Eu, 1);
    } else { /* Q_U = U R_u^-1 */
        for (k = 0; k < r * r; k++) Eu[k] = (double)(k % (r + 1) == 0);
        solve_left(r, Ru, Eu);
        count = 0;
    }
    RT_PROF_BEGIN(RT_PROF_ALROM_ROWS);
    if (al->decoder) form_rows(m, count, Eu);
    else form_used(m, count, Eu);
    rt_form_element_G(m); /* the step's G_e, for all of its Newton iterations and line searches */
    RT_PROF_END(RT_PROF_ALROM_ROWS);
    return ROMRT_OK;
}
