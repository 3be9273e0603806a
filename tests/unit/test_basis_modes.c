/* Linear modes against independent computations: a dense element-by-element K and M solved by
 * LAPACK's generalized symmetric eigensolver, the six rigid modes of a free object, and a slender
 * cantilever's bending frequencies against Euler-Bernoulli beam theory. */
#include <lapacke.h>

#include "basis/basis.h"
#include "fem_body.h"
#include "testlib.h"

static const rk_material steel_ish = {RK_MAT_NEOHOOKEAN, 2e6, 0.3, 1200};

/* Dense K (rest Hessian, element by element) and M (consistent P1, written out here from the
 * formula rho V / 20 (1 + delta_ab), or lumped rho V / 4) over the dofs with keep[i] >= 0. */
static void dense_system(const fem_body *b, const int *keep, int nfree, int lumped, double *K, double *M)
{
    const rk_fem *f = &b->f;
    memset(K, 0, sizeof(double) * nfree * nfree);
    memset(M, 0, sizeof(double) * nfree * nfree);
    for (int t = 0; t < f->nt; t++) {
        const int *tv = &f->tets[4 * t];
        double xe[12], He[144];
        for (int a = 0; a < 4; a++)
            for (int c = 0; c < 3; c++) xe[3 * a + c] = f->X[3 * tv[a] + c];
        rk_tet_hessian(f->model[t], f->mu[t], f->lambda[t], xe, &f->Dm_inv[9 * t], f->vol[t], He, 0);
        double m = f->density[t] * f->vol[t] / 20.0;
        for (int p = 0; p < 12; p++)
            for (int q = 0; q < 12; q++) {
                int i = keep[3 * tv[p / 3] + p % 3], j = keep[3 * tv[q / 3] + q % 3];
                if (i < 0 || j < 0) continue;
                K[(size_t)i * nfree + j] += He[12 * p + q];
                if (p % 3 != q % 3) continue;
                if (lumped) M[(size_t)i * nfree + j] += p == q ? 5 * m : 0; /* rho V / 4 */
                else M[(size_t)i * nfree + j] += p / 3 == q / 3 ? 2 * m : m;
            }
    }
}

/* Compares rk_basis_modes to LAPACK dsygvd on the same problem. */
static int compare_dense(fem_body *b, const unsigned char *fixed, int lumped, int count, int expect_zero,
                         char *why, size_t whylen)
{
    rk_error err;
    int ndof = 3 * b->f.nv, nfree = 0;
    int *keep = malloc(sizeof(int) * ndof);
    for (int i = 0; i < ndof; i++) keep[i] = fixed && fixed[i / 3] ? -1 : nfree++;
    double *K = malloc(sizeof(double) * nfree * nfree), *M = malloc(sizeof(double) * nfree * nfree);
    double *w = malloc(sizeof(double) * nfree);
    dense_system(b, keep, nfree, lumped, K, M);
    int bad = LAPACKE_dsygvd(LAPACK_ROW_MAJOR, 1, 'N', 'U', nfree, K, nfree, M, nfree, w) != 0;
    rk_basis basis;
    if (bad) snprintf(why, whylen, "dsygvd failed");
    else if (rk_basis_modes(&b->f, fixed, lumped, count, &basis, &err)) {
        snprintf(why, whylen, "rk_basis_modes: %s", err.msg);
        bad = 1;
    } else {
        double scale = w[nfree - 1];
        for (int i = 0; i < count && !bad; i++) {
            /* Rigid modes are zero up to roundoff of the largest eigenvalue; the others must
             * agree to 1e-8 relative. */
            double tol = i < expect_zero ? 1e-10 * scale : 1e-8 * fabs(w[i]);
            if (fabs(basis.values[i] - w[i]) > tol) {
                snprintf(why, whylen, "eigenvalue %d: %.15g vs dense %.15g", i, basis.values[i], w[i]);
                bad = 1;
            }
        }
        if (!bad && basis.nzero != expect_zero) {
            snprintf(why, whylen, "%d zero eigenvalues reported, expected %d", basis.nzero, expect_zero);
            bad = 1;
        }
        rk_basis_free(&basis);
    }
    free(keep); free(K); free(M); free(w);
    return bad;
}

TEST(modes_match_dense_lapack_clamped)
{
    rk_error err;
    fem_body b;
    CHECK_OK(fem_body_box(&b, 1.0, 0.3, 0.2, 5, 2, 2, steel_ish, &err));
    unsigned char *fixed = fem_body_fix_x_below(&b, 1e-9);
    char why[256];
    int bad = compare_dense(&b, fixed, 0, 12, 0, why, sizeof why);
    int bad_lumped = bad ? 0 : compare_dense(&b, fixed, 1, 12, 0, why, sizeof why);
    free(fixed);
    fem_body_free(&b);
    CHECK(!bad && !bad_lumped, "%s mass: %s", bad ? "consistent" : "lumped", why);
}

TEST(free_object_has_exactly_six_rigid_modes)
{
    rk_error err;
    fem_body b;
    CHECK_OK(fem_body_box(&b, 1.0, 0.3, 0.2, 5, 2, 2, steel_ish, &err));
    char why[256];
    int bad = compare_dense(&b, NULL, 0, 10, 6, why, sizeof why);
    fem_body_free(&b);
    CHECK(!bad, "%s", why);
}

TEST(modes_are_mass_orthonormal_eigenvectors)
{
    rk_error err;
    fem_body b;
    CHECK_OK(fem_body_box(&b, 2.0, 0.4, 0.4, 10, 2, 2, steel_ish, &err));
    unsigned char *fixed = fem_body_fix_x_below(&b, 1e-9);
    rk_basis basis;
    int rc = rk_basis_modes(&b.f, fixed, 0, 8, &basis, &err);
    rk_sparse K = {0}, M = {0};
    if (!rc) {
        rk_sparse_alloc_pattern(&b.f, &K, &err);
        rk_sparse_alloc_pattern(&b.f, &M, &err);
        rk_fem_add_rest_stiffness(&b.f, 1.0, &K);
        rk_fem_add_mass(&b.f, 0, 1.0, &M);
    }
    double worst_orth = 0, worst_res = 0;
    int n3 = 3 * b.f.nv;
    double *Kv = malloc(sizeof(double) * n3), *Mv = malloc(sizeof(double) * n3);
    for (int i = 0; !rc && i < basis.r; i++) {
        const double *u = basis.U + (size_t)i * n3;
        for (int j = 0; j < basis.r; j++)
            worst_orth = fmax(worst_orth, fabs(rk_sparse_dot(&M, u, basis.U + (size_t)j * n3) - (i == j)));
        rk_sparse_mul(&K, u, Kv);
        rk_sparse_mul(&M, u, Mv);
        double num = 0, den = 0;
        for (int k = 0; k < n3; k++) {
            if (fixed[k / 3]) { CHECK(u[k] == 0, "mode %d moves fixed dof %d", i, k); continue; }
            num += pow(Kv[k] - basis.values[i] * Mv[k], 2);
            den += pow(Kv[k], 2);
        }
        worst_res = fmax(worst_res, sqrt(num / den));
    }
    free(Kv); free(Mv); free(fixed);
    rk_sparse_free(&K); rk_sparse_free(&M);
    if (!rc) rk_basis_free(&basis);
    fem_body_free(&b);
    CHECK(rc == 0, "%s", err.msg);
    CHECK(worst_orth < 1e-10, "U^T M U differs from I by %.3g", worst_orth);
    CHECK(worst_res < 1e-9, "relative residual |K u - lambda M u| / |K u| = %.3g", worst_res);
}

/* Euler-Bernoulli cantilever: omega_k = (beta_k L)^2 sqrt(E I / (rho A L^4)). With nu = 0 there
 * is no Poisson coupling; P1 tetrahedra are too stiff in bending and converge from above. */
TEST(cantilever_frequencies_converge_to_beam_theory)
{
    const double L = 1.0, a = 0.05, E = 1e7, rho = 1000;
    const double inertia = a * a * a * a / 12, area = a * a;
    const double beta[2] = {1.875104069, 4.694091133};
    double prev = INFINITY, split = 0, prev_split = INFINITY;
    printf("# cantilever %gx%gx%g m, E %g, nu 0: first and second bending frequency (Hz) vs Euler-Bernoulli\n", L, a, a, E);
    printf("# %8s %8s %12s %12s %8s %12s %12s %8s\n", "cells", "tets", "f1", "f1 beam", "err1", "f2", "f2 beam", "err2");
    for (int k = 1; k <= 5; k++) {
        rk_error err;
        fem_body b;
        rk_material mat = {RK_MAT_LINEAR, E, 0.0, rho};
        CHECK_OK(fem_body_box(&b, L, a, a, 20 * k, k, k, mat, &err));
        unsigned char *fixed = fem_body_fix_x_below(&b, 1e-9);
        rk_basis basis;
        int rc = rk_basis_modes(&b.f, fixed, 0, 6, &basis, &err);
        free(fixed);
        int nt = b.f.nt;
        fem_body_free(&b);
        CHECK(rc == 0, "%s", err.msg);
        /* Modes 0-1 bend about y and z, modes 2-3 are the second bending pair (torsion is at
         * 16 Hz, axial at 25 Hz, both above). The tet pattern of the box is not symmetric in y
         * and z, so a pair splits on coarse meshes and closes as the mesh refines. */
        double f1 = sqrt(basis.values[0]) / (2 * M_PI), f1b = sqrt(basis.values[1]) / (2 * M_PI);
        double f2 = sqrt(basis.values[2]) / (2 * M_PI);
        split = (f1b - f1) / f1;
        rk_basis_free(&basis);
        double w1 = beta[0] * beta[0] * sqrt(E * inertia / (rho * area * pow(L, 4))) / (2 * M_PI);
        double w2 = beta[1] * beta[1] * sqrt(E * inertia / (rho * area * pow(L, 4))) / (2 * M_PI);
        double e1 = (f1 - w1) / w1, e2 = (f2 - w2) / w2;
        printf("# %5dx%dx%d %8d %12.5f %12.5f %7.2f%% %12.5f %12.5f %7.2f%%   y/z split %.2f%%\n", 20 * k, k, k, nt, f1,
               w1, 100 * e1, f2, w2, 100 * e2, 100 * split);
        CHECK(e1 > -0.01, "P1 tets must be stiffer than the beam, got %.2f%%", 100 * e1);
        CHECK(e1 < prev, "error did not shrink with refinement: %.3f%% after %.3f%%", 100 * e1, 100 * prev);
        CHECK(split < prev_split, "the y/z split did not shrink: %.3f%% after %.3f%%", 100 * split, 100 * prev_split);
        prev = e1;
        prev_split = split;
    }
    CHECK(prev < 0.05, "finest mesh still %.2f%% above beam theory", 100 * prev);

}

TEST(asking_too_much_or_nothing_free_fails_clearly)
{
    rk_error err;
    fem_body b;
    CHECK_OK(fem_body_box(&b, 1.0, 1.0, 1.0, 1, 1, 1, steel_ish, &err));
    rk_basis basis;
    CHECK(rk_basis_modes(&b.f, NULL, 0, 24, &basis, &err) != 0, "24 modes of 24 dofs accepted");
    CHECK(strstr(err.msg, "24 free degrees of freedom"), "message: %s", err.msg);
    unsigned char all[8] = {1, 1, 1, 1, 1, 1, 1, 1};
    CHECK(rk_basis_modes(&b.f, all, 0, 2, &basis, &err) != 0, "fully constrained object accepted");
    CHECK(strstr(err.msg, "no free degrees"), "message: %s", err.msg);
    fem_body_free(&b);
}

/* A singular problem: the shift sitting on an eigenvalue (sigma = 0 for a free object, whose K
 * is singular) is refused with a message that says so. (A mass matrix with a zero row is not an
 * error: mode 3 allows a semi-definite B.) */
TEST(singular_problems_are_refused)
{
    rk_error err;
    fem_body b;
    CHECK_OK(fem_body_box(&b, 1.0, 0.3, 0.3, 3, 1, 1, steel_ish, &err));
    rk_sparse K = {0}, M = {0};
    rk_sparse_alloc_pattern(&b.f, &K, &err);
    rk_sparse_alloc_pattern(&b.f, &M, &err);
    rk_fem_add_rest_stiffness(&b.f, 1.0, &K);
    rk_fem_add_mass(&b.f, 0, 1.0, &M);
    double vals[4];
    int on_eigenvalue = rk_eigs_smallest(&K, &M, 4, 0.0, vals, NULL, &err) != 0 && strstr(err.msg, "singular");
    char m1[1024];
    snprintf(m1, sizeof m1, "%s", err.msg);
    rk_sparse_free(&K);
    rk_sparse_free(&M);
    fem_body_free(&b);
    CHECK(on_eigenvalue, "sigma on an eigenvalue: %s", m1);
}

int main(void)
{
    RUN(modes_match_dense_lapack_clamped);
    RUN(free_object_has_exactly_six_rigid_modes);
    RUN(modes_are_mass_orthonormal_eigenvectors);
    RUN(cantilever_frequencies_converge_to_beam_theory);
    RUN(asking_too_much_or_nothing_free_fails_clearly);
    RUN(singular_problems_are_refused);
    return test_finish();
}
