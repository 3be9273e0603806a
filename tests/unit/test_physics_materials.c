/* Constitutive models (physics/physics.h): P and dP/dF against central finite differences of
 * Psi and P on a set of deformation gradients (rotated, stretched, near-singular, inverted,
 * repeated singular values, random), the rest state (Psi = 0, P = 0, dP/dF = the linear
 * elasticity tensor), rotation invariance and frame indifference, and PSD projection. */
#include "testlib.h"
#include "physics/physics.h"
#include "util/util.h"

#define NMODELS 4
static const rk_material_model models[NMODELS] = {RK_MAT_LINEAR, RK_MAT_COROTATED, RK_MAT_STVK,
                                                  RK_MAT_NEOHOOKEAN};
static const char *const model_names[NMODELS] = {"linear", "corotated", "stvk", "neohookean"};

/* Deterministic: the project's generator (util/util.h), uniform in [-1, 1). */
static uint64_t rng = 0x9e3779b97f4a7c15ULL;
static double urand(void)
{
    return 2 * rk_uniform(&rng) - 1;
}

static void mul3(const double A[9], const double B[9], double C[9])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            C[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
}

static double det3(const double A[9])
{
    return A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) +
           A[2] * (A[3] * A[7] - A[4] * A[6]);
}

/* A random rotation (Rodrigues' formula about a random axis). */
static void rand_rot(double Q[9])
{
    double a[3] = {urand(), urand(), urand()}, n = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    double th = 3.14159265358979 * urand(), c = cos(th), s = sin(th);
    for (int i = 0; i < 3; i++) a[i] /= n;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double K = 0; /* cross-product matrix [a]x */
            if (i == 0 && j == 1) K = -a[2];
            if (i == 0 && j == 2) K = a[1];
            if (i == 1 && j == 0) K = a[2];
            if (i == 1 && j == 2) K = -a[0];
            if (i == 2 && j == 0) K = -a[1];
            if (i == 2 && j == 1) K = a[0];
            Q[3 * i + j] = (i == j ? c : 0) + s * K + (1 - c) * a[i] * a[j];
        }
}

/* F = Q1 diag(s) Q2 with random rotations. */
static void make_F(double s0, double s1, double s2, double F[9])
{
    double Q1[9], Q2[9], D[9] = {s0, 0, 0, 0, s1, 0, 0, 0, s2}, T[9];
    rand_rot(Q1);
    rand_rot(Q2);
    mul3(Q1, D, T);
    mul3(T, Q2, F);
}

#define NF 10
static const char *const F_names[NF] = {
    "rotation",        "rotated+stretch", "stretched",    "near-singular", "inverted",
    "inverted-strong", "repeated-sv",     "two-equal-sv", "random",        "random-large"};
static void test_Fs(double Fs[NF][9])
{
    double Q[9], S[9] = {1.05, 0.02, -0.03, 0.02, 0.97, 0.01, -0.03, 0.01, 1.02};
    rng = 0x9e3779b97f4a7c15ULL;
    rand_rot(Fs[0]);
    rand_rot(Q);
    mul3(Q, S, Fs[1]);
    make_F(1.4, 0.9, 0.7, Fs[2]);
    make_F(1.1, 0.8, 1e-3, Fs[3]);
    make_F(1.2, 0.9, -0.3, Fs[4]);
    make_F(0.9, 0.6, -0.55, Fs[5]);
    make_F(1.2, 1.2, 1.2, Fs[6]);
    make_F(1.1, 1.1, 0.6, Fs[7]);
    for (int i = 0; i < 9; i++) Fs[8][i] = (i % 4 == 0 ? 1.0 : 0.0) + 0.3 * urand();
    for (int i = 0; i < 9; i++) Fs[9][i] = 1.2 * urand();
}

/* max |a - b| / max(max |b|, 1) */
static double rel_err(int n, const double *a, const double *b)
{
    double e = 0, m = 1;
    for (int i = 0; i < n; i++) {
        e = fmax(e, fabs(a[i] - b[i]));
        m = fmax(m, fabs(b[i]));
    }
    return e / m;
}

static const double MU = 1.3, LAMBDA = 4.1, H = 1e-6, FD_TOL = 1e-6;

TEST(lame_parameters)
{
    double mu, la;
    rk_lame(1e6, 0.25, &mu, &la);
    CHECK_CLOSE(mu / 4e5, 1.0, 1e-14);
    CHECK_CLOSE(la / 4e5, 1.0, 1e-14);
    rk_lame(5e6, 0.45, &mu, &la);
    CHECK_CLOSE(mu, 5e6 / 2.9, 1e-14 * 5e6);
    CHECK_CLOSE(la, 5e6 * 0.45 / (1.45 * 0.1), 1e-14 * 5e7);
}

TEST(pk1_matches_finite_differences_of_energy)
{
    double Fs[NF][9], worst = 0;
    test_Fs(Fs);
    CHECK(det3(Fs[4]) < 0 && det3(Fs[5]) < 0, "inverted test F has det >= 0");
    CHECK(fabs(det3(Fs[3])) < 2e-3, "near-singular test F has det %g", det3(Fs[3]));
    for (int m = 0; m < NMODELS; m++)
        for (int f = 0; f < NF; f++) {
            double P[9], Pfd[9], Fp[9];
            rk_pk1(models[m], MU, LAMBDA, Fs[f], P);
            for (int a = 0; a < 9; a++) {
                memcpy(Fp, Fs[f], sizeof Fp);
                Fp[a] += H;
                double ep = rk_psi(models[m], MU, LAMBDA, Fp);
                Fp[a] -= 2 * H;
                double em = rk_psi(models[m], MU, LAMBDA, Fp);
                Pfd[a] = (ep - em) / (2 * H);
            }
            double e = rel_err(9, P, Pfd);
            worst = fmax(worst, e);
            CHECK(e < FD_TOL, "%s at %s F: P vs FD relative error %g", model_names[m], F_names[f],
                  e);
        }
    printf("# P vs FD(Psi): worst relative error %.2e\n", worst);
}

TEST(dpdf_matches_finite_differences_of_pk1)
{
    double Fs[NF][9], worst = 0;
    test_Fs(Fs);
    for (int m = 0; m < NMODELS; m++)
        for (int f = 0; f < NF; f++) {
            double D[81], Dfd[81], Fp[9], Pp[9], Pm[9];
            rk_dpdf(models[m], MU, LAMBDA, Fs[f], D, 0);
            for (int b = 0; b < 9; b++) {
                memcpy(Fp, Fs[f], sizeof Fp);
                Fp[b] += H;
                rk_pk1(models[m], MU, LAMBDA, Fp, Pp);
                Fp[b] -= 2 * H;
                rk_pk1(models[m], MU, LAMBDA, Fp, Pm);
                for (int a = 0; a < 9; a++) Dfd[9 * a + b] = (Pp[a] - Pm[a]) / (2 * H);
            }
            double e = rel_err(81, D, Dfd);
            worst = fmax(worst, e);
            CHECK(e < FD_TOL, "%s at %s F: dP/dF vs FD relative error %g", model_names[m],
                  F_names[f], e);
            for (int a = 0; a < 9; a++)
                for (int b = 0; b < a; b++)
                    CHECK(D[9 * a + b] == D[9 * b + a], "%s at %s F: dP/dF not symmetric",
                          model_names[m], F_names[f]);
        }
    printf("# dP/dF vs FD(P): worst relative error %.2e\n", worst);
}

/* mu (d_ik d_jl + d_il d_jk) + lambda d_ij d_kl */
static void linear_tensor(double mu, double la, double C[81])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++)
                for (int l = 0; l < 3; l++)
                    C[9 * (3 * i + j) + 3 * k + l] =
                        mu * ((i == k && j == l) + (i == l && j == k)) + la * (i == j && k == l);
}

TEST(rest_state_is_stress_free_and_linearizes_to_linear_elasticity)
{
    const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const double params[3][2] = {{1.3, 4.1}, {1.0, 0.0}, {3.4e5, 1.6e7}}; /* incl. nu = 0.49 */
    for (int p = 0; p < 3; p++) {
        double mu = params[p][0], la = params[p][1], C[81];
        linear_tensor(mu, la, C);
        for (int m = 0; m < NMODELS; m++) {
            double P[9], D[81], psi = rk_psi(models[m], mu, la, I);
            rk_pk1(models[m], mu, la, I, P);
            rk_dpdf(models[m], mu, la, I, D, 0);
            CHECK(fabs(psi) <= 1e-15 * (mu + la), "%s: Psi(I) = %g", model_names[m], psi);
            for (int a = 0; a < 9; a++)
                CHECK(fabs(P[a]) <= 1e-15 * (mu + la), "%s: P(I)[%d] = %g", model_names[m], a,
                      P[a]);
            double e = 0;
            for (int a = 0; a < 81; a++) e = fmax(e, fabs(D[a] - C[a]) / (2 * mu + la));
            CHECK(e < 1e-14, "%s (mu %g, lambda %g): dP/dF(I) differs from linear elasticity by %g",
                  model_names[m], mu, la, e);
            rk_dpdf(models[m], mu, la, I, D, 1); /* already PSD: projection must not change it */
            e = rel_err(81, D, C);
            CHECK(e < 1e-12, "%s: projected dP/dF(I) changed by %g", model_names[m], e);
        }
    }
}

TEST(energy_is_rotation_invariant_and_frame_indifferent)
{
    double Fs[NF][9];
    test_Fs(Fs);
    for (int m = 1; m < NMODELS; m++) /* all but linear */
        for (int f = 0; f < NF; f++) {
            double Q[9], QF[9], FQ[9], P[9], PQ[9], QP[9];
            rand_rot(Q);
            mul3(Q, Fs[f], QF);
            mul3(Fs[f], Q, FQ);
            double psi = rk_psi(models[m], MU, LAMBDA, Fs[f]);
            double scale = fmax(1.0, fabs(psi));
            CHECK(fabs(rk_psi(models[m], MU, LAMBDA, QF) - psi) < 1e-12 * scale,
                  "%s at %s F: Psi(QF) = %.15g, Psi(F) = %.15g", model_names[m], F_names[f],
                  rk_psi(models[m], MU, LAMBDA, QF), psi);
            CHECK(fabs(rk_psi(models[m], MU, LAMBDA, FQ) - psi) < 1e-12 * scale,
                  "%s at %s F: Psi(FQ) != Psi(F) (isotropy)", model_names[m], F_names[f]);
            rk_pk1(models[m], MU, LAMBDA, Fs[f], P); /* P(QF) = Q P(F) */
            rk_pk1(models[m], MU, LAMBDA, QF, PQ);
            mul3(Q, P, QP);
            double e = rel_err(9, PQ, QP);
            CHECK(e < 1e-12, "%s at %s F: P(QF) != Q P(F) (%g)", model_names[m], F_names[f], e);
        }
}

TEST(pure_rotation_has_zero_energy_and_stress)
{
    for (int r = 0; r < 5; r++) {
        double Q[9], P[9];
        rand_rot(Q);
        for (int m = 1; m < NMODELS; m++) {
            double psi = rk_psi(models[m], MU, LAMBDA, Q);
            CHECK(fabs(psi) < 1e-13, "%s: Psi(rotation) = %g", model_names[m], psi);
            rk_pk1(models[m], MU, LAMBDA, Q, P);
            for (int a = 0; a < 9; a++)
                CHECK(fabs(P[a]) < 1e-13, "%s: P(rotation)[%d] = %g", model_names[m], a, P[a]);
        }
    }
    /* ... which is exactly what small-strain linear elasticity gets wrong */
    double Q[9];
    rand_rot(Q);
    CHECK(rk_psi(RK_MAT_LINEAR, MU, LAMBDA, Q) > 1e-3, "linear energy of a rotation should be > 0");
}

/* Eigenvalues of a symmetric 9x9 via the library's Jacobi; checked separately in
 * test_physics_impl.c. */
static double min_eig_rel(const double D[81])
{
    double w[9], V[81];
    rk_sym_eig(9, D, w, V);
    return w[0] / fmax(fabs(w[8]), fabs(w[0]));
}

TEST(projected_dpdf_is_psd_and_projection_keeps_psd_input)
{
    double Fs[NF][9];
    int indefinite = 0;
    test_Fs(Fs);
    for (int m = 0; m < NMODELS; m++)
        for (int f = 0; f < NF; f++) {
            double D[81], Dp[81];
            rk_dpdf(models[m], MU, LAMBDA, Fs[f], D, 0);
            rk_dpdf(models[m], MU, LAMBDA, Fs[f], Dp, 1);
            double lo = min_eig_rel(D), lop = min_eig_rel(Dp);
            CHECK(lop > -1e-10, "%s at %s F: projected dP/dF has eigenvalue %g (relative)",
                  model_names[m], F_names[f], lop);
            if (lo < -1e-8)
                indefinite++;
            else
                CHECK(rel_err(81, Dp, D) < 1e-10, "%s at %s F: PSD dP/dF changed by projection",
                      model_names[m], F_names[f]);
        }
    /* corotated/StVK/neohookean are indefinite somewhere in this set: the projection was used */
    CHECK(indefinite >= 3, "only %d indefinite cases: the test exercises nothing", indefinite);
    printf("# %d of %d (model, F) cases had an indefinite dP/dF\n", indefinite, NMODELS * NF);
}

TEST(analytic_projection_matches_the_jacobi_reference)
{
    /* The analytic eigensystem (Smith et al. 2019) against a 9 x 9 Jacobi eigen-solve of the raw
     * dP/dF, on 2000 random deformation gradients per model: singular values from 0.2 to 2.5 of
     * either sign in the last (inverted), repeated ones, near-rest and near-singular ones, and two
     * materials (nu 0.3 and 0.49, and a negative lambda for the linear model's clamp). */
    double worst[NMODELS] = {0}, mus[2] = {MU, 1.0}, lambdas[2] = {LAMBDA, 49.0};
    int projected[NMODELS] = {0};
    rng = 77;
    for (int m = 0; m < NMODELS; m++)
        for (int trial = 0; trial < 2000; trial++) {
            double s[3], F[9], A[81], J[81], scale = 0, e = 0;
            int kind = trial % 5;
            for (int i = 0; i < 3; i++) s[i] = 0.2 + 2.3 * fabs(urand());
            if (kind == 1) s[2] = -s[2];                     /* inverted */
            if (kind == 2) s[1] = s[0];                      /* repeated */
            if (kind == 3) s[0] = 1 + 1e-4 * urand(), s[1] = 1 + 1e-4 * urand(), s[2] = 1 + 1e-4 * urand();
            if (kind == 4) s[2] = 1e-3 * urand();            /* near-singular, either sign */
            make_F(s[0], s[1], s[2], F);
            double mu = mus[trial % 2], la = m == 0 && trial % 7 == 0 ? -mu : lambdas[trial % 2];
            rk_dpdf(models[m], mu, la, F, A, 1);
            rk_dpdf(models[m], mu, la, F, J, RK_PROJECT_JACOBI);
            for (int a = 0; a < 81; a++) scale = fmax(scale, fabs(J[a])), e = fmax(e, fabs(A[a] - J[a]));
            double raw[81];
            rk_dpdf(models[m], mu, la, F, raw, 0);
            projected[m] += memcmp(raw, A, sizeof raw) != 0;
            worst[m] = fmax(worst[m], e / scale);
        }
    for (int m = 0; m < NMODELS; m++) {
        printf("# analytic projection of %s against Jacobi: worst relative difference %.2g (%d of 2000 projected)\n",
               model_names[m], worst[m], projected[m]);
        CHECK(worst[m] < 1e-10, "%s: analytic projection off by %g", model_names[m], worst[m]);
        CHECK(projected[m] > 0, "%s: no case needed projection", model_names[m]);
    }
}

TEST(corotated_survives_opposite_singular_values)
{
    /* s = (1, 1, -1) after a rotation: s1 + s2 = 0, where R is discontinuous. Outputs must stay
     * finite and the projected tensor PSD. */
    double Fs[3][9] = {{1, 0, 0, 0, 1, 0, 0, 0, -1}, {-1, 0, 0, 0, 1, 0, 0, 0, 1}}, D[81], P[9];
    rng = 42;
    make_F(1, 1, -1, Fs[2]); /* s1 + s2 ~ 1e-16 rather than exactly 0 */
    for (int c = 0; c < 3; c++) {
        const double *F = Fs[c];
        rk_dpdf(RK_MAT_COROTATED, MU, LAMBDA, F, D, 0);
        rk_pk1(RK_MAT_COROTATED, MU, LAMBDA, F, P);
        for (int a = 0; a < 81; a++) CHECK(isfinite(D[a]), "dP/dF[%d] = %g", a, D[a]);
        for (int a = 0; a < 9; a++) CHECK(isfinite(P[a]), "P[%d] = %g", a, P[a]);
        CHECK(isfinite(rk_psi(RK_MAT_COROTATED, MU, LAMBDA, F)), "Psi not finite");
        rk_dpdf(RK_MAT_COROTATED, MU, LAMBDA, F, D, 1);
        for (int a = 0; a < 81; a++) CHECK(isfinite(D[a]), "projected dP/dF[%d] = %g", a, D[a]);
        CHECK(min_eig_rel(D) > -1e-10, "projected dP/dF not PSD: %g", min_eig_rel(D));
    }
    /* F = 0: every model returns finite numbers */
    double Z[9] = {0};
    for (int m = 0; m < NMODELS; m++) {
        rk_dpdf(models[m], MU, LAMBDA, Z, D, 1);
        rk_pk1(models[m], MU, LAMBDA, Z, P);
        for (int a = 0; a < 81; a++)
            CHECK(isfinite(D[a]), "%s: dP/dF(0) not finite", model_names[m]);
        for (int a = 0; a < 9; a++) CHECK(isfinite(P[a]), "%s: P(0) not finite", model_names[m]);
    }
}

TEST(neohookean_energy_matches_eq16)
{
    /* Psi = 1/2 [lbar (J - gamma)^2 + mu tr(F^T F) - E0], evaluated independently here. */
    double Fs[NF][9];
    test_Fs(Fs);
    for (int f = 0; f < NF; f++) {
        double lbar = LAMBDA + MU, gamma = 1 + MU / lbar, J = det3(Fs[f]), I1 = 0;
        for (int a = 0; a < 9; a++) I1 += Fs[f][a] * Fs[f][a];
        double E0 = lbar * (1 - gamma) * (1 - gamma) + 3 * MU; /* Psi(I) = 0 */
        double want = 0.5 * (lbar * (J - gamma) * (J - gamma) + MU * I1 - E0);
        CHECK_CLOSE(rk_psi(RK_MAT_NEOHOOKEAN, MU, LAMBDA, Fs[f]), want, 1e-13);
    }
}

int main(void)
{
    RUN(lame_parameters);
    RUN(pk1_matches_finite_differences_of_energy);
    RUN(dpdf_matches_finite_differences_of_pk1);
    RUN(rest_state_is_stress_free_and_linearizes_to_linear_elasticity);
    RUN(energy_is_rotation_invariant_and_frame_indifferent);
    RUN(pure_rotation_has_zero_energy_and_stress);
    RUN(projected_dpdf_is_psd_and_projection_keeps_psd_input);
    RUN(analytic_projection_matches_the_jacobi_reference);
    RUN(corotated_survives_opposite_singular_values);
    RUN(neohookean_energy_matches_eq16);
    return test_finish();
}
