/* physics_impl.h itself: included here twice more, as float (prefix rkf_) and as a second
 * double copy (prefix rkd_), which also exposes its static helpers (rkd_svd3, rkd_polar3).
 * Checks the eigen-decomposition (Jacobi; for n > 3 tridiagonal QL, against LAPACK), the PSD
 * projection, the signed 3x3 SVD / polar decomposition, that float results match double, and
 * that the second double copy agrees with the library's rk_* functions. */
#include <lapacke.h>

#include "testlib.h"
#include "physics/physics.h"
#include "util/util.h"

#define PHYS_REAL float
#define PHYS_FLOAT 1
#define PHYS_FN(name) rkf_##name
#include "physics/physics_impl.h"
#undef PHYS_REAL
#undef PHYS_FLOAT
#undef PHYS_FN

#define PHYS_REAL double
#define PHYS_FN(name) rkd_##name
#include "physics/physics_impl.h"
#undef PHYS_REAL
#undef PHYS_FN

#define NMODELS 4
static const rk_material_model models[NMODELS] = {RK_MAT_LINEAR, RK_MAT_COROTATED, RK_MAT_STVK,
                                                  RK_MAT_NEOHOOKEAN};
static const char *const model_names[NMODELS] = {"linear", "corotated", "stvk", "neohookean"};

static uint64_t rng = 0x853c49e6748fea9bULL;
static double urand(void) /* uniform in [-1, 1), the project's generator (util/util.h) */
{
    return 2 * rk_uniform(&rng) - 1;
}

/* A random n x n orthogonal matrix: modified Gram-Schmidt (twice) on a random matrix;
 * columns are the orthonormal vectors (row-major). */
static void rand_orth(int n, double *Q)
{
    for (int i = 0; i < n * n; i++) Q[i] = urand();
    for (int pass = 0; pass < 2; pass++)
        for (int c = 0; c < n; c++) {
            for (int p = 0; p < c; p++) {
                double d = 0;
                for (int r = 0; r < n; r++) d += Q[n * r + p] * Q[n * r + c];
                for (int r = 0; r < n; r++) Q[n * r + c] -= d * Q[n * r + p];
            }
            double nrm = 0;
            for (int r = 0; r < n; r++) nrm += Q[n * r + c] * Q[n * r + c];
            nrm = sqrt(nrm);
            for (int r = 0; r < n; r++) Q[n * r + c] /= nrm;
        }
}

/* A = Q diag(w) Q^T */
static void compose(int n, const double *Q, const double *w, double *A)
{
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            double s = 0;
            for (int k = 0; k < n; k++) s += Q[n * i + k] * w[k] * Q[n * j + k];
            A[n * i + j] = s;
        }
}

static double max_abs(int n, const double *a)
{
    double m = 0;
    for (int i = 0; i < n; i++) m = fmax(m, fabs(a[i]));
    return m;
}

/* Checks A = V diag(w) V^T, V^T V = I, w ascending; returns a message or NULL. */
static const char *check_eig(int n, const double *A, const double *w, const double *V, double tol)
{
    static double R[144];
    double scale = fmax(max_abs(n * n, A), 1e-300);
    compose(n, V, w, R);
    for (int i = 0; i < n * n; i++)
        if (fabs(R[i] - A[i]) > tol * scale) return "V diag(w) V^T does not reconstruct A";
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            double d = 0;
            for (int k = 0; k < n; k++) d += V[n * k + i] * V[n * k + j];
            if (fabs(d - (i == j)) > tol) return "V is not orthonormal";
        }
    for (int i = 0; i + 1 < n; i++)
        if (w[i] > w[i + 1]) return "eigenvalues not ascending";
    return NULL;
}

TEST(jacobi_random_symmetric)
{
    const int sizes[3] = {3, 9, 12};
    for (int s = 0; s < 3; s++)
        for (int trial = 0; trial < 20; trial++) {
            int n = sizes[s];
            double A[144], w[12], V[144];
            for (int i = 0; i < n; i++)
                for (int j = 0; j <= i; j++) A[n * i + j] = A[n * j + i] = urand() * 10;
            rk_sym_eig(n, A, w, V);
            const char *msg = check_eig(n, A, w, V, 1e-12);
            CHECK(!msg, "n = %d trial %d: %s", n, trial, msg);
        }
}

TEST(jacobi_known_spectra_with_repeats)
{
    static const double spectra[][12] = {
        {2, 2, 2},
        {1, 1, 4},
        {-3, 0, 0},
        {1e-9, 1, 1e6},
        {-2, -2, 0, 0, 0, 1, 1, 5, 5},
        {3, 3, 3, 3, 3, 3, 3, 3, 7},
        {-1, -1, -1, 0, 0, 0, 2, 2, 2, 6, 6, 6},
        {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1},
    };
    static const int ns[] = {3, 3, 3, 3, 9, 9, 12, 12};
    for (int c = 0; c < 8; c++) {
        int n = ns[c];
        double Q[144], A[144], w[12], V[144];
        rand_orth(n, Q);
        compose(n, Q, spectra[c], A);
        rk_sym_eig(n, A, w, V);
        const char *msg = check_eig(n, A, w, V, 1e-12);
        CHECK(!msg, "case %d (n = %d): %s", c, n, msg);
        double scale = max_abs(n, spectra[c]);
        for (int i = 0; i < n; i++)
            CHECK(fabs(w[i] - spectra[c][i]) < 1e-12 * scale, "case %d: w[%d] = %.15g, want %g", c,
                  i, w[i], spectra[c][i]);
    }
}

TEST(jacobi_trivial_inputs)
{
    double Z[81] = {0}, D[81] = {0}, w[9], V[81];
    rk_sym_eig(9, Z, w, V);
    for (int i = 0; i < 9; i++) CHECK(w[i] == 0, "zero matrix: w[%d] = %g", i, w[i]);
    for (int i = 0; i < 81; i++) CHECK(V[i] == (i % 10 == 0), "zero matrix: V not identity");
    for (int i = 0; i < 9; i++) D[10 * i] = 9 - i; /* diagonal, descending */
    rk_sym_eig(9, D, w, V);
    for (int i = 0; i < 9; i++) CHECK(w[i] == i + 1, "diagonal: w[%d] = %g", i, w[i]);
    const char *msg = check_eig(9, D, w, V, 0);
    CHECK(!msg, "diagonal: %s", msg);
    double one[1] = {-2.5}, w1[1], V1[1];
    rk_sym_eig(1, one, w1, V1);
    CHECK(w1[0] == -2.5 && V1[0] == 1, "1x1");
}

TEST(psd_projection)
{
    /* indefinite with a known spectrum: result is Q max(w, 0) Q^T */
    static const double spectra[][12] = {
        {-5, -1e-3, 0, 0.5, 0.5, 2, 3, 3, 40},
        {-1, -1, -1, -1, 2, 2, 2, 3, 4, 5, 6, 7},
        {-1, -2, -3, -4, -5, -6, -7, -8, -9},
    };
    static const int ns[] = {9, 12, 9};
    for (int c = 0; c < 3; c++) {
        int n = ns[c];
        double Q[144], A[144], want[144], wp[12];
        rand_orth(n, Q);
        compose(n, Q, spectra[c], A);
        for (int i = 0; i < n; i++) wp[i] = fmax(spectra[c][i], 0);
        compose(n, Q, wp, want);
        rk_project_psd(n, A);
        double scale = max_abs(n, spectra[c]);
        for (int i = 0; i < n * n; i++)
            CHECK(fabs(A[i] - want[i]) < 1e-12 * scale, "case %d: projected[%d] = %g, want %g", c,
                  i, A[i], want[i]);
        for (int i = 0; i < n; i++)
            for (int j = 0; j < i; j++)
                CHECK(A[n * i + j] == A[n * j + i], "case %d: not symmetric", c);
    }
    /* already PSD (full rank, and rank-deficient B B^T): unchanged */
    for (int rank = 12; rank >= 4; rank -= 8) {
        double B[144], A[144], A0[144];
        for (int i = 0; i < 144; i++) B[i] = urand();
        for (int i = 0; i < 12; i++)
            for (int j = 0; j < 12; j++) {
                double s = 0;
                for (int k = 0; k < rank; k++) s += B[12 * i + k] * B[12 * j + k];
                A[12 * i + j] = s;
            }
        memcpy(A0, A, sizeof A);
        rk_project_psd(12, A);
        for (int i = 0; i < 144; i++)
            CHECK(fabs(A[i] - A0[i]) < 1e-12 * max_abs(144, A0), "rank %d PSD input changed at %d",
                  rank, i);
    }
}

static double det3(const double A[9])
{
    return A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) +
           A[2] * (A[3] * A[7] - A[4] * A[6]);
}

/* |M^T M - I| and |det M - 1| */
static double rotation_defect(const double M[9])
{
    double e = fabs(det3(M) - 1);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double d = M[i] * M[j] + M[3 + i] * M[3 + j] + M[6 + i] * M[6 + j];
            e = fmax(e, fabs(d - (i == j)));
        }
    return e;
}

TEST(signed_svd_and_polar)
{
    double Fs[16][9] = {
        {1, 0, 0, 0, 1, 0, 0, 0, 1},          {0, 0, 0, 0, 0, 0, 0, 0, 0},
        {1, 0, 0, 0, 1, 0, 0, 0, -1},         {-1, 0, 0, 0, 1, 0, 0, 0, 1},
        {-1, 0, 0, 0, -1, 0, 0, 0, -1},       {1, 2, 3, 2, 4, 6, 3, 6, 9}, /* rank 1 */
        {1, 2, 3, 4, 5, 6, 7, 8, 9},                                       /* rank 2 */
        {0, 0, 0, 0, 0, 0, 0, 0, 2.5},                                     /* rank 1, aligned */
        {2, 0, 0, 0, 2, 0, 0, 0, 1e-14},                                   /* nearly singular */
        {1e-3, 0, 0, 0, 1e-3, 0, 0, 0, 1e-3},
    };
    for (int c = 10; c < 16; c++) { /* random, some inverted */
        for (int i = 0; i < 9; i++) Fs[c][i] = urand() * (c - 8);
    }
    for (int c = 0; c < 16; c++) {
        const double *F = Fs[c];
        double U[9], s[3], V[9], R[9], sp[3], USV[9], RtF[9];
        double scale = fmax(max_abs(9, F), 1e-300);
        rkd_svd3(F, U, s, V);
        CHECK(rotation_defect(U) < 1e-12, "case %d: U not a rotation (%g)", c, rotation_defect(U));
        CHECK(rotation_defect(V) < 1e-12, "case %d: V not a rotation (%g)", c, rotation_defect(V));
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                USV[3 * i + j] = U[3 * i] * s[0] * V[3 * j] + U[3 * i + 1] * s[1] * V[3 * j + 1] +
                                 U[3 * i + 2] * s[2] * V[3 * j + 2];
        for (int i = 0; i < 9; i++)
            CHECK(fabs(USV[i] - F[i]) < 1e-12 * scale, "case %d: U S V^T differs from F by %g", c,
                  fabs(USV[i] - F[i]));
        CHECK(s[0] >= s[1] - 1e-12 * scale && s[1] >= fabs(s[2]) - 1e-12 * scale,
              "case %d: singular values not ordered: %g %g %g", c, s[0], s[1], s[2]);
        if (fabs(det3(F)) > 1e-9 * scale * scale * scale)
            CHECK((s[2] < 0) == (det3(F) < 0), "case %d: sign of s2 = %g, det F = %g", c, s[2],
                  det3(F));
        rkd_polar3(F, R, sp);
        CHECK(rotation_defect(R) < 1e-12, "case %d: R not a rotation", c);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                RtF[3 * i + j] = R[i] * F[j] + R[3 + i] * F[3 + j] + R[6 + i] * F[6 + j];
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < i; j++)
                CHECK(fabs(RtF[3 * i + j] - RtF[3 * j + i]) < 1e-12 * scale,
                      "case %d: R^T F not symmetric", c);
    }
}

/* F for the precision comparison: moderate strains, one inverted. */
#define NFP 5
static void moderate_Fs(double Fs[NFP][9])
{
    static const double base[NFP][9] = {
        {1.2, 0.1, 0.0, -0.05, 0.9, 0.1, 0.02, 0.0, 1.05},
        {0.8, -0.3, 0.1, 0.3, 0.8, 0.0, 0.0, 0.1, 1.3},
        {1.0, 0.4, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0},
        {1.1, 0.0, 0.1, 0.0, 0.95, 0.0, 0.0, 0.1, -0.5},
        {0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0}, /* a rotation */
    };
    for (int c = 0; c < NFP; c++)
        for (int i = 0; i < 9; i++) Fs[c][i] = (double)(float)base[c][i]; /* same inputs */
}

/* max |float - double| / max |double| */
static double prec_err(int n, const float *f, const double *d)
{
    double e = 0, m = 1e-300;
    for (int i = 0; i < n; i++) {
        e = fmax(e, fabs((double)f[i] - d[i]));
        m = fmax(m, fabs(d[i]));
    }
    return e / m;
}

/* Small strains in float: energy and stress come from Hd = F - I (physics_impl.h), so they keep
 * their relative precision however small the strain; through F they would lose it (at strain 1e-5,
 * float resolves |F|^2 - 3 and J - 1 to ~1e-2 and the energy not at all). Corotated still goes
 * through F's polar decomposition and is reported, not held to this. */
TEST(float_keeps_small_strains)
{
    const double mu = 3.4e5, la = 1.6e6;
    for (double strain = 1e-3; strain >= 1e-6; strain /= 10)
        for (int m = 0; m < NMODELS; m++) {
            double Hd[9], P[9];
            float Hf[9], Pf[9];
            for (int i = 0; i < 9; i++) {
                Hf[i] = (float)(strain * (2 * urand() - 1));
                Hd[i] = Hf[i];
            }
            double psi = rk_psi_h(models[m], mu, la, Hd);
            float psif = rkf_psi_h(models[m], (float)mu, (float)la, Hf);
            rk_pk1_h(models[m], mu, la, Hd, P);
            rkf_pk1_h(models[m], (float)mu, (float)la, Hf, Pf);
            double epsi = fabs((double)psif - psi) / fabs(psi), eP = prec_err(9, Pf, P);
            if (models[m] == RK_MAT_COROTATED) {
                printf("# corotated at strain %g: float Psi off by %.2g, P by %.2g (relative)\n", strain, epsi, eP);
                continue;
            }
            CHECK(epsi < 1e-4, "%s at strain %g: float Psi off by %.3g relative", model_names[m], strain, epsi);
            CHECK(eP < 1e-5, "%s at strain %g: float P off by %.3g relative", model_names[m], strain, eP);
        }
}

TEST(float_matches_double)
{
    const double mu = 3.4e5, la = 1.6e6, tol = 1e-5;
    double Fs[NFP][9], worst = 0;
    moderate_Fs(Fs);
    for (int m = 0; m < NMODELS; m++)
        for (int c = 0; c < NFP; c++) {
            float Ff[9], Pf[9], Df[81], mf, lf;
            double P[9], D[81];
            for (int i = 0; i < 9; i++) Ff[i] = (float)Fs[c][i];
            mf = (float)mu;
            lf = (float)la;
            double psi = rk_psi(models[m], mu, la, Fs[c]);
            float psif = rkf_psi(models[m], mf, lf, Ff);
            /* Psi and P of nearly stress-free states are differences of terms of size ~ mu and
             * lambda, which float resolves only to ~eps (lambda + mu): compare them to the
             * energy / stress of a 1% strain, 1e-2 (2 mu + lambda), when they are smaller. */
            const double ref_min = 1e-2 * (2 * mu + la);
            double e = fabs((double)psif - psi) / fmax(fabs(psi), ref_min);
            worst = fmax(worst, e);
            CHECK(e < tol, "%s F%d: Psi float %.8g double %.15g", model_names[m], c, psif, psi);
            rk_pk1(models[m], mu, la, Fs[c], P);
            rkf_pk1(models[m], mf, lf, Ff, Pf);
            double Pscale = 0;
            for (int i = 0; i < 9; i++) Pscale = fmax(Pscale, fabs(P[i]));
            e = 0;
            for (int i = 0; i < 9; i++) e = fmax(e, fabs(Pf[i] - P[i]));
            e /= fmax(Pscale, ref_min);
            worst = fmax(worst, e);
            CHECK(e < tol, "%s F%d: P float vs double %g", model_names[m], c, e);
            for (int project = 0; project < 2; project++) {
                rk_dpdf(models[m], mu, la, Fs[c], D, project);
                rkf_dpdf(models[m], mf, lf, Ff, Df, project);
                e = prec_err(81, Df, D);
                worst = fmax(worst, e);
                CHECK(e < tol, "%s F%d: dP/dF (project %d) float vs double %g", model_names[m], c,
                      project, e);
            }
        }
    /* tet kernels */
    const double X[12] = {0, 0, 0, 0.1, 0, 0, 0.01, 0.09, 0, 0.02, 0.01, 0.1};
    float Xf[12], xf[12], Dmf[9], gf[12] = {0}, Hf[144];
    double Dm[9], x[12], g[12] = {0}, H[144];
    for (int i = 0; i < 12; i++) {
        Xf[i] = (float)X[i];
        x[i] = X[i] * 1.1 + 0.01 * urand();
        xf[i] = (float)x[i];
        x[i] = xf[i];
    }
    double vol = rk_tet_rest(X, Dm);
    float volf = rkf_tet_rest(Xf, Dmf);
    CHECK(fabs(volf - vol) < tol * vol, "tet volume float %g double %g", volf, vol);
    for (int m = 0; m < NMODELS; m++) {
        double E = rk_tet_energy(models[m], mu, la, x, Dm, vol);
        float Ef = rkf_tet_energy(models[m], (float)mu, (float)la, xf, Dmf, volf);
        CHECK(fabs(Ef - E) < tol * fabs(E), "%s: tet energy float %g double %g", model_names[m], Ef,
              E);
        memset(g, 0, sizeof g);
        memset(gf, 0, sizeof gf);
        rk_tet_gradient(models[m], mu, la, x, Dm, vol, g);
        rkf_tet_gradient(models[m], (float)mu, (float)la, xf, Dmf, volf, gf);
        double e = prec_err(12, gf, g);
        CHECK(e < tol, "%s: tet gradient float vs double %g", model_names[m], e);
        rk_tet_hessian(models[m], mu, la, x, Dm, vol, H, 1);
        rkf_tet_hessian(models[m], (float)mu, (float)la, xf, Dmf, volf, Hf, 1);
        e = prec_err(144, Hf, H);
        CHECK(e < tol, "%s: tet Hessian float vs double %g", model_names[m], e);
    }
    printf("# float vs double (material level): worst relative difference %.2e\n", worst);
}

TEST(float_jacobi)
{
    double Q[81], A[81], w[9], V[81];
    float Af[81], wf[9], Vf[81];
    static const double spec[9] = {-2, -1, 0, 0.5, 1, 1, 3, 4, 10};
    rand_orth(9, Q);
    compose(9, Q, spec, A);
    for (int i = 0; i < 81; i++) {
        Af[i] = (float)A[i];
        A[i] = Af[i];
    }
    rk_sym_eig(9, A, w, V);
    rkf_sym_eig(9, Af, wf, Vf);
    CHECK(prec_err(9, wf, w) < 1e-5, "float eigenvalues differ by %g", prec_err(9, wf, w));
    for (int i = 0; i < 9; i++)
        for (int j = 0; j < 9; j++) {
            double d = 0;
            for (int k = 0; k < 9; k++) d += (double)Vf[9 * k + i] * Vf[9 * k + j];
            CHECK(fabs(d - (i == j)) < 1e-5, "float V not orthonormal (%d, %d): %g", i, j, d);
        }
}

/* sym_eig for 3 < n <= 12 (Householder tridiagonalization and implicit QL) against LAPACK's dsyev:
 * random symmetric matrices, repeated eigenvalues, rank-deficient B B^T, scales of 1e-300 and
 * 1e300 (no square may under- or overflow), and a NaN in, NaN everywhere out. */
static const char *against_lapack(int n, const double *A, double tol)
{
    double Al[144], wl[12], w[12], V[144];
    memcpy(Al, A, sizeof(double) * (size_t)(n * n));
    if (LAPACKE_dsyev(LAPACK_ROW_MAJOR, 'N', 'U', n, Al, n, wl)) return "dsyev failed";
    rk_sym_eig(n, A, w, V);
    double scale = fmax(max_abs(n, wl), 1e-300 * 1e-8);
    for (int i = 0; i < n; i++)
        if (!(fabs(w[i] - wl[i]) <= tol * scale)) return "eigenvalues differ from LAPACK's";
    return check_eig(n, A, w, V, tol);
}

TEST(sym_eig_tridiagonal_ql_matches_lapack)
{
    static const int sizes[] = {4, 6, 9, 12};
    for (int s = 0; s < 4; s++)
        for (int trial = 0; trial < 50; trial++) {
            int n = sizes[s];
            double A[144];
            for (int i = 0; i < n; i++)
                for (int j = 0; j <= i; j++) A[n * i + j] = A[n * j + i] = urand() * 10;
            if (trial % 5 == 4) /* an already tridiagonal one and one with zero columns */
                for (int i = 0; i < n; i++)
                    for (int j = 0; j < n; j++)
                        if (abs(i - j) > 1 || (trial % 10 == 9 && (i == 1 || j == 1))) A[n * i + j] = 0;
            const char *msg = against_lapack(n, A, 1e-12);
            CHECK(!msg, "random n = %d trial %d: %s", n, trial, msg);
        }
    /* repeated eigenvalues */
    static const double spec[][12] = {{-1, -1, -1, 0, 0, 0, 2, 2, 2, 6, 6, 6}, {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1},
                                      {-3, -3, -3, -3, -3, -3, 5, 5, 5, 5, 5, 5}};
    for (int c = 0; c < 3; c++) {
        double Q[144], A[144];
        rand_orth(12, Q);
        compose(12, Q, spec[c], A);
        const char *msg = against_lapack(12, A, 1e-12);
        CHECK(!msg, "repeated spectrum %d: %s", c, msg);
    }
    /* rank-deficient PSD, and the same scaled by 1e-300 and 1e300 */
    for (int rank = 1; rank <= 9; rank += 4) {
        double B[144], A[144], As[144], w[12], ws[12], V[144];
        for (int i = 0; i < 144; i++) B[i] = urand();
        for (int i = 0; i < 12; i++)
            for (int j = 0; j < 12; j++) {
                double t = 0;
                for (int k = 0; k < rank; k++) t += B[12 * i + k] * B[12 * j + k];
                A[12 * i + j] = t;
            }
        const char *msg = against_lapack(12, A, 1e-12);
        CHECK(!msg, "rank %d: %s", rank, msg);
        rk_sym_eig(12, A, w, V);
        for (int i = 0; i < 12 - rank; i++) CHECK(fabs(w[i]) < 1e-13 * w[11], "rank %d: w[%d] = %g", rank, i, w[i]);
        for (int e = -300; e <= 300; e += 600) {
            double f = pow(10, e);
            for (int i = 0; i < 144; i++) As[i] = A[i] * f;
            rk_sym_eig(12, As, ws, V);
            for (int i = 0; i < 12; i++)
                CHECK(fabs(ws[i] / f - w[i]) <= 1e-12 * w[11], "rank %d scaled 1e%d: w[%d] = %g, want %g", rank, e, i,
                      ws[i] / f, w[i]);
            msg = check_eig(12, As, ws, V, 1e-12);
            CHECK(!msg, "rank %d scaled 1e%d: %s", rank, e, msg);
        }
    }
    /* NaN in, NaN out (w and V) */
    {
        double A[81], w[9], V[81];
        for (int i = 0; i < 81; i++) A[i] = 1;
        A[40] = NAN;
        rk_sym_eig(9, A, w, V);
        for (int i = 0; i < 9; i++) CHECK(isnan(w[i]), "NaN in: w[%d] = %g", i, w[i]);
        for (int i = 0; i < 81; i++) CHECK(isnan(V[i]), "NaN in: V[%d] = %g", i, V[i]);
    }
    /* float: 12 x 12 indefinite, against double */
    {
        double Q[144], A[144], w[12], V[144];
        float Af[144], wf[12], Vf[144];
        static const double sp[12] = {-7, -2, -2, -1e-3, 0, 0, 0.5, 1, 3, 3, 9, 20};
        rand_orth(12, Q);
        compose(12, Q, sp, A);
        for (int i = 0; i < 144; i++) Af[i] = (float)A[i], A[i] = Af[i];
        rk_sym_eig(12, A, w, V);
        rkf_sym_eig(12, Af, wf, Vf);
        for (int i = 0; i < 12; i++) CHECK(fabs(wf[i] - w[i]) < 2e-5 * 20, "float w[%d] = %g, want %g", i, wf[i], w[i]);
    }
}

TEST(second_double_copy_agrees_with_library)
{
    double Fs[NFP][9];
    moderate_Fs(Fs);
    for (int m = 0; m < NMODELS; m++)
        for (int c = 0; c < NFP; c++) {
            double D1[81], D2[81], P1[9], P2[9];
            double e1 = rk_psi(models[m], 1.5, 2.5, Fs[c]),
                   e2 = rkd_psi(models[m], 1.5, 2.5, Fs[c]);
            CHECK(fabs(e1 - e2) <= 1e-14 * (fabs(e1) + 1), "%s: Psi differs", model_names[m]);
            rk_pk1(models[m], 1.5, 2.5, Fs[c], P1);
            rkd_pk1(models[m], 1.5, 2.5, Fs[c], P2);
            for (int i = 0; i < 9; i++)
                CHECK(fabs(P1[i] - P2[i]) <= 1e-14 * (fabs(P1[i]) + 1), "%s: P differs",
                      model_names[m]);
            rk_dpdf(models[m], 1.5, 2.5, Fs[c], D1, 1);
            rkd_dpdf(models[m], 1.5, 2.5, Fs[c], D2, 1);
            for (int i = 0; i < 81; i++)
                CHECK(fabs(D1[i] - D2[i]) <= 1e-14 * (fabs(D1[i]) + 1), "%s: dP/dF differs",
                      model_names[m]);
        }
}

int main(void)
{
    RUN(jacobi_random_symmetric);
    RUN(jacobi_known_spectra_with_repeats);
    RUN(jacobi_trivial_inputs);
    RUN(psd_projection);
    RUN(signed_svd_and_polar);
    RUN(float_matches_double);
    RUN(float_keeps_small_strains);
    RUN(float_jacobi);
    RUN(sym_eig_tridiagonal_ql_matches_lapack);
    RUN(second_double_copy_agrees_with_library);
    return test_finish();
}
