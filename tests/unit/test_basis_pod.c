/* POD: exact singular values of a synthetic snapshot set, the tolerance rule, Eckart-Young on
 * full-order snapshots (the projection error equals the discarded singular values), errors. */
#include "basis/basis.h"
#include "fom/fom.h"
#include "fem_body.h"
#include "testlib.h"

static const rk_material rubber = {RK_MAT_NEOHOOKEAN, 1e6, 0.4, 1000};

/* D = sum_k s_k u_k v_k^T with u_k linear modes (M-orthonormal) and v_k orthonormal in time. */
static double *synthetic(const rk_basis *modes, int T, const double *s, int ks)
{
    int n3 = 3 * modes->n;
    double *D = calloc((size_t)n3 * T, sizeof(double));
    for (int k = 0; k < ks; k++)
        for (int t = 0; t < T; t++) {
            double v = sqrt(2.0 / T) * cos(M_PI * (k + 1) * (t + 0.5) / T);
            for (int i = 0; i < n3; i++) D[(size_t)t * n3 + i] += s[k] * v * modes->U[(size_t)k * n3 + i];
        }
    return D;
}

TEST(pod_recovers_known_singular_values_and_tolerance_picks_the_size)
{
    rk_error err;
    fem_body b;
    CHECK_OK(fem_body_box(&b, 1.0, 0.3, 0.3, 6, 2, 2, rubber, &err));
    rk_basis modes;
    CHECK_OK(rk_basis_modes(&b.f, NULL, 0, 10, &modes, &err));
    rk_sparse M = {0};
    rk_sparse_alloc_pattern(&b.f, &M, &err);
    rk_fem_add_mass(&b.f, 0, 1.0, &M);
    const double s[4] = {10, 1, 0.1, 0.01};
    int T = 40;
    double *D = synthetic(&modes, T, s, 4);
    rk_basis pod;
    int rc = rk_basis_pod(D, b.f.nv, T, &M, 4, 0, &pod, &err);
    double worst = 0, span = 0;
    int n3 = 3 * b.f.nv;
    for (int k = 0; !rc && k < 4; k++) {
        worst = fmax(worst, fabs(pod.values[k] - s[k]) / s[k]);
        double c = rk_sparse_dot(&M, pod.U + (size_t)k * n3, modes.U + (size_t)k * n3);
        span = fmax(span, 1 - fabs(c));
    }
    double fifth = rc ? 1 : pod.values[4];
    if (!rc) rk_basis_free(&pod);
    int rc2 = rk_basis_pod(D, b.f.nv, T, &M, 4, 0.05, &pod, &err);
    int r_tol = rc2 ? -1 : pod.r;
    if (!rc2) rk_basis_free(&pod);
    free(D);
    rk_sparse_free(&M);
    rk_basis_free(&modes);
    fem_body_free(&b);
    CHECK(rc == 0 && rc2 == 0, "%s", err.msg);
    CHECK(worst < 1e-10, "singular values off by %.3g relative", worst);
    CHECK(span < 1e-10, "POD direction differs from the planted one by %.3g", span);
    /* The method of snapshots resolves singular values down to ~sqrt(eps) of the largest. */
    CHECK(fifth < 1e-7 * s[0], "a fifth singular value %.3g where the data has rank 4", fifth);
    /* Discarded energy after 1: sqrt(1.0101 / 101.0101) = 0.1 > 0.05; after 2: 0.01. */
    CHECK(r_tol == 2, "tolerance 0.05 chose %d modes, expected 2", r_tol);
}

TEST(projection_error_of_fom_snapshots_equals_the_discarded_energy)
{
    rk_error err;
    fem_body b;
    CHECK_OK(fem_body_box(&b, 2.0, 0.3, 0.3, 12, 2, 2, rubber, &err));
    int nfix = 0;
    for (int v = 0; v < b.f.nv; v++) nfix += b.f.X[3 * v] < 1e-9;
    int *fv = malloc(sizeof(int) * nfix);
    for (int v = 0, k = 0; v < b.f.nv; v++) if (b.f.X[3 * v] < 1e-9) fv[k++] = v;
    rk_fom_options o;
    rk_fom_default_options(&o);
    o.gravity[1] = -9.81;
    rk_prescribed pin = {.kind = RK_MOTION_FIXED, .count = nfix, .verts = fv};
    o.nprescribed = 1;
    o.prescribed = &pin;
    rk_fom fom;
    CHECK_OK(rk_fom_init(&fom, &b.f, &o, &err));
    int T = 30, n3 = 3 * b.f.nv;
    double *D = malloc(sizeof(double) * n3 * T);
    for (int t = 0; t < T; t++) {
        CHECK_OK(rk_fom_step(&fom, &err));
        for (int i = 0; i < n3; i++) D[(size_t)t * n3 + i] = fom.x[i] - b.f.X[i];
    }
    rk_fom_free(&fom);
    rk_sparse M = {0};
    rk_sparse_alloc_pattern(&b.f, &M, &err);
    rk_fem_add_mass(&b.f, 0, 1.0, &M);
    rk_basis pod;
    CHECK_OK(rk_basis_pod(D, b.f.nv, T, &M, 5, 0, &pod, &err));
    /* |D - U U^T M D|_M^2 over all frames vs sum_{k > 5} s_k^2. */
    double err2 = 0, total = 0, tail = 0;
    double *res = malloc(sizeof(double) * n3);
    for (int t = 0; t < T; t++) {
        double *d = D + (size_t)t * n3;
        memcpy(res, d, sizeof(double) * n3);
        for (int k = 0; k < pod.r; k++) {
            double c = rk_sparse_dot(&M, pod.U + (size_t)k * n3, d);
            for (int i = 0; i < n3; i++) res[i] -= c * pod.U[(size_t)k * n3 + i];
        }
        err2 += rk_sparse_dot(&M, res, res);
        total += rk_sparse_dot(&M, d, d);
    }
    for (int k = pod.r; k < pod.nvalues; k++) tail += pod.values[k] * pod.values[k];
    printf("# POD of %d full-order frames: relative projection error with 5 modes %.4g, from singular values %.4g\n",
           T, sqrt(err2 / total), sqrt(tail / total));
    double diff = fabs(sqrt(err2) - sqrt(tail)) / sqrt(total);
    free(res); free(D); free(fv);
    rk_sparse_free(&M);
    rk_basis_free(&pod);
    fem_body_free(&b);
    CHECK(diff < 1e-8, "projection error and discarded energy differ by %.3g (relative to the data)", diff);
}

TEST(pod_refuses_more_modes_than_the_data_holds)
{
    rk_error err;
    fem_body b;
    CHECK_OK(fem_body_box(&b, 1.0, 0.3, 0.3, 4, 2, 2, rubber, &err));
    rk_basis modes;
    CHECK_OK(rk_basis_modes(&b.f, NULL, 0, 8, &modes, &err));
    const double s[2] = {1, 0.5};
    double *D = synthetic(&modes, 10, s, 2);
    rk_basis pod;
    int too_many = rk_basis_pod(D, b.f.nv, 10, NULL, 11, 0, &pod, &err) != 0 && strstr(err.msg, "at most 10");
    char first[1024];
    snprintf(first, sizeof first, "%s", err.msg);
    int rank = rk_basis_pod(D, b.f.nv, 10, NULL, 3, 0, &pod, &err) != 0 && strstr(err.msg, "span only 2");
    D[17] = NAN;
    int nan = rk_basis_pod(D, b.f.nv, 10, NULL, 2, 0, &pod, &err) != 0 && strstr(err.msg, "not finite");
    free(D);
    rk_basis_free(&modes);
    fem_body_free(&b);
    CHECK(too_many, "11 modes from 10 snapshots: %s", first);
    CHECK(rank && nan, "rank / NaN message: %s", err.msg);
}

int main(void)
{
    RUN(pod_recovers_known_singular_values_and_tolerance_picks_the_size);
    RUN(projection_error_of_fom_snapshots_equals_the_discarded_energy);
    RUN(pod_refuses_more_modes_than_the_data_holds);
    return test_finish();
}
