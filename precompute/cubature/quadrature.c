/* The reduced elastic energy as a weighted sum over points with F_i = I + G_i q (cubature.h). */
#include "cubature/cubature.h"

#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* G of tet t: F = Ds Dm^-1 with Ds's column k = x_{k+1} - x_0, so
 * dF_ab/dq = sum_k (U[x_{k+1}, a] - U[x_0, a]) Dm^-1_kb. */
static void tet_G(const rk_fem *f, int t, const double *U, int r, double *G)
{
    const int *v = &f->tets[4 * t];
    const double *Dinv = &f->Dm_inv[9 * t];
    size_t rows = 3 * (size_t)f->nv;
    for (int j = 0; j < r; j++) {
        const double *u = U + rows * j;
        for (int a = 0; a < 3; a++) {
            double e[3];
            for (int k = 0; k < 3; k++) e[k] = u[3 * v[k + 1] + a] - u[3 * v[0] + a];
            for (int b = 0; b < 3; b++)
                G[(size_t)(3 * a + b) * r + j] = e[0] * Dinv[b] + e[1] * Dinv[3 + b] + e[2] * Dinv[6 + b];
        }
    }
}

int rk_quadrature_alloc(rk_quadrature *Q, int r, int count, int skin_H, const char *what, rk_error *err)
{
    memset(Q, 0, sizeof *Q);
    size_t n = (size_t)(count > 0 ? count : 1), L = 4 * (size_t)skin_H;
    Q->r = r;
    Q->count = count;
    Q->G = rk_calloc(n * 9 * r, sizeof(double), err);
    Q->weight = rk_calloc(n, sizeof(double), err);
    Q->model = rk_calloc(n, sizeof *Q->model, err);
    Q->mu = rk_calloc(n, sizeof(double), err);
    Q->lambda = rk_calloc(n, sizeof(double), err);
    Q->source = rk_calloc(n, sizeof(int), err);
    Q->scratch = rk_calloc(n * (18 + 9 * (size_t)r), sizeof(double), err);
    Q->skin_H = skin_H;
    if (skin_H) {
        Q->N = rk_calloc(n * 3 * L, sizeof(double), err);
        Q->skin_scratch = rk_calloc(81 * n + L * L, sizeof(double), err);
    }
    if (!Q->G || !Q->weight || !Q->model || !Q->mu || !Q->lambda || !Q->source || !Q->scratch ||
        (skin_H && (!Q->N || !Q->skin_scratch))) {
        rk_quadrature_free(Q);
        return rk_error_prefix(err, "quadrature of %d %s in %d columns", count, what, r);
    }
    return 0;
}

int rk_quadrature_elements(const rk_fem *f, const double *U, int r, int count, const int *elements,
                           const double *weights, rk_quadrature *Q, rk_error *err)
{
    memset(Q, 0, sizeof *Q);
    if (r < 1 || count < 0) return rk_fail(err, "quadrature: %d columns, %d points", r, count);
    if (rk_quadrature_alloc(Q, r, count, 0, "points", err)) return -1;
    for (int k = 0; k < count; k++) {
        int t = elements ? elements[k] : k;
        if (t < 0 || t >= f->nt) {
            rk_quadrature_free(Q);
            return rk_fail(err, "quadrature: element %d out of range (the mesh has %d)", t, f->nt);
        }
        double w = weights ? weights[k] : 1.0;
        if (!(isfinite(w) && w >= 0)) {
            rk_quadrature_free(Q);
            return rk_fail(err, "quadrature: weight %g of element %d is not a non-negative number", w, t);
        }
        tet_G(f, t, U, r, Q->G + (size_t)k * 9 * r);
        Q->weight[k] = f->vol[t] * w;
        Q->model[k] = f->model[t];
        Q->mu[k] = f->mu[t];
        Q->lambda[k] = f->lambda[t];
        Q->source[k] = t;
    }
    return 0;
}

void rk_quadrature_free(rk_quadrature *Q)
{
    free(Q->G);
    free(Q->weight);
    free(Q->model);
    free(Q->mu);
    free(Q->lambda);
    free(Q->source);
    free(Q->scratch);
    free(Q->N);
    free(Q->skin_scratch);
    free(Q->vol_phi);
    free(Q->vol_scratch);
    memset(Q, 0, sizeof *Q);
}

void rk_quadrature_point_F(const rk_quadrature *Q, int i, const double *q, double F[9])
{
    cblas_dgemv(CblasRowMajor, CblasNoTrans, 9, Q->r, 1.0, Q->G + (size_t)i * 9 * Q->r, Q->r, q, 1, 0.0, F, 1);
    F[0] += 1;
    F[4] += 1;
    F[8] += 1;
}

void rk_quadrature_point_force(const rk_quadrature *Q, int i, const double F[9], double *out)
{
    double P[9];
    rk_pk1(Q->model[i], Q->mu[i], Q->lambda[i], F, P);
    cblas_dgemv(CblasRowMajor, CblasTrans, 9, Q->r, Q->weight[i], Q->G + (size_t)i * 9 * Q->r, Q->r, P, 1,
                0.0, out, 1);
}

/* Point i's lambda in its own Psi: 0 with a projected volume, which carries lambda instead. */
static double point_lambda(const rk_quadrature *Q, int i) { return Q->vol_k ? 0 : Q->lambda[i]; }

/* Point i's w-less tangent dP/dF, with its projected pressure's term when the volume is projected. */
static void point_dpdf(const rk_quadrature *Q, int i, const double *F, double *D, int project)
{
    const double *dth, *pres = Q->vol_k ? rk_quadrature_volume_pressure(Q, &dth) : NULL;
    rk_dpdf_p(Q->model[i], Q->mu[i], point_lambda(Q, i), pres ? pres[i] : 0, F + 9 * (size_t)i, D, project);
}

/* The Hessian of a skinning-structured quadrature (rk_quadrature_points): row (a, b) of G_i is
 * N_i[., b] on the 4H coordinates of row a of the handles, so block (a, a') of G^T D G over those
 * coordinates is sum_i N_i^T (w_i D_i[(a, .), (a', .)]) N_i: with the points' N stacked (3n x 4H),
 * one product (4H x 3n)(3n x 4H) per block a <= a', a fifth of the dense product's work. F (9n)
 * at the current q; C (3n x 4H) is the caller's scratch, D and B the quadrature's own. */
static void skin_hessian(rk_quadrature *Q, const double *F, double *H, int project, double *C)
{
    int n = Q->count, L = 4 * Q->skin_H, r = Q->r;
    double *D = Q->skin_scratch, *B = D + 81 * (size_t)n;
    for (int i = 0; i < n; i++) point_dpdf(Q, i, F, D + 81 * (size_t)i, project);
    for (int a = 0; a < 3; a++)
        for (int a2 = a; a2 < 3; a2++) {
            for (int i = 0; i < n; i++) /* C_i = (w D_i[(a, b), (a2, b2)]) N_i, rows b */
                for (int b = 0; b < 3; b++) {
                    double *Cb = C + ((size_t)i * 3 + b) * L;
                    const double *Drow = D + 81 * (size_t)i + 9 * (3 * a + b) + 3 * a2;
                    const double *N = Q->N + (size_t)i * 3 * L;
                    for (int x = 0; x < L; x++)
                        Cb[x] = Q->weight[i] * (Drow[0] * N[x] + Drow[1] * N[L + x] + Drow[2] * N[2 * L + x]);
                }
            cblas_dgemm(CblasRowMajor, CblasTrans, CblasNoTrans, L, L, 3 * n, 1.0, Q->N, L, C, L, 0.0, B, L);
            for (int y = 0; y < L; y++) /* B[x][y]: coordinate (a, x) against (a2, y) */
                for (int x = 0; x < L; x++) {
                    int i = 12 * (x / 4) + 4 * a + x % 4, j = 12 * (y / 4) + 4 * a2 + y % 4;
                    H[i + (size_t)r * j] += B[x * L + y];
                    if (a != a2) H[j + (size_t)r * i] += B[x * L + y];
                }
        }
}

double rk_quadrature_eval(rk_quadrature *Q, const double *q, double *g, double *H, int project)
{
    int r = Q->r, n = Q->count;
    if (n == 0) return 0;
    double *F = Q->scratch, *P = F + 9 * (size_t)n, *DG = P + 9 * (size_t)n;
    /* All deformation gradients at once: the stacked G (9n x r) times q. */
    cblas_dgemv(CblasRowMajor, CblasNoTrans, 9 * n, r, 1.0, Q->G, r, q, 1, 0.0, F, 1);
    double E = 0;
    for (int i = 0; i < n; i++) {
        double *Fi = F + 9 * i;
        Fi[0] += 1;
        Fi[4] += 1;
        Fi[8] += 1;
        E += Q->weight[i] * rk_psi(Q->model[i], Q->mu[i], point_lambda(Q, i), Fi);
    }
    if (Q->vol_k) E += rk_quadrature_volume_energy(Q, F);
    if (!isfinite(E)) return INFINITY;
    if (g) {
        const double *dth = NULL, *pres = Q->vol_k ? rk_quadrature_volume_pressure(Q, &dth) : NULL;
        for (int i = 0; i < n; i++) {
            rk_pk1(Q->model[i], Q->mu[i], point_lambda(Q, i), F + 9 * i, P + 9 * i);
            if (pres)
                for (int k = 0; k < 9; k++) P[9 * i + k] += pres[i] * dth[9 * i + k];
            for (int k = 0; k < 9; k++) P[9 * i + k] *= Q->weight[i];
        }
        cblas_dgemv(CblasRowMajor, CblasTrans, 9 * n, r, 1.0, Q->G, r, P, 1, 1.0, g, 1);
    }
    if (H && Q->skin_H) {
        skin_hessian(Q, F, H, project, DG);
    } else if (H) {
        /* H += sum_i G_i^T (w_i dP/dF_i G_i): per point a 9x9 by 9xr product, then one
         * (r x 9n) by (9n x r) product for all points. */
        for (int i = 0; i < n; i++) {
            double D[81];
            point_dpdf(Q, i, F, D, project);
            cblas_dgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, 9, r, 9, Q->weight[i], D, 9,
                        Q->G + (size_t)i * 9 * r, r, 0.0, DG + (size_t)i * 9 * r, r);
        }
        /* Row-major r x r result = column-major (symmetric) H. */
        cblas_dgemm(CblasRowMajor, CblasTrans, CblasNoTrans, r, r, 9 * n, 1.0, Q->G, r, DG, r, 1.0, H, r);
    }
    if (H && Q->vol_k) rk_quadrature_volume_hessian(Q, H);
    return E;
}
