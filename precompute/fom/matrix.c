/* The Newton matrix with contact (fom_impl.h): the elements' fixed pattern plus the vertex pairs
 * the contact stencils couple. The pattern is rebuilt (and CHOLMOD's symbolic analysis redone)
 * only when that set of pairs changes; without contact it is the elements' pattern exactly. */
#include "fom/fom_impl.h"

#include <stdlib.h>
#include <string.h>

#include "util/util.h"

static int cmp_pair(const void *a, const void *b)
{
    const int *x = a, *y = b;
    return x[0] != y[0] ? (x[0] > y[0]) - (x[0] < y[0]) : (x[1] > y[1]) - (x[1] < y[1]);
}

/* Index of row r in column c of S, or -1. */
static int find(const rk_sparse *S, int r, int c)
{
    int lo = S->colptr[c], hi = S->colptr[c + 1];
    while (lo < hi) {
        int m = (lo + hi) / 2;
        if (S->rowind[m] < r) lo = m + 1;
        else hi = m;
    }
    return lo < S->colptr[c + 1] && S->rowind[lo] == r ? lo : -1;
}

void rk_newton_matrix_free(rk_newton_matrix *N)
{
    rk_sparse_free(&N->A);
    free(N->base_map);
    free(N->pairs);
    free(N->blocks);
    memset(N, 0, sizeof *N);
}

/* Whether the base pattern (or, beyond it, the obstacle vertices' diagonal blocks) holds the
 * upper 3 x 3 block of vertices u <= w. */
static int in_base(const rk_newton_matrix *N, const rk_sparse *base, int u, int w)
{
    if (w >= N->nmesh) return u == w;
    return find(base, 3 * u, 3 * w) >= 0;
}

/* A's pattern from the base pattern, the obstacle vertices' diagonal blocks and N->pairs (vertex
 * pairs a < b: their 3 x 3 upper block in columns 3b..3b+2, rows 3a..3a+2). */
static int build_pattern(rk_newton_matrix *N, const rk_sparse *base, rk_error *err)
{
    int nb = base->n, n = nb + 3 * N->nobs;
    int *count = rk_calloc((size_t)n + 1, sizeof(int), err);
    if (!count) return -1;
    /* extra entries per column: 3 per pair for each of the pair's three columns */
    for (int p = 0; p < N->npairs; p++)
        for (int j = 0; j < 3; j++) count[3 * N->pairs[2 * p + 1] + j] += 3;
    for (int c = nb; c < n; c++) count[c] += c % 3 + 1; /* the obstacle vertices' diagonal blocks */
    rk_sparse A = {0};
    A.n = n;
    A.colptr = rk_calloc((size_t)n + 1, sizeof(int), err);
    int nnz = base->nnz;
    for (int c = 0; c < n; c++) nnz += count[c];
    A.rowind = rk_calloc((size_t)nnz + 1, sizeof(int), err);
    A.val = rk_calloc((size_t)nnz + 1, sizeof(double), err);
    int *map = rk_calloc((size_t)base->nnz + 1, sizeof(int), err);
    int *rows = rk_calloc((size_t)n + 1, sizeof(int), err);
    if (!A.colptr || !A.rowind || !A.val || !map || !rows) {
        free(count), free(map), free(rows);
        rk_sparse_free(&A);
        return -1;
    }
    /* pairs sorted by (a, b): for column c = 3b + j gather the rows 3a + i of its pairs */
    int *by_col_first = rk_calloc((size_t)n / 3 + 2, sizeof(int), err), *order = rk_calloc((size_t)N->npairs + 1, sizeof(int), err);
    if (!by_col_first || !order) {
        free(count), free(map), free(rows), free(by_col_first), free(order);
        rk_sparse_free(&A);
        return -1;
    }
    for (int p = 0; p < N->npairs; p++) by_col_first[N->pairs[2 * p + 1] + 1]++;
    for (int v = 0; v < n / 3; v++) by_col_first[v + 1] += by_col_first[v];
    int *fill = rk_calloc((size_t)n / 3 + 1, sizeof(int), err);
    if (!fill) {
        free(count), free(map), free(rows), free(by_col_first), free(order);
        rk_sparse_free(&A);
        return -1;
    }
    for (int p = 0; p < N->npairs; p++) {
        int b = N->pairs[2 * p + 1];
        order[by_col_first[b] + fill[b]++] = N->pairs[2 * p];
    }
    free(fill);
    int k = 0;
    for (int c = 0; c < n; c++) {
        A.colptr[c] = k;
        /* merge: base rows (sorted) and the extra rows (pairs' a are sorted: pairs sorted by a) */
        int nr = 0, v = c / 3;
        for (int q = by_col_first[v]; q < by_col_first[v + 1]; q++)
            for (int i = 0; i < 3; i++) rows[nr++] = 3 * order[q] + i;
        if (c >= nb)
            for (int i = 3 * v; i <= c; i++) rows[nr++] = i; /* an obstacle vertex's own block */
        int bi = c < nb ? base->colptr[c] : 0, be = c < nb ? base->colptr[c + 1] : 0, ri = 0;
        while (bi < be || ri < nr) {
            if (ri >= nr || (bi < be && base->rowind[bi] < rows[ri])) {
                map[bi] = k;
                A.rowind[k++] = base->rowind[bi++];
            } else {
                A.rowind[k++] = rows[ri++];
            }
        }
    }
    A.colptr[n] = k;
    A.nnz = k;
    free(count), free(rows), free(by_col_first), free(order);
    rk_sparse_free(&N->A);
    free(N->base_map);
    N->A = A;
    N->base_map = map;
    return 0;
}

int rk_newton_matrix_init(rk_newton_matrix *N, const rk_sparse *base, int nobs, rk_error *err)
{
    memset(N, 0, sizeof *N);
    N->nmesh = base->n / 3;
    N->nobs = nobs;
    return build_pattern(N, base, err);
}

int rk_newton_matrix_couple(rk_newton_matrix *N, const rk_sparse *base, int *changed, rk_error *err)
{
    /* the vertex pairs of the recorded blocks that the base pattern lacks */
    int cap = 0, np = 0, *pairs = NULL;
    for (int k = 0; k < N->nblocks; k++) {
        const rk_contact_block *b = &N->blocks[k];
        for (int i = 0; i < b->np; i++)
            for (int j = 0; j < b->np; j++) {
                int u = b->id[i], w = b->id[j];
                if (u < 0 || w < 0 || u >= w || in_base(N, base, u, w)) continue;
                if (np == cap) {
                    cap = cap ? 2 * cap : 64;
                    int *grown = realloc(pairs, sizeof(int) * 2 * (size_t)cap);
                    if (!grown) {
                        free(pairs);
                        return rk_fail(err, "out of memory for the contact couplings");
                    }
                    pairs = grown;
                }
                pairs[2 * np] = u;
                pairs[2 * np + 1] = w;
                np++;
            }
    }
    if (np) qsort(pairs, (size_t)np, 2 * sizeof(int), cmp_pair);
    int u = 0;
    for (int p = 0; p < np; p++)
        if (u == 0 || pairs[2 * p] != pairs[2 * (u - 1)] || pairs[2 * p + 1] != pairs[2 * (u - 1) + 1]) {
            pairs[2 * u] = pairs[2 * p];
            pairs[2 * u + 1] = pairs[2 * p + 1];
            u++;
        }
    *changed = u != N->npairs || (u && memcmp(pairs, N->pairs, sizeof(int) * 2 * (size_t)u) != 0);
    if (!*changed) {
        free(pairs);
        return 0;
    }
    free(N->pairs);
    N->pairs = pairs;
    N->npairs = u;
    return build_pattern(N, base, err);
}

void rk_newton_matrix_fill(rk_newton_matrix *N, const rk_sparse *base)
{
    if (N->npairs == 0 && N->A.nnz == base->nnz) {
        memcpy(N->A.val, base->val, sizeof(double) * (size_t)base->nnz);
    } else {
        memset(N->A.val, 0, sizeof(double) * (size_t)N->A.nnz);
        for (int k = 0; k < base->nnz; k++) N->A.val[N->base_map[k]] = base->val[k];
    }
    for (int k = 0; k < N->nblocks; k++) {
        const rk_contact_block *b = &N->blocks[k];
        int dim = 3 * b->np;
        for (int i = 0; i < b->np; i++)
            for (int j = 0; j < b->np; j++) {
                int u = b->id[i], w = b->id[j];
                if (u < 0 || w < 0 || u > w) continue;
                for (int a = 0; a < 3; a++)
                    for (int c = 0; c < 3; c++) {
                        int r = 3 * u + a, col = 3 * w + c;
                        if (r > col) continue;
                        int at = find(&N->A, r, col);
                        if (at >= 0) N->A.val[at] += b->H[dim * (3 * i + a) + 3 * j + c];
                    }
            }
    }
}

void rk_newton_matrix_record(void *ctx, const int *id, int npoints, const double *H)
{
    rk_newton_matrix *N = ctx;
    if (N->nblocks == N->capblocks) {
        int cap = N->capblocks ? 2 * N->capblocks : 64;
        rk_contact_block *grown = realloc(N->blocks, sizeof *grown * (size_t)cap);
        if (!grown) {
            N->overflow = 1;
            return;
        }
        N->blocks = grown;
        N->capblocks = cap;
    }
    rk_contact_block *b = &N->blocks[N->nblocks++];
    b->np = npoints;
    for (int k = 0; k < npoints; k++) /* obstacle vertex k is matrix vertex nmesh + k when unknown, else
                                        * stays -1 - k (dropped from A; a caller moving the obstacles
                                        * by their progress reads it, rk_fom_view) */
        b->id[k] = id[k] >= 0 || !N->nobs ? id[k] : N->nmesh + (-1 - id[k]);
    memcpy(b->H, H, sizeof(double) * 9 * (size_t)npoints * npoints);
}
