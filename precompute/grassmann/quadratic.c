/* The quadratic-manifold decoder (grassmann.h): g(p) = Phi p + 1/2 sum_ij Psi_ij p_i p_j from linear
 * modes and their modal derivatives, its Jacobian, and an encoder that finds the closest point of
 * the manifold in the mass norm (Gauss-Newton from the linear mass projection). */
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
    double *J, *MJ, *A, *res, *Mres, *rhs, *ptry; /* n x r, n x r, r x r, n, n, r, r */
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

/* One least-squares solve (J^T M J) x = J^T M b for the current J: x into p_out (r). */
static int mass_lsq(rk_quadratic *q, const double *b, double *x, rk_error *err)
{
    int n = q->n, r = q->r;
    for (int k = 0; k < r; k++) rk_sparse_mul(&q->M, q->J + (size_t)k * n, q->MJ + (size_t)k * n);
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, r, r, n, 1.0, q->J, n, q->MJ, n, 0.0, q->A, r);
    cblas_dgemv(CblasColMajor, CblasTrans, n, r, 1.0, q->MJ, n, b, 1, 0.0, x, 1);
    double scale = 0;
    for (int i = 0; i < r; i++) scale = fmax(scale, q->A[(size_t)i * r + i]);
    for (int i = 0; i < r; i++) q->A[(size_t)i * r + i] += 1e-12 * scale; /* rigid or repeated columns */
    int rc = LAPACKE_dposv(LAPACK_COL_MAJOR, 'L', r, 1, q->A, r, x, r);
    return rc ? rk_fail(err, "the decoder's Jacobian has rank below %d (mass least squares, LAPACK %d)", r, rc) : 0;
}

/* |u - g(p)|_M^2, the residual u - g(p) into res */
static double misfit(rk_quadratic *q, const double *u, const double *p, double *res)
{
    decode(q, p, res, NULL);
    for (int i = 0; i < q->n; i++) res[i] = u[i] - res[i];
    return rk_sparse_dot(&q->M, res, res);
}

/* Gauss-Newton on |g(p) - u|_M^2 from the linear projection, each step halved until it lowers the
 * misfit (up to 10 times; none that does: a minimum to round-off). Why the backtracking (issue
 * 33): undamped, far from the manifold the iterates oscillated, and the code after the last one
 * was a chaotic function of u: one step of the bar in test_runtime_alrom with the decoder's basis
 * alone multiplied a perturbation by 1.8e5. A descent method ends at a local minimum's code. */
static int encode(void *ctx, const double *u, double *p, rk_error *err)
{
    rk_quadratic *q = ctx;
    int n = q->n, r = q->r;
    memcpy(q->J, q->Phi, sizeof(double) * (size_t)n * r);
    if (mass_lsq(q, u, p, err)) return -1; /* the linear projection */
    double f = misfit(q, u, p, q->res);
    for (int it = 0; it < ENCODE_ITERATIONS; it++) {
        jacobian(q, p, q->J, err);
        if (mass_lsq(q, q->res, q->rhs, err)) return -1;
        double t = 1, ft = INFINITY;
        for (int h = 0; h < 10; h++, t *= 0.5) {
            for (int k = 0; k < r; k++) q->ptry[k] = p[k] + t * q->rhs[k];
            if ((ft = misfit(q, u, q->ptry, q->Mres)) < f) break;
        }
        if (!(ft < f)) break;
        double step = 0, size = 0, *swap = q->res;
        for (int k = 0; k < r; k++) {
            step = fmax(step, fabs(q->ptry[k] - p[k]));
            p[k] = q->ptry[k];
            size = fmax(size, fabs(p[k]));
        }
        q->res = q->Mres; /* the accepted residual */
        q->Mres = swap;
        f = ft;
        if (step <= 1e-12 * (size > 0 ? size : 1)) break;
    }
    return 0;
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
    size_t nr = (size_t)n * r;
    q->Phi = malloc(sizeof(double) * nr);
    q->Psi = malloc(sizeof(double) * (size_t)n * q->npairs);
    q->J = malloc(sizeof(double) * nr);
    q->MJ = malloc(sizeof(double) * nr);
    q->A = malloc(sizeof(double) * (size_t)r * r);
    q->res = malloc(sizeof(double) * (size_t)n);
    q->Mres = malloc(sizeof(double) * (size_t)n);
    q->rhs = malloc(sizeof(double) * (size_t)r);
    q->ptry = malloc(sizeof(double) * (size_t)r);
    q->M = *M;
    q->M.colptr = malloc(sizeof(int) * ((size_t)n + 1));
    q->M.rowind = malloc(sizeof(int) * (size_t)M->nnz);
    q->M.val = malloc(sizeof(double) * (size_t)M->nnz);
    dec->ctx = q;
    dec->destroy = destroy;
    if (!q->Phi || !q->Psi || !q->J || !q->MJ || !q->A || !q->res || !q->Mres || !q->rhs || !q->ptry || !q->M.colptr ||
        !q->M.rowind || !q->M.val) {
        rk_decoder_free(dec);
        return rk_fail(err, "out of memory for the quadratic decoder (%d x %d)", n, r);
    }
    memcpy(q->Phi, Phi, sizeof(double) * nr);
    memcpy(q->Psi, Psi, sizeof(double) * (size_t)n * q->npairs);
    memcpy(q->M.colptr, M->colptr, sizeof(int) * ((size_t)n + 1));
    memcpy(q->M.rowind, M->rowind, sizeof(int) * (size_t)M->nnz);
    memcpy(q->M.val, M->val, sizeof(double) * (size_t)M->nnz);
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
        free(q->J);
        free(q->MJ);
        free(q->A);
        free(q->res);
        free(q->Mres);
        free(q->rhs);
        free(q->ptry);
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
