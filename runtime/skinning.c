/* The elastic energy of a skinning basis through its structure (SKIN, formats/ROMBIN.md): with
 * linear blend skinning over H affine handles, x_v = X_v + sum_j w_j(v) A_j (X_v, 1), q holding
 * each A_j row by row (column 12 j + 4 a + c is A_j[a][c]). A cubature element's deformation
 * gradient is then F = I + sum_j A_j N_j with N_j the 4 x 3 matrix
 *
 *   N[(j, c), b] = sum_c' Dm^-1_c'b (w_j(v_c'+1) X̄_c(v_c'+1) - w_j(v_0) X̄_c(v_0)),   X̄ = (X, 1),
 *
 * so row (a, b) of G_e touches only the 4 H coordinates of row a of the handles: the dense 9 x r
 * G_e has a third of its entries non-zero. With n = 4 H and the coordinates ordered (a, j, c),
 * the element Hessian G^T A G is 3 x 3 blocks of n x n, block (a, a') = N^T A_aa' N (A_aa' the
 * 3 x 3 block of dP/dF between F's rows a and a'): 1.5 r^2 multiply-adds for the upper triangle
 * against the dense 4.5 r^2 (FreeForm paper, Eq. 1 and 22: F from the weights and the handles).
 * The energy, gradient and Hessian are the dense path's (potential.c) up to rounding.
 *
 * A mesh-free integration point (IPNT) is an element whose N comes straight from the weights and
 * their gradients at the point (freeform paper Eq. 21): N[(j, c), b] = X̄_c dw_j/dX_b + w_j delta_cb. */
#include <math.h>
#include <string.h>

#include "runtime/loader_impl.h"

/* The a = 0 row of stored vertex v (ROWS): entry 12 j + c is w_j(v) X̄_c(v). */
static const romrt_real *row0(const romrt_model *m, uint32_t v)
{
    return m->rows + (size_t)3 * v * (size_t)m->r;
}

/* That entry, w_j(v) X̄_c(v), from the rows or formed from the weights (WGHT: the same product). */
static romrt_real wx(const romrt_model *m, uint32_t v, int j, int c)
{
    return m->w ? m->w[(size_t)v * (size_t)m->skin + (size_t)j] * (c < 3 ? m->X[3 * (size_t)v + (size_t)c] : RT_K(1))
                : row0(m, v)[12 * j + c];
}

/* The handles [*j0, *j1) whose weight reaches one of element e's 4 vertices: outside them every
 * w_j(v) X̄_c(v) of its vertices is zero, and so are its u and N. With several objects an element
 * lies in one, whose handles alone reach it (with RKPM's compact kernels, fewer still). */
static void element_handles(const romrt_model *m, int e, int *j0, int *j1)
{
    const uint32_t *ev = m->elem + 5 * (size_t)e;
    int k, j;
    *j0 = m->skin, *j1 = 0;
    for (k = 0; k < 4; k++)
        for (j = 0; j < m->skin; j++)
            if (rt_weight(m, ev[k], j) != 0) {
                if (j < *j0) *j0 = j;
                if (j + 1 > *j1) *j1 = j + 1;
            }
    if (*j1 <= *j0) *j0 = *j1 = 0;
}

/* m->skin_N = N_e, 3 rows (b) of RT_PAD(4 H), zero outside its handles [j0, j1). */
static void element_N(romrt_model *m, int e, int j0, int j1)
{
    const uint32_t *ev = m->elem + 5 * (size_t)e;
    const romrt_real *Dm = m->elem_real + 12 * (size_t)e;
    int H = m->skin, np = RT_PAD(4 * H), j, c, b;
    romrt_real *N = m->skin_N;
    for (b = 0; b < 3; b++)
        for (j = 0; j < np; j++) N[np * b + j] = 0;
    for (j = j0; j < j1; j++)
        for (c = 0; c < 4; c++) {
            int x = 4 * j + c;
            romrt_real p0 = wx(m, ev[0], j, c), e1 = wx(m, ev[1], j, c) - p0, e2 = wx(m, ev[2], j, c) - p0,
                       e3 = wx(m, ev[3], j, c) - p0;
            for (b = 0; b < 3; b++) N[np * b + x] = e1 * Dm[b] + e2 * Dm[3 + b] + e3 * Dm[6 + b];
        }
}

/* m->skin_N for integration point p: from its weights and gradients (IPNT). */
static void point_N(romrt_model *m, int p)
{
    int H = m->skin, np = RT_PAD(4 * H), j, c, b;
    const romrt_real *s = m->pt + (6 + 4 * (size_t)H) * (size_t)p, *X = s;
    romrt_real *N = m->skin_N;
    for (j = 0; j < H; j++) {
        const romrt_real *wj = s + 6 + 4 * j; /* w_j, dw_j/dX_0..2 */
        for (b = 0; b < 3; b++) {
            romrt_real *Nb = N + np * b + 4 * j;
            for (c = 0; c < 3; c++) Nb[c] = X[c] * wj[1 + b] + (c == b ? wj[0] : 0);
            Nb[3] = wj[1 + b];
        }
    }
    for (b = 0; b < 3; b++)
        for (j = 4 * H; j < np; j++) N[np * b + j] = 0;
}

/* F - I = sum_j A_j N_j with N in m->skin_N (an integration point's). */
static void point_H(const romrt_model *m, romrt_real Hd[9])
{
    int np = RT_PAD(4 * m->skin), a, b, x;
    for (a = 0; a < 3; a++)
        for (b = 0; b < 3; b++) {
            const romrt_real *Q = m->skin_Q + (size_t)np * a, *N = m->skin_N + (size_t)np * b;
            romrt_real s = 0;
            for (x = 0; x < 4 * m->skin; x++) s += Q[x] * N[x];
            Hd[3 * a + b] = s;
        }
}

/* F - I of element e: u_{k, a} = B_{v_k, a} q through the weights (over its handles [j0, j1):
 * the rest add exact zeros), then Dm^-1 (as element_H). */
static void element_H(const romrt_model *m, int e, int j0, int j1, romrt_real Hd[9])
{
    const uint32_t *ev = m->elem + 5 * (size_t)e;
    const romrt_real *Dm = m->elem_real + 12 * (size_t)e;
    int np = RT_PAD(4 * m->skin), k, a, b, c, j;
    romrt_real u[12];
    for (k = 0; k < 4; k++)
        for (a = 0; a < 3; a++) {
            const romrt_real *Q = m->skin_Q + (size_t)np * a;
            romrt_real s = 0;
            for (j = j0; j < j1; j++)
                for (c = 0; c < 4; c++) s += wx(m, ev[k], j, c) * Q[4 * j + c];
            u[3 * k + a] = s;
        }
    for (a = 0; a < 3; a++)
        for (b = 0; b < 3; b++) {
            romrt_real s = 0;
            for (c = 0; c < 3; c++) s += (u[3 * (c + 1) + a] - u[a]) * Dm[3 * c + b];
            Hd[3 * a + b] = s;
        }
}

/* out[x] += C0[x] n0 + C1[x] n1 + C2[x] n2 over len entries: one column of a rank-3 block update. */
static void rank3_column(int len, const romrt_real *RT_RESTRICT C0, const romrt_real *RT_RESTRICT C1,
                         const romrt_real *RT_RESTRICT C2, romrt_real n0, romrt_real n1, romrt_real n2,
                         romrt_real *RT_RESTRICT out)
{
    int x;
    for (x = 0; x < len; x++) out[x] += C0[x] * n0 + C1[x] * n1 + C2[x] * n2;
}

/* C[b'] = sum_b A[(a, b), (a', b')] N[b] over np entries. */
static void block_C(int np, int x0, int x1, const romrt_real *RT_RESTRICT N, const romrt_real *A, int a, int a2,
                    romrt_real w, romrt_real *RT_RESTRICT C)
{
    int b2, x;
    for (b2 = 0; b2 < 3; b2++) {
        romrt_real k0 = w * A[9 * (3 * a) + 3 * a2 + b2], k1 = w * A[9 * (3 * a + 1) + 3 * a2 + b2],
                   k2 = w * A[9 * (3 * a + 2) + 3 * a2 + b2];
        romrt_real *RT_RESTRICT Cb = C + (size_t)np * b2;
        for (x = x0; x < x1; x++) Cb[x] = k0 * N[x] + k1 * N[np + x] + k2 * N[2 * np + x];
    }
}

/* m->He (3 RT_PAD(4H) square, coordinates ordered (a, j, c)) += G^T (w A) G over its upper blocks,
 * on the coordinates [x0, x1) where N is non-zero alone (the rest of G is zero). */
static void element_hessian(romrt_model *m, const romrt_real A[81], romrt_real w, int x0, int x1)
{
    int np = RT_PAD(4 * m->skin), L = 3 * np, a, a2, y;
    const romrt_real *N = m->skin_N, *C = m->skin_C;
    for (a = 0; a < 3; a++)
        for (a2 = a; a2 < 3; a2++) {
            block_C(np, x0, x1, N, A, a, a2, w, m->skin_C);
            for (y = x0; y < x1; y++)
                rank3_column((a == a2 ? y + 1 : x1) - x0, C + x0, C + np + x0, C + 2 * np + x0, N[y], N[np + y],
                             N[2 * np + y], m->He + (size_t)L * (a2 * np + y) + a * np + x0);
        }
}

/* The handles [x0 / 4, x1 / 4) outside which N's 3 rows are zero: with several objects an element
 * lies in one of them and its weights reach that object's handles only (with RKPM's compact
 * kernels, fewer still), so its gradient and Hessian need not visit the rest. */
static void element_span(const romrt_model *m, int *x0, int *x1)
{
    int np = RT_PAD(4 * m->skin), lo = 4 * m->skin, hi = 0, x, b;
    const romrt_real *N = m->skin_N;
    for (x = 0; x < 4 * m->skin; x++)
        for (b = 0; b < 3; b++)
            if (N[np * b + x] != 0) {
                if (x < lo) lo = x;
                hi = x + 1;
            }
    if (hi <= lo) lo = hi = 0;
    *x0 = lo / 4 * 4, *x1 = (hi + 3) / 4 * 4;
}

/* Where coordinate i = 12 j + 4 a + c sits in the (a, j, c) order of m->He. */
static int block_index(int i, int np) { return i % 12 / 4 * np + i / 12 * 4 + i % 4; }

/* Element or point e's Hd from m->skin_Q (rt_volume_gather's pass): an integration point's
 * straight from its weights, Hd_ab = sum_j (A_j[a] . X̄) dw_j/dX_b + w_j A_j[a][b] (no N formed). */
static void skin_Hd(romrt_model *m, int e, const romrt_real *q, romrt_real Hd[9])
{
    int j0, j1, np = RT_PAD(4 * m->skin), j, a, b;
    (void)q;
    if (e >= m->ne) {
        const romrt_real *s = m->pt + (6 + 4 * (size_t)m->skin) * (size_t)(e - m->ne), *X = s;
        for (a = 0; a < 9; a++) Hd[a] = 0;
        for (j = 0; j < m->skin; j++) {
            const romrt_real *wj = s + 6 + 4 * j; /* w_j, dw_j/dX_0..2 */
            for (a = 0; a < 3; a++) {
                const romrt_real *A = m->skin_Q + (size_t)np * a + 4 * j;
                romrt_real u = A[0] * X[0] + A[1] * X[1] + A[2] * X[2] + A[3];
                for (b = 0; b < 3; b++) Hd[3 * a + b] += u * wj[1 + b] + wj[0] * A[b];
            }
        }
        return;
    }
    element_handles(m, e, &j0, &j1);
    element_H(m, e, j0, j1, Hd);
}

/* The projected volume's dtheta/dq of e (N in m->skin_N, non-zero on handles [x0 / 4, x1 / 4))
 * into C (rt_volume_add): dtheta/dA_j[a][c] = sum_b dtheta/dF_ab N[(j, c), b], at q's column
 * 12 j + 4 a + c. */
static void skin_volume_add(romrt_model *m, int e, romrt_real w, const romrt_real Hd[9], int x0, int x1)
{
    int np = RT_PAD(4 * m->skin), r = m->r, a, c, j;
    const romrt_real *lame, *N = m->skin_N;
    romrt_real dth[9], *t = m->vt;
    RT_PHYS(volume_h)(rt_material(m, e, &lame), Hd, dth);
    for (j = 0; j < r; j++) t[j] = 0;
    for (j = x0 / 4; j < x1 / 4; j++)
        for (a = 0; a < 3; a++)
            for (c = 0; c < 4; c++) {
                int x = 4 * j + c;
                t[12 * j + 4 * a + c] = dth[3 * a] * N[x] + dth[3 * a + 1] * N[np + x] + dth[3 * a + 2] * N[2 * np + x];
            }
    rt_volume_add(m, e, w, t);
}

romrt_real rt_skin_elastic(romrt_model *m, const romrt_real *q, romrt_real *g, romrt_real *H, int ld)
{
    int r = m->r, np = RT_PAD(4 * m->skin), L = 3 * np, e, i, j, a, b, x;
    romrt_real E = 0;
    for (i = 0; i < 3 * np; i++) m->skin_Q[i] = m->skin_gQ[i] = 0;
    for (i = 0; i < r; i++) m->skin_Q[block_index(i, np)] = q[i];
    if (m->vk) {
        E = rt_volume_gather(m, q, H != 0, skin_Hd);
        if (!isfinite(E)) return (romrt_real)INFINITY;
    }
    if (H)
        for (i = 0; i < L * L; i++) m->He[i] = 0;
    for (e = 0; e < m->ne + m->np; e++) {
        int point = e >= m->ne;
        int x0, x1, j0 = 0, j1 = 0;
        romrt_real Hd[9], P[9], A[81], psi,
            w = point ? m->pt[(6 + 4 * (size_t)m->skin) * (size_t)(e - m->ne) + 3] : m->elem_real[12 * (size_t)e + 9];
        if (m->vk) { /* Hd formed by rt_volume_gather; N only where a derivative needs it */
            for (i = 0; i < 9; i++) Hd[i] = m->vHd[9 * (size_t)e + i];
            if (point && (g || H)) point_N(m, e - m->ne);
            if (!point) element_handles(m, e, &j0, &j1);
        } else if (point) {
            point_N(m, e - m->ne);
            point_H(m, Hd);
        } else {
            element_handles(m, e, &j0, &j1);
            element_H(m, e, j0, j1, Hd);
        }
        psi = rt_element_psi(m, e, Hd);
        if (!isfinite(psi)) return (romrt_real)INFINITY;
        E += w * psi;
        if (!g && !H) continue;
        if (!point) element_N(m, e, j0, j1);
        element_span(m, &x0, &x1);
        rt_element_stress(m, e, Hd, g ? P : 0, H ? A : 0);
        if (g) { /* dE/dA_j[a][c] = w sum_b P_ab N[(j, c), b] */
            for (a = 0; a < 3; a++) {
                romrt_real *gQ = m->skin_gQ + (size_t)np * a;
                for (b = 0; b < 3; b++) {
                    const romrt_real *Nb = m->skin_N + (size_t)np * b;
                    romrt_real wp = w * P[3 * a + b];
                    for (x = x0; x < x1; x++) gQ[x] += wp * Nb[x];
                }
            }
        }
        if (H) element_hessian(m, A, w, x0, x1);
        if (H && m->vk) skin_volume_add(m, e, w, Hd, x0, x1);
    }
    if (g)
        for (i = 0; i < r; i++) g[i] += m->skin_gQ[block_index(i, np)];
    if (H)
        for (j = 0; j < r; j++) {
            int bj = block_index(j, np);
            for (i = 0; i <= j; i++) { /* the block matrix keeps its upper triangle in (a, j, c) order */
                int bi = block_index(i, np), lo = bi < bj ? bi : bj, hi = bi < bj ? bj : bi;
                H[i + (size_t)ld * j] += m->He[lo + (size_t)L * hi];
            }
        }
    if (H && m->vk) rt_volume_hessian(m, H, ld);
    return E;
}

romrt_status rt_skin_check(rt_loader *L, const romrt_model *m)
{
    /* The rows are stored rounded: w_j X̄_c rounded against the rounded w_j times the rounded X̄_c
     * differ by a few units in the last place of the coarser of the file's and this build's reals. */
    double eps = L->file.real_type == ROMBIN_REAL_F32 || sizeof(romrt_real) == 4 ? 1.1920928955078125e-7
                                                                                : 2.220446049250313e-16;
    int r = m->r, v, a, col;
    if (r != 12 * m->skin)
        return rt_fail_nn(L->err, ROMRT_E_MODEL, ROMBIN_SKIN, "names ", (uint64_t)m->skin, " handles, but r = ",
                          (uint64_t)r, " (12 per handle)");
    for (v = 0; v < m->nv; v++) {
        const romrt_real *X = m->X + 3 * (size_t)v;
        for (a = 0; a < 3; a++) {
            const romrt_real *row = m->rows + ((size_t)3 * v + (size_t)a) * (size_t)r;
            for (col = 0; col < r; col++) {
                int j = col / 12, c = col % 4;
                double wj = (double)row0(m, (uint32_t)v)[12 * j + 3], xc = c == 3 ? 1.0 : (double)X[c];
                double want = col % 12 / 4 != a ? 0 : wj * xc;
                if (!(fabs((double)row[col] - want) <= 8 * eps * fabs(want)))
                    return rt_fail_nn(L->err, ROMRT_E_MODEL, ROMBIN_SKIN, "stored vertex ", (uint64_t)v,
                                      "'s rows do not follow linear blend skinning (column ", (uint64_t)col, ")");
            }
        }
    }
    return ROMRT_OK;
}
