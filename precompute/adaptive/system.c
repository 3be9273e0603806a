/* The Newton-iterate system (adaptive-subspace paper, Eq. 19) and its Schur-complement solve
 * (Sec. 3.10, Eq. 21-22):
 *
 *   [H_q  C  ] [d_q]     [g_q]        H_q = B_a^T H B_a (a x a, dense, factored once)
 *   [C^T  H_x] [d_x] = - [g_x]        H_x = S_x^T H S_x (sparse), C = B_a^T H S_x
 *
 *   (H_x - C^T H_q^-1 C) d_x = C^T H_q^-1 g_q - g_x      by block-Jacobi PCG
 *   d_q = -H_q^-1 (C d_x + g_q)
 *
 * Because B_a is zero on the enriched dofs, C's columns are non-zero only at enriched dofs that
 * share an element (or a contact pair) with a modal one: the interface. Every element touching an
 * enriched vertex lies in an exact subdomain (model.c), so the enriched rows of H are exact. */
#include "adaptive/adaptive_impl.h"

#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The PCG's rows (or C's columns) per scheduled chunk (below, "the PCG's products"): about 1024 x 45
 * multiply-adds, some 50 us, against 10-20 us to wake a sleeping worker; a PCG iteration runs three
 * such loops, so small enriched sets (under 1024 dofs) stay on the calling thread. */
#define RK_SCHUR_CHUNK 1024

static int grow_int(int **p, size_t count, rk_error *err)
{
    int *q = realloc(*p, sizeof(int) * (count ? count : 1));
    if (!q) return rk_fail(err, "out of memory for the enriched system");
    *p = q;
    return 0;
}

static int grow_double(double **p, size_t count, rk_error *err)
{
    double *q = realloc(*p, sizeof(double) * (count ? count : 1));
    if (!q) return rk_fail(err, "out of memory for the enriched system");
    *p = q;
    return 0;
}

typedef struct {
    rk_adaptive_impl *im;
    double wi, wd;
} rows_job;

/* The enriched rows [begin, end) of H in im->Hf: inertia and damping (each row its own). */
static void inertia_rows(void *ctx, long begin, long end)
{
    rows_job *j = ctx;
    rk_adaptive_impl *im = j->im;
    const rk_full_pattern *P = &im->P;
    for (long k = begin; k < end; k++) {
        int r = im->xdof[k];
        for (int e = P->rowptr[r]; e < P->rowptr[r + 1]; e++)
            im->Hf[e] = j->wi * im->Mf[e] + (im->Cf ? j->wd * im->Cf[e] : 0);
    }
}

/* The enriched rows of H in im->Hf: inertia and damping, then every exact element's Hessian (in
 * element order, serial: elements share entries). */
static void enriched_rows(rk_adaptive *ad, const rk_fom_terms *T)
{
    rk_adaptive_impl *im = ad->impl;
    const rk_fem *f = im->f;
    const rk_full_pattern *P = &im->P;
    rows_job j = {im, T->w_inertia, T->w_damping};
    rk_parallel_for(im->nx, 256, inertia_rows, &j);
    for (int t = 0; t < f->nt; t++) {
        const int *v = &f->tets[4 * t];
        if (!(im->enriched[v[0]] || im->enriched[v[1]] || im->enriched[v[2]] || im->enriched[v[3]])) continue;
        const double *h = im->He + (size_t)t * RK_TET_SLOTS;
        const int *slot = &f->slot[(size_t)t * RK_TET_SLOTS];
        int i = 0;
        for (int p = 0; p < 12; p++)
            for (int q = p; q < 12; q++, i++) {
                int s = slot[i], rp = 3 * v[p / 3] + p % 3, rq = 3 * v[q / 3] + q % 3;
                /* upper entry (min, max): up is at row min, lo at row max */
                int rlo = rp < rq ? rp : rq, rhi = rp < rq ? rq : rp;
                if (im->xindex[rlo] >= 0) im->Hf[P->up[s]] += h[i];
                if (rlo != rhi && im->xindex[rhi] >= 0) im->Hf[P->lo[s]] += h[i];
            }
    }
}

/* C[:, j] = sum over modal i of B_a[i, :] H[j, i] for the coupled dofs [begin, end), from the
 * elastic, inertia and damping rows (the contact pairs' part is added after). */
static void coupling_columns(void *ctx, long begin, long end)
{
    rk_adaptive_impl *im = ctx;
    const rk_full_pattern *P = &im->P;
    int a = im->a, n = im->n;
    for (long cj = begin; cj < end; cj++) {
        int r = im->xdof[im->coup_dof[cj]];
        double *col = im->Cq + (size_t)cj * a;
        memset(col, 0, sizeof(double) * (size_t)a);
        for (int e = P->rowptr[r]; e < P->rowptr[r + 1]; e++) {
            int c = P->col[e];
            if (im->xindex[c] >= 0 || im->Hf[e] == 0) continue;
            for (int j = 0; j < a; j++) col[j] += im->Ba[(size_t)j * n + c] * im->Hf[e];
        }
    }
}

/* H_x (CSR over the enriched dofs), C's columns and the block-Jacobi preconditioner. */
static int build_blocks(rk_adaptive *ad, rk_error *err)
{
    rk_adaptive_impl *im = ad->impl;
    const rk_full_pattern *P = &im->P;
    int nx = im->nx, a = im->a, n = im->n;
    size_t cap = 0;
    for (int k = 0; k < nx; k++) cap += (size_t)(P->rowptr[im->xdof[k] + 1] - P->rowptr[im->xdof[k]]);
    if (grow_int(&im->hx_rowptr, (size_t)nx + 1, err) || grow_int(&im->hx_col, cap, err) ||
        grow_double(&im->hx_val, cap, err) || grow_int(&im->coup_dof, (size_t)nx, err))
        return -1;
    char *coupled = im->part_mark_dofs;
    memset(coupled, 0, (size_t)nx);
    int nnz = 0;
    im->hx_rowptr[0] = 0;
    for (int k = 0; k < nx; k++) {
        int r = im->xdof[k];
        for (int e = P->rowptr[r]; e < P->rowptr[r + 1]; e++) {
            int c = P->col[e], xc = im->xindex[c];
            if (xc >= 0) {
                im->hx_col[nnz] = xc;
                im->hx_val[nnz++] = im->Hf[e];
            } else if (!im->view.prescribed[c] && im->Hf[e] != 0) {
                coupled[k] = 1;
            }
        }
        im->hx_rowptr[k + 1] = nnz;
    }
    const rk_contact_block *blocks = im->view.blocks;
    for (int b = 0; b < im->view.nblocks; b++) { /* a pair with enriched and modal points couples them */
        int has_x = 0, has_q = 0;
        for (int p = 0; p < blocks[b].np; p++) {
            int id = blocks[b].id[p];
            if (id < 0) continue;
            if (im->enriched[id]) has_x = 1;
            else has_q = 1;
        }
        if (!has_x || !has_q) continue;
        for (int p = 0; p < blocks[b].np; p++)
            for (int c = 0; c < 3 && blocks[b].id[p] >= 0; c++) {
                int xd = im->xindex[3 * blocks[b].id[p] + c];
                if (xd >= 0) coupled[xd] = 1;
            }
    }
    /* the contact pairs' entries among enriched dofs, listed once for the PCG's products */
    im->nctri = 0;
    for (int b = 0; b < im->view.nblocks; b++) {
        const rk_contact_block *blk = &blocks[b];
        int m = 3 * blk->np;
        for (int p = 0; p < m; p++) {
            int xr = blk->id[p / 3] >= 0 ? im->xindex[3 * blk->id[p / 3] + p % 3] : -1;
            for (int q = 0; q < m && xr >= 0; q++) {
                int xc = blk->id[q / 3] >= 0 ? im->xindex[3 * blk->id[q / 3] + q % 3] : -1;
                if (xc < 0 || blk->H[p * m + q] == 0) continue;
                if (im->nctri == im->capctri) {
                    int grown = im->capctri ? 2 * im->capctri : 1024;
                    int *ri = realloc(im->ctri_r, sizeof(int) * 2 * (size_t)grown);
                    double *rv = realloc(im->ctri_v, sizeof(double) * (size_t)grown);
                    if (ri) im->ctri_r = ri;
                    if (rv) im->ctri_v = rv;
                    if (!ri || !rv) return rk_fail(err, "out of memory for the enriched contact entries");
                    im->capctri = grown;
                }
                im->ctri_r[2 * im->nctri] = xr;
                im->ctri_r[2 * im->nctri + 1] = xc;
                im->ctri_v[im->nctri++] = blk->H[p * m + q];
            }
        }
    }
    im->ncoup = 0;
    for (int k = 0; k < nx; k++)
        if (coupled[k]) {
            im->coup_pos[k] = im->ncoup;
            im->coup_dof[im->ncoup++] = k;
        } else {
            im->coup_pos[k] = -1;
        }
    if (grow_double(&im->Cq, (size_t)a * im->ncoup, err) ||
        grow_double(&im->c_part, (size_t)a * ((im->ncoup + RK_SCHUR_CHUNK - 1) / RK_SCHUR_CHUNK), err))
        return -1;
    rk_parallel_for(im->ncoup, 64, coupling_columns, im); /* each column its own */
    for (int b = 0; b < im->view.nblocks; b++) {
        const rk_contact_block *blk = &blocks[b];
        int m = 3 * blk->np;
        for (int p = 0; p < m; p++) {
            if (blk->id[p / 3] < 0) continue;
            int xr = im->xindex[3 * blk->id[p / 3] + p % 3];
            if (xr < 0 || im->coup_pos[xr] < 0) continue;
            double *col = im->Cq + (size_t)im->coup_pos[xr] * a;
            for (int q = 0; q < m; q++) {
                if (blk->id[q / 3] < 0) continue;
                int c = 3 * blk->id[q / 3] + q % 3;
                if (im->xindex[c] >= 0) continue;
                for (int j = 0; j < a; j++) col[j] += im->Ba[(size_t)j * n + c] * blk->H[p * m + q];
            }
        }
    }
    return 0;
}

/* ---- the PCG's products on the threads (issue 34). Rows are independent, so the row loops split
 * anywhere; C x sums over C's columns, so it is summed in fixed chunks of RK_SCHUR_CHUNK columns
 * and the chunks' partial sums added in chunk order: the same additions whatever the thread count
 * (the chunking does not depend on it), as full order's assembly does (fem/elastic.c). ---- */

typedef struct {
    const rk_adaptive_impl *im;
    const double *x;
    double *y;
} schur_job;

static void hx_rows(void *ctx, long begin, long end)
{
    schur_job *j = ctx;
    const rk_adaptive_impl *im = j->im;
    for (long k = begin; k < end; k++) {
        double s = 0;
        for (int e = im->hx_rowptr[k]; e < im->hx_rowptr[k + 1]; e++) s += im->hx_val[e] * j->x[im->hx_col[e]];
        j->y[k] = s;
    }
}

/* Chunk c's share of C x into y + c a (x: the enriched dofs). */
static void c_chunks(void *ctx, long begin, long end)
{
    schur_job *j = ctx;
    const rk_adaptive_impl *im = j->im;
    int a = im->a;
    for (long c = begin; c < end; c++) {
        double *t = j->y + (size_t)c * a;
        memset(t, 0, sizeof(double) * (size_t)a);
        int last = (int)((c + 1) * RK_SCHUR_CHUNK < im->ncoup ? (c + 1) * RK_SCHUR_CHUNK : im->ncoup);
        for (int cj = (int)c * RK_SCHUR_CHUNK; cj < last; cj++) {
            double v = j->x[im->coup_dof[cj]];
            if (v == 0) continue;
            const double *col = im->Cq + (size_t)cj * a;
            for (int i = 0; i < a; i++) t[i] += col[i] * v;
        }
    }
}

/* C x's partial sums, chunk by chunk, into im->c_part; then added in chunk order into t (a). */
static long c_chunk_count(const rk_adaptive_impl *im)
{
    return (im->ncoup + RK_SCHUR_CHUNK - 1) / RK_SCHUR_CHUNK;
}

static void c_sum(const rk_adaptive_impl *im, double *t)
{
    int a = im->a;
    memset(t, 0, sizeof(double) * (size_t)a);
    for (long c = 0; c < c_chunk_count(im); c++)
        for (int i = 0; i < a; i++) t[i] += im->c_part[(size_t)c * a + i];
}

/* t (a) = C x (x over the enriched dofs). */
static void c_apply(const rk_adaptive_impl *im, const double *x, double *t)
{
    schur_job j = {im, x, im->c_part};
    rk_parallel_for(c_chunk_count(im), 1, c_chunks, &j);
    c_sum(im, t);
}

/* H_x x's rows and C x's chunks in one loop (one hand-out a PCG product, not two): chunk k holds
 * H_x's rows k RK_SCHUR_CHUNK on and C's k-th chunk of columns. */
static void hx_and_c_chunks(void *ctx, long begin, long end)
{
    schur_job *j = ctx;
    const rk_adaptive_impl *im = j->im;
    schur_job c = {im, j->x, im->c_part};
    for (long k = begin; k < end; k++) {
        long r1 = (k + 1) * RK_SCHUR_CHUNK < im->nx ? (k + 1) * RK_SCHUR_CHUNK : im->nx;
        hx_rows(ctx, k * RK_SCHUR_CHUNK, r1);
        if (k < c_chunk_count(im)) c_chunks(&c, k, k + 1);
    }
}

/* y = H_x x (the sparse rows and the contact pairs among enriched points) and t = C x. */
static void hx_and_c_apply(const rk_adaptive_impl *im, const double *x, double *y, double *t)
{
    schur_job j = {im, x, y};
    rk_parallel_for((im->nx + RK_SCHUR_CHUNK - 1) / RK_SCHUR_CHUNK, 1, hx_and_c_chunks, &j);
    for (int k = 0; k < im->nctri; k++) y[im->ctri_r[2 * k]] += im->ctri_v[k] * x[im->ctri_r[2 * k + 1]];
    c_sum(im, t);
}

static void hq_solve(const rk_adaptive_impl *im, double *t)
{
    if (im->a) LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'L', im->a, 1, im->Lq, im->a, t, im->a);
}

/* y[coupled dof j] -= C[:, j] . t, column by column. */
static void ct_columns(void *ctx, long begin, long end)
{
    schur_job *j = ctx;
    const rk_adaptive_impl *im = j->im;
    for (long cj = begin; cj < end; cj++) {
        const double *col = im->Cq + (size_t)cj * im->a;
        double v = 0;
        for (int i = 0; i < im->a; i++) v += col[i] * j->x[i];
        j->y[im->coup_dof[cj]] -= v;
    }
}

static void schur_apply(void *ctx, const double *x, double *y)
{
    rk_adaptive_impl *im = ctx;
    double *t = im->sc_a;
    hx_and_c_apply(im, x, y, t);
    hq_solve(im, t);
    schur_job j = {im, t, y};
    rk_parallel_for(im->ncoup, RK_SCHUR_CHUNK, ct_columns, &j);
}

/* The inverse of each vertex's diagonal block of H_x (1 to 3 free dofs), for the preconditioner. */
static void block_jacobi(rk_adaptive_impl *im)
{
    double col[3];
    for (int k = 0; k < im->nx;) {
        int v = im->xdof[k] / 3, m = 1;
        while (k + m < im->nx && im->xdof[k + m] / 3 == v) m++;
        double B[9] = {0};
        for (int i = 0; i < m; i++) { /* column i of the block: H_x e_i restricted */
            for (int r = 0; r < m; r++) {
                double s = 0;
                int row = k + r;
                for (int e = im->hx_rowptr[row]; e < im->hx_rowptr[row + 1]; e++)
                    if (im->hx_col[e] == k + i) s += im->hx_val[e];
                B[3 * r + i] = s;
            }
        }
        /* invert by Cholesky (the block of a PSD-projected Hessian plus mass is positive definite) */
        double L[9];
        memcpy(L, B, sizeof L);
        int ok = LAPACKE_dpotrf(LAPACK_ROW_MAJOR, 'L', m, L, 3) == 0;
        double *D = &im->Dinv[9 * (size_t)k];
        memset(D, 0, 9 * sizeof(double));
        for (int i = 0; i < m; i++) {
            for (int r = 0; r < m; r++) col[r] = r == i;
            if (ok) LAPACKE_dpotrs(LAPACK_ROW_MAJOR, 'L', m, 1, L, 3, col, 1);
            else
                for (int r = 0; r < m; r++) col[r] = r == i && B[4 * r] > 0 ? 1 / B[4 * r] : (r == i);
            for (int r = 0; r < m; r++) D[3 * r + i] = col[r];
        }
        im->block_size[k] = m;
        for (int i = 1; i < m; i++) im->block_size[k + i] = 0; /* not a block's first dof */
        k += m;
    }
}

/* z = D^-1 r for the blocks that start in [begin, end). */
static void precondition_rows(void *ctx, long begin, long end)
{
    schur_job *j = ctx;
    const rk_adaptive_impl *im = j->im;
    for (long k = begin; k < end; k++) {
        int m = im->block_size[k];
        const double *D = &im->Dinv[9 * (size_t)k];
        for (int i = 0; i < m; i++) {
            double s = 0;
            for (int c = 0; c < m; c++) s += D[3 * i + c] * j->x[k + c];
            j->y[k + i] = s;
        }
    }
}

static void precondition(void *ctx, const double *r, double *z)
{
    rk_adaptive_impl *im = ctx;
    schur_job j = {im, r, z};
    rk_parallel_for(im->nx, RK_SCHUR_CHUNK, precondition_rows, &j);
}

typedef struct {
    int n, a;
    const double *A, *c;
    double *y;
} combine_job;

static void combine_rows(void *ctx, long begin, long end)
{
    combine_job *j = ctx;
    memset(j->y + begin, 0, sizeof(double) * (size_t)(end - begin));
    for (int k = 0; k < j->a; k++) { /* each row's terms in column order, however the rows split */
        const double *col = j->A + (size_t)k * j->n, c = j->c[k];
        for (long i = begin; i < end; i++) j->y[i] += col[i] * c;
    }
}

void rk_adaptive_combine(int n, int a, const double *A, const double *c, double *y)
{
    combine_job j = {n, a, A, c, y};
    rk_parallel_for(n, 4 * RK_SCHUR_CHUNK, combine_rows, &j);
}

int rk_adaptive_solve(rk_adaptive *ad, const rk_fom_terms *T, const double *g, double *d, rk_error *err)
{
    rk_adaptive_impl *im = ad->impl;
    int a = im->a, n = im->n, nx = im->nx;
    double t0 = rk_now();
    rk_dense_atb(n, a, 1, im->Ba, g, im->gq);
    if (rk_spd_solve_shifted(a, im->Hq, im->Lq, im->gq, im->dq, RK_ADAPTIVE_SHIFTS))
        return rk_fail(err, "the subspace Hessian (%d modes) is not positive definite", a);
    double *dx = im->dx;
    if (nx > 0) {
        double t1 = rk_now();
        enriched_rows(ad, T);
        if (build_blocks(ad, err)) return -1;
        block_jacobi(im);
        ad->stats.seconds_system += rk_now() - t1;
        /* rhs = C^T H_q^-1 g_q - g_x: im->dq holds H_q^-1 g_q */
        for (int k = 0; k < nx; k++) im->rhs[k] = -g[im->xdof[k]];
        for (int cj = 0; cj < im->ncoup; cj++) {
            const double *col = im->Cq + (size_t)cj * a;
            double v = 0;
            for (int j = 0; j < a; j++) v += col[j] * im->dq[j];
            im->rhs[im->coup_dof[cj]] += v;
        }
        memset(dx, 0, sizeof(double) * (size_t)nx);
        rk_pcg_problem p = {nx, im, schur_apply, precondition};
        double relres;
        int it = rk_pcg(&p, im->rhs, dx, ad->opt.pcg_tol, ad->opt.pcg_max_iter, im->pcg_work, &relres);
        ad->stats.pcg_iterations += it;
        /* d_q = -H_q^-1 (C d_x + g_q) */
        c_apply(im, dx, im->dq);
        for (int j = 0; j < a; j++) im->dq[j] += im->gq[j];
        hq_solve(im, im->dq);
    }
    for (int j = 0; j < a; j++) im->dq[j] = -im->dq[j];
    ad->stats.solves++;
    /* d = B_a d_q + S_x d_x */
    rk_adaptive_combine(n, a, im->Ba, im->dq, d);
    for (int k = 0; k < nx; k++) d[im->xdof[k]] = dx[k];
    ad->stats.seconds_pcg += rk_now() - t0;
    return 0;
}
