/* The quadratic-manifold decoder (grassmann.h): g(p) = Phi p + 1/2 sum_ij Psi_ij p_i p_j from linear
 * modes and their modal derivatives, its Jacobian, and an encoder that finds the closest point of
 * the manifold in the mass norm (Gauss-Newton from the linear mass projection).
 *
 * The encoder works in r-space (issue 33, as the runtime's, runtime/alrom_decoder.c): with B =
 * [Phi | Psi] (n x R, R = r + pairs), g(p) = B c(p), c(p) = (p, the pairs' p_i p_j halved on the
 * diagonal), and J(p) = B C(p), C's column k = e_k + sum_j p_j e_(r + pair(k, j)); so the mass
 * least squares needs B^T M B (formed once) and B^T M u (one pass a call), and a trial's change of
 * the misfit |u - g|_M^2 is -2 dc . B^T M (u - g) + dc^T B^T M B dc, dc = c(p + d) - c(p). */
#include "grassmann/grassmann.h"

#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define ENCODE_ITERATIONS 20

static void destroy(void *ctx);

struct rk_quadratic {
    int n, r, npairs;
    double *Phi, *Psi;  /* n x r, n x npairs */
    rk_sparse M;        /* a copy */
    double *G, *GC;     /* R x R: B^T M B; R x r: G C(p) */
    double *Mu, *gres, *dc, *Gdc, *A, *rhs, *ptry, *d; /* n, R, R, R, r x r, r, r, r */
};

/* Pair (i, j), i <= j, in row-major order over r. */
static int pair(int r, int i, int j)
{
    if (i > j) {
        int t = i;
        i = j;
        j = t;
    }
    return i * r - i * (i - 1) / 2 + (j - i);
}

void rk_quadratic_pairs(int n, int r, int nrigid, const double *raw, double *Psi)
{
    int k = r - nrigid;
    memset(Psi, 0, sizeof(double) * (size_t)n * ((size_t)r * (r + 1) / 2));
    for (int a = 0, src = 0; a < k; a++)
        for (int b = a; b < k; b++, src++)
            memcpy(Psi + (size_t)pair(r, a + nrigid, b + nrigid) * n, raw + (size_t)src * n, sizeof(double) * (size_t)n);
}

static int decode(void *ctx, const double *p, double *u, rk_error *err)
{
    rk_quadratic *q = ctx;
    int n = q->n, r = q->r;
    cblas_dgemv(CblasColMajor, CblasNoTrans, n, r, 1.0, q->Phi, n, p, 1, 0.0, u, 1);
    for (int i = 0; i < r; i++)
        for (int j = i; j < r; j++) {
            double c = (i == j ? 0.5 : 1.0) * p[i] * p[j];
            if (c != 0) cblas_daxpy(n, c, q->Psi + (size_t)pair(r, i, j) * n, 1, u, 1);
        }
    (void)err;
    return 0;
}

static int jacobian(void *ctx, const double *p, double *U, rk_error *err)
{
    rk_quadratic *q = ctx;
    int n = q->n, r = q->r;
    memcpy(U, q->Phi, sizeof(double) * (size_t)n * r);
    for (int k = 0; k < r; k++) /* d/dp_k: Phi_k + sum_j Psi_kj p_j */
        for (int j = 0; j < r; j++)
            if (p[j] != 0) cblas_daxpy(n, p[j], q->Psi + (size_t)pair(r, k, j) * n, 1, U + (size_t)k * n, 1);
    (void)err;
    return 0;
}

/* dc = c(p + d) - c(p), the pairs as d_i p_j + p_i d_j + d_i d_j (no cancellation for a small d). */
static void code_change(int r, const double *p, const double *d, double *dc)
{
    for (int k = 0; k < r; k++) dc[k] = d[k];
    for (int i = 0, q = r; i < r; i++)
        for (int j = i; j < r; j++, q++) {
            double x = d[i] * p[j] + p[i] * d[j] + d[i] * d[j];
            dc[q] = i == j ? 0.5 * x : x;
        }
}

/* x = (C^T G C + 1e-12 max diag I)^-1 C^T gres at p: the mass least squares of the residual whose
 * B^T M is gres. */
static int code_step(rk_quadratic *q, const double *p, const double *gres, double *x, rk_error *err)
{
    int r = q->r, R = r + q->npairs;
    for (int k = 0; k < r; k++) { /* GC column k = G e_k + sum_j p_j G e_(r + pair(k, j)) */
        double *c = q->GC + (size_t)k * R;
        memcpy(c, q->G + (size_t)k * R, sizeof(double) * (size_t)R);
        for (int j = 0; j < r; j++)
            if (p[j] != 0) cblas_daxpy(R, p[j], q->G + (size_t)(r + pair(r, k, j)) * R, 1, c, 1);
    }
    for (int k = 0; k < r; k++) {
        x[k] = gres[k];
        for (int j = 0; j < r; j++) x[k] += p[j] * gres[r + pair(r, k, j)];
        for (int l = 0; l < r; l++) {
            const double *c = q->GC + (size_t)l * R;
            double s = c[k];
            for (int j = 0; j < r; j++) s += p[j] * c[r + pair(r, k, j)];
            q->A[(size_t)l * r + k] = s;
        }
    }
    double scale = 0;
    for (int i = 0; i < r; i++) scale = fmax(scale, q->A[(size_t)i * r + i]);
    for (int i = 0; i < r; i++) q->A[(size_t)i * r + i] += 1e-12 * scale; /* rigid or repeated columns */
    int rc = LAPACKE_dposv(LAPACK_COL_MAJOR, 'U', r, 1, q->A, r, x, r);
    return rc ? rk_fail(err, "the decoder's Jacobian has rank below %d (mass least squares, LAPACK %d)", r, rc) : 0;
}

/* Gauss-Newton on |g(p) - u|_M^2 from the linear projection (a step from 0, where c = 0 and the
 * residual is u), each step halved until it lowers the misfit (up to 10 times; none that does: a
 * minimum to round-off). Why the backtracking (issue 33): undamped, far from the manifold the
 * iterates oscillated, and the code after the last one was a chaotic function of u: one step of
 * the bar in test_runtime_alrom with the decoder's basis alone multiplied a perturbation by 1.8e5.
 * A descent method ends at a local minimum's code. */
static int encode(void *ctx, const double *u, double *p, rk_error *err)
{
    rk_quadratic *q = ctx;
    int n = q->n, r = q->r, R = r + q->npairs;
    rk_sparse_mul(&q->M, u, q->Mu); /* gres = B^T M u */
    cblas_dgemv(CblasColMajor, CblasTrans, n, r, 1.0, q->Phi, n, q->Mu, 1, 0.0, q->gres, 1);
    cblas_dgemv(CblasColMajor, CblasTrans, n, q->npairs, 1.0, q->Psi, n, q->Mu, 1, 0.0, q->gres + r, 1);
    memset(q->d, 0, sizeof(double) * (size_t)r);
    if (code_step(q, q->d, q->gres, p, err)) return -1; /* the linear projection */
    code_change(r, q->d, p, q->dc);                    /* gres -= G c(p) */
    cblas_dgemv(CblasColMajor, CblasNoTrans, R, R, 1.0, q->G, R, q->dc, 1, 0.0, q->Gdc, 1);
    cblas_daxpy(R, -1.0, q->Gdc, 1, q->gres, 1);
    for (int it = 0; it < ENCODE_ITERATIONS; it++) {
        if (code_step(q, p, q->gres, q->rhs, err)) return -1;
        double t = 1, change = INFINITY;
        for (int h = 0; h < 10; h++, t *= 0.5) {
            for (int k = 0; k < r; k++) {
                q->ptry[k] = p[k] + t * q->rhs[k];
                q->d[k] = q->ptry[k] - p[k];
            }
            code_change(r, p, q->d, q->dc);
            cblas_dgemv(CblasColMajor, CblasNoTrans, R, R, 1.0, q->G, R, q->dc, 1, 0.0, q->Gdc, 1);
            change = 0;
            for (int a = 0; a < R; a++) change += q->dc[a] * (q->Gdc[a] - 2 * q->gres[a]);
            if (change < 0) break;
        }
        if (!(change < 0)) break;
        double step = 0, size = 0;
        for (int k = 0; k < r; k++) {
            step = fmax(step, fabs(q->d[k]));
            p[k] = q->ptry[k];
            size = fmax(size, fabs(p[k]));
        }
        cblas_daxpy(R, -1.0, q->Gdc, 1, q->gres, 1);
        if (step <= 1e-12 * (size > 0 ? size : 1)) break;
    }
    return 0;
}

/* G = B^T M B, B = [Phi | Psi]: its blocks by columns of M B. */
static void gram(rk_quadratic *q)
{
    int n = q->n, r = q->r, P = q->npairs, R = r + P;
    for (int k = 0; k < R; k++) {
        const double *b = k < r ? q->Phi + (size_t)k * n : q->Psi + (size_t)(k - r) * n;
        rk_sparse_mul(&q->M, b, q->Mu);
        cblas_dgemv(CblasColMajor, CblasTrans, n, r, 1.0, q->Phi, n, q->Mu, 1, 0.0, q->G + (size_t)k * R, 1);
        cblas_dgemv(CblasColMajor, CblasTrans, n, P, 1.0, q->Psi, n, q->Mu, 1, 0.0, q->G + (size_t)k * R + r, 1);
    }
}

int rk_quadratic_decoder(int n, int r, const double *Phi, const double *Psi, const rk_sparse *M, rk_decoder *dec,
                         rk_error *err)
{
    memset(dec, 0, sizeof *dec);
    if (r < 1 || n < 3 || M->n != n) return rk_fail(err, "quadratic decoder: %d latent coordinates over %d dofs (mass %d)", r, n, M->n);
    rk_quadratic *q = rk_calloc(1, sizeof *q, err);
    if (!q) return -1;
    q->n = n;
    q->r = r;
    q->npairs = r * (r + 1) / 2;
    size_t nr = (size_t)n * r, R = (size_t)r + (size_t)q->npairs;
    q->Phi = malloc(sizeof(double) * nr);
    q->Psi = malloc(sizeof(double) * (size_t)n * q->npairs);
    q->G = malloc(sizeof(double) * R * R);
    q->GC = malloc(sizeof(double) * R * r);
    q->Mu = malloc(sizeof(double) * (size_t)n);
    q->gres = malloc(sizeof(double) * R);
    q->dc = malloc(sizeof(double) * R);
    q->Gdc = malloc(sizeof(double) * R);
    q->A = malloc(sizeof(double) * (size_t)r * r);
    q->rhs = malloc(sizeof(double) * (size_t)r);
    q->ptry = malloc(sizeof(double) * (size_t)r);
    q->d = malloc(sizeof(double) * (size_t)r);
    q->M = *M;
    q->M.colptr = malloc(sizeof(int) * ((size_t)n + 1));
    q->M.rowind = malloc(sizeof(int) * (size_t)M->nnz);
    q->M.val = malloc(sizeof(double) * (size_t)M->nnz);
    dec->ctx = q;
    dec->destroy = destroy;
    if (!q->Phi || !q->Psi || !q->G || !q->GC || !q->Mu || !q->gres || !q->dc || !q->Gdc || !q->A || !q->rhs ||
        !q->ptry || !q->d || !q->M.colptr || !q->M.rowind || !q->M.val) {
        rk_decoder_free(dec);
        return rk_fail(err, "out of memory for the quadratic decoder (%d x %d)", n, r);
    }
    memcpy(q->Phi, Phi, sizeof(double) * nr);
    memcpy(q->Psi, Psi, sizeof(double) * (size_t)n * q->npairs);
    memcpy(q->M.colptr, M->colptr, sizeof(int) * ((size_t)n + 1));
    memcpy(q->M.rowind, M->rowind, sizeof(int) * (size_t)M->nnz);
    memcpy(q->M.val, M->val, sizeof(double) * (size_t)M->nnz);
    gram(q);
    dec->n = n;
    dec->r = r;
    dec->encode = encode;
    dec->jacobian = jacobian;
    dec->decode = decode;
    return 0;
}

static void destroy(void *ctx)
{
    rk_quadratic *q = ctx;
    if (q) {
        free(q->Phi);
        free(q->Psi);
        free(q->G);
        free(q->GC);
        free(q->Mu);
        free(q->gres);
        free(q->dc);
        free(q->Gdc);
        free(q->A);
        free(q->rhs);
        free(q->ptry);
        free(q->d);
        free(q->M.colptr);
        free(q->M.rowind);
        free(q->M.val);
        free(q);
    }
}

void rk_decoder_free(rk_decoder *dec)
{
    if (dec->destroy) dec->destroy(dec->ctx);
    memset(dec, 0, sizeof *dec);
}
