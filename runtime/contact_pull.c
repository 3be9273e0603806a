/* A contact stencil's gradient and Hessian pulled into the r x r system through its collision
 * vertices' basis rows (the reduced simulator's J^T B J, precompute/rom/contact.c): the barrier's
 * per point (rt_obstacles_pull, 12 rows) and friction's per pair (rt_obstacles_pull_slip: its
 * potential depends on the points through the relative motion sum_i w_i x_i alone, so 3 rows
 * sum_i w_i B_i carry it, where the 12 x 12 (w w^T) x B form pulled 12).
 *
 * Only the columns some row touches take part: a collision vertex's basis row is zero outside its
 * own object's columns (the objects' bases sit side by side, block-diagonal) and, for a skinning
 * basis, outside the handles whose weight reaches it. The rows are packed to those c columns
 * (cols), a skinning basis's ordered by axis first (column 12 j + 4 a + c to (a, j, c)): there
 * row (v, a) is non-zero only in axis a's third, a contiguous span. A skinning basis's rows are
 * formed packed from its weights (row 3 v + a holds w_j(v) Xbar_c at column 12 j + 4 a + c,
 * rows.c), the handles found first: no r-wide row is written or scanned (that was half the pull's
 * time in the 8-object pour, r = 192, c = 48). J^T B J is formed on the packed columns in a dense
 * c x c upper triangle (contiguous, it vectorizes), each row over its span alone, and added into
 * H once. The skipped terms are exact zeros: for a pair between two of 8 objects' skinning bases
 * c = r / 4, and each row costs c^2 / 6 multiply-adds on average against r^2 / 2 over all columns. */
#include "runtime/romrt_impl.h"

typedef struct {
    int n, c, cp;                /* rows, packed columns, the packed rows' stride */
    int rows[12], lo[12], hi[12]; /* each row's index into gx and B, and the span of its non-zeros */
    int cols[ROMRT_MAX_R];       /* packed column i's column of q */
    int ord[ROMRT_MAX_R];        /* the packed columns in ascending cols */
    int run;                     /* ord comes in runs of this many consecutive cols, packed alike */
} packed;

static int skin_rows(const romrt_model *m)
{
    return m->w && m->skin > 0 && m->r == 12 * m->skin;
}

/* Row l: per_point, collision point k's basis row on axis a (l = 3 k + a); else sum_k w_k of
 * them on axis a (l = a). Into P packed, from a skinning basis's weights. */
static void pack_skin(const romrt_model *m, const int32_t id[4], const romrt_real w[4], int per_point, packed *K,
                      romrt_real *P)
{
    int S[ROMRT_MAX_R / 12 + 1], ns = 0, skin = m->skin, j, k, a, s, i, b; /* (+1: no zero-size array when ROMRT_MAX_R < 12) */
    for (j = 0; j < skin; j++) {
        for (k = 0; k < 4; k++)
            if (id[k] >= 0 && w[k] != 0 && m->w[(size_t)m->cv[id[k]] * (size_t)skin + (size_t)j] != 0) break;
        if (k < 4) S[ns++] = j;
    }
    K->c = 12 * ns, K->cp = RT_PAD(K->c), K->n = 0, K->run = 4; /* (a, j, c) packed, (j, a, c) in H */
    for (a = 0; a < 3; a++)
        for (s = 0; s < ns; s++)
            for (i = 0; i < 4; i++) {
                K->cols[4 * ns * a + 4 * s + i] = 12 * S[s] + 4 * a + i;
                K->ord[12 * s + 4 * a + i] = 4 * ns * a + 4 * s + i;
            }
    for (k = 0; k < 4; k++) {
        if (id[k] < 0 || w[k] == 0 || (!per_point && K->n > 0)) continue;
        for (a = 0; a < 3; a++) {
            romrt_real *Pl = P + (size_t)K->cp * K->n;
            int l = K->n++, base = 4 * ns * a;
            for (i = 0; i < K->c; i++) Pl[i] = 0;
            K->rows[l] = per_point ? 3 * k + a : a;
            K->lo[l] = base, K->hi[l] = base + 4 * ns;
            for (b = per_point ? k : 0; b < (per_point ? k + 1 : 4); b++) {
                const romrt_real *X, *wv;
                if (id[b] < 0 || w[b] == 0) continue;
                X = m->X + 3 * (size_t)m->cv[id[b]];
                wv = m->w + (size_t)m->cv[id[b]] * (size_t)skin;
                for (s = 0; s < ns; s++) {
                    romrt_real ws = w[b] * wv[S[s]], *o = Pl + base + 4 * s;
                    o[0] += ws * X[0], o[1] += ws * X[1], o[2] += ws * X[2], o[3] += ws;
                }
            }
        }
    }
}

/* The same rows of any basis: formed r-wide (rows.c), then packed to the columns where some row
 * is non-zero. */
static void pack_rows(romrt_model *m, const int32_t id[4], const romrt_real w[4], int per_point, packed *K, romrt_real *P)
{
    int r = m->r, rp = RT_PAD(r), n = 0, c = 0, cp, axes = m->skin > 0 && r == 12 * m->skin ? 3 : 1, k, a, i, j, l;
    romrt_real *J = m->pair_J;
    if (per_point) {
        for (k = 0; k < 4; k++)
            for (a = 0; a < 3 && id[k] >= 0; a++) {
                rt_row(m, m->cv[id[k]], a, J + (size_t)rp * (3 * k + a));
                K->rows[n++] = 3 * k + a;
            }
    } else {
        for (a = 0; a < 3; a++) {
            for (j = 0; j < r; j++) J[(size_t)rp * a + j] = 0;
            K->rows[a] = a;
        }
        for (k = 0; k < 4; k++)
            for (a = 0; a < 3 && id[k] >= 0 && w[k] != 0; a++) {
                rt_row_axpy(m, m->cv[id[k]], a, w[k], J + (size_t)rp * a);
                n = 3;
            }
    }
    for (a = 0; a < axes; a++)
        for (j = 0; j < r; j++) {
            if (axes == 3 && j % 12 / 4 != a) continue;
            for (l = 0; l < n && J[(size_t)rp * K->rows[l] + j] == 0; l++) continue;
            if (l < n) K->cols[c++] = j;
        }
    K->n = n, K->c = c, K->cp = cp = RT_PAD(c), K->run = 1;
    for (j = 0; j < c; j++) { /* ord: insertion sort (axis first, cols runs in 3 ascending runs) */
        int o = j;
        for (; o > 0 && K->cols[K->ord[o - 1]] > K->cols[j]; o--) K->ord[o] = K->ord[o - 1];
        K->ord[o] = j;
    }
    for (l = 0; l < n; l++) {
        const romrt_real *Jl = J + (size_t)rp * K->rows[l];
        romrt_real *Pl = P + (size_t)cp * l;
        K->lo[l] = c, K->hi[l] = 0;
        for (i = 0; i < c; i++) {
            Pl[i] = Jl[K->cols[i]];
            if (Pl[i] != 0) {
                if (i < K->lo[l]) K->lo[l] = i;
                K->hi[l] = i + 1;
            }
        }
    }
}

/* g += P^T gx, H += P^T B P over the packed rows (gx, B indexed by K->rows: B 12 x 12). */
static void pull_packed(romrt_model *m, const packed *K, const romrt_real *P, const romrt_real *gx, const romrt_real *B,
                        romrt_real *g, romrt_real *H, int ld)
{
    int n = K->n, c = K->c, cp = K->cp, rp = RT_PAD(m->r), kept[12], nb = 0, i, j, k, l, ii, jj;
    const int *rows = K->rows, *lo = K->lo, *hi = K->hi, *cols = K->cols, *ord = K->ord;
    romrt_real *JB = m->pair_JB, *Hc = m->pair_H + 12 * (size_t)cp;
    if (g && gx)
        for (l = 0; l < n; l++) {
            const romrt_real *Pl = P + (size_t)cp * l;
            romrt_real s = gx[rows[l]];
            if (s != 0)
                for (i = lo[l]; i < hi[l]; i++) g[cols[i]] += s * Pl[i];
        }
    if (!H || !B) return;
    /* JB row nb = sum_k B[l][k] P[k] for the rows l that B keeps (kept[nb] = l) */
    for (l = 0; l < n; l++) {
        romrt_real *out = JB + (size_t)rp * nb;
        int any = 0;
        for (i = 0; i < c; i++) out[i] = 0;
        for (k = 0; k < n; k++) {
            romrt_real b = B[12 * rows[l] + rows[k]];
            const romrt_real *Pk = P + (size_t)cp * k;
            if (b != 0)
                for (i = lo[k], any = 1; i < hi[k]; i++) out[i] += b * Pk[i];
        }
        if (any) kept[nb++] = l;
    }
    /* Hc = P^T JB over its upper triangle in the packed order, then H += Hc on (cols, cols) */
    for (j = 0; j < c; j++)
        for (i = 0; i <= j; i++) Hc[i + (size_t)cp * j] = 0;
    for (l = 0; l < nb; l++) {
        const romrt_real *RT_RESTRICT Pl = P + (size_t)cp * kept[l], *Bl = JB + (size_t)rp * l;
        int i0 = lo[kept[l]], i1 = hi[kept[l]];
        for (j = i0; j < c; j++) {
            romrt_real s = Bl[j], *RT_RESTRICT Hj = Hc + (size_t)cp * j;
            int end = j + 1 < i1 ? j + 1 : i1;
            if (s != 0)
                for (i = i0; i < end; i++) Hj[i] += Pl[i] * s;
        }
    }
    /* H's columns in ascending order (ord), each taken down to its diagonal in ascending rows: the
     * writes run down one column of H at a time (the packed order's own, axis first, sent half
     * of them across H's rows, a cache line each, and the scatter took half the pull) */
    for (j = 0; j < c; j++) /* Hc's lower triangle from its upper: Hc symmetric, read by columns */
        for (i = j + 1; i < c; i++) Hc[i + (size_t)cp * j] = Hc[j + (size_t)cp * i];
    for (jj = 0; jj < c; jj++) {
        int jc = ord[jj];
        romrt_real *RT_RESTRICT Hq = H + (size_t)ld * cols[jc];
        const romrt_real *RT_RESTRICT Hcj = Hc + (size_t)cp * jc;
        for (ii = 0; ii <= jj; ii += K->run) { /* a run of consecutive columns, consecutive packed */
            int ic = ord[ii], p = cols[ic], t, len = jj - ii + 1 < K->run ? jj - ii + 1 : K->run;
            for (t = 0; t < len; t++) Hq[p + t] += Hcj[ic + t];
        }
    }
}

static void pull(romrt_model *m, const int32_t id[4], const romrt_real w[4], int per_point, const romrt_real *gx,
                 const romrt_real *B, romrt_real *g, romrt_real *H, int ld)
{
    packed K;
    if (skin_rows(m)) pack_skin(m, id, w, per_point, &K, m->pair_H);
    else pack_rows(m, id, w, per_point, &K, m->pair_H);
    if (K.n) pull_packed(m, &K, m->pair_H, gx, B, g, H, ld);
}

void rt_obstacles_pull(romrt_model *m, const int32_t id[4], const romrt_real *gx, const romrt_real *B, romrt_real *g,
                       romrt_real *H, int ld)
{
    static const romrt_real ones[4] = {1, 1, 1, 1};
    pull(m, id, ones, 1, gx, B, g, H, ld);
}

void rt_obstacles_pull_slip(romrt_model *m, const int32_t id[4], const romrt_real w[4], const romrt_real gt[3],
                            const romrt_real *B3, romrt_real *g, romrt_real *H, int ld)
{
    romrt_real B[36];
    int a, b;
    for (a = 0; a < 3 && B3; a++) /* B indexed 12 rows[l] + rows[k] with rows 0..2: its first 3 rows */
        for (b = 0; b < 3; b++) B[12 * a + b] = B3[3 * a + b];
    pull(m, id, w, 0, gt, B3 ? B : 0, g, H, ld);
}
