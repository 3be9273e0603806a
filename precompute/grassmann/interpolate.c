/* Grassmann interpolation (adaptive-linear-rom paper, Algorithm 4) and principal angles. */
#include "grassmann/grassmann_impl.h"

#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A diagonal of R below this fraction of the largest is rank loss. Not round-off's 1e-12: the
 * history basis D P^T (P P^T + 1e-8 I)^-1 of a history that spans fewer than r directions has its
 * missing columns at round-off amplified by the regularisation (1e-10 of the others and more),
 * and a QR that took them would blend directions set by rounding, different in every
 * implementation; at 1e-6 the blend is decided by the data (the runtime uses the same floor). */
#define RK_THINQ_TOL 1e-6

int rk_thin_q(int n, int r, const double *A, double *Q, const char *what, rk_error *err)
{
    double *tau = malloc(sizeof(double) * (size_t)r);
    if (!tau) return rk_fail(err, "out of memory for a QR factorization");
    memcpy(Q, A, sizeof(double) * (size_t)n * r);
    int rc = LAPACKE_dgeqrf(LAPACK_COL_MAJOR, n, r, Q, n, tau);
    double big = 0, small = INFINITY;
    for (int i = 0; i < r && !rc; i++) {
        double d = fabs(Q[(size_t)i * n + i]);
        big = fmax(big, d);
        small = fmin(small, d);
    }
    if (!rc && !(small > RK_THINQ_TOL * big && big > 0)) {
        free(tau);
        return rk_fail(err, "%s has rank below %d (its QR's smallest diagonal %.3g, largest %.3g)", what, r, small, big);
    }
    if (!rc) rc = LAPACKE_dorgqr(LAPACK_COL_MAJOR, n, r, r, Q, n, tau);
    free(tau);
    return rc ? rk_fail(err, "LAPACK QR of %s failed (%d)", what, rc) : 0;
}

/* M = A^T B (r x r) and its SVD M = V diag(s) W^T (s descending: the cosines of the principal
 * angles, ascending angles). */
static int cosines(int n, int r, const double *QA, const double *QB, double *V, double *s, double *WT, rk_error *err)
{
    double *M = malloc(sizeof(double) * ((size_t)r * r + r));
    if (!M) return rk_fail(err, "out of memory for the principal angles");
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, r, r, n, 1.0, QA, n, QB, n, 0.0, M, r);
    int rc = LAPACKE_dgesvd(LAPACK_COL_MAJOR, 'A', 'A', r, r, M, r, s, V, r, WT, r, M + (size_t)r * r);
    free(M);
    return rc ? rk_fail(err, "LAPACK SVD of the bases' inner products failed (%d)", rc) : 0;
}

int rk_principal_angles(int n, int r, const double *A, const double *B, double *theta, rk_error *err)
{
    double *QA = malloc(sizeof(double) * (2 * (size_t)n * r + 2 * (size_t)r * r));
    if (!QA) return rk_fail(err, "out of memory for the principal angles");
    double *QB = QA + (size_t)n * r, *V = QB + (size_t)n * r, *WT = V + (size_t)r * r;
    int rc = rk_thin_q(n, r, A, QA, "the first basis", err) || rk_thin_q(n, r, B, QB, "the second basis", err) ||
             cosines(n, r, QA, QB, V, theta, WT, err);
    for (int i = 0; i < r && !rc; i++) theta[i] = acos(fmin(1.0, fmax(-1.0, theta[i])));
    free(QA);
    return rc ? -1 : 0;
}

int rk_grassmann_interpolate(int n, int r, const double *Phi, const double *U, double lambda, double *out,
                             rk_error *err)
{
    if (!(lambda >= 0 && lambda <= 1)) return rk_fail(err, "lambda must be in [0, 1], got %g", lambda);
    size_t nr = (size_t)n * r, rr = (size_t)r * r;
    double *QP = malloc(sizeof(double) * (3 * nr + 2 * rr + 2 * (size_t)r));
    if (!QP) return rk_fail(err, "out of memory for the Grassmann interpolation");
    double *QU = QP + nr, *S = QU + nr, *V = S + nr, *WT = V + rr, *c = WT + rr, *theta = c + r;
    int rc = rk_thin_q(n, r, Phi, QP, "the history basis", err) || rk_thin_q(n, r, U, QU, "the decoder's basis", err) ||
             cosines(n, r, QP, QU, V, c, WT, err);
    if (!rc) {
        /* S = (Q_U W - Q_Phi V cos) / sin, column by column; QPV = Q_Phi V into out for now */
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, n, r, r, 1.0, QU, n, WT, r, 0.0, S, n);
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n, r, r, 1.0, QP, n, V, r, 0.0, out, n);
        for (int j = 0; j < r; j++) {
            double cj = fmin(1.0, fmax(-1.0, c[j]));
            theta[j] = acos(cj);
            double sj = sin(theta[j]);
            double *Sj = S + (size_t)j * n, *Gj = out + (size_t)j * n;
            /* a zero angle: the spans share this direction, which the geodesic keeps (S_j = 0) */
            double inv = sj > 1e-12 ? 1.0 / sj : 0;
            double a = cos(lambda * theta[j]), b = sin(lambda * theta[j]);
            for (int i = 0; i < n; i++) {
                double s = (Sj[i] - Gj[i] * cj) * inv;
                Gj[i] = Gj[i] * a + s * b; /* G = Q_Phi V cos(lambda theta) + S sin(lambda theta) */
            }
        }
        memcpy(S, out, sizeof(double) * nr);
        rc = rk_thin_q(n, r, S, out, "the interpolated basis", err);
    }
    free(QP);
    return rc ? -1 : 0;
}
