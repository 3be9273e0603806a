/* precompute/grassmann: Grassmann interpolation (Algorithm 4) along the geodesic, the history basis
 * (Eq. 13) recovering a known basis, and the quadratic-manifold decoder's Jacobian and encoder. */
#include "grassmann/grassmann.h"
#include "testlib.h"
#include "fem_body.h"

static double rnd(unsigned *s)
{
    *s = *s * 1664525u + 1013904223u;
    return (*s >> 8) / 16777216.0 - 0.5;
}

static void random_matrix(int n, int r, unsigned seed, double *A)
{
    for (int k = 0; k < n * r; k++) A[k] = rnd(&seed);
}

static double max_angle(int n, int r, const double *A, const double *B)
{
    rk_error err;
    double th[16];
    if (rk_principal_angles(n, r, A, B, th, &err)) return INFINITY;
    double m = 0;
    for (int i = 0; i < r; i++) m = fmax(m, th[i]);
    return m;
}

TEST(interpolation_follows_the_geodesic)
{
    enum { n = 40, r = 4 };
    double Phi[n * r], U[n * r], G[n * r], th0[r], th[r];
    random_matrix(n, r, 1, Phi);
    random_matrix(n, r, 2, U);
    rk_error err;
    CHECK_OK(rk_principal_angles(n, r, Phi, U, th0, &err));
    CHECK_OK(rk_grassmann_interpolate(n, r, Phi, U, 0, G, &err));
    CHECK(max_angle(n, r, G, Phi) < 1e-7, "lambda 0 is %g rad from span(Phi)", max_angle(n, r, G, Phi));
    CHECK_OK(rk_grassmann_interpolate(n, r, Phi, U, 1, G, &err));
    CHECK(max_angle(n, r, G, U) < 1e-7, "lambda 1 is %g rad from span(U)", max_angle(n, r, G, U));
    for (double lambda = 0.2; lambda < 0.9; lambda += 0.3) {
        CHECK_OK(rk_grassmann_interpolate(n, r, Phi, U, lambda, G, &err));
        for (int i = 0; i < r; i++) /* orthonormal columns */
            for (int j = 0; j < r; j++) {
                double d = 0;
                for (int k = 0; k < n; k++) d += G[i * n + k] * G[j * n + k];
                CHECK(fabs(d - (i == j)) < 1e-12, "columns %d, %d: %g", i, j, d);
            }
        /* on the geodesic every principal angle to the ends scales by lambda and 1 - lambda */
        CHECK_OK(rk_principal_angles(n, r, G, Phi, th, &err));
        for (int i = 0; i < r; i++) CHECK(fabs(th[i] - lambda * th0[i]) < 1e-9, "angle %d to Phi %g, expected %g", i, th[i], lambda * th0[i]);
        CHECK_OK(rk_principal_angles(n, r, G, U, th, &err));
        for (int i = 0; i < r; i++) CHECK(fabs(th[r - 1 - i] - (1 - lambda) * th0[r - 1 - i]) < 1e-9, "angle %d to U", i);
    }
    double Z[n * r] = {0};
    CHECK(rk_grassmann_interpolate(n, r, Z, U, 0.5, G, &err) != 0 && strstr(err.msg, "history basis"),
          "a zero history was accepted: %s", err.msg);
}

TEST(history_basis_recovers_a_basis_that_explains_the_history)
{
    enum { n = 30, r = 3, m = 8 };
    double B[n * r], P[r * m], D[n * m], Phi[n * r];
    random_matrix(n, r, 3, B);
    random_matrix(r, m, 4, P);
    for (int j = 0; j < m; j++)
        for (int i = 0; i < n; i++) {
            double s = 0;
            for (int k = 0; k < r; k++) s += B[k * n + i] * P[j * r + k];
            D[j * n + i] = s;
        }
    rk_error err;
    CHECK_OK(rk_history_basis(n, r, m, D, P, NULL, 0, 0, Phi, &err));
    for (int k = 0; k < n * r; k++) CHECK(fabs(Phi[k] - B[k]) < 1e-10, "entry %d: %g vs %g", k, Phi[k], B[k]);
    CHECK_OK(rk_history_basis(n, r, m, D, P, NULL, 0, 1e-8, Phi, &err));
    for (int k = 0; k < n * r; k++) CHECK(fabs(Phi[k] - B[k]) < 1e-6, "regularised entry %d: %g vs %g", k, Phi[k], B[k]);
}

/* A quadratic manifold on a small box: the Jacobian by central differences of the decoder, and the
 * encoder inverting the decoder. */
TEST(quadratic_decoder_jacobian_and_encoder)
{
    rk_error err;
    fem_body b;
    CHECK_OK(fem_body_box(&b, 1, 0.5, 0.5, 2, 1, 1, (rk_material){RK_MAT_NEOHOOKEAN, 1e5, 0.3, 1000}, &err));
    int n = 3 * b.f.nv, r = 3, np = r * (r + 1) / 2;
    double *Phi = malloc(sizeof(double) * n * r), *Psi = malloc(sizeof(double) * n * np);
    random_matrix(n, r, 5, Phi);
    random_matrix(n, np, 6, Psi);
    rk_sparse M;
    CHECK_OK(rk_sparse_alloc_pattern(&b.f, &M, &err));
    rk_fem_add_mass(&b.f, 0, 1.0, &M);
    rk_decoder dec;
    CHECK_OK(rk_quadratic_decoder(n, r, Phi, Psi, &M, &dec, &err));
    double p[3] = {0.3, -0.2, 0.1}, J[1024], up[512], um[512], pe[3];
    CHECK_OK(dec.jacobian(dec.ctx, p, J, &err));
    for (int k = 0; k < r; k++) {
        double e = 1e-6, q[3] = {p[0], p[1], p[2]};
        q[k] += e;
        dec.decode(dec.ctx, q, up, &err);
        q[k] -= 2 * e;
        dec.decode(dec.ctx, q, um, &err);
        for (int i = 0; i < n; i++) {
            double fd = (up[i] - um[i]) / (2 * e);
            CHECK(fabs(fd - J[k * n + i]) < 1e-7 * (1 + fabs(fd)), "dg_%d/dp_%d: %g vs %g", i, k, J[k * n + i], fd);
        }
    }
    dec.decode(dec.ctx, p, up, &err);
    CHECK_OK(dec.encode(dec.ctx, up, pe, &err));
    for (int k = 0; k < r; k++) CHECK(fabs(pe[k] - p[k]) < 1e-9, "encode(decode(p))_%d = %g, p = %g", k, pe[k], p[k]);
    rk_decoder_free(&dec);
    rk_sparse_free(&M);
    free(Phi);
    free(Psi);
    fem_body_free(&b);
}

/* Frames drawn exactly from a quadratic manifold whose second-order term is mass-orthogonal to its
 * linear part: the fit recovers that term (up to its 1e-6 ridge) and leaves nothing unexplained. */
TEST(quadratic_fit_recovers_a_known_manifold)
{
    rk_error err;
    fem_body b;
    CHECK_OK(fem_body_box(&b, 1, 0.5, 0.5, 3, 2, 2, (rk_material){RK_MAT_NEOHOOKEAN, 1e5, 0.3, 1000}, &err));
    int n = 3 * b.f.nv, r = 3, np = r * (r + 1) / 2, T = 40;
    double *V = malloc(sizeof(double) * n * r), *Psi = malloc(sizeof(double) * n * np), *fit = malloc(sizeof(double) * n * np);
    double *D = malloc(sizeof(double) * n * T), *Mx = malloc(sizeof(double) * n);
    rk_sparse M;
    CHECK_OK(rk_sparse_alloc_pattern(&b.f, &M, &err));
    rk_fem_add_mass(&b.f, 1, 1.0, &M);
    random_matrix(n, r, 11, V);
    random_matrix(n, np, 12, Psi);
    /* V mass-orthonormal (Gram-Schmidt in M), Psi's columns M-orthogonal to V */
    for (int j = 0; j < r + np; j++) {
        double *x = j < r ? V + (size_t)j * n : Psi + (size_t)(j - r) * n;
        for (int k = 0; k < (j < r ? j : r); k++) {
            rk_sparse_mul(&M, V + (size_t)k * n, Mx);
            double d = 0;
            for (int i = 0; i < n; i++) d += x[i] * Mx[i];
            for (int i = 0; i < n; i++) x[i] -= d * V[(size_t)k * n + i];
        }
        if (j < r) {
            rk_sparse_mul(&M, x, Mx);
            double nn = 0;
            for (int i = 0; i < n; i++) nn += x[i] * Mx[i];
            for (int i = 0; i < n; i++) x[i] /= sqrt(nn);
        }
    }
    unsigned seed = 13;
    for (int t = 0; t < T; t++) {
        double p[3] = {rnd(&seed), rnd(&seed), rnd(&seed)};
        double *u = D + (size_t)t * n;
        for (int i = 0; i < n; i++) {
            double s = 0;
            for (int k = 0; k < r; k++) s += V[(size_t)k * n + i] * p[k];
            for (int a = 0, k = 0; a < r; a++)
                for (int c = a; c < r; c++, k++) s += (a == c ? 0.5 : 1.0) * p[a] * p[c] * Psi[(size_t)k * n + i];
            u[i] = s;
        }
    }
    double lin, miss;
    CHECK_OK(rk_quadratic_fit(n, r, V, &M, D, T, fit, &lin, &miss, &err));
    double worst = 0, top = 0;
    for (int k = 0; k < n * np; k++) {
        worst = fmax(worst, fabs(fit[k] - Psi[k]));
        top = fmax(top, fabs(Psi[k]));
    }
    printf("# quadratic fit: the linear part misses %.3g of the frames' energy, the fit %.3g; Psi to %.3g\n", lin, miss,
           worst / top);
    CHECK(lin > 1e-3, "the frames are almost linear (%g): the test shows nothing", lin);
    CHECK(miss < 1e-9 && worst < 1e-4 * top, "fit misses %g, Psi off by %g of %g", miss, worst, top);
    /* too few frames for r: refused */
    CHECK(rk_quadratic_fit(n, r, V, &M, D, 0, fit, NULL, NULL, &err) != 0, "no frames accepted");
    rk_sparse_free(&M);
    free(V);
    free(Psi);
    free(fit);
    free(D);
    free(Mx);
    fem_body_free(&b);
}

int main(void)
{
    RUN(interpolation_follows_the_geodesic);
    RUN(history_basis_recovers_a_basis_that_explains_the_history);
    RUN(quadratic_decoder_jacobian_and_encoder);
    RUN(quadratic_fit_recovers_a_known_manifold);
    return test_finish();
}
