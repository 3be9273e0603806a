/* Modal derivatives: the stiffness derivative against finite differences of the internal
 * forces, the derivative equation's residual, the second-order static response of the
 * full nonlinear model, and the final basis. */
#include "basis/basis.h"
#include "fom/fom.h"
#include "fem_body.h"
#include "testlib.h"
#include "util/util.h"

static const rk_material rubber = {RK_MAT_NEOHOOKEAN, 1e6, 0.4, 1000};

TEST(stiffness_derivative_matches_force_differences)
{
    rk_error err;
    fem_body b;
    CHECK_OK(fem_body_box(&b, 1.0, 0.3, 0.3, 4, 2, 2, rubber, &err));
    int n3 = 3 * b.f.nv;
    double *a = malloc(sizeof(double) * n3), *c = malloc(sizeof(double) * n3);
    double *out = malloc(sizeof(double) * n3), *fd = calloc(n3, sizeof(double));
    double *x = malloc(sizeof(double) * n3);
    uint64_t rng = 3; /* the project's generator (util/util.h): the same a and c everywhere */
    for (int i = 0; i < n3; i++) {
        a[i] = 0.01 * (rk_uniform(&rng) - 0.5);
        c[i] = 0.01 * (rk_uniform(&rng) - 0.5);
    }
    rk_stiffness_derivative(&b.f, a, c, out);
    /* d2 g / (ds dt) at x = X + s a + t c, s = t = 0: four internal-force evaluations. */
    const double h = 1e-3;
    const int sgn[4][2] = {{1, 1}, {1, -1}, {-1, 1}, {-1, -1}};
    for (int k = 0; k < 4; k++) {
        for (int i = 0; i < n3; i++) x[i] = b.f.X[i] + h * (sgn[k][0] * a[i] + sgn[k][1] * c[i]);
        rk_fem_add_gradient(&b.f, x, sgn[k][0] * sgn[k][1] / (4 * h * h), fd);
    }
    double diff = 0;
    for (int i = 0; i < n3; i++) diff += pow(out[i] - fd[i], 2);
    double rel = sqrt(diff) / test_norm(fd, n3);
    free(a); free(c); free(out); free(fd); free(x);
    fem_body_free(&b);
    CHECK(rel < 1e-5, "(H : a) b differs from force differences by %.3g relative", rel);
}

/* Recomputes K Psi_ij and the right-hand side -(H : psi_i) psi_j independently of the solver. */
TEST(derivatives_satisfy_their_equation)
{
    rk_error err;
    fem_body b;
    CHECK_OK(fem_body_box(&b, 2.0, 0.4, 0.4, 10, 2, 2, rubber, &err));
    unsigned char *fixed = fem_body_fix_x_below(&b, 1e-9);
    rk_basis modes;
    CHECK_OK(rk_basis_modes(&b.f, fixed, 0, 4, &modes, &err));
    int n3 = 3 * b.f.nv, npairs = 10;
    double *Psi = malloc(sizeof(double) * n3 * npairs), residual = 1;
    int rc = rk_modal_derivatives(&b.f, fixed, 0, modes.U, 4, 0, Psi, &residual, &err);
    rk_sparse K = {0};
    rk_sparse_alloc_pattern(&b.f, &K, &err);
    rk_fem_add_rest_stiffness(&b.f, 1.0, &K);
    double *lhs = malloc(sizeof(double) * n3), *rhs = malloc(sizeof(double) * n3), worst = 0;
    for (int i = 0, p = 0; !rc && i < 4; i++)
        for (int j = i; j < 4; j++, p++) {
            rk_sparse_mul(&K, Psi + (size_t)p * n3, lhs);
            rk_stiffness_derivative(&b.f, modes.U + (size_t)i * n3, modes.U + (size_t)j * n3, rhs);
            double num = 0, den = 0;
            for (int q = 0; q < n3; q++) {
                if (fixed[q / 3]) continue;
                num += pow(lhs[q] + rhs[q], 2);
                den += rhs[q] * rhs[q];
            }
            worst = fmax(worst, sqrt(num / den));
        }
    free(lhs); free(rhs); free(Psi); free(fixed);
    rk_sparse_free(&K);
    rk_basis_free(&modes);
    fem_body_free(&b);
    CHECK(rc == 0, "%s", err.msg);
    printf("# modal derivatives, clamped beam: largest relative residual %.3g (solver's own %.3g)\n", worst, residual);
    CHECK(worst < 1e-8, "relative residual %.3g", worst);
}

TEST(free_object_derivatives_satisfy_the_projected_equation)
{
    rk_error err;
    fem_body b;
    CHECK_OK(fem_body_box(&b, 1.0, 0.3, 0.3, 6, 2, 2, rubber, &err));
    rk_basis basis;
    CHECK_OK(rk_basis_modes(&b.f, NULL, 0, 9, &basis, &err));
    CHECK(basis.nzero == 6, "%d rigid modes", basis.nzero);
    int n3 = 3 * b.f.nv;
    double *Psi = malloc(sizeof(double) * n3 * 6), residual = 1;
    int rc = rk_modal_derivatives(&b.f, NULL, 0, basis.U, 9, 6, Psi, &residual, &err);
    free(Psi);
    rk_basis_free(&basis);
    fem_body_free(&b);
    CHECK(rc == 0, "%s", err.msg);
    CHECK(residual < 1e-8, "relative residual %.3g", residual);
}

/* The nonlinear static response to the force q K psi_1 is q psi_1 + q^2/2 Psi_11 + O(q^3), so
 * (u(q) + u(-q)) / q^2 -> Psi_11: the full-order solver checks the derivative. */
TEST(derivative_is_the_second_order_static_response)
{
    rk_error err;
    fem_body b;
    CHECK_OK(fem_body_box(&b, 2.0, 0.4, 0.4, 10, 2, 2, rubber, &err));
    unsigned char *fixed = fem_body_fix_x_below(&b, 1e-9);
    rk_basis modes;
    CHECK_OK(rk_basis_modes(&b.f, fixed, 0, 1, &modes, &err));
    int n3 = 3 * b.f.nv;
    double *Psi = malloc(sizeof(double) * n3), residual;
    CHECK_OK(rk_modal_derivatives(&b.f, fixed, 0, modes.U, 1, 0, Psi, &residual, &err));
    rk_sparse K = {0};
    rk_sparse_alloc_pattern(&b.f, &K, &err);
    rk_fem_add_rest_stiffness(&b.f, 1.0, &K);
    double *Kpsi = malloc(sizeof(double) * n3), *force = malloc(sizeof(double) * n3);
    double *sum = calloc(n3, sizeof(double));
    rk_sparse_mul(&K, modes.U, Kpsi);
    /* Scale so the linear tip deflection is 2% of the length. */
    double umax = 0;
    for (int i = 0; i < n3; i++) umax = fmax(umax, fabs(modes.U[i]));
    double q = 0.04 / umax;
    int nfix = 0;
    for (int v = 0; v < b.f.nv; v++) nfix += fixed[v];
    int *fv = malloc(sizeof(int) * nfix);
    for (int v = 0, k = 0; v < b.f.nv; v++) if (fixed[v]) fv[k++] = v;
    int rc = 0;
    for (int s = -1; s <= 1 && !rc; s += 2) {
        rk_fom_options o;
        rk_fom_default_options(&o);
        o.is_static = 1;
        o.newton_tol = 1e-13;
        for (int i = 0; i < n3; i++) force[i] = s * q * Kpsi[i];
        o.force = force;
        rk_prescribed pin = {.kind = RK_MOTION_FIXED, .count = nfix, .verts = fv};
        o.nprescribed = 1;
        o.prescribed = &pin;
        rk_fom fom;
        rc = rk_fom_init(&fom, &b.f, &o, &err) || rk_fom_static(&fom, &err);
        if (!rc) for (int i = 0; i < n3; i++) sum[i] += fom.x[i] - b.f.X[i];
        rk_fom_free(&fom);
    }
    double num = 0, den = 0;
    for (int i = 0; i < n3; i++) {
        num += pow(2 * sum[i] / (q * q) - 2 * Psi[i], 2);
        den += pow(2 * Psi[i], 2);
    }
    double rel = sqrt(num / den);
    printf("# second-order static response vs modal derivative Psi_11: relative difference %.3g (q psi tip 4 cm)\n", rel);
    free(Psi); free(Kpsi); free(force); free(sum); free(fv); free(fixed);
    rk_sparse_free(&K);
    rk_basis_free(&modes);
    fem_body_free(&b);
    CHECK(rc == 0, "static solve: %s", err.msg);
    CHECK(rel < 0.02, "relative difference %.3g", rel);
}

TEST(modal_derivative_basis_is_mass_orthonormal_and_contains_the_modes)
{
    rk_error err;
    fem_body b;
    CHECK_OK(fem_body_box(&b, 2.0, 0.4, 0.4, 10, 2, 2, rubber, &err));
    unsigned char *fixed = fem_body_fix_x_below(&b, 1e-9);
    rk_basis md, modes;
    CHECK_OK(rk_basis_modal_derivatives(&b.f, fixed, 0, 12, 0, &md, &err));
    CHECK_OK(rk_basis_modes(&b.f, fixed, 0, 2, &modes, &err));
    rk_sparse M = {0};
    rk_sparse_alloc_pattern(&b.f, &M, &err);
    rk_fem_add_mass(&b.f, 0, 1.0, &M);
    int n3 = 3 * b.f.nv;
    double worst = 0, captured = 0;
    for (int i = 0; i < md.r; i++) {
        for (int j = 0; j < md.r; j++)
            worst = fmax(worst, fabs(rk_sparse_dot(&M, md.U + (size_t)i * n3, md.U + (size_t)j * n3) - (i == j)));
        double c = rk_sparse_dot(&M, md.U + (size_t)i * n3, modes.U);
        captured += c * c;
    }
    CHECK(md.r == 12 && md.nzero == 0, "r %d, rigid %d", md.r, md.nzero);
    rk_sparse_free(&M);
    rk_basis_free(&md);
    rk_basis_free(&modes);
    free(fixed);
    fem_body_free(&b);
    CHECK(worst < 1e-10, "U^T M U differs from I by %.3g", worst);
    CHECK(fabs(captured - 1) < 1e-6, "the first linear mode is only %.8f inside the basis", captured);
}

int main(void)
{
    RUN(stiffness_derivative_matches_force_differences);
    RUN(derivatives_satisfy_their_equation);
    RUN(free_object_derivatives_satisfy_the_projected_equation);
    RUN(derivative_is_the_second_order_static_response);
    RUN(modal_derivative_basis_is_mass_orthonormal_and_contains_the_modes);
    return test_finish();
}
