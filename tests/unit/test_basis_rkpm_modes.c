/* RKPM skinning eigenmodes (freeform paper Sec. 3.2): on a bar the first non-constant mode is
 * nearly a linear field (Fig. 3b) with the 1D eigenvalue (lambda + 4 mu)(pi/L)^2, a
 * two-material bar shifts it as Prop. 1 says, weights are orthonormal in the RKPM mass (Eq. 14),
 * a point cloud (Gaussian splats) works without a mesh, and bad requests fail clearly. */
#include "basis/basis.h"
#include "bar_1d.h"
#include "testlib.h"

static const rk_material soft = {RK_MAT_NEOHOOKEAN, 1e5, 0.3, 1000};

/* Integration points of a box bar and a per-point coefficient (two materials split at x = a). */
static int bar_points(double L, int target, double a, rk_material left, rk_material right,
                      rk_rkpm_points *pts, double **coef, rk_error *err)
{
    rk_mesh m;
    if (rk_mesh_box((double[3]){L, 0.5, 0.5}, (int[3]){16, 2, 2}, &m, err)) return -1;
    int rc = rk_rkpm_sample_mesh(&m, target, pts, err);
    rk_mesh_free(&m);
    if (rc) return -1;
    *coef = malloc(sizeof(double) * pts->n);
    for (int i = 0; i < pts->n; i++) (*coef)[i] = lame_sum(pts->X[3 * i] < a ? left : right);
    return 0;
}

TEST(first_mode_is_nearly_linear_with_the_bar_eigenvalue)
{
    rk_error err;
    const double L = 4.0;
    rk_rkpm_points pts;
    double *coef;
    CHECK_OK(bar_points(L, 12000, L, soft, soft, &pts, &coef, &err));
    rk_basis b;
    CHECK_OK(rk_basis_rkpm_skinning(&pts, coef, 400, 3, pts.X, pts.n, NULL, NULL, 0, &b, NULL, &err));
    /* Least-squares linear fit w ~ c0 + c1 x + c2 y + c3 z over the points (normal equations). */
    const double *w = b.W + (size_t)pts.n;
    double A[4][5] = {{0}};
    for (int i = 0; i < pts.n; i++) {
        double p[4] = {1, pts.X[3 * i], pts.X[3 * i + 1], pts.X[3 * i + 2]};
        for (int r = 0; r < 4; r++) {
            for (int c = 0; c < 4; c++) A[r][c] += p[r] * p[c];
            A[r][4] += p[r] * w[i];
        }
    }
    for (int k = 0; k < 4; k++) /* Gauss-Jordan, SPD so no pivoting needed */
        for (int r = 0; r < 4; r++) {
            if (r == k) continue;
            double f = A[r][k] / A[k][k];
            for (int c = k; c < 5; c++) A[r][c] -= f * A[k][c];
        }
    double res = 0, tot = 0, mean = 0;
    for (int i = 0; i < pts.n; i++) mean += w[i] / pts.n;
    for (int i = 0; i < pts.n; i++) {
        double p[4] = {1, pts.X[3 * i], pts.X[3 * i + 1], pts.X[3 * i + 2]}, fit = 0;
        for (int k = 0; k < 4; k++) fit += A[k][4] / A[k][k] * p[k];
        res += pow(w[i] - fit, 2);
        tot += pow(w[i] - mean, 2);
    }
    double rel = sqrt(res / tot), exact = lame_sum(soft) * pow(M_PI / L, 2);
    /* The continuous mode is cos(pi x / L), whose best linear fit leaves 12% (R^2 = 0.986). */
    printf("# RKPM bar (400 kernels, %d points): lambda_1 %.6g vs (lambda + 4 mu)(pi/L)^2 = %.6g; "
           "first mode's distance from a linear field %.3f (cos: 0.120)\n", pts.n, b.values[1], exact, rel);
    double e = fabs(b.values[1] - exact) / exact;
    rk_basis_free(&b);
    rk_rkpm_points_free(&pts);
    free(coef);
    CHECK(rel < 0.15, "first mode is %.3f away from linear", rel);
    CHECK(e < 0.03, "eigenvalue off by %.3g relative", e);
}

TEST(two_material_bar_matches_proposition_1)
{
    rk_error err;
    const double L = 4.0, a = 1.5;
    rk_material stiff = {RK_MAT_NEOHOOKEAN, 1e6, 0.45, 3000};
    rk_rkpm_points pts;
    double *coef;
    CHECK_OK(bar_points(L, 12000, a, stiff, soft, &pts, &coef, &err));
    rk_basis b;
    CHECK_OK(rk_basis_rkpm_skinning(&pts, coef, 400, 1, pts.X, pts.n, NULL, NULL, 0, &b, NULL, &err));
    double exact = two_material_eigenvalue(lame_sum(stiff), lame_sum(soft), a, L);
    double homogeneous = lame_sum(soft) * pow(M_PI / L, 2);
    printf("# RKPM two-material bar: lambda_1 %.6g, 1D analytic %.6g (all soft: %.6g)\n", b.values[1], exact, homogeneous);
    double e = fabs(b.values[1] - exact) / exact;
    rk_basis_free(&b);
    rk_rkpm_points_free(&pts);
    free(coef);
    CHECK(e < 0.05, "eigenvalue off by %.3g relative", e);
}

TEST(weights_are_orthonormal_in_the_rkpm_mass)
{
    rk_error err;
    rk_rkpm_points pts;
    double *coef;
    CHECK_OK(bar_points(2.0, 6000, 2.0, soft, soft, &pts, &coef, &err));
    rk_basis b;
    CHECK_OK(rk_basis_rkpm_skinning(&pts, coef, 200, 5, pts.X, pts.n, NULL, NULL, 0, &b, NULL, &err));
    /* W evaluated at the integration points: sum_i v_i W_a(X_i) W_b(X_i) is c^T M c (Eq. 14). */
    double worst = 0;
    for (int p = 0; p < b.m; p++)
        for (int q = 0; q < b.m; q++) {
            double g = 0;
            for (int i = 0; i < pts.n; i++) g += pts.weight[i] * b.W[(size_t)p * pts.n + i] * b.W[(size_t)q * pts.n + i];
            worst = fmax(worst, fabs(g - (p == q)));
        }
    int zero = b.nzero, m = b.m, r = b.r;
    rk_basis_free(&b);
    rk_rkpm_points_free(&pts);
    free(coef);
    CHECK(zero == 1 && m == 6 && r == 72, "zero %d, weights %d, columns %d", zero, m, r);
    CHECK(worst < 1e-9, "W^T M W differs from I by %.3g", worst);
}

TEST(gaussian_splats_give_weights_without_a_mesh)
{
    rk_error err;
    double *X;
    int n;
    CHECK_OK(rk_points_load(test_data("meshes/donut_3dgs.ply"), &X, &n, &err));
    rk_rkpm_points pts;
    CHECK_OK(rk_rkpm_sample_cloud(X, n, 40000, &pts, &err));
    double *coef = malloc(sizeof(double) * pts.n);
    for (int i = 0; i < pts.n; i++) coef[i] = lame_sum(soft);
    rk_basis b;
    rk_rkpm_timing tm;
    int rc = rk_basis_rkpm_skinning(&pts, coef, 1000, 16, X, n, NULL, NULL, 0, &b, &tm, &err);
    if (!rc) {
        printf("# donut splats: %d points, %d integration points, 1000 kernels, 16 modes: fps %.3f s, "
               "assemble %.3f s, eigensolve %.3f s, weights at the splats %.3f s\n",
               n, pts.n, tm.fps, tm.assemble, tm.eigs, tm.evaluate);
        int finite = 1;
        for (size_t i = 0; i < (size_t)n * b.m; i++) finite &= isfinite(b.W[i]);
        CHECK(finite, "non-finite weight");
        CHECK(b.nzero == 1 && b.values[1] > 0, "values %g %g", b.values[0], b.values[1]);
        rk_basis_free(&b);
    }
    free(coef);
    free(X);
    rk_rkpm_points_free(&pts);
    CHECK(rc == 0, "%s", err.msg);
}

TEST(bad_requests_fail_clearly)
{
    rk_error err;
    rk_rkpm_points pts;
    double *coef;
    CHECK_OK(bar_points(2.0, 2000, 2.0, soft, soft, &pts, &coef, &err));
    rk_basis b;
    int too_many_kernels = rk_basis_rkpm_skinning(&pts, coef, pts.n + 1, 4, pts.X, pts.n, NULL, NULL, 0, &b, NULL, &err) != 0;
    char m1[1024];
    snprintf(m1, sizeof m1, "%s", err.msg);
    int too_many_modes = rk_basis_rkpm_skinning(&pts, coef, 20, 19, pts.X, pts.n, NULL, NULL, 0, &b, NULL, &err) != 0;
    char m2[1024];
    snprintf(m2, sizeof m2, "%s", err.msg);
    /* Weights asked 100 m away from every kernel. */
    double far[6] = {0.5, 0.25, 0.25, 100, 0, 0};
    int far_point = rk_basis_rkpm_skinning(&pts, coef, 50, 2, far, 2, NULL, NULL, 0, &b, NULL, &err) != 0;
    rk_rkpm_points_free(&pts);
    free(coef);
    CHECK(too_many_kernels && strstr(m1, "RKPM"), "more kernels than points: %s", m1);
    CHECK(too_many_modes && strstr(m2, "19 skinning weights"), "19 weights from 20 kernels: %s", m2);
    CHECK(far_point && strstr(err.msg, "point 1") && strstr(err.msg, "too sparse"), "far point: %s", err.msg);
}

/* Two bars 10 m apart: no kernel bridges them, so the constant mode is double (one per piece)
 * and the weight-space problem has no unique answer. */
TEST(disconnected_point_clouds_are_refused)
{
    rk_error err;
    rk_rkpm_points pts;
    double *coef;
    CHECK_OK(bar_points(2.0, 3000, 2.0, soft, soft, &pts, &coef, &err));
    int n = pts.n;
    double *X = malloc(sizeof(double) * 6 * n), *v = malloc(sizeof(double) * 2 * n), *c = malloc(sizeof(double) * 2 * n);
    for (int i = 0; i < n; i++) {
        for (int d = 0; d < 3; d++) {
            X[3 * i + d] = pts.X[3 * i + d];
            X[3 * (n + i) + d] = pts.X[3 * i + d] + (d == 1 ? 10.0 : 0.0);
        }
        v[i] = v[n + i] = pts.weight[i];
        c[i] = c[n + i] = coef[i];
    }
    rk_rkpm_points two = {.n = 2 * n, .X = X, .weight = v};
    rk_basis b;
    int rc = rk_basis_rkpm_skinning(&two, c, 100, 3, X, 2 * n, NULL, NULL, 0, &b, NULL, &err);
    free(X); free(v); free(c); free(coef);
    rk_rkpm_points_free(&pts);
    CHECK(rc != 0, "two separate pieces accepted");
    CHECK(strstr(err.msg, "disconnected pieces"), "message: %s", err.msg);
}

int main(void)
{
    RUN(first_mode_is_nearly_linear_with_the_bar_eigenvalue);
    RUN(two_material_bar_matches_proposition_1);
    RUN(weights_are_orthonormal_in_the_rkpm_mass);
    RUN(gaussian_splats_give_weights_without_a_mesh);
    RUN(bad_requests_fail_clearly);
    RUN(disconnected_point_clouds_are_refused);
    return test_finish();
}
