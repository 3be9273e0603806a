/* The projected volume of a quadrature (cubature.h, "the projected volume"): the pressure space's
 * condensed form Phi, and the energy's volumetric part and its rank-k Hessian term. */
#include "cubature/cubature.h"

#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* vol_scratch: dtheta (9 n), pressure (n), T (n r), c (k), C (k r). */
static size_t scratch_size(int n, int r, int k) { return (size_t)n * (10 + (size_t)r) + (size_t)k * (1 + (size_t)r); }

/* Eigen-decomposition of the symmetric k x k A (column-major, overwritten by its eigenvectors). */
static int sym_eig(int k, double *A, double *w) { return LAPACKE_dsyev(LAPACK_COL_MAJOR, 'V', 'U', k, A, k, w) != 0; }

int rk_quadrature_volume(rk_quadrature *Q, int k, const double *psi, rk_error *err)
{
    int n = Q->count, r = Q->r;
    free(Q->vol_phi);
    free(Q->vol_scratch);
    Q->vol_phi = Q->vol_scratch = NULL;
    Q->vol_k = 0;
    if (k < 1 || n < 1) return 0;
    for (size_t x = 0; x < (size_t)n * k; x++)
        if (!isfinite(psi[x])) return rk_fail(err, "volume projection: pressure function %zu at point %zu is not finite",
                                              x % k, x / k);
    double *G = rk_calloc((size_t)k * k, sizeof(double), err), *GL = rk_calloc((size_t)k * k, sizeof(double), err),
           *ev = rk_calloc(k, sizeof(double), err), *S = rk_calloc((size_t)k * k, sizeof(double), err),
           *Wpsi = rk_calloc((size_t)n * k, sizeof(double), err);
    int rc = -1;
    if (!G || !GL || !ev || !S || !Wpsi) goto out;
    /* G = Psi^T W Psi, GL = Psi^T W Lambda Psi */
    for (int i = 0; i < n; i++)
        for (int a = 0; a < k; a++) Wpsi[(size_t)i * k + a] = Q->weight[i] * psi[(size_t)i * k + a];
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, k, k, n, 1.0, Wpsi, k, psi, k, 0.0, G, k);
    for (int i = 0; i < n; i++)
        for (int a = 0; a < k; a++) Wpsi[(size_t)i * k + a] *= Q->lambda[i];
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, k, k, n, 1.0, Wpsi, k, psi, k, 0.0, GL, k);
    if (sym_eig(k, G, ev)) {
        rk_fail(err, "volume projection: the pressure space's Gram matrix (%d x %d) has no eigen-decomposition", k, k);
        goto out;
    }
    /* G^+ = V diag(1/ev) V^T over the eigenvalues above round-off of the largest */
    double cut = 1e-10 * fabs(ev[k - 1]);
    memset(S, 0, sizeof(double) * k * k);
    for (int e = 0; e < k; e++) {
        if (!(ev[e] > cut)) continue;
        const double *v = G + (size_t)k * e;
        for (int b = 0; b < k; b++)
            for (int a = 0; a < k; a++) S[a + (size_t)k * b] += v[a] * v[b] / ev[e];
    }
    /* S = G^+ GL G^+ (reusing G as the product's scratch) */
    cblas_dsymm(CblasColMajor, CblasLeft, CblasUpper, k, k, 1.0, GL, k, S, k, 0.0, G, k);
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, k, k, k, 1.0, S, k, G, k, 0.0, GL, k);
    for (int b = 0; b < k; b++) /* symmetrise the round-off */
        for (int a = 0; a < b; a++) GL[a + (size_t)k * b] = GL[b + (size_t)k * a] = 0.5 * (GL[a + (size_t)k * b] + GL[b + (size_t)k * a]);
    if (sym_eig(k, GL, ev)) {
        rk_fail(err, "volume projection: the projected stiffness (%d x %d) has no eigen-decomposition", k, k);
        goto out;
    }
    /* Phi = Psi Q sqrt(E) over S's non-zero eigenvalues (none where lambda = 0: pointwise stays) */
    int kept = 0;
    double top = ev[k - 1];
    for (int e = 0; e < k; e++) kept += ev[e] > 1e-12 * top && top > 0;
    rc = 0;
    if (kept == 0) goto out;
    Q->vol_phi = rk_calloc((size_t)n * kept, sizeof(double), err);
    Q->vol_scratch = rk_calloc(scratch_size(n, r, kept), sizeof(double), err);
    if (!Q->vol_phi || !Q->vol_scratch) {
        free(Q->vol_phi);
        free(Q->vol_scratch);
        Q->vol_phi = Q->vol_scratch = NULL;
        rc = -1;
        goto out;
    }
    for (int e = k - kept, col = 0; e < k; e++, col++) {
        const double *v = GL + (size_t)k * e;
        double s = sqrt(ev[e]);
        for (int i = 0; i < n; i++) Q->vol_phi[(size_t)i * kept + col] = s * cblas_ddot(k, psi + (size_t)i * k, 1, v, 1);
    }
    Q->vol_k = kept;
out:
    free(G);
    free(GL);
    free(ev);
    free(S);
    free(Wpsi);
    if (rc) return rk_error_prefix(err, "volume projection over %d points, %d pressure functions", n, k);
    return 0;
}

double rk_quadrature_volume_energy(rk_quadrature *Q, const double *F)
{
    int n = Q->count, k = Q->vol_k, r = Q->r;
    double *dth = Q->vol_scratch, *pres = dth + 9 * (size_t)n, *c = pres + n + (size_t)n * r;
    /* pres holds w_i theta_i until c is known */
    for (int i = 0; i < n; i++) {
        double Hd[9];
        for (int x = 0; x < 9; x++) Hd[x] = F[9 * i + x] - (x % 4 == 0);
        pres[i] = Q->weight[i] * rk_volume_h(Q->model[i], Hd, dth + 9 * (size_t)i);
    }
    cblas_dgemv(CblasRowMajor, CblasTrans, n, k, 1.0, Q->vol_phi, k, pres, 1, 0.0, c, 1);
    cblas_dgemv(CblasRowMajor, CblasNoTrans, n, k, 1.0, Q->vol_phi, k, c, 1, 0.0, pres, 1);
    return 0.5 * cblas_ddot(k, c, 1, c, 1);
}

const double *rk_quadrature_volume_pressure(const rk_quadrature *Q, const double **dtheta)
{
    *dtheta = Q->vol_scratch;
    return Q->vol_scratch + 9 * (size_t)Q->count;
}

void rk_quadrature_volume_hessian(rk_quadrature *Q, double *H)
{
    int n = Q->count, k = Q->vol_k, r = Q->r;
    double *dth = Q->vol_scratch, *T = dth + 10 * (size_t)n, *C = T + (size_t)n * r + k;
    for (int i = 0; i < n; i++) /* row i of T: w_i G_i^T dtheta_i */
        cblas_dgemv(CblasRowMajor, CblasTrans, 9, r, Q->weight[i], Q->G + (size_t)i * 9 * r, r, dth + 9 * (size_t)i, 1,
                    0.0, T + (size_t)i * r, 1);
    /* C (k x r, row-major) = Phi^T (W T); H += C^T C (column-major H, symmetric) */
    cblas_dgemm(CblasRowMajor, CblasTrans, CblasNoTrans, k, r, n, 1.0, Q->vol_phi, k, T, r, 0.0, C, r);
    cblas_dgemm(CblasRowMajor, CblasTrans, CblasNoTrans, r, r, k, 1.0, C, r, C, r, 1.0, H, r);
}
