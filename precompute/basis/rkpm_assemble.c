/* The RKPM weight-space Hessian H_w (freeform paper Prop. 1 / Eq. 17) and mass M (Eq. 14):
 *   H_w[k][l] = sum_i v_i coef_i grad phi_k(X_i) . grad phi_l(X_i),  M[k][l] = sum_i v_i phi_k(X_i) phi_l(X_i).
 * Two passes over the integration points in spatial chunks (rkpm_chunks.c):
 *   1. pattern: per chunk, a bit mask per covering kernel of the kernels it shares a point with;
 *      each kernel's column is the sorted union of its rows over the chunks (plus the diagonal);
 *   2. values: per chunk, the dense blocks G^T G and F^T F (BLAS dsyrk), where G holds
 *      sqrt(v_i coef_i) grad phi_k(X_i) (3 rows a point) and F holds sqrt(v_i) phi_k(X_i), both
 *      over the chunk's kernels; the blocks are then added into the sparse upper triangles.
 * An entry of a block that no point of the chunk co-supports is an exact zero (every product in
 * it has a zero factor), so skipping block entries outside the pattern loses nothing. */
#include "basis/rkpm_chunks_impl.h"

#include <cblas.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    int *rows;
    int len, cap;
} column;

/* col = col U add (both sorted, unique); scratch holds K ints. */
static int merge_into(column *col, const int *add, int m, int *scratch, rk_error *err)
{
    int i = 0, j = 0, o = 0;
    while (i < col->len || j < m) {
        if (j >= m || (i < col->len && col->rows[i] < add[j])) scratch[o++] = col->rows[i++];
        else if (i >= col->len || add[j] < col->rows[i]) scratch[o++] = add[j++];
        else scratch[o++] = col->rows[i++], j++;
    }
    if (o == col->len) return 0; /* nothing new */
    if (o > col->cap) {
        int cap = o > 2 * col->cap ? o : 2 * col->cap;
        int *grown = realloc(col->rows, (size_t)cap * sizeof(int));
        if (!grown) return rk_fail(err, "RKPM assembly: out of memory");
        col->rows = grown;
        col->cap = cap;
    }
    memcpy(col->rows, scratch, (size_t)o * sizeof(int));
    col->len = o;
    return 0;
}

/* Grows *buf to hold count elements of size bytes. */
static int reserve(void **buf, size_t *have, size_t count, size_t size, rk_error *err)
{
    if (count <= *have) return 0;
    void *grown = realloc(*buf, count * size);
    if (!grown) return rk_fail(err, "RKPM assembly: out of memory (%zu x %zu bytes)", count, size);
    *buf = grown;
    *have = count;
    return 0;
}

static void free_columns(column *cols, int K)
{
    for (int c = 0; cols && c < K; c++) free(cols[c].rows);
    free(cols);
}

/* Pass 1: the pattern (colptr, rowind) and the largest chunk sizes. */
static int pattern(rkpm_chunks *ch, rk_sparse *P, int *max_np, int *max_u, rk_error *err)
{
    const int K = ch->k->K;
    column *cols = rk_calloc((size_t)K, sizeof *cols, err);
    int *scratch = rk_calloc((size_t)K, sizeof(int), err), *emit = rk_calloc((size_t)K, sizeof(int), err);
    unsigned char *covered = rk_calloc((size_t)K, 1, err);
    uint64_t *rmask = NULL, *pmask = NULL;
    size_t have_r = 0, have_p = 0;
    int rc = -1, more;
    if (!cols || !scratch || !emit || !covered) goto done;
    for (int c = 0; c < K; c++) {
        cols[c].rows = malloc(8 * sizeof(int));
        if (!cols[c].rows) {
            rk_fail(err, "RKPM assembly: out of memory");
            goto done;
        }
        cols[c].rows[0] = c;
        cols[c].len = 1;
        cols[c].cap = 8;
    }
    *max_np = *max_u = 0;
    while ((more = rkpm_chunks_next(ch, err)) == 1) {
        int u = ch->u, W = (u + 63) / 64;
        if (ch->np > *max_np) *max_np = ch->np;
        if (u > *max_u) *max_u = u;
        if (reserve((void **)&rmask, &have_r, (size_t)u * W, sizeof *rmask, err) ||
            reserve((void **)&pmask, &have_p, (size_t)W, sizeof *pmask, err))
            goto done;
        memset(rmask, 0, (size_t)u * W * sizeof *rmask);
        for (int t = 0; t < ch->np; t++) {
            const int *cv = &ch->cover[ch->cover_start[t]];
            int cnt = ch->cover_start[t + 1] - ch->cover_start[t];
            memset(pmask, 0, (size_t)W * sizeof *pmask);
            for (int q = 0; q < cnt; q++) pmask[cv[q] >> 6] |= (uint64_t)1 << (cv[q] & 63);
            for (int q = 0; q < cnt; q++) {
                uint64_t *row = &rmask[(size_t)cv[q] * W];
                for (int w = 0; w < W; w++) row[w] |= pmask[w];
            }
        }
        for (int a = 0; a < u; a++) {
            const uint64_t *row = &rmask[(size_t)a * W];
            int m = 0;
            for (int w = 0; w <= a >> 6; w++)
                for (uint64_t bits = row[w]; bits; bits &= bits - 1) {
                    int b = (w << 6) + __builtin_ctzll(bits);
                    if (b <= a) emit[m++] = ch->U[b];
                }
            covered[ch->U[a]] = 1;
            if (merge_into(&cols[ch->U[a]], emit, m, scratch, err)) goto done;
        }
    }
    if (more < 0) goto done;
    for (int c = 0; c < K; c++)
        if (!covered[c]) {
            const double *p = &ch->k->centers[3 * c];
            rk_fail(err, "RKPM kernel %d at (%g, %g, %g) covers no integration point (its mass row would be zero)", c, p[0],
                    p[1], p[2]);
            goto done;
        }
    long long nnz = 0;
    for (int c = 0; c < K; c++) nnz += cols[c].len;
    if (nnz > INT32_MAX) {
        rk_fail(err, "RKPM assembly: %lld non-zeros is too many", nnz);
        goto done;
    }
    P->n = K;
    P->nnz = (int)nnz;
    P->colptr = rk_calloc((size_t)K + 1, sizeof(int), err);
    P->rowind = rk_calloc((size_t)nnz, sizeof(int), err);
    if (!P->colptr || !P->rowind) goto done;
    for (int c = 0; c < K; c++) {
        P->colptr[c + 1] = P->colptr[c] + cols[c].len;
        memcpy(&P->rowind[P->colptr[c]], cols[c].rows, (size_t)cols[c].len * sizeof(int));
    }
    rc = 0;
done:
    free_columns(cols, K);
    free(scratch);
    free(emit);
    free(covered);
    free(rmask);
    free(pmask);
    return rc;
}

/* Pass 2: the values. */
static int values(rkpm_chunks *ch, const double *v, const double *coef, int max_np, int max_u, rk_sparse *H,
                  rk_sparse *M, int *regularized, rk_error *err)
{
    const rk_rkpm *k = ch->k;
    const int K = k->K, cap = k->max_support;
    size_t gsize = (size_t)3 * max_np * max_u, fsize = (size_t)max_np * max_u, bsize = (size_t)max_u * max_u;
    double *G = rk_calloc(gsize, sizeof(double), err), *F = rk_calloc(fsize, sizeof(double), err);
    double *Hb = rk_calloc(bsize, sizeof(double), err), *Mb = rk_calloc(bsize, sizeof(double), err);
    double *phi = rk_calloc((size_t)cap, sizeof(double), err), *grad = rk_calloc(3 * (size_t)cap, sizeof(double), err);
    int *kid = rk_calloc((size_t)cap, sizeof(int), err), *pos = rk_calloc((size_t)K, sizeof(int), err);
    int rc = -1, more;
    if (!G || !F || !Hb || !Mb || !phi || !grad || !kid || !pos) goto done;
    for (int c = 0; c < K; c++) pos[c] = -1;
    while ((more = rkpm_chunks_next(ch, err)) == 1) {
        const int np = ch->np, u = ch->u, ldg = 3 * np;
        memset(G, 0, (size_t)ldg * u * sizeof *G);
        memset(F, 0, (size_t)np * u * sizeof *F);
        for (int t = 0; t < np; t++) {
            int i = ch->pts[t];
            if (!isfinite(v[i]) || v[i] < 0 || !isfinite(coef[i]) || coef[i] < 0) {
                rk_fail(err, "RKPM assembly: integration point %d has weight %g and coefficient %g (both must be finite and >= 0)",
                        i, v[i], coef[i]);
                goto done;
            }
            const int *cv = &ch->cover[ch->cover_start[t]];
            int cnt = ch->cover_start[t + 1] - ch->cover_start[t];
            for (int q = 0; q < cnt; q++) kid[q] = ch->U[cv[q]];
            int damped = 0;
            if (rkpm_shape_at(k, &ch->X[3 * i], i, cnt, kid, phi, grad, regularized ? &damped : NULL, err)) goto done;
            if (regularized) *regularized += damped;
            double sg = sqrt(v[i] * coef[i]), sm = sqrt(v[i]);
            for (int q = 0; q < cnt; q++) {
                double *g = &G[3 * t + (size_t)ldg * cv[q]];
                g[0] = sg * grad[3 * q];
                g[1] = sg * grad[3 * q + 1];
                g[2] = sg * grad[3 * q + 2];
                F[t + (size_t)np * cv[q]] = sm * phi[q];
            }
        }
        cblas_dsyrk(CblasColMajor, CblasUpper, CblasTrans, u, ldg, 1.0, G, ldg, 0.0, Hb, u);
        cblas_dsyrk(CblasColMajor, CblasUpper, CblasTrans, u, np, 1.0, F, np, 0.0, Mb, u);
        for (int a = 0; a < u; a++) {
            int col = ch->U[a];
            for (int s = H->colptr[col]; s < H->colptr[col + 1]; s++) pos[H->rowind[s]] = s;
            const double *hb = &Hb[(size_t)u * a], *mb = &Mb[(size_t)u * a];
            for (int b = 0; b <= a; b++) {
                int s = pos[ch->U[b]];
                if (s < 0) continue; /* never co-supported: the block entry is an exact zero */
                H->val[s] += hb[b];
                M->val[s] += mb[b];
            }
            for (int s = H->colptr[col]; s < H->colptr[col + 1]; s++) pos[H->rowind[s]] = -1;
        }
    }
    if (more < 0) goto done;
    rc = 0;
done:
    free(G);
    free(F);
    free(Hb);
    free(Mb);
    free(phi);
    free(grad);
    free(kid);
    free(pos);
    return rc;
}

int rk_rkpm_assemble(const rk_rkpm *k, const double *X, const double *v, const double *coef, int n,
                     rk_sparse *H, rk_sparse *M, int *regularized, rk_error *err)
{
    if (regularized) *regularized = 0;
    memset(H, 0, sizeof *H);
    memset(M, 0, sizeof *M);
    if (n < 1) return rk_fail(err, "RKPM assembly: no integration points");
    int bad = rkpm_first_nonfinite(X, n);
    if (bad >= 0)
        return rk_fail(err, "RKPM assembly: integration point %d is not finite (%g, %g, %g)", bad, X[3 * bad],
                       X[3 * bad + 1], X[3 * bad + 2]);
    rkpm_chunks ch;
    int max_np = 0, max_u = 0;
    if (rkpm_chunks_init(&ch, k, X, n, err)) return -1;
    if (pattern(&ch, H, &max_np, &max_u, err)) goto fail;
    M->n = H->n;
    M->nnz = H->nnz;
    M->colptr = rk_calloc((size_t)H->n + 1, sizeof(int), err);
    M->rowind = rk_calloc((size_t)H->nnz, sizeof(int), err);
    H->val = rk_calloc((size_t)H->nnz, sizeof(double), err);
    M->val = rk_calloc((size_t)H->nnz, sizeof(double), err);
    if (!M->colptr || !M->rowind || !H->val || !M->val) goto fail;
    memcpy(M->colptr, H->colptr, ((size_t)H->n + 1) * sizeof(int));
    memcpy(M->rowind, H->rowind, (size_t)H->nnz * sizeof(int));
    if (values(&ch, v, coef, max_np, max_u, H, M, regularized, err)) goto fail;
    rkpm_chunks_free(&ch);
    return 0;
fail:
    rkpm_chunks_free(&ch);
    rk_sparse_free(H);
    rk_sparse_free(M);
    return -1;
}
