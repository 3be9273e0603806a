/* Tet element kernels (physics/physics.h): rest data, F, and the gradient / Hessian against
 * central finite differences of the energy / gradient, for every material, at rest-mapped,
 * stretched, near-degenerate and inverted configurations; projected Hessians are PSD. */
#include "testlib.h"
#include "physics/physics.h"
#include "util/util.h"

#define NMODELS 4
static const rk_material_model models[NMODELS] = {RK_MAT_LINEAR, RK_MAT_COROTATED, RK_MAT_STVK,
                                                  RK_MAT_NEOHOOKEAN};
static const char *const model_names[NMODELS] = {"linear", "corotated", "stvk", "neohookean"};

static uint64_t rng = 0x2545f4914f6cdd1dULL;
static double urand(void) /* uniform in [-1, 1), the project's generator (util/util.h) */
{
    return 2 * rk_uniform(&rng) - 1;
}

/* max |a - b| / max(max |b|, ref_min) */
static double rel_err(int n, const double *a, const double *b, double ref_min)
{
    double e = 0, m = ref_min;
    for (int i = 0; i < n; i++) {
        e = fmax(e, fabs(a[i] - b[i]));
        m = fmax(m, fabs(b[i]));
    }
    return e / m;
}

/* A well-shaped rest tet of edge ~0.1 m with a random offset, positively oriented. */
static const double X_REST[12] = {0.31, -0.20, 0.05, 0.41, -0.18, 0.06,
                                  0.33, -0.11, 0.04, 0.32, -0.19, 0.14};

/* x = A X + t (+ noise) for the rest tet */
static void deform(const double A[9], double noise, double x[12])
{
    for (int v = 0; v < 4; v++)
        for (int i = 0; i < 3; i++) {
            double s = 0.05 * i;
            for (int j = 0; j < 3; j++) s += A[3 * i + j] * X_REST[3 * v + j];
            x[3 * v + i] = s + noise * urand();
        }
}

#define NX 6
static const char *const x_names[NX] = {"rest",      "stretched", "random",
                                        "near-flat", "inverted",  "sheared"};
static void test_xs(double xs[NX][12])
{
    const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const double S[9] = {1.3, 0, 0, 0, 0.8, 0, 0, 0, 1.1};
    const double Flat[9] = {1, 0, 0, 0, 1, 0, 0, 0, 0.002};
    const double Inv[9] = {0.9, 0.1, 0, 0, 1.1, 0, 0, 0, -0.4};
    const double Sh[9] = {1, 0.6, 0, 0, 1, 0.3, 0, 0, 1};
    rng = 0x2545f4914f6cdd1dULL;
    deform(I, 0, xs[0]);
    deform(S, 0, xs[1]);
    deform(I, 0.02, xs[2]);
    deform(Flat, 0, xs[3]);
    deform(Inv, 0.005, xs[4]);
    deform(Sh, 0, xs[5]);
}

static const double MU = 3.4e5, LAMBDA = 1.6e6; /* E = 1e6 Pa, nu = 0.41 */

TEST(rest_data_and_deformation_gradient)
{
    double Dm_inv[9], F[9], x[12];
    const double unit[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    double vol = rk_tet_rest(unit, Dm_inv);
    CHECK_CLOSE(vol, 1.0 / 6.0, 1e-15);
    for (int a = 0; a < 9; a++) CHECK(Dm_inv[a] == (a % 4 == 0), "Dm_inv of the unit tet");
    /* swapping two vertices flips the sign of the volume */
    double sw[12];
    memcpy(sw, unit, sizeof sw);
    memcpy(sw + 3, unit + 6, 3 * sizeof(double));
    memcpy(sw + 6, unit + 3, 3 * sizeof(double));
    CHECK_CLOSE(rk_tet_rest(sw, Dm_inv), -1.0 / 6.0, 1e-15);
    /* F of x = A X + t is A */
    const double A[9] = {1.2, 0.3, -0.1, 0.05, 0.9, 0.2, -0.3, 0.1, 1.05};
    vol = rk_tet_rest(X_REST, Dm_inv);
    CHECK(vol > 0, "rest tet volume %g", vol);
    deform(A, 0, x);
    rk_tet_F(x, Dm_inv, F);
    for (int a = 0; a < 9; a++)
        CHECK(fabs(F[a] - A[a]) < 1e-12, "F[%d] = %.15g, want %g", a, F[a], A[a]);
    /* a degenerate tet gives zero volume and Dm_inv, no NaN */
    const double flat[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    CHECK(rk_tet_rest(flat, Dm_inv) == 0, "flat tet volume");
    for (int a = 0; a < 9; a++) CHECK(Dm_inv[a] == 0, "flat tet Dm_inv[%d] = %g", a, Dm_inv[a]);
}

TEST(gradient_matches_finite_differences_of_energy)
{
    double xs[NX][12], Dm_inv[9], worst = 0;
    double vol = rk_tet_rest(X_REST, Dm_inv);
    test_xs(xs);
    for (int m = 0; m < NMODELS; m++)
        for (int c = 0; c < NX; c++) {
            double g[12] = {0}, gfd[12], xp[12], h = 1e-6 * 0.1; /* step relative to edge */
            rk_tet_gradient(models[m], MU, LAMBDA, xs[c], Dm_inv, vol, g);
            for (int a = 0; a < 12; a++) {
                memcpy(xp, xs[c], sizeof xp);
                xp[a] += h;
                double ep = rk_tet_energy(models[m], MU, LAMBDA, xp, Dm_inv, vol);
                xp[a] -= 2 * h;
                double em = rk_tet_energy(models[m], MU, LAMBDA, xp, Dm_inv, vol);
                gfd[a] = (ep - em) / (2 * h);
            }
            /* ref_min: the gradient of a 1% strain, so a stress-free state compares to ~0 */
            double e = rel_err(12, g, gfd, 1e-2 * (2 * MU + LAMBDA) * vol / 0.1);
            worst = fmax(worst, e);
            CHECK(e < 1e-6, "%s at %s: gradient vs FD relative error %g", model_names[m],
                  x_names[c], e);
            /* translation invariance: the forces on the four vertices sum to zero */
            for (int k = 0; k < 3; k++) {
                double s = g[k] + g[3 + k] + g[6 + k] + g[9 + k];
                CHECK(fabs(s) < 1e-12 * (fabs(g[k]) + fabs(g[3 + k]) + fabs(g[6 + k]) +
                                         fabs(g[9 + k]) + 1e-300),
                      "%s at %s: net force %g", model_names[m], x_names[c], s);
            }
        }
    printf("# tet gradient vs FD(energy): worst relative error %.2e\n", worst);
}

TEST(gradient_adds_into_g)
{
    double Dm_inv[9], x[12], g1[12] = {0}, g2[12];
    const double S[9] = {1.3, 0.1, 0, 0, 0.8, 0, 0, 0, 1.1};
    double vol = rk_tet_rest(X_REST, Dm_inv);
    deform(S, 0, x);
    rk_tet_gradient(RK_MAT_NEOHOOKEAN, MU, LAMBDA, x, Dm_inv, vol, g1);
    for (int a = 0; a < 12; a++) g2[a] = 1.0;
    rk_tet_gradient(RK_MAT_NEOHOOKEAN, MU, LAMBDA, x, Dm_inv, vol, g2);
    for (int a = 0; a < 12; a++) CHECK(g2[a] == g1[a] + 1.0, "g[%d] was overwritten", a);
}

TEST(hessian_matches_finite_differences_of_gradient)
{
    double xs[NX][12], Dm_inv[9], worst = 0;
    double vol = rk_tet_rest(X_REST, Dm_inv);
    test_xs(xs);
    for (int m = 0; m < NMODELS; m++)
        for (int c = 0; c < NX; c++) {
            double H[144], Hfd[144], xp[12], gp[12], gm[12], h = 1e-6 * 0.1;
            rk_tet_hessian(models[m], MU, LAMBDA, xs[c], Dm_inv, vol, H, 0);
            for (int b = 0; b < 12; b++) {
                memcpy(xp, xs[c], sizeof xp);
                xp[b] += h;
                memset(gp, 0, sizeof gp);
                rk_tet_gradient(models[m], MU, LAMBDA, xp, Dm_inv, vol, gp);
                xp[b] -= 2 * h;
                memset(gm, 0, sizeof gm);
                rk_tet_gradient(models[m], MU, LAMBDA, xp, Dm_inv, vol, gm);
                for (int a = 0; a < 12; a++) Hfd[12 * a + b] = (gp[a] - gm[a]) / (2 * h);
            }
            double e = rel_err(144, H, Hfd, 0);
            worst = fmax(worst, e);
            CHECK(e < 1e-6, "%s at %s: Hessian vs FD relative error %g", model_names[m], x_names[c],
                  e);
            for (int a = 0; a < 12; a++)
                for (int b = 0; b < a; b++)
                    CHECK(H[12 * a + b] == H[12 * b + a], "%s at %s: H not symmetric",
                          model_names[m], x_names[c]);
        }
    printf("# tet Hessian vs FD(gradient): worst relative error %.2e\n", worst);
}

TEST(projected_hessian_is_psd)
{
    double xs[NX][12], Dm_inv[9];
    double vol = rk_tet_rest(X_REST, Dm_inv);
    int indefinite = 0;
    test_xs(xs);
    for (int m = 0; m < NMODELS; m++)
        for (int c = 0; c < NX; c++) {
            double H[144], Hp[144], w[12], V[144];
            rk_tet_hessian(models[m], MU, LAMBDA, xs[c], Dm_inv, vol, H, 0);
            rk_tet_hessian(models[m], MU, LAMBDA, xs[c], Dm_inv, vol, Hp, 1);
            rk_sym_eig(12, H, w, V);
            double scale = fmax(fabs(w[0]), fabs(w[11]));
            if (w[0] < -1e-8 * scale) indefinite++;
            rk_sym_eig(12, Hp, w, V);
            CHECK(w[0] > -1e-10 * scale, "%s at %s: projected Hessian eigenvalue %g (max %g)",
                  model_names[m], x_names[c], w[0], scale);
            /* rigid translations stay in the null space */
            for (int k = 0; k < 3; k++)
                for (int a = 0; a < 12; a++) {
                    double s = Hp[12 * a + k] + Hp[12 * a + 3 + k] + Hp[12 * a + 6 + k] +
                               Hp[12 * a + 9 + k];
                    CHECK(fabs(s) < 1e-10 * scale, "%s at %s: H t != 0", model_names[m],
                          x_names[c]);
                }
        }
    CHECK(indefinite >= 3, "only %d indefinite Hessians: the test exercises nothing", indefinite);
}

int main(void)
{
    RUN(rest_data_and_deformation_gradient);
    RUN(gradient_matches_finite_differences_of_energy);
    RUN(gradient_adds_into_g);
    RUN(hessian_matches_finite_differences_of_gradient);
    RUN(projected_hessian_is_psd);
    return test_finish();
}
