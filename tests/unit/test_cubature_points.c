/* precompute/cubature mesh-free integration points (freeform paper Eq. 21-22): rk_skin_points_G,
 * rk_quadrature_points and rk_quadrature_eval over them, on points built here by hand with
 * analytic weights W_j(X) whose gradients are known exactly:
 *   - F = I + G q against the finite-difference Jacobian of the skinned map
 *     x(X) = X + sum_j W_j(X) A_j (X, 1) (q holds A_j row by row: column 12 j + 4 a + c);
 *   - the patch test: a constant weight w on handle 0 alone, A_0 = [M | t] / w, gives F = I + M;
 *   - the energy against sum_i v_i Psi(F_i) with F_i formed here, its gradient against central
 *     differences of the energy and its Hessian against central differences of the gradient,
 *     for Neo-Hookean and StVK;
 *   - a selection (index, weights): each point's weight, source and G, and the errors. */
#include "cubature/cubature.h"
#include "testlib.h"
#include "util/util.h"

static uint64_t rng = 777;
static double uni(void) { return rk_uniform(&rng); }

#define NH 3 /* handles */

/* W_0 = w0 (constant), W_1 = 0.3 + x - 0.5 y^2 + 0.2 x z, W_2 = sin(x) cos(y) + 0.1 z^3 - 0.4 y z. */
static void weights_at(const double *X, double w0, double W[NH], double dW[NH][3])
{
    double x = X[0], y = X[1], z = X[2];
    W[0] = w0;
    dW[0][0] = dW[0][1] = dW[0][2] = 0;
    W[1] = 0.3 + x - 0.5 * y * y + 0.2 * x * z;
    dW[1][0] = 1 + 0.2 * z, dW[1][1] = -y, dW[1][2] = 0.2 * x;
    W[2] = sin(x) * cos(y) + 0.1 * z * z * z - 0.4 * y * z;
    dW[2][0] = cos(x) * cos(y), dW[2][1] = -sin(x) * sin(y) - 0.4 * z, dW[2][2] = 0.3 * z * z - 0.4 * y;
}

/* n points in [0, 1]^3 with the weights above, random volumes, one material. */
static void make_points(rk_skin_points *P, int n, double w0, rk_material_model model)
{
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
        weights_at(&P->X[3 * i], w0, W, dW);
        for (int j = 0; j < NH; j++) {
            P->W[i + (size_t)n * j] = W[j];
            for (int b = 0; b < 3; b++) P->dW[3 * (size_t)i + b + 3 * (size_t)n * j] = dW[j][b];
        }
        P->volume[i] = 1e-3 * (0.5 + uni());
        P->density[i] = 1000;
        P->model[i] = model;
        P->mu[i] = 3e4 * (1 + i % 2); /* two materials */
        P->lambda[i] = 5e4;
    }
}

/* x(X) = X + sum_j W_j(X) A_j (X, 1), A_j = q[12 j + 4 a + c]. */
static void skinned(const double *X, double w0, const double *q, double x[3])
{
    double W[NH], dW[NH][3];
    weights_at(X, w0, W, dW);
    for (int a = 0; a < 3; a++) {
        x[a] = X[a];
        for (int j = 0; j < NH; j++) {
            const double *A = &q[12 * j + 4 * a];
            x[a] += W[j] * (A[0] * X[0] + A[1] * X[1] + A[2] * X[2] + A[3]);
        }
    }
}

/* F (9, row-major) = I + G q from rk_skin_points_G. */
static void F_from_G(const rk_skin_points *P, int i, const double *q, double F[9])
{
    int r = 12 * P->H;
    double *G = calloc((size_t)9 * r, sizeof *G);
    rk_skin_points_G(P, i, G);
    for (int k = 0; k < 9; k++) {
        F[k] = k % 4 == 0;
        for (int c = 0; c < r; c++) F[k] += G[(size_t)k * r + c] * q[c];
    }
    free(G);
}

TEST(F_is_the_jacobian_of_the_skinned_map)
{
    rk_skin_points P;
    make_points(&P, 8, 0.8, RK_MAT_NEOHOOKEAN);
    double q[12 * NH], worst = 0, h = 1e-5;
    for (int c = 0; c < 12 * NH; c++) q[c] = 0.4 * (uni() - 0.5);
    for (int i = 0; i < P.n; i++) {
        double F[9];
        F_from_G(&P, i, q, F);
        for (int b = 0; b < 3; b++) {
            double Xp[3], Xm[3], xp[3], xm[3];
            memcpy(Xp, &P.X[3 * i], sizeof Xp);
            memcpy(Xm, &P.X[3 * i], sizeof Xm);
            Xp[b] += h, Xm[b] -= h;
            skinned(Xp, 0.8, q, xp);
            skinned(Xm, 0.8, q, xm);
            for (int a = 0; a < 3; a++) {
                double fd = (xp[a] - xm[a]) / (2 * h);
                worst = fmax(worst, fabs(F[3 * a + b] - fd));
                CHECK(fabs(F[3 * a + b] - fd) < 1e-7, "point %d: F[%d][%d] = %.12g, FD Jacobian %.12g", i, a, b,
                      F[3 * a + b], fd);
            }
        }
    }
    printf("# I + G q against the finite-difference Jacobian of x(X): %.3g\n", worst);
    rk_skin_points_free(&P);
}

TEST(patch_test_constant_weight_gives_an_affine_map)
{
    rk_skin_points P;
    double w = 0.7;
    make_points(&P, 6, w, RK_MAT_STVK);
    const double M[9] = {0.1, -0.3, 0.05, 0.2, -0.15, 0.4, -0.25, 0.12, 0.3}, t[3] = {1.5, -2, 0.5};
    double q[12 * NH] = {0}, worst = 0;
    for (int a = 0; a < 3; a++) {
        for (int c = 0; c < 3; c++) q[4 * a + c] = M[3 * a + c] / w;
        q[4 * a + 3] = t[a] / w;
    }
    for (int i = 0; i < P.n; i++) {
        double F[9];
        F_from_G(&P, i, q, F);
        for (int k = 0; k < 9; k++) {
            worst = fmax(worst, fabs(F[k] - ((k % 4 == 0) + M[k])));
            CHECK(fabs(F[k] - ((k % 4 == 0) + M[k])) < 1e-14, "point %d: F[%d] = %.17g, I + M = %.17g", i, k, F[k],
                  (k % 4 == 0) + M[k]);
        }
    }
    /* and the quadrature's F at each point is the same */
    rk_error err;
    rk_quadrature Q;
    CHECK_OK(rk_quadrature_points(&P, P.n, NULL, NULL, &Q, &err));
    for (int i = 0; i < P.n; i++) {
        double F[9];
        rk_quadrature_point_F(&Q, i, q, F);
        for (int k = 0; k < 9; k++) CHECK(fabs(F[k] - ((k % 4 == 0) + M[k])) < 1e-14, "quadrature point %d: F[%d] = %.17g", i, k, F[k]);
    }
    printf("# patch test: |F - (I + M)| = %.3g\n", worst);
    rk_quadrature_free(&Q);
    rk_skin_points_free(&P);
}

/* Energy, gradient (of +E: rk_quadrature_eval adds dE/dq) and Hessian of the exact quadrature. */
static void check_derivatives(rk_material_model model, const char *name, double *eE, double *eg, double *eH, int *failed)
{
    rk_error err;
    rk_skin_points P;
    rk_quadrature Q;
    make_points(&P, 10, 0.9, model);
    int r = 12 * NH;
    *failed = 1;
    if (rk_quadrature_points(&P, P.n, NULL, NULL, &Q, &err)) {
        printf("# %s: %s\n", name, err.msg);
        rk_skin_points_free(&P);
        return;
    }
    double q[12 * NH], g[12 * NH] = {0}, *H = calloc((size_t)r * r, sizeof *H);
    for (int c = 0; c < r; c++) q[c] = 0.15 * (uni() - 0.5);
    double E = rk_quadrature_eval(&Q, q, g, H, 0), Eref = 0;
    for (int i = 0; i < P.n; i++) {
        double F[9], W[NH], dW[NH][3];
        weights_at(&P.X[3 * i], 0.9, W, dW);
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) { /* F = I + sum_j A_j (Xbar grad W_j^T + W_j [I; 0]) */
                double s = a == b;
                for (int j = 0; j < NH; j++) {
                    const double *A = &q[12 * j + 4 * a];
                    s += (A[0] * P.X[3 * i] + A[1] * P.X[3 * i + 1] + A[2] * P.X[3 * i + 2] + A[3]) * dW[j][b] + A[b] * W[j];
                }
                F[3 * a + b] = s;
            }
        Eref += P.volume[i] * rk_psi(model, P.mu[i], P.lambda[i], F);
    }
    *eE = fabs(E - Eref) / fabs(Eref);
    double gscale = test_norm(g, r), hscale = 0, step = 1e-6;
    for (int k = 0; k < r * r; k++) hscale = fmax(hscale, fabs(H[k]));
    *eg = *eH = 0;
    for (int k = 0; k < r; k++) {
        double qp[12 * NH], qm[12 * NH], gp[12 * NH] = {0}, gm[12 * NH] = {0};
        memcpy(qp, q, sizeof q);
        memcpy(qm, q, sizeof q);
        qp[k] += step, qm[k] -= step;
        double Ep = rk_quadrature_eval(&Q, qp, gp, NULL, 0), Em = rk_quadrature_eval(&Q, qm, gm, NULL, 0);
        *eg = fmax(*eg, fabs(g[k] - (Ep - Em) / (2 * step)) / gscale);
        for (int j = 0; j < r; j++) *eH = fmax(*eH, fabs(H[j + (size_t)r * k] - (gp[j] - gm[j]) / (2 * step)) / hscale);
    }
    printf("# %s over %d points: energy %.3g relative to sum v Psi(F) formed here; gradient %.3g, Hessian %.3g relative "
           "to finite differences\n", name, P.n, *eE, *eg, *eH);
    *failed = !(Eref > 0 && gscale > 0 && hscale > 0);
    free(H);
    rk_quadrature_free(&Q);
    rk_skin_points_free(&P);
}

TEST(energy_gradient_and_hessian_neohookean)
{
    double eE, eg, eH;
    int failed;
    check_derivatives(RK_MAT_NEOHOOKEAN, "neohookean", &eE, &eg, &eH, &failed);
    CHECK(!failed, "nothing to compare (zero energy, gradient or Hessian)");
    CHECK(eE < 1e-12, "energy differs from sum v Psi(F) by %.3g", eE);
    CHECK(eg < 1e-7, "gradient differs from finite differences by %.3g", eg);
    CHECK(eH < 1e-7, "Hessian differs from finite differences of the gradient by %.3g", eH);
}

TEST(energy_gradient_and_hessian_stvk)
{
    double eE, eg, eH;
    int failed;
    check_derivatives(RK_MAT_STVK, "stvk", &eE, &eg, &eH, &failed);
    CHECK(!failed, "nothing to compare (zero energy, gradient or Hessian)");
    CHECK(eE < 1e-12, "energy differs from sum v Psi(F) by %.3g", eE);
    CHECK(eg < 1e-7, "gradient differs from finite differences by %.3g", eg);
    CHECK(eH < 1e-7, "Hessian differs from finite differences of the gradient by %.3g", eH);
}

TEST(selection_weights_and_sources)
{
    rk_error err;
    rk_skin_points P;
    rk_quadrature Q;
    make_points(&P, 6, 1.0, RK_MAT_NEOHOOKEAN);
    P.model[1] = RK_MAT_STVK;
    int r = 12 * NH, index[3] = {4, 1, 4};
    double weights[3] = {0.5, 2.0, 1e-3};
    CHECK_OK(rk_quadrature_points(&P, 3, index, weights, &Q, &err));
    CHECK(Q.count == 3 && Q.r == r, "count %d, r %d", Q.count, Q.r);
    double *G = calloc((size_t)9 * r, sizeof *G);
    for (int k = 0; k < 3; k++) {
        int i = index[k];
        CHECK(Q.weight[k] == P.volume[i] * weights[k], "point %d: weight %.17g, volume x weight %.17g", k, Q.weight[k],
              P.volume[i] * weights[k]);
        CHECK(Q.source[k] == i, "point %d: source %d, expected %d", k, Q.source[k], i);
        CHECK(Q.model[k] == P.model[i] && Q.mu[k] == P.mu[i] && Q.lambda[k] == P.lambda[i], "point %d: material", k);
        rk_skin_points_G(&P, i, G);
        CHECK(memcmp(G, Q.G + (size_t)k * 9 * r, sizeof(double) * 9 * r) == 0, "point %d: G is not point %d's", k, i);
    }
    /* the energy of the selection: weights[k] v_i Psi(F_i) */
    double q[12 * NH], E = 0;
    for (int c = 0; c < r; c++) q[c] = 0.1 * (uni() - 0.5);
    for (int k = 0; k < 3; k++) {
        double F[9];
        F_from_G(&P, index[k], q, F);
        E += weights[k] * P.volume[index[k]] * rk_psi(P.model[index[k]], P.mu[index[k]], P.lambda[index[k]], F);
    }
    CHECK_CLOSE(rk_quadrature_eval(&Q, q, NULL, NULL, 0) / E, 1.0, 1e-12);
    rk_quadrature_free(&Q);
    /* no weights: volumes; no index: all points in order */
    CHECK_OK(rk_quadrature_points(&P, 2, index, NULL, &Q, &err));
    CHECK(Q.weight[0] == P.volume[4] && Q.weight[1] == P.volume[1], "weights NULL: %g %g", Q.weight[0], Q.weight[1]);
    rk_quadrature_free(&Q);
    CHECK_OK(rk_quadrature_points(&P, P.n, NULL, NULL, &Q, &err));
    for (int i = 0; i < P.n; i++) CHECK(Q.source[i] == i && Q.weight[i] == P.volume[i], "all points: point %d", i);
    rk_quadrature_free(&Q);
    /* zero points: an empty quadrature, energy 0 */
    CHECK_OK(rk_quadrature_points(&P, 0, NULL, NULL, &Q, &err));
    CHECK(Q.count == 0 && rk_quadrature_eval(&Q, q, NULL, NULL, 0) == 0, "empty quadrature");
    rk_quadrature_free(&Q);

    /* errors, each leaving Q empty */
    int out_of_range[2] = {0, 6}, negative[2] = {-1, 0};
    CHECK(rk_quadrature_points(&P, 2, out_of_range, NULL, &Q, &err) != 0 && strstr(err.msg, "6"), "index 6 of 6: %s", err.msg);
    CHECK(Q.G == NULL && Q.weight == NULL, "a failed call left Q allocated");
    CHECK(rk_quadrature_points(&P, 2, negative, NULL, &Q, &err) != 0 && strstr(err.msg, "-1"), "index -1: %s", err.msg);
    double bad[3][2] = {{1, -0.5}, {NAN, 1}, {1, INFINITY}};
    for (int b = 0; b < 3; b++) {
        CHECK(rk_quadrature_points(&P, 2, index, bad[b], &Q, &err) != 0 && strstr(err.msg, "weight"), "weights %g %g: %s",
              bad[b][0], bad[b][1], err.msg);
        CHECK(Q.G == NULL, "a failed call left Q allocated");
    }
    CHECK(rk_quadrature_points(&P, -1, NULL, NULL, &Q, &err) != 0, "count -1 accepted");
    P.H = 0;
    CHECK(rk_quadrature_points(&P, 1, NULL, NULL, &Q, &err) != 0, "no handles accepted");
    P.H = NH;
    free(G);
    rk_skin_points_free(&P);
}

int main(void)
{
    RUN(F_is_the_jacobian_of_the_skinned_map);
    RUN(patch_test_constant_weight_gives_an_affine_map);
    RUN(energy_gradient_and_hessian_neohookean);
    RUN(energy_gradient_and_hessian_stvk);
    RUN(selection_weights_and_sources);
    return test_finish();
}
