/* One Gaussian splat under a deformation gradient F (rk_splats_write).
 *
 * 3DGS (Kerbl et al. 2023, Sec. 4) stores a splat's covariance as Sigma = R S S^T R^T, R the
 * rotation of the quaternion rot_0..3 (w x y z), S = diag(exp(scale_0..2)). Under an affine map
 * with gradient F a Gaussian stays Gaussian with Sigma' = F Sigma F^T; the view-dependent colour
 * turns with the rotation R_F of F's polar decomposition F = R_F S_F. This is PhysGaussian's
 * kinematics (Xie et al. 2023, Sec. 3.3 and Eq. 5; ref. [46] of the FreeForm paper, which deforms
 * splats with its reduced model the same way, Fig. 1).
 *
 * Sigma' is decomposed without being formed: Sigma' = A A^T with A = F R S, so A = U diag(sigma) V^T
 * (the SVD) gives Sigma' = U diag(sigma^2) U^T, the new rotation U and log scales log sigma. The SVD
 * is LAPACK's one-sided Jacobi (LAPACKE dgesvj, Demmel & Veselic 1992), which computes the singular
 * values of A = (F R) S to high relative accuracy when F R is well conditioned whatever the spread
 * of the scales (a flat splat's small axis keeps its digits, which an eigen-solver on the formed
 * Sigma' would lose to exp(2 s_max) rounding), and which leaves already orthogonal columns alone
 * (F = I, or a pure rotation, gives U = F R to rounding).
 *
 * U's columns are only defined up to order and sign (and, for equal singular values, up to a
 * rotation among them), so they are matched to the reference frame Q0 = R_F R (the old axes carried
 * by F's rotation): the order and signs that best align them, then det +1, then for singular values
 * equal to 1e-9 (relative) the axes nearest Q0's in their common plane or space. So F = I writes
 * back the same axes and scales in the same order, and a rotation F = Rot gives the quaternion
 * Rot q. */
#include <lapacke.h>
#include <math.h>
#include <string.h>

#include "mesh/mesh_impl.h"

/* Singular values closer than this (relative) are treated as equal: their axes are not
 * determined, and choosing them changes Sigma' by less than this relative to those eigenvalues. */
#define TIE 1e-9

void rk_quat_to_matrix(const double q[4], double R[9])
{
    double len = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    double w = q[0] / len, x = q[1] / len, y = q[2] / len, z = q[3] / len;
    R[0] = 1 - 2 * (y * y + z * z), R[1] = 2 * (x * y - w * z), R[2] = 2 * (x * z + w * y);
    R[3] = 2 * (x * y + w * z), R[4] = 1 - 2 * (x * x + z * z), R[5] = 2 * (y * z - w * x);
    R[6] = 2 * (x * z - w * y), R[7] = 2 * (y * z + w * x), R[8] = 1 - 2 * (x * x + y * y);
}

/* Shepperd's method: the largest of 4w^2, 4x^2, 4y^2, 4z^2 first; unit, w >= 0. */
static void matrix_to_quat(const double R[9], double q[4])
{
    double t = R[0] + R[4] + R[8];
    if (t >= R[0] && t >= R[4] && t >= R[8]) {
        double r = sqrt(1 + t);
        q[0] = 0.5 * r;
        q[1] = (R[7] - R[5]) / (2 * r);
        q[2] = (R[2] - R[6]) / (2 * r);
        q[3] = (R[3] - R[1]) / (2 * r);
    } else if (R[0] >= R[4] && R[0] >= R[8]) {
        double r = sqrt(1 + R[0] - R[4] - R[8]);
        q[0] = (R[7] - R[5]) / (2 * r);
        q[1] = 0.5 * r;
        q[2] = (R[1] + R[3]) / (2 * r);
        q[3] = (R[2] + R[6]) / (2 * r);
    } else if (R[4] >= R[8]) {
        double r = sqrt(1 - R[0] + R[4] - R[8]);
        q[0] = (R[2] - R[6]) / (2 * r);
        q[1] = (R[1] + R[3]) / (2 * r);
        q[2] = 0.5 * r;
        q[3] = (R[5] + R[7]) / (2 * r);
    } else {
        double r = sqrt(1 - R[0] - R[4] + R[8]);
        q[0] = (R[3] - R[1]) / (2 * r);
        q[1] = (R[2] + R[6]) / (2 * r);
        q[2] = (R[5] + R[7]) / (2 * r);
        q[3] = 0.5 * r;
    }
    double len = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]), sign = q[0] < 0 ? -1 : 1;
    for (int i = 0; i < 4; i++) q[i] *= sign / len;
}

static void cross(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static double det_cols(const double c[3][3])
{
    double x[3];
    cross(c[0], c[1], x);
    return dot(x, c[2]);
}

/* C = A B, row-major 3 x 3. */
static void mul(const double A[9], const double B[9], double C[9])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) C[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
}

/* SVD of the row-major A by one-sided Jacobi: u[i] (unit columns, descending sigma). v (may be
 * NULL): the right singular vectors as columns v[i]. Singular values that underflow leave a zero
 * column in u. -1 when LAPACK fails or the values are not finite. */
static int svd3(const double A[9], double u[3][3], double sigma[3], double v[3][3])
{
    double a[9], V[9], work[6];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) a[i + 3 * j] = A[3 * i + j]; /* column-major */
    lapack_int info = LAPACKE_dgesvj_work(LAPACK_COL_MAJOR, 'G', 'U', v ? 'V' : 'N', 3, 3, a, 3, sigma, 0, V,
                                          v ? 3 : 1, work, 6);
    if (info < 0) return -1;
    /* info > 0: not converged in 30 sweeps; the result is still what the sweeps reached (never
     * seen for 3 x 3). */
    for (int i = 0; i < 3; i++) {
        sigma[i] *= work[0]; /* dgesvj returns the singular values scaled by work[0] */
        if (!isfinite(sigma[i])) return -1;
        for (int r = 0; r < 3; r++) {
            u[i][r] = a[r + 3 * i];
            if (v) v[i][r] = V[r + 3 * i];
        }
    }
    return 0;
}

int rk_polar_rotation(const double F[9], double R[9])
{
    double u[3][3], v[3][3], sigma[3];
    for (int i = 0; i < 9; i++)
        if (!isfinite(F[i])) return -1;
    if (svd3(F, u, sigma, v)) return -1;
    /* A rank-deficient F leaves u's last columns zero: complete them (any completion is a valid
     * polar rotation then). Rank below 2 cannot be completed uniquely enough to be useful. */
    if (!(sigma[1] > 0) || fabs(dot(u[1], u[1]) - 1) > 1e-6) return -1;
    if (!(sigma[2] > 0) || fabs(dot(u[2], u[2]) - 1) > 1e-6) cross(u[0], u[1], u[2]);
    double d = det_cols(u) * det_cols(v) < 0 ? -1 : 1; /* det(U V^T) */
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) R[3 * i + j] = u[0][i] * v[0][j] + u[1][i] * v[1][j] + d * u[2][i] * v[2][j];
    return 0;
}

int rk_splat_deform_covariance(const double F[9], const double RF[9], const double q[4], const double s[3],
                               double qo[4], double so[3])
{
    double R[9], A[9], FR[9], Q0[9], u[3][3], sigma[3];
    rk_quat_to_matrix(q, R);
    mul(F, R, FR);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) A[3 * i + j] = FR[3 * i + j] * exp(s[j]);
    if (svd3(A, u, sigma, NULL)) return -1;
    for (int i = 0; i < 3; i++)
        if (!(sigma[i] > 0) || fabs(dot(u[i], u[i]) - 1) > 1e-6) return -1; /* collapsed */
    mul(RF, R, Q0);
    double q0[3][3]; /* Q0's columns: the old axes turned by F's rotation */
    for (int k = 0; k < 3; k++)
        for (int r = 0; r < 3; r++) q0[k][r] = Q0[3 * r + k];

    /* Slot k gets U's column perm[k]: the order that best aligns them, then the signs. */
    static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    double D[3][3], best = -1;
    int p = 0;
    for (int k = 0; k < 3; k++)
        for (int i = 0; i < 3; i++) D[k][i] = dot(q0[k], u[i]);
    for (int c = 0; c < 6; c++) {
        double score = fabs(D[0][perms[c][0]]) + fabs(D[1][perms[c][1]]) + fabs(D[2][perms[c][2]]);
        if (score > best) best = score, p = c;
    }
    double axis[3][3], sig[3];
    int weakest = 0;
    for (int k = 0; k < 3; k++) {
        int i = perms[p][k];
        double sign = D[k][i] < 0 ? -1 : 1;
        for (int r = 0; r < 3; r++) axis[k][r] = sign * u[i][r];
        sig[k] = sigma[i];
        if (fabs(D[k][i]) < fabs(D[weakest][perms[p][weakest]])) weakest = k;
    }
    if (det_cols(axis) < 0)
        for (int r = 0; r < 3; r++) axis[weakest][r] = -axis[weakest][r];

    /* Equal singular values: the axes among them are free; take Q0's. */
    int tie[3], ties = 0; /* tie[c]: the pair opposite slot c is equal */
    for (int c = 0; c < 3; c++) {
        int a = (c + 1) % 3, b = (c + 2) % 3;
        tie[c] = fabs(sig[a] - sig[b]) <= TIE * fmax(sig[a], sig[b]);
        ties += tie[c];
    }
    if (ties >= 2) {
        memcpy(axis, q0, sizeof axis);
    } else if (ties == 1) {
        int c = tie[0] ? 0 : tie[1] ? 1 : 2, a = (c + 1) % 3, b = (c + 2) % 3;
        double proj[3], d = dot(q0[a], axis[c]), len;
        for (int r = 0; r < 3; r++) proj[r] = q0[a][r] - d * axis[c][r];
        len = sqrt(dot(proj, proj));
        if (len > 1e-3) { /* else q0[a] is near the fixed axis: keep U's */
            for (int r = 0; r < 3; r++) axis[a][r] = proj[r] / len;
            cross(axis[c], axis[a], axis[b]); /* right-handed: axis[b] = axis[b+1] x axis[b+2] */
        }
    }
    double Q[9];
    for (int k = 0; k < 3; k++) {
        for (int r = 0; r < 3; r++) Q[3 * r + k] = axis[k][r];
        so[k] = log(sig[k]);
        if (!isfinite(so[k])) return -1;
    }
    matrix_to_quat(Q, qo);
    return 0;
}

void rk_splat_deform_normal(const double F[9], const double n[3], double out[3])
{
    /* F^-T = cof(F) / det F; the cofactor matrix's rows are cross products of F's rows. */
    double cof[9], det;
    cross(F + 3, F + 6, cof);
    cross(F + 6, F, cof + 3);
    cross(F, F + 3, cof + 6);
    det = dot(F, cof);
    double sign = det < 0 ? -1 : 1, len;
    for (int i = 0; i < 3; i++) out[i] = sign * (cof[3 * i] * n[0] + cof[3 * i + 1] * n[1] + cof[3 * i + 2] * n[2]);
    len = sqrt(dot(out, out));
    for (int i = 0; i < 3; i++) out[i] = len > 0 ? out[i] / len : 0;
}
