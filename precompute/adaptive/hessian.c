/* The subspace Hessians (adaptive-subspace paper, Sec. 3.9): the unmasked H_a = U_a^T H U_a the
 * oracle's direction uses (Eq. 18) and the masked H_q = B_a^T H B_a of the system (Eq. 19).
 * Inertia, damping and contact are exact; elasticity is one BFGS matrix per subdomain (Eq. 20),
 * restarted at the exact subspace Hessian at each solve's start and whenever the active columns
 * change, and integrated exactly in subdomains that hold an enriched vertex (where a BFGS matrix
 * would no longer agree with the coupling block C, and could break H's definiteness).
 * Each subdomain's exact Hessian is its elements' (PSD-projected) Hessians assembled into a small
 * dense matrix over its own vertices, then sandwiched with two dense products. */
#include "adaptive/adaptive_impl.h"

#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* C's columns per product: fixed blocks (not one per thread), so that each block is the same
 * OpenBLAS call, with the same sums, on any thread count. */
#define RK_ATB_COLUMNS 16

typedef struct {
    int n, a, b;
    const double *A, *B;
    double *C;
} atb_job;

static void atb_blocks(void *ctx, long begin, long end)
{
    atb_job *j = ctx;
    for (long k = begin; k < end; k++) {
        int c0 = (int)k * RK_ATB_COLUMNS, w = j->b - c0 < RK_ATB_COLUMNS ? j->b - c0 : RK_ATB_COLUMNS;
        cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, j->a, w, j->n, 1.0, j->A, j->n,
                    j->B + (size_t)c0 * j->n, j->n, 0.0, j->C + (size_t)c0 * j->a, j->a);
    }
}

void rk_dense_atb(int n, int a, int b, const double *A, const double *B, double *C)
{
    if (a == 0 || b == 0) return;
    atb_job j = {n, a, b, A, B, C};
    rk_parallel_for((b + RK_ATB_COLUMNS - 1) / RK_ATB_COLUMNS, 1, atb_blocks, &j);
}

/* ---- element Hessians ---- */

typedef struct {
    rk_adaptive_impl *im;
    const double *x;
    int all;
} hess_job;

static void hessian_range(void *ctx, long begin, long end)
{
    hess_job *j = ctx;
    const rk_fem *f = j->im->f;
    for (long t = begin; t < end; t++) {
        if (!j->all && !j->im->elem_exact[t]) continue;
        double xe[12], He[144], *out = j->im->He + (size_t)t * RK_TET_SLOTS;
        rk_fem_gather(f, (int)t, j->x, xe);
        rk_tet_hessian(f->model[t], f->mu[t], f->lambda[t], xe, &f->Dm_inv[9 * t], f->vol[t], He, 1);
        for (int p = 0; p < 12; p++)
            for (int q = p; q < 12; q++) *out++ = He[12 * p + q];
    }
}

int rk_adaptive_element_hessians(rk_adaptive *ad, const double *x, int all, rk_error *err)
{
    hess_job j = {ad->impl, x, all};
    rk_parallel_for(ad->impl->f->nt, 256, hessian_range, &j);
    return 0;
}

/* ---- one subdomain's exact subspace Hessians ---- */

/* Rows of the n x a matrix A at the subdomain's vertices: the 3 nv_l x a local block. */
static void gather_rows(const rk_adaptive_impl *im, const rk_subdomain *s, const double *A, double *out)
{
    int m = 3 * s->nv;
    for (int j = 0; j < im->a; j++)
        for (int i = 0; i < s->nv; i++)
            for (int k = 0; k < 3; k++) out[(size_t)j * m + 3 * i + k] = A[(size_t)j * im->n + 3 * s->vert[i] + k];
}

/* K: the subdomain's elastic Hessian, dense 3 nv_l square, from the element Hessians in im->He. */
static void local_stiffness(const rk_adaptive_impl *im, const rk_subdomain *s, double *K)
{
    int m = 3 * s->nv;
    memset(K, 0, sizeof(double) * (size_t)m * (size_t)m);
    for (int e = 0; e < s->ne; e++) {
        const double *h = im->He + (size_t)s->elem[e] * RK_TET_SLOTS;
        const int *lv = &s->local[4 * e];
        for (int p = 0; p < 12; p++)
            for (int q = p; q < 12; q++) {
                int r = 3 * lv[p / 3] + p % 3, c = 3 * lv[q / 3] + q % 3;
                double v = *h++;
                K[(size_t)c * m + r] += v;
                if (r != c || p != q) K[(size_t)r * m + c] += v;
            }
    }
}

typedef struct {
    rk_adaptive *ad;
    int restart;  /* all subdomains, unmasked into B (a BFGS restart); else exact ones, both */
} sub_job;

static void subdomain_range(void *ctx, long begin, long end)
{
    sub_job *j = ctx;
    rk_adaptive_impl *im = j->ad->impl;
    int a = im->a;
    for (long l = begin; l < end; l++) {
        rk_subdomain *s = &im->sub[l];
        if (!j->restart && !s->exact) continue;
        int m = 3 * s->nv;
        double *K = malloc(sizeof(double) * ((size_t)m * m + 2 * (size_t)m * a + 1));
        if (!K) { /* leave it as it was; the BFGS matrix stays what it is */
            continue;
        }
        double *Ul = K + (size_t)m * m, *Y = Ul + (size_t)m * a;
        local_stiffness(im, s, K);
        gather_rows(im, s, im->Ua, Ul);
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, m, a, m, 1.0, K, m, Ul, m, 0.0, Y, m);
        rk_dense_atb(m, a, a, Ul, Y, j->restart ? s->B : s->Bu);
        if (!j->restart) { /* the masked one: enriched rows out */
            gather_rows(im, s, im->Ba, Ul);
            size_t nz = 0, ma = (size_t)m * a;
            while (nz < ma && Ul[nz] == 0) nz++;
            if (nz == ma) { /* every row enriched or prescribed: B_a^T K B_a is zero, skip its products */
                memset(s->B, 0, sizeof(double) * (size_t)a * a);
            } else {
                cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, m, a, m, 1.0, K, m, Ul, m, 0.0, Y, m);
                rk_dense_atb(m, a, a, Ul, Y, s->B);
            }
        }
        free(K);
    }
}

static void run_subdomains(rk_adaptive *ad, int restart)
{
    int before = rk_threads_blas(1); /* one subdomain per thread, each with small products */
    sub_job j = {ad, restart};
    rk_parallel_for(ad->impl->L, 1, subdomain_range, &j);
    rk_threads_blas(before);
}

int rk_adaptive_bfgs_restart(rk_adaptive *ad, const double *x, rk_error *err)
{
    rk_adaptive_impl *im = ad->impl;
    if (rk_adaptive_element_hessians(ad, x, 1, err)) return -1;
    run_subdomains(ad, 1);
    for (int l = 0; l < im->L; l++) im->sub[l].have_proj = 0;
    im->have_step = 0;
    return 0;
}

/* ---- BFGS (Eq. 20) ---- */

typedef struct {
    rk_adaptive *ad;
    const double *x;
} bfgs_job;

/* B <- B - (B s)(B s)^T / s^T B s + y y^T / y^T s, skipped unless y^T s is safely positive (the
 * curvature condition that keeps B positive definite; Nocedal and Wright, Sec. 6.1). */
static int bfgs(int a, double *B, const double *s, const double *y, double *Bs)
{
    double ys = 0, sBs = 0, ss = 0, yy = 0;
    for (int i = 0; i < a; i++) {
        double v = 0;
        for (int k = 0; k < a; k++) v += B[(size_t)k * a + i] * s[k];
        Bs[i] = v;
        sBs += s[i] * v;
        ys += y[i] * s[i];
        ss += s[i] * s[i];
        yy += y[i] * y[i];
    }
    if (!(ys > 1e-12 * sqrt(ss * yy)) || !(sBs > 0)) return 0;
    for (int j = 0; j < a; j++)
        for (int i = 0; i < a; i++) B[(size_t)j * a + i] += y[i] * y[j] / ys - Bs[i] * Bs[j] / sBs;
    return 1;
}

static void bfgs_range(void *ctx, long begin, long end)
{
    bfgs_job *j = ctx;
    rk_adaptive_impl *im = j->ad->impl;
    int a = im->a;
    for (long l = begin; l < end; l++) {
        rk_subdomain *s = &im->sub[l];
        if (s->exact) continue;
        int m = 3 * s->nv;
        double *g = calloc((size_t)m + 3 * (size_t)a + 1, sizeof(double));
        if (!g) continue;
        double *proj = g + m, *y = proj + a, *Bs = y + a;
        for (int e = 0; e < s->ne; e++) { /* the subdomain's own elastic energy's gradient */
            const double *ge = &im->elem_g[12 * (size_t)s->elem[e]];
            for (int k = 0; k < 12; k++) g[3 * s->local[4 * e + k / 3] + k % 3] += ge[k];
        }
        for (int c = 0; c < a; c++) {
            double v = 0;
            for (int i = 0; i < s->nv; i++)
                for (int k = 0; k < 3; k++) v += im->Ua[(size_t)c * im->n + 3 * s->vert[i] + k] * g[3 * i + k];
            proj[c] = v;
        }
        if (s->have_proj && im->have_step) {
            for (int c = 0; c < a; c++) y[c] = proj[c] - s->proj[c];
            int done = bfgs(a, s->B, im->dq_last, y, Bs);
            s->have_proj = done ? 1 : 2; /* 2: skipped, still has a projection */
        } else {
            s->have_proj = 1;
        }
        memcpy(s->proj, proj, sizeof(double) * (size_t)a);
        free(g);
    }
}

void rk_adaptive_bfgs_update(rk_adaptive *ad, const double *x)
{
    rk_adaptive_impl *im = ad->impl;
    bfgs_job j = {ad, x};
    int had_step = im->have_step;
    rk_parallel_for(im->L, 1, bfgs_range, &j);
    for (int l = 0; l < im->L && had_step; l++) {
        rk_subdomain *s = &im->sub[l];
        if (s->exact) continue;
        if (s->have_proj == 2) ad->stats.bfgs_skipped++;
        else ad->stats.bfgs_updates++;
        s->have_proj = 1;
    }
    im->have_step = 0;
}

/* ---- inertia, damping and contact, exactly ---- */

/* SA = S A and AtSA = A^T S A for the full-pattern matrix S (values val) and U_a (n x a): the
 * columns of S A on the threads (each its own), then the product (rk_dense_atb, fixed blocks). */
typedef struct {
    const rk_adaptive_impl *im;
    const double *val;
    double *SA;
} sandwich_job;

static void sandwich_columns(void *ctx, long begin, long end)
{
    sandwich_job *j = ctx;
    size_t n = (size_t)j->im->n;
    for (long c = begin; c < end; c++) rk_full_mul(&j->im->P, j->val, j->im->Ua + c * n, j->SA + c * n);
}

static void sandwich(rk_adaptive_impl *im, const double *val, double *SA, double *AtSA)
{
    sandwich_job j = {im, val, SA};
    rk_parallel_for(im->a, 1, sandwich_columns, &j);
    rk_dense_atb(im->n, im->a, im->a, im->Ua, SA, AtSA);
}

/* B^T S B from U^T S U and S U, B = U - E with E the enriched rows of U: only those rows enter,
 *   B^T S B = U^T S U - E^T S U - U^T S E + E^T S E,
 * so a change of the enriched set costs its rows, not the whole mesh. On the threads: the enriched
 * rows of U, of S U and of S E (t below) gathered row-major (rows independent), then each column
 * of the a x a result summed over those rows in row order, whatever the thread count. */
typedef struct {
    const rk_adaptive_impl *im;
    const double *val, *SU;
    long first;              /* the block's first enriched row */
    int rows;                /* rows in this block */
    double *X, *Y, *T, *out; /* rows x a each, row-major: U's, S U's and S E's enriched rows */
} masked_job;

/* Enriched rows per block: bounds the gathered copies (3 x 4096 x a doubles). */
#define RK_MASKED_ROWS 4096

static void masked_rows(void *ctx, long begin, long end)
{
    masked_job *j = ctx;
    const rk_adaptive_impl *im = j->im;
    int n = im->n, a = im->a;
    for (long k = begin; k < end; k++) {
        int r = im->xdof[j->first + k];
        double *X = j->X + (size_t)k * a, *Y = j->Y + (size_t)k * a, *t = j->T + (size_t)k * a;
        for (int i = 0; i < a; i++) {
            X[i] = im->Ua[(size_t)i * n + r];
            Y[i] = j->SU[(size_t)i * n + r];
        }
        /* E^T S E's row r: sum over enriched columns c of S[r, c] U[c, :] */
        memset(t, 0, sizeof(double) * (size_t)a);
        for (int e = im->P.rowptr[r]; e < im->P.rowptr[r + 1]; e++) {
            int c = im->P.col[e];
            if (im->xindex[c] < 0 || j->val[e] == 0) continue;
            for (int i = 0; i < a; i++) t[i] += j->val[e] * im->Ua[(size_t)i * n + c];
        }
    }
}

static void masked_columns(void *ctx, long begin, long end)
{
    masked_job *j = ctx;
    int a = j->im->a;
    for (long c = begin; c < end; c++) {
        double *o = j->out + (size_t)c * a;
        for (int k = 0; k < j->rows; k++) {
            const double *X = j->X + (size_t)k * a, *Y = j->Y + (size_t)k * a;
            double xc = X[c], yc = Y[c], tc = j->T[(size_t)k * a + c];
            for (int i = 0; i < a; i++) o[i] += -X[i] * yc - Y[i] * xc + X[i] * tc;
        }
    }
}

static int masked(rk_adaptive_impl *im, const double *val, const double *SU, const double *UtSU, double *out,
                  rk_error *err)
{
    int a = im->a, nx = im->nx;
    memcpy(out, UtSU, sizeof(double) * (size_t)a * a);
    if (nx == 0 || a == 0) return 0;
    int block = nx < RK_MASKED_ROWS ? nx : RK_MASKED_ROWS;
    double *X = rk_calloc(3 * (size_t)block * a, sizeof(double), err);
    if (!X) return -1;
    masked_job j = {im, val, SU, 0, 0, X, X + (size_t)block * a, X + 2 * (size_t)block * a, out};
    for (j.first = 0; j.first < nx; j.first += block) { /* blocks in row order: each entry's sum too */
        j.rows = (int)(nx - j.first < block ? nx - j.first : block);
        rk_parallel_for(j.rows, 256, masked_rows, &j);
        rk_parallel_for(a, 1, masked_columns, &j);
    }
    free(X);
    return 0;
}

static int inertia(rk_adaptive *ad, rk_error *err)
{
    rk_adaptive_impl *im = ad->impl;
    size_t aa = (size_t)im->a * im->a;
    if (!im->columns_valid) {
        sandwich(im, im->Mf, im->MU, im->UMU);
        if (im->Cf) sandwich(im, im->Cf, im->CU, im->UCU);
        else memset(im->UCU, 0, sizeof(double) * aa);
        im->columns_valid = 1;
        im->inertia_valid = 0;
    }
    if (im->inertia_valid) return 0;
    if (masked(im, im->Mf, im->MU, im->UMU, im->BMB, err)) return -1;
    if (im->Cf) {
        if (masked(im, im->Cf, im->CU, im->UCU, im->BCB, err)) return -1;
    } else {
        memset(im->BCB, 0, sizeof(double) * aa);
    }
    im->inertia_valid = 1;
    return 0;
}

int rk_adaptive_subspace_hessian(rk_adaptive *ad, const rk_fom_terms *T, const double *x, rk_error *err)
{
    rk_adaptive_impl *im = ad->impl;
    int a = im->a;
    size_t aa = (size_t)a * a;
    if (inertia(ad, err) || rk_adaptive_element_hessians(ad, x, 0, err)) return -1;
    run_subdomains(ad, 0);
    rk_fom_view_get(&ad->fom, &im->view);
    double wi = T->w_inertia, wd = T->w_damping;
    for (size_t k = 0; k < aa; k++) {
        im->Ha[k] = wi * im->UMU[k] + wd * im->UCU[k];
        im->Hq[k] = wi * im->BMB[k] + wd * im->BCB[k];
    }
    for (int l = 0; l < im->L; l++) { /* in subdomain order: the same sums on any thread count */
        rk_subdomain *s = &im->sub[l];
        const double *u = s->exact ? s->Bu : s->B;
        for (size_t k = 0; k < aa; k++) {
            im->Ha[k] += u[k];
            im->Hq[k] += s->B[k];
        }
    }
    rk_fom_contact_sandwich(&im->view, im->n, a, im->Ua, im->work, im->Ha);
    rk_fom_contact_sandwich(&im->view, im->n, a, im->Ba, im->work, im->Hq);
    return 0;
}
