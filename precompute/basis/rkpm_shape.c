/* RKPM shape functions with the linear reproducing correction (freeform paper Eq. 7-11) and
 * their analytic gradients.
 *
 * Basis. P(X) = [1, x, y, z] is replaced by Q_k = [1, (p_k - X)/h] at each evaluation point X
 * (h a fixed length there: the kernels' weighted mean radius). Q_k = T(X) P(p_k) for an invertible
 * T(X), so Eq. 7-11 give the same phi_k, but M(X) = sum_k w_k Q_k Q_k^T (Eq. 10) is O(1) and
 * well conditioned, and the right-hand side of Eq. 9 becomes Q(X) at p = X, i.e. e_1:
 *   b = M^-1 e_1,  s_k = Q_k^T b,  phi_k = w_k s_k                 (w_k: the tapered Gaussian)
 * Gradient (d_j = d/dX_j, h held fixed: phi_k does not depend on h). With d_j Q_k = -e_{j+1}/h,
 *   d_j M b = g_j - e_{j+1}/h - (b_{j+1}/h) M e_1,   g_j = sum_l (d_j w_l) s_l Q_l,
 * using sum_l w_l s_l = e_1^T M b = 1 and sum_l w_l Q_l = M e_1; so d_j b = -M^-1 (d_j M) b gives
 *   d_j phi_k = (d_j w_k) s_k - w_k b_{j+1}/h + w_k Q_k^T d_j b
 *             = (d_j w_k) s_k + w_k Q_k^T v_j,   v_j = M^-1 (e_{j+1}/h - g_j)
 * (the b_{j+1} terms cancel because Q_k[0] = 1). */
#include "basis/rkpm_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char SPARSE[] = "the point cloud is too sparse for its kernels";

static int too_sparse(rk_error *err, int point, const double X[3], const char *why)
{
    char where[160];
    if (point >= 0) snprintf(where, sizeof where, "point %d at (%g, %g, %g)", point, X[0], X[1], X[2]);
    else snprintf(where, sizeof where, "the point at (%g, %g, %g)", X[0], X[1], X[2]);
    return rk_fail(err, "%s %s: %s", where, why, SPARSE);
}

/* Cholesky M = L L^T of the symmetric 4x4 (lower triangle read); -1 if not positive definite.
 * Hand-written: it runs once per evaluation point, where a LAPACK call would cost more than the
 * arithmetic, and the explicit inverse it gives is needed anyway (the gradients, the 1-norm
 * condition estimate). */
static int chol4(const double M[4][4], double L[4][4])
{
    memset(L, 0, 16 * sizeof(double));
    for (int j = 0; j < 4; j++) {
        double s = M[j][j];
        for (int q = 0; q < j; q++) s -= L[j][q] * L[j][q];
        if (!(s > 0) || !isfinite(s)) return -1;
        L[j][j] = sqrt(s);
        for (int i = j + 1; i < 4; i++) {
            double t = M[i][j];
            for (int q = 0; q < j; q++) t -= L[i][q] * L[j][q];
            L[i][j] = t / L[j][j];
        }
    }
    return 0;
}

/* A = M^-1 from the Cholesky factor, column by column. */
static void chol4_inverse(const double L[4][4], double A[4][4])
{
    for (int c = 0; c < 4; c++) {
        double y[4];
        for (int i = 0; i < 4; i++) {
            double t = i == c;
            for (int q = 0; q < i; q++) t -= L[i][q] * y[q];
            y[i] = t / L[i][i];
        }
        for (int i = 3; i >= 0; i--) {
            double t = y[i];
            for (int q = i + 1; q < 4; q++) t -= L[q][i] * A[q][c];
            A[i][c] = t / L[i][i];
        }
    }
}

static double norm1(const double A[4][4])
{
    double best = 0;
    for (int c = 0; c < 4; c++) {
        double s = 0;
        for (int i = 0; i < 4; i++) s += fabs(A[i][c]);
        best = fmax(best, s);
    }
    return best;
}

int rkpm_shape_at(const rk_rkpm *k, const double X[3], int point, int n, const int *kid, double *phi,
                  double *grad, int *regularized, rk_error *err)
{
    char why[200];
    if (regularized) *regularized = 0;
    if (n < (regularized ? 1 : 4)) {
        snprintf(why, sizeof why, "is covered by %d kernel%s (4 needed for linear reproduction)", n, n == 1 ? "" : "s");
        return too_sparse(err, point, X, why);
    }
    /* Kernel values (and gradients, stored in grad for now); h = weighted mean radius. */
    double wsum = 0, wr = 0;
    for (int a = 0; a < n; a++) {
        phi[a] = rkpm_window(k, kid[a], X, grad ? &grad[3 * a] : NULL);
        wsum += phi[a];
        wr += phi[a] * k->radius[kid[a]];
    }
    double h = wsum > 0 ? wr / wsum : 1, M[4][4] = {{0}};
    for (int a = 0; a < n; a++) {
        const double *p = &k->centers[3 * kid[a]];
        double Q[4] = {1, (p[0] - X[0]) / h, (p[1] - X[1]) / h, (p[2] - X[2]) / h};
        for (int i = 0; i < 4; i++)
            for (int j = 0; j <= i; j++) M[i][j] += phi[a] * Q[i] * Q[j];
    }
    for (int i = 0; i < 4; i++)
        for (int j = i + 1; j < 4; j++) M[i][j] = M[j][i];
    double L[4][4], A[4][4], rcond = 0;
    if (chol4(M, L) == 0) {
        chol4_inverse(L, A);
        rcond = 1 / (norm1(M) * norm1(A));
    }
    if (regularized && !(rcond >= RK_RKPM_REGULARIZE_RCOND)) {
        /* Tolerant evaluation (weights at vertices or splats in thin features, where the
         * kernels nearby lie along a line or in a plane): damp the linear block. The first row
         * of the damping is zero, so e_1^T M b = 1 still holds and constants are reproduced
         * exactly; linear fields lose exactness only along the missing directions. The gradient
         * formulas above hold with M + damping in place of M, plus the damping's own derivative
         * (below, where the gradients are formed). */
        for (int i = 1; i < 4; i++) M[i][i] += RK_RKPM_REGULARIZE * M[0][0];
        rcond = 0;
        if (chol4(M, L) == 0) {
            chol4_inverse(L, A);
            rcond = 1 / (norm1(M) * norm1(A));
        }
        *regularized = 1;
    }
    if (!(rcond >= RK_RKPM_MIN_RCOND)) {
        snprintf(why, sizeof why,
                 "is covered by %d kernels whose centres are (nearly) coplanar (the moment matrix of Eq. 10 has "
                 "reciprocal condition number %.3g < %g)",
                 n, rcond, RK_RKPM_MIN_RCOND);
        return too_sparse(err, point, X, why);
    }
    double b[4] = {A[0][0], A[1][0], A[2][0], A[3][0]}, v[3][4];
    if (grad) {
        double g[3][4] = {{0}}, dsum[3] = {0, 0, 0}, drsum[3] = {0, 0, 0};
        for (int a = 0; a < n; a++) {
            const double *p = &k->centers[3 * kid[a]];
            double Q[4] = {1, (p[0] - X[0]) / h, (p[1] - X[1]) / h, (p[2] - X[2]) / h};
            double s = Q[0] * b[0] + Q[1] * b[1] + Q[2] * b[2] + Q[3] * b[3];
            for (int j = 0; j < 3; j++) {
                for (int i = 0; i < 4; i++) g[j][i] += grad[3 * a + j] * s * Q[i];
                dsum[j] += grad[3 * a + j];
                drsum[j] += grad[3 * a + j] * k->radius[kid[a]];
            }
        }
        for (int j = 0; j < 3; j++)
            for (int i = 0; i < 4; i++) {
                double t = A[i][j + 1] / h;
                for (int q = 0; q < 4; q++) t -= A[i][q] * g[j][q];
                v[j][i] = t;
            }
        if (regularized && *regularized) {
            /* The damping d M00 diag(0, 1, 1, 1) (d = RK_RKPM_REGULARIZE) varies with X through
             * M00 = wsum and, since it acts in the scaled basis, through h: phi_k then depends
             * on h, which the undamped derivation could hold fixed. With e_j = d_j h / h and
             * D b = (0, b1, b2, b3), differentiating M b = e_1 adds to d_j b
             *   -d (2 e_j M00 + d_j M00) M^-1 D b,
             * and nothing else (the other e_j terms cancel as the b_{j+1} ones do, since D e_1 = 0
             * and e_1^T D = 0). */
            double u[4];
            for (int i = 0; i < 4; i++) u[i] = A[i][1] * b[1] + A[i][2] * b[2] + A[i][3] * b[3];
            for (int j = 0; j < 3; j++) {
                double eta = (drsum[j] - h * dsum[j]) / (wsum * h);
                double coef = RK_RKPM_REGULARIZE * (2 * eta * wsum + dsum[j]);
                for (int i = 0; i < 4; i++) v[j][i] -= coef * u[i];
            }
        }
    }
    for (int a = 0; a < n; a++) {
        const double *p = &k->centers[3 * kid[a]];
        double Q[4] = {1, (p[0] - X[0]) / h, (p[1] - X[1]) / h, (p[2] - X[2]) / h};
        double s = Q[0] * b[0] + Q[1] * b[1] + Q[2] * b[2] + Q[3] * b[3], w = phi[a];
        if (grad)
            for (int j = 0; j < 3; j++)
                grad[3 * a + j] = grad[3 * a + j] * s + w * (Q[0] * v[j][0] + Q[1] * v[j][1] + Q[2] * v[j][2] + Q[3] * v[j][3]);
        phi[a] = w * s;
    }
    if (k->clamp.n > 0) { /* the clamp mask: d phi_k, grad (d phi_k) = d grad phi_k + phi_k grad d */
        double gd[3], d = rkpm_clamp_at(&k->clamp, X, gd);
        for (int a = 0; a < n; a++) {
            if (grad)
                for (int j = 0; j < 3; j++) grad[3 * a + j] = d * grad[3 * a + j] + phi[a] * gd[j];
            phi[a] *= d;
        }
    }
    return 0;
}

int rk_rkpm_eval(const rk_rkpm *k, const double X[3], int cap, int *idx, double *phi, double *grad,
                 rk_error *err)
{
    if (!isfinite(X[0]) || !isfinite(X[1]) || !isfinite(X[2]))
        return rk_fail(err, "RKPM evaluation at a non-finite point (%g, %g, %g)", X[0], X[1], X[2]);
    int n = rkpm_cover(k, X, cap, idx, err);
    if (n < 0 || rkpm_shape_at(k, X, -1, n, idx, phi, grad, NULL, err)) return -1;
    return n;
}
