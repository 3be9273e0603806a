/* The adaptive linear ROM's step basis (alrom_impl.h, the paper's Algorithm 3, lines 3-6): the
 * history basis (Eq. 13), thin QRs, the SVD of Q_Phi^T Q_U and the Grassmann geodesic point at
 * lambda (Algorithm 4), in double in either build. */
#include <math.h>
#include <string.h>

#include "runtime/alrom_impl.h"

/* Q: orthonormal columns spanning A's (n x r; Q may be A), classical Gram-Schmidt run twice per
 * column (as stable as Householder for this purpose, and row by row over memory). -1 when a
 * column's remainder, R's diagonal, is below RT_ALROM_RANK_TOL of the largest: rank below r. */
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
    return small > RT_ALROM_RANK_TOL * big ? 0 : -1;
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

/* The history's ridge in units of tr(P P^T) over the newest `count` ring entries, the
 * precompute's history_ridge (precompute/grassmann/alrom.c: why): at least the asset's ridge and
 * h |v| |u| / (budget sum_k |u_k|^2) over the free stored dofs; -1 at rest (the decoder's basis
 * alone). */
static double history_ridge(const romrt_model *m, int count)
{
    const rt_alrom *al = &m->al;
    double uu = 0, vv = 0, dd = 0, rate;
    int i, e, slots = al->m + 1;
    for (i = 0; i < 3 * m->nv; i++)
        if (!rt_alrom_prescribed(al, i)) uu += al->u_t[i] * al->u_t[i], vv += al->v[i] * al->v[i];
    for (e = 0; e < count; e++) {
        const double *d = al->D + (size_t)((al->head - e + slots) % slots) * (size_t)(3 * m->nv);
        for (i = 0; i < 3 * m->nv; i++)
            if (!rt_alrom_prescribed(al, i)) dd += d[i] * d[i];
    }
    if (!(dd > 0)) return -1;
    if (!(al->budget > 0)) return (double)al->ridge;
    rate = (double)m->h * sqrt(vv * uu) / ((double)al->budget * dd);
    return rate > (double)al->ridge ? rate : (double)al->ridge;
}

/* Phi_h = D P^T (P P^T + reg I)^-1 over the newest `count` ring entries (Eq. 13) into al->Q1, with
 * the ridge toward the decoder's basis U (history.c): (D P^T + rho U)(P P^T + (rho + reg) I)^-1,
 * rho = ridge tr(P P^T); the order of the entries does not matter to it. -1 when the matrix is not
 * positive definite. */
static int history_basis(romrt_model *m, int count, double ridge)
{
    rt_alrom *al = &m->al;
    int r = m->r, n = 3 * m->nv, slots = al->m + 1, e, i, j, k;
    double *A = al->work, *G = A + (size_t)r * (size_t)r, trace = 0, rho;
    for (k = 0; k < r * r; k++) A[k] = 0;
    for (e = 0; e < count; e++) {
        const double *p = al->P + (size_t)((al->head - e + slots) % slots) * (size_t)r;
        for (j = 0; j < r; j++)
            for (k = 0; k <= j; k++) A[k + (size_t)r * j] += p[k] * p[j];
    }
    for (k = 0; k < r; k++) trace += A[k + (size_t)r * k];
    rho = ridge > 0 ? ridge * trace : 0;
    for (k = 0; k < r; k++) A[k + (size_t)r * k] += rho + (double)al->reg;
    if (rt_cholesky_wide(r, A)) return -1;
    /* G = rho A^-1 (symmetric), column by column */
    for (j = 0; j < r && rho > 0; j++) {
        double *g = G + (size_t)r * j;
        for (k = 0; k < r; k++) g[k] = k == j ? rho : 0;
        rt_cholesky_solve_wide(r, A, g);
    }
    /* Phi_h = D C with C's row e = (A^-1 p_e)^T: count small solves, then one pass over the rows */
    for (e = 0; e < count; e++) {
        double *c = al->coef + (size_t)e * (size_t)r;
        memcpy(c, al->P + (size_t)((al->head - e + slots) % slots) * (size_t)r, sizeof(double) * (size_t)r);
        rt_cholesky_solve_wide(r, A, c);
    }
    for (i = 0; i < n; i++) { /* rho U A^-1, row by row */
        double *Phi = al->Q1 + (size_t)i * (size_t)r;
        const double *Ui = al->U + (size_t)i * (size_t)r;
        for (j = 0; j < r; j++) {
            double s = 0;
            for (k = 0; k < r && rho > 0; k++) s += Ui[k] * G[k + (size_t)r * j];
            Phi[j] = s;
        }
    }
    for (e = 0; e < count; e++) {
        const double *d = al->D + (size_t)((al->head - e + slots) % slots) * (size_t)n, *c = al->coef + (size_t)e * (size_t)r;
        for (i = 0; i < n; i++) {
            double *Phi = al->Q1 + (size_t)i * (size_t)r, di = d[i];
            for (j = 0; j < r; j++) Phi[j] += di * c[j];
        }
    }
    return 0;
}

romrt_status rt_alrom_step_basis(romrt_model *m, romrt_error *err)
{
    rt_alrom *al = &m->al;
    int n = 3 * m->nv, r = m->r, i, count, blended = 0;
    double *basis = al->Q2, ridge;
    romrt_status st;
    memcpy(al->u, al->u_t, sizeof(double) * (size_t)n);
    if ((st = rt_alrom_encode(m, err))) return st;
    rt_alrom_zero_prescribed(m, al->U);
    if (thin_q(n, r, al->U, al->Q2))
        return rt_fail(err, ROMRT_E_DIVERGED, ROMBIN_QDRV, "the decoder's basis lost rank at this state");
    memcpy(al->D + (size_t)al->head * (size_t)n, al->u, sizeof(double) * (size_t)n);
    memcpy(al->P + (size_t)al->head * (size_t)r, al->p, sizeof(double) * (size_t)r);
    count = al->count < al->m ? al->count + 1 : al->m;
    ridge = history_ridge(m, count);
    /* a history of one state is no motion yet (and at rest there is none) */
    if (count >= 2 && ridge >= 0 && !history_basis(m, count, ridge)) { /* Phi_h in Q1, then the geodesic from it toward Q2 into U */
        rt_alrom_zero_prescribed(m, al->Q1);
        if (!thin_q(n, r, al->Q1, al->Q1)) {
            geodesic(m, al->U);
            blended = !thin_q(n, r, al->U, al->U);
        }
    }
    if (blended) basis = al->U;
    for (i = 0; i < n * r; i++) al->rows[i] = (romrt_real)basis[i];
    return ROMRT_OK;
}
