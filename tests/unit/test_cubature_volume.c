/* precompute/cubature's projected volume (cubature.h, rk_quadrature_volume), on mesh-free points
 * built here with analytic skinning weights (as test_cubature_points.c):
 *   - the energy against sum_i w_i [Psi(mu, 0; F_i) + lambda_i/2 theta_bar_i^2] with theta_bar the
 *     weighted least-squares fit of theta over the pressure functions, solved here directly;
 *   - its gradient and Hessian against central differences, for every material model, on both
 *     Hessian paths (skinning-structured and dense);
 *   - the limits: a pressure function per point (theta_bar = theta) gives back the pointwise energy,
 *     and lambda = 0 leaves the quadrature exactly pointwise;
 *   - the projected Hessian is positive semi-definite where the point terms are projected. */
#include <lapacke.h>

#include "cubature/cubature.h"
#include "testlib.h"
#include "util/util.h"

static uint64_t rng = 4242;
static double uni(void) { return rk_uniform(&rng); }

#define NH 3
#define NP 40

static void weights_at(const double *X, double W[NH], double dW[NH][3])
{
    double x = X[0], y = X[1], z = X[2];
    W[0] = 0.5, dW[0][0] = dW[0][1] = dW[0][2] = 0;
    W[1] = 0.3 + x - 0.5 * y * y + 0.2 * x * z;
    dW[1][0] = 1 + 0.2 * z, dW[1][1] = -y, dW[1][2] = 0.2 * x;
    W[2] = sin(x) * cos(y) + 0.1 * z * z * z - 0.4 * y * z;
    dW[2][0] = cos(x) * cos(y), dW[2][1] = -sin(x) * sin(y) - 0.4 * z, dW[2][2] = 0.3 * z * z - 0.4 * y;
}

static void make_points(rk_skin_points *P, rk_material_model model, double lambda)
{
    int n = NP;
    memset(P, 0, sizeof *P);
    P->n = n, P->H = NH;
    P->X = calloc(3 * (size_t)n, sizeof(double));
    P->W = calloc((size_t)n * NH, sizeof(double));
    P->dW = calloc(3 * (size_t)n * NH, sizeof(double));
    P->volume = calloc((size_t)n, sizeof(double));
    P->density = calloc((size_t)n, sizeof(double));
    P->model = calloc((size_t)n, sizeof *P->model);
    P->mu = calloc((size_t)n, sizeof(double));
    P->lambda = calloc((size_t)n, sizeof(double));
    for (int i = 0; i < n; i++) {
        double W[NH], dW[NH][3];
        for (int d = 0; d < 3; d++) P->X[3 * i + d] = uni();
        weights_at(&P->X[3 * i], W, dW);
        for (int j = 0; j < NH; j++) {
            P->W[i + (size_t)n * j] = W[j];
            for (int b = 0; b < 3; b++) P->dW[3 * (size_t)i + b + 3 * (size_t)n * j] = dW[j][b];
        }
        P->volume[i] = 1e-3 * (0.5 + uni());
        P->density[i] = 1000;
        P->model[i] = model;
        P->mu[i] = 3e4;
        P->lambda[i] = lambda * (1 + 0.5 * (i % 2)); /* two materials */
    }
}

/* The pressure space {W_j}, or {W_j (1, x, y, z)} with affine. */
static int pressure_space(const rk_skin_points *P, int affine, double *psi)
{
    int k = affine ? 4 * NH : NH;
    for (int i = 0; i < P->n; i++)
        for (int j = 0; j < NH; j++) {
            double w = P->W[i + (size_t)P->n * j];
            if (!affine) {
                psi[(size_t)i * k + j] = w;
                continue;
            }
            psi[(size_t)i * k + 4 * j] = w;
            for (int a = 0; a < 3; a++) psi[(size_t)i * k + 4 * j + 1 + a] = w * (P->X[3 * i + a] - 0.5);
        }
    return k;
}

/* sum_i w_i [Psi(mu, 0; F_i) + lambda_i / 2 theta_bar_i^2], theta_bar the W-weighted least-squares
 * fit of theta over psi (k functions), by its normal equations. */
static double direct_energy(const rk_quadrature *Q, const double *psi, int k, const double *q)
{
    int n = Q->count;
    double E = 0, *G = calloc((size_t)k * k, sizeof(double)), *b = calloc(k, sizeof(double)), theta[NP];
    for (int i = 0; i < n; i++) {
        double F[9], Hd[9], dth[9];
        rk_quadrature_point_F(Q, i, q, F);
        for (int x = 0; x < 9; x++) Hd[x] = F[x] - (x % 4 == 0);
        E += Q->weight[i] * rk_psi(Q->model[i], Q->mu[i], 0, F);
        theta[i] = rk_volume_h(Q->model[i], Hd, dth);
        for (int a = 0; a < k; a++) {
            b[a] += Q->weight[i] * psi[(size_t)i * k + a] * theta[i];
            for (int c = 0; c < k; c++) G[a + (size_t)k * c] += Q->weight[i] * psi[(size_t)i * k + a] * psi[(size_t)i * k + c];
        }
    }
    lapack_int piv[64];
    LAPACKE_dgesv(LAPACK_COL_MAJOR, k, 1, G, k, piv, b, k);
    for (int i = 0; i < n; i++) {
        double tb = 0;
        for (int a = 0; a < k; a++) tb += psi[(size_t)i * k + a] * b[a];
        E += Q->weight[i] * 0.5 * Q->lambda[i] * tb * tb;
    }
    free(G);
    free(b);
    return E;
}

/* A dense (not skinning-structured) copy of Q's points, for rk_quadrature_eval's other Hessian. */
static int dense_copy(const rk_quadrature *Q, rk_quadrature *D, rk_error *err)
{
    if (rk_quadrature_alloc(D, Q->r, Q->count, 0, "points", err)) return -1;
    memcpy(D->G, Q->G, sizeof(double) * 9 * (size_t)Q->r * Q->count);
    for (int i = 0; i < Q->count; i++) {
        D->weight[i] = Q->weight[i], D->model[i] = Q->model[i], D->mu[i] = Q->mu[i], D->lambda[i] = Q->lambda[i];
        D->source[i] = Q->source[i];
    }
    return 0;
}

/* Gradient and Hessian of Q at q against central differences (relative to their largest entries). */
static void fd_errors(rk_quadrature *Q, const double *q, double *eg, double *eH, double *hscale)
{
    int r = Q->r;
    double g[12 * NH] = {0}, *H = calloc((size_t)r * r, sizeof *H), step = 1e-6;
    rk_quadrature_eval(Q, q, g, H, 0);
    double gscale = test_norm(g, r);
    *hscale = 0;
    for (int k = 0; k < r * r; k++) *hscale = fmax(*hscale, fabs(H[k]));
    *eg = *eH = 0;
    for (int k = 0; k < r; k++) {
        double qp[12 * NH], qm[12 * NH], gp[12 * NH] = {0}, gm[12 * NH] = {0};
        memcpy(qp, q, sizeof qp);
        memcpy(qm, q, sizeof qm);
        qp[k] += step, qm[k] -= step;
        double Ep = rk_quadrature_eval(Q, qp, gp, NULL, 0), Em = rk_quadrature_eval(Q, qm, gm, NULL, 0);
        *eg = fmax(*eg, fabs(g[k] - (Ep - Em) / (2 * step)) / gscale);
        for (int j = 0; j < r; j++) *eH = fmax(*eH, fabs(H[j + (size_t)r * k] - (gp[j] - gm[j]) / (2 * step)) / *hscale);
    }
    free(H);
}

TEST(energy_gradient_and_hessian_of_the_projected_volume)
{
    static const rk_material_model models[] = {RK_MAT_LINEAR, RK_MAT_NEOHOOKEAN, RK_MAT_STVK, RK_MAT_COROTATED};
    static const char *const names[] = {"linear", "neohookean", "stvk", "corotated"};
    rk_error err;
    for (int m = 0; m < 4; m++)
        for (int affine = 0; affine < 2; affine++) {
            rk_skin_points P;
            rk_quadrature Q, D;
            make_points(&P, models[m], 4e5);
            double psi[NP * 4 * NH], q[12 * NH];
            int k = pressure_space(&P, affine, psi);
            CHECK_OK(rk_quadrature_points(&P, P.n, NULL, NULL, &Q, &err));
            CHECK_OK(dense_copy(&Q, &D, &err));
            CHECK_OK(rk_quadrature_volume(&Q, k, psi, &err));
            CHECK_OK(rk_quadrature_volume(&D, k, psi, &err));
            CHECK(Q.vol_k == k, "%s: %d of %d pressure functions kept", names[m], Q.vol_k, k);
            for (int c = 0; c < 12 * NH; c++) q[c] = 0.1 * (uni() - 0.5);
            double E = rk_quadrature_eval(&Q, q, NULL, NULL, 0), Eref = direct_energy(&Q, psi, k, q);
            double eg, eH, hs, egd, eHd, hsd;
            fd_errors(&Q, q, &eg, &eH, &hs);
            fd_errors(&D, q, &egd, &eHd, &hsd);
            printf("# %-10s %s: energy %.2e off the direct projection; gradient %.2e, Hessian %.2e (dense path %.2e, "
                   "%.2e) off finite differences\n", names[m], affine ? "weights_affine" : "weights       ",
                   fabs(E - Eref) / Eref, eg, eH, egd, eHd);
            CHECK(Eref > 0 && fabs(E - Eref) < 1e-11 * Eref, "%s: energy %.17g, direct %.17g", names[m], E, Eref);
            CHECK(eg < 1e-7 && egd < 1e-7, "%s: gradient off by %.3g / %.3g", names[m], eg, egd);
            CHECK(eH < 1e-6 && eHd < 1e-6, "%s: Hessian off by %.3g / %.3g", names[m], eH, eHd);
            CHECK(fabs(hs - hsd) < 1e-12 * hs, "%s: the two Hessian paths differ (%.17g, %.17g)", names[m], hs, hsd);
            rk_quadrature_free(&Q);
            rk_quadrature_free(&D);
            rk_skin_points_free(&P);
        }
}

/* One pressure function per point: theta_bar = theta, the pointwise energy back; lambda = 0: the
 * projection keeps nothing and the quadrature is exactly the pointwise one. */
TEST(the_limits_rich_space_and_zero_lambda)
{
    rk_error err;
    for (int zero = 0; zero < 2; zero++) {
        rk_skin_points P;
        rk_quadrature Q, R;
        make_points(&P, RK_MAT_NEOHOOKEAN, zero ? 0 : 4e5);
        double *psi = calloc((size_t)NP * NP, sizeof(double)), q[12 * NH];
        for (int i = 0; i < NP; i++) psi[(size_t)i * NP + i] = 1;
        CHECK_OK(rk_quadrature_points(&P, P.n, NULL, NULL, &Q, &err));
        CHECK_OK(rk_quadrature_points(&P, P.n, NULL, NULL, &R, &err));
        CHECK_OK(rk_quadrature_volume(&Q, NP, psi, &err));
        for (int c = 0; c < 12 * NH; c++) q[c] = 0.1 * (uni() - 0.5);
        double g1[12 * NH] = {0}, g2[12 * NH] = {0};
        double E1 = rk_quadrature_eval(&Q, q, g1, NULL, 0), E2 = rk_quadrature_eval(&R, q, g2, NULL, 0);
        double dg = 0;
        for (int c = 0; c < 12 * NH; c++) dg = fmax(dg, fabs(g1[c] - g2[c]));
        printf("# lambda %s, a pressure per point: %d functions kept, energy %.2e, gradient %.2e off the pointwise\n",
               zero ? "0" : "4e5", Q.vol_k, fabs(E1 - E2) / E2, dg / test_norm(g2, 12 * NH));
        if (zero) {
            CHECK(Q.vol_k == 0 && E1 == E2 && dg == 0, "lambda = 0 changed the quadrature: %d kept, %.17g vs %.17g",
                  Q.vol_k, E1, E2);
        } else {
            CHECK(fabs(E1 - E2) < 1e-11 * E2, "energy %.17g, pointwise %.17g", E1, E2);
            CHECK(dg < 1e-10 * test_norm(g2, 12 * NH), "gradient off the pointwise by %.3g", dg);
        }
        free(psi);
        rk_quadrature_free(&Q);
        rk_quadrature_free(&R);
        rk_skin_points_free(&P);
    }
}

/* With the point terms projected (the solver's Hessian) the whole is positive semi-definite: the
 * coupling C^T C is, by construction. */
TEST(the_projected_hessian_is_psd)
{
    rk_error err;
    rk_skin_points P;
    rk_quadrature Q;
    make_points(&P, RK_MAT_NEOHOOKEAN, 4e5);
    double psi[NP * 4 * NH], q[12 * NH];
    int k = pressure_space(&P, 1, psi), r = 12 * NH;
    CHECK_OK(rk_quadrature_points(&P, P.n, NULL, NULL, &Q, &err));
    CHECK_OK(rk_quadrature_volume(&Q, k, psi, &err));
    for (int c = 0; c < r; c++) q[c] = 0.6 * (uni() - 0.5); /* large enough to invert some points' eigenvalues */
    double *H = calloc((size_t)r * r, sizeof *H), w[12 * NH];
    rk_quadrature_eval(&Q, q, NULL, H, 1);
    LAPACKE_dsyev(LAPACK_COL_MAJOR, 'N', 'U', r, H, r, w);
    printf("# projected Hessian's eigenvalues: %.3g .. %.3g\n", w[0], w[r - 1]);
    CHECK(w[0] > -1e-10 * w[r - 1], "smallest eigenvalue %.3g of largest %.3g", w[0], w[r - 1]);
    CHECK_OK(rk_quadrature_volume(&Q, 1, (double[NP]){0}, &err) ? -1 : 0); /* psi = 0: a singular Gram, nothing kept */
    CHECK(Q.vol_k == 0, "a zero pressure space kept %d functions", Q.vol_k);
    double bad[NP * NH];
    for (int i = 0; i < NP * NH; i++) bad[i] = i == 7 ? NAN : 1;
    CHECK(rk_quadrature_volume(&Q, NH, bad, &err) != 0 && strstr(err.msg, "pressure function 1 at point 2 is not finite"),
          "accepted a NaN or wrong message: %s", err.msg);
    free(H);
    rk_quadrature_free(&Q);
    rk_skin_points_free(&P);
}

int main(void)
{
    RUN(energy_gradient_and_hessian_of_the_projected_volume);
    RUN(the_limits_rich_space_and_zero_lambda);
    RUN(the_projected_hessian_is_psd);
    return test_finish();
}
