/* precompute/basis rk_rkpm_interpolate's gradients (dW, freeform paper Eq. 21: what F at a
 * mesh-free integration point is made of), checked independently of their derivation:
 *   - against central finite differences of W itself, at random points of a jittered grid of
 *     kernel centres with random nodal values;
 *   - dW NULL gives the same W bit for bit, and evaluating all points at once (chunked) gives
 *     what evaluating them one at a time gives;
 *   - linear reproduction: nodal values c_k = a . p_k + b give W = a . X + b and dW = a;
 *   - the tolerant (regularized) path: at points where the moment matrix is damped, dW against
 *     finite differences of the same damped W. */
#include "basis/basis.h"
#include "testlib.h"
#include "util/util.h"

static uint64_t rng = 20261125;
static double uni(void) { return rk_uniform(&rng); } /* [0, 1) */

/* A jittered nx x ny x nz grid of spacing s (jitter +-s/4 per coordinate), origin 0. */
static double *jittered_grid(int nx, int ny, int nz, double s, int *K)
{
    *K = nx * ny * nz;
    double *C = calloc(3 * (size_t)*K, sizeof *C);
    int k = 0;
    for (int z = 0; z < nz; z++)
        for (int y = 0; y < ny; y++)
            for (int x = 0; x < nx; x++, k++) {
                int idx[3] = {x, y, z};
                for (int d = 0; d < 3; d++) C[3 * k + d] = s * (idx[d] + 0.5 * (uni() - 0.5));
            }
    return C;
}

/* Worst |dW - FD(W)| / scale over n points and m fields, scale = max |dW| over all of them.
 * Central differences of step h per coordinate. regularized: NULL (strict) or a counter. */
static int fd_gradient_error(const rk_rkpm *k, const double *X, int n, const double *c, int m, double h,
                             int *regularized, double *worst, double *scale, rk_error *err)
{
    double *W = calloc((size_t)n * m, sizeof *W), *dW = calloc(3 * (size_t)n * m, sizeof *dW);
    double *Xp = calloc(3 * (size_t)n, sizeof *Xp), *Xm = calloc(3 * (size_t)n, sizeof *Xm);
    double *Wp = calloc((size_t)n * m, sizeof *Wp), *Wm = calloc((size_t)n * m, sizeof *Wm);
    int rc = rk_rkpm_interpolate(k, X, n, c, m, W, dW, regularized, err);
    *worst = 0;
    *scale = 0;
    for (size_t e = 0; rc == 0 && e < 3 * (size_t)n * m; e++) *scale = fmax(*scale, fabs(dW[e]));
    for (int b = 0; rc == 0 && b < 3; b++) {
        memcpy(Xp, X, 3 * (size_t)n * sizeof *X);
        memcpy(Xm, X, 3 * (size_t)n * sizeof *X);
        for (int i = 0; i < n; i++) Xp[3 * i + b] += h, Xm[3 * i + b] -= h;
        int dummy;
        rc = rk_rkpm_interpolate(k, Xp, n, c, m, Wp, NULL, regularized ? &dummy : NULL, err) ||
             rk_rkpm_interpolate(k, Xm, n, c, m, Wm, NULL, regularized ? &dummy : NULL, err);
        for (int j = 0; rc == 0 && j < m; j++)
            for (int i = 0; i < n; i++) {
                double fd = (Wp[i + (size_t)n * j] - Wm[i + (size_t)n * j]) / (2 * h);
                *worst = fmax(*worst, fabs(dW[3 * (size_t)i + b + 3 * (size_t)n * j] - fd));
            }
    }
    *worst /= *scale > 0 ? *scale : 1;
    free(W), free(dW), free(Xp), free(Xm), free(Wp), free(Wm);
    return rc;
}

TEST(gradients_match_finite_differences)
{
    rk_error err;
    rk_rkpm k;
    int K, m = 3, n = 300;
    double s = 0.2, *C = jittered_grid(7, 5, 4, s, &K);
    CHECK_OK(rk_rkpm_init(&k, C, K, &err));
    double *c = calloc((size_t)K * m, sizeof *c), *X = calloc(3 * (size_t)n, sizeof *X);
    for (int e = 0; e < K * m; e++) c[e] = 2 * uni() - 1;
    /* points anywhere in the grid's interior box (kernels reach 3.5 radii, ~2 spacings) */
    for (int i = 0; i < n; i++) X[3 * i] = 6 * s * uni(), X[3 * i + 1] = 4 * s * uni(), X[3 * i + 2] = 3 * s * uni();
    double worst, scale;
    CHECK_OK(fd_gradient_error(&k, X, n, c, m, 1e-5 * s, NULL, &worst, &scale, &err));
    printf("# dW against central differences (h = 1e-5 s): %.3g relative to max |dW| = %.3g\n", worst, scale);
    CHECK(scale > 1, "the random fields have no gradient to speak of (max |dW| = %g)", scale);
    CHECK(worst < 1e-6, "dW differs from finite differences of W by %.3g (relative)", worst);
    /* halving h should shrink a truncation error, not reveal a different derivative */
    double worst2;
    CHECK_OK(fd_gradient_error(&k, X, n, c, m, 1e-4 * s, NULL, &worst2, &scale, &err));
    CHECK(worst2 < 1e-5, "FD with h = 1e-4 s: %.3g", worst2);
    free(c), free(X), free(C);
    rk_rkpm_free(&k);
}

TEST(gradients_do_not_change_the_weights)
{
    rk_error err;
    rk_rkpm k;
    int K, m = 4, n = 500;
    double s = 0.25, *C = jittered_grid(6, 6, 3, s, &K);
    CHECK_OK(rk_rkpm_init(&k, C, K, &err));
    double *c = calloc((size_t)K * m, sizeof *c), *X = calloc(3 * (size_t)n, sizeof *X);
    double *W1 = calloc((size_t)n * m, sizeof *W1), *W2 = calloc((size_t)n * m, sizeof *W2);
    double *dW = calloc(3 * (size_t)n * m, sizeof *dW), W0[4], dW0[12];
    for (int e = 0; e < K * m; e++) c[e] = uni();
    for (int i = 0; i < n; i++) X[3 * i] = 5 * s * uni(), X[3 * i + 1] = 5 * s * uni(), X[3 * i + 2] = 2 * s * uni();
    CHECK_OK(rk_rkpm_interpolate(&k, X, n, c, m, W1, NULL, NULL, &err));
    CHECK_OK(rk_rkpm_interpolate(&k, X, n, c, m, W2, dW, NULL, &err));
    CHECK(memcmp(W1, W2, sizeof(double) * n * m) == 0, "W with dW differs from W without");
    /* one point at a time (its own chunk) against all at once (spatial chunks, any order) */
    double worst = 0;
    for (int i = 0; i < n; i++) {
        CHECK_OK(rk_rkpm_interpolate(&k, &X[3 * i], 1, c, m, W0, dW0, NULL, &err));
        for (int j = 0; j < m; j++) {
            worst = fmax(worst, fabs(W0[j] - W2[i + (size_t)n * j]));
            for (int b = 0; b < 3; b++) worst = fmax(worst, fabs(dW0[b + 3 * j] - dW[3 * i + b + 3 * (size_t)n * j]));
        }
    }
    printf("# one point at a time against %d at once: %.3g\n", n, worst);
    CHECK(worst < 1e-12, "point by point differs from all at once by %g", worst);
    free(c), free(X), free(W1), free(W2), free(dW), free(C);
    rk_rkpm_free(&k);
}

TEST(linear_fields_have_exact_constant_gradients)
{
    rk_error err;
    rk_rkpm k;
    int K, m = 3, n = 400;
    double s = 0.2, *C = jittered_grid(6, 5, 5, s, &K);
    CHECK_OK(rk_rkpm_init(&k, C, K, &err));
    const double a[3][3] = {{1.5, -2, 0.25}, {0, 0, 3}, {-0.7, 0.4, 1.1}}, b[3] = {0.5, -1, 2};
    double *c = calloc((size_t)K * m, sizeof *c), *X = calloc(3 * (size_t)n, sizeof *X);
    double *W = calloc((size_t)n * m, sizeof *W), *dW = calloc(3 * (size_t)n * m, sizeof *dW);
    for (int j = 0; j < m; j++)
        for (int q = 0; q < K; q++)
            c[q + (size_t)K * j] = a[j][0] * C[3 * q] + a[j][1] * C[3 * q + 1] + a[j][2] * C[3 * q + 2] + b[j];
    for (int i = 0; i < n; i++) X[3 * i] = 5 * s * uni(), X[3 * i + 1] = 4 * s * uni(), X[3 * i + 2] = 4 * s * uni();
    CHECK_OK(rk_rkpm_interpolate(&k, X, n, c, m, W, dW, NULL, &err));
    double ew = 0, eg = 0;
    for (int j = 0; j < m; j++)
        for (int i = 0; i < n; i++) {
            double ref = a[j][0] * X[3 * i] + a[j][1] * X[3 * i + 1] + a[j][2] * X[3 * i + 2] + b[j];
            ew = fmax(ew, fabs(W[i + (size_t)n * j] - ref));
            for (int d = 0; d < 3; d++) eg = fmax(eg, fabs(dW[3 * i + d + 3 * (size_t)n * j] - a[j][d]));
        }
    printf("# linear reproduction: |W - a.X - b| %.3g, |dW - a| %.3g\n", ew, eg);
    CHECK(ew < 1e-10, "W misses the linear field by %g", ew);
    CHECK(eg < 1e-10, "dW misses the linear field's gradient by %g", eg);
    free(c), free(X), free(W), free(dW), free(C);
    rk_rkpm_free(&k);
}

/* Tolerant evaluation where the moment matrix is damped: a single layer of kernels (a flat sheet:
 * every point's covering kernels are nearly coplanar), points in the sheet. The header promises
 * dW = the analytic gradients of W, there too. */
TEST(regularized_gradients_match_finite_differences)
{
    rk_error err;
    rk_rkpm k;
    int K = 0, nx = 8, ny = 8, m = 2, n = 100;
    double s = 0.2, *C = calloc(3 * (size_t)nx * ny, sizeof *C);
    for (int y = 0; y < ny; y++)
        for (int x = 0; x < nx; x++, K++) {
            C[3 * K] = s * (x + 0.5 * (uni() - 0.5));
            C[3 * K + 1] = s * (y + 0.5 * (uni() - 0.5));
            C[3 * K + 2] = 0; /* exactly flat */
        }
    CHECK_OK(rk_rkpm_init(&k, C, K, &err));
    double *c = calloc((size_t)K * m, sizeof *c), *X = calloc(3 * (size_t)n, sizeof *X), *W = calloc((size_t)n * m, sizeof *W);
    for (int e = 0; e < K * m; e++) c[e] = 2 * uni() - 1;
    for (int i = 0; i < n; i++) X[3 * i] = (1 + 5 * uni()) * s, X[3 * i + 1] = (1 + 5 * uni()) * s, X[3 * i + 2] = 0.05 * s * (uni() - 0.5);
    CHECK(rk_rkpm_interpolate(&k, X, n, c, m, W, NULL, NULL, &err) != 0, "strict evaluation in a flat sheet succeeded");
    int damped = 0;
    CHECK_OK(rk_rkpm_interpolate(&k, X, n, c, m, W, NULL, &damped, &err));
    CHECK(damped == n, "only %d of %d points in the sheet were damped", damped, n);
    double worst, scale;
    CHECK_OK(fd_gradient_error(&k, X, n, c, m, 1e-5 * s, &damped, &worst, &scale, &err));
    printf("# damped points: dW against central differences %.3g relative to max |dW| = %.3g\n", worst, scale);
    CHECK(worst < 1e-8, "at damped points dW differs from finite differences of W by %.3g (relative)", worst);
    free(c), free(X), free(W), free(C);
    rk_rkpm_free(&k);
}

int main(void)
{
    RUN(gradients_match_finite_differences);
    RUN(gradients_do_not_change_the_weights);
    RUN(linear_fields_have_exact_constant_gradients);
    RUN(regularized_gradients_match_finite_differences);
    return test_finish();
}
