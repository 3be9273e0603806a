/* Rotation of real spherical harmonics in the basis 3D Gaussian Splatting uses (Kerbl et al. 2023;
 * graphdeco-inria gaussian-splatting utils/sh_utils.py: the constants C1..C3 and the basis order
 * below). A rotation maps each band l (the harmonic homogeneous polynomials of degree l) onto
 * itself, so the colour of band l seen from direction R d with rotated coefficients c' equals the
 * colour from d with c when, for every direction e,
 *     sum_m c'_m Y_m(e) = sum_k c_k Y_k(R^T e).
 * Both sides lie in the same (2l+1)-dimensional space, so it is enough to ask it at 2l+1 directions
 * e_j where the basis is independent: A c' = B c with A_jm = Y_m(e_j), B_jk = Y_k(R^T e_j), and the
 * band's rotation matrix is M = A^-1 B (exact up to rounding; the method of evaluating the basis at
 * generic directions and solving a small linear system, instead of the Ivanic-Ruedenberg 1996
 * recurrences). The directions are a golden-angle spiral, z_j = 1 - 2 (j + 0.05) / (2l+1),
 * phi_j = 2.39996 j, chosen so that A is well conditioned: 2-norm condition numbers 3.05, 7.34 and
 * 3.44 for bands 1, 2 and 3 (the symmetric spiral with j + 0.5 makes bands 1 and 3 singular, as
 * odd bands vanish on antipodal pairs). A's LU factors (LAPACKE dgetrf) are computed once per
 * rk_sh_rotator and reused for every rotation (dgetrs). */
#include <lapacke.h>
#include <math.h>
#include <string.h>

#include "mesh/mesh_impl.h"

_Static_assert(sizeof(lapack_int) == sizeof(int), "rk_sh_rotator keeps LAPACK pivots as int");

static const double C1 = 0.4886025119029199;
static const double C2[5] = {1.0925484305920792, -1.0925484305920792, 0.31539156525252005, -1.0925484305920792,
                             0.5462742152960396};
static const double C3[7] = {-0.5900435899266435, 2.890611442640554, -0.4570457994644658, 0.3731763325901154,
                             -0.4570457994644658, 1.445305721320277, -0.5900435899266435};

/* Band l (1..3) of the 3DGS basis at d (any length: the polynomials are homogeneous). */
static void sh_band(int l, const double d[3], double *Y)
{
    double x = d[0], y = d[1], z = d[2], xx = x * x, yy = y * y, zz = z * z;
    if (l == 1) {
        Y[0] = -C1 * y;
        Y[1] = C1 * z;
        Y[2] = -C1 * x;
    } else if (l == 2) {
        Y[0] = C2[0] * x * y;
        Y[1] = C2[1] * y * z;
        Y[2] = C2[2] * (2 * zz - xx - yy);
        Y[3] = C2[3] * x * z;
        Y[4] = C2[4] * (xx - yy);
    } else {
        Y[0] = C3[0] * y * (3 * xx - yy);
        Y[1] = C3[1] * x * y * z;
        Y[2] = C3[2] * y * (4 * zz - xx - yy);
        Y[3] = C3[3] * z * (2 * zz - 3 * xx - 3 * yy);
        Y[4] = C3[4] * x * (4 * zz - xx - yy);
        Y[5] = C3[5] * z * (xx - yy);
        Y[6] = C3[6] * x * (xx - 3 * yy);
    }
}

/* The j-th of the 2l+1 fitting directions of band l. */
static void direction(int l, int j, double e[3])
{
    int n = 2 * l + 1;
    double z = 1 - 2 * (j + 0.05) / n, r = sqrt(fmax(0, 1 - z * z)), phi = 2.399963229728653 * j;
    e[0] = r * cos(phi);
    e[1] = r * sin(phi);
    e[2] = z;
}

int rk_sh_band_offset(int l)
{
    return l <= 1 ? 0 : l == 2 ? 9 : 34;
}

int rk_sh_rotator_init(rk_sh_rotator *rot, rk_error *err)
{
    memset(rot, 0, sizeof *rot);
    for (int l = 1; l <= RK_SPLATS_MAX_DEGREE; l++) {
        int n = 2 * l + 1;
        double *A = rot->lu[l - 1];
        for (int j = 0; j < n; j++) {
            double e[3], Y[7];
            direction(l, j, e);
            sh_band(l, e, Y);
            for (int m = 0; m < n; m++) A[j + n * m] = Y[m]; /* column-major */
        }
        lapack_int info = LAPACKE_dgetrf(LAPACK_COL_MAJOR, n, n, A, n, rot->piv[l - 1]);
        if (info != 0) return rk_fail(err, "spherical harmonics band %d: fitting matrix is singular (dgetrf info %d)", l, (int)info);
    }
    return 0;
}

void rk_sh_rotator_matrices(const rk_sh_rotator *rot, const double R[9], int degree, double *M)
{
    for (int l = 1; l <= degree && l <= RK_SPLATS_MAX_DEGREE; l++) {
        int n = 2 * l + 1;
        double *B = M + rk_sh_band_offset(l);
        for (int j = 0; j < n; j++) {
            double e[3], re[3], Y[7];
            direction(l, j, e);
            for (int a = 0; a < 3; a++) re[a] = R[a] * e[0] + R[3 + a] * e[1] + R[6 + a] * e[2]; /* R^T e */
            sh_band(l, re, Y);
            for (int k = 0; k < n; k++) B[j + n * k] = Y[k];
        }
        /* The factors are read only (dgetrs takes a non-const pointer). */
        LAPACKE_dgetrs_work(LAPACK_COL_MAJOR, 'N', n, n, (double *)rot->lu[l - 1], n, rot->piv[l - 1], B, n);
    }
}

void rk_sh_apply(const double *M, int degree, const double *in, double *out)
{
    int k0 = 0;
    for (int l = 1; l <= degree && l <= RK_SPLATS_MAX_DEGREE; l++) {
        int n = 2 * l + 1;
        const double *Mb = M + rk_sh_band_offset(l);
        for (int m = 0; m < n; m++) {
            double v = 0;
            for (int k = 0; k < n; k++) v += Mb[m + n * k] * in[k0 + k];
            out[k0 + m] = v;
        }
        k0 += n;
    }
}

int rk_rotation_check(const double R[9], double tol)
{
    for (int i = 0; i < 9; i++)
        if (!isfinite(R[i])) return 0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double d = R[i] * R[j] + R[3 + i] * R[3 + j] + R[6 + i] * R[6 + j];
            if (fabs(d - (i == j)) > tol) return 0;
        }
    double det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) +
                 R[2] * (R[3] * R[7] - R[4] * R[6]);
    return fabs(det - 1) <= tol;
}

int rk_sh_rotate(const double R[9], int degree, int channels, double *coef, rk_error *err)
{
    if (degree < 0 || degree > RK_SPLATS_MAX_DEGREE)
        return rk_fail(err, "spherical harmonics: degree %d is outside 0..%d", degree, RK_SPLATS_MAX_DEGREE);
    if (channels < 0) return rk_fail(err, "spherical harmonics: %d channels", channels);
    if (!rk_rotation_check(R, 1e-6)) return rk_fail(err, "spherical harmonics: the matrix is not a rotation (orthonormal, det +1, to 1e-6)");
    if (degree == 0 || channels == 0) return 0;
    rk_sh_rotator rot;
    double M[RK_SH_ROTATION_SIZE], in[15];
    if (rk_sh_rotator_init(&rot, err)) return -1;
    rk_sh_rotator_matrices(&rot, R, degree, M);
    int K = (degree + 1) * (degree + 1) - 1;
    for (int c = 0; c < channels; c++) {
        memcpy(in, coef + (size_t)c * K, (size_t)K * sizeof *in);
        rk_sh_apply(M, degree, in, coef + (size_t)c * K);
    }
    return 0;
}
