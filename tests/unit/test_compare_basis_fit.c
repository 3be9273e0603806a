/* rk_compare_basis_fit (FreeForm Eq. 36) against frames built to known answers: frames inside the
 * subspace fit to round-off, and a component orthogonal to it of known size is exactly the residual
 * (normalized MSE by the squared bounding-box diagonal). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pipeline/method.h"
#include "testlib.h"

enum { NV = 40, NDOF = 3 * NV, R = 7, T = 5 };

static double rnd(unsigned *s)
{
    *s = *s * 1103515245u + 12345u;
    return ((*s >> 8) & 0xffff) / 65536.0 - 0.5;
}

TEST(frames_in_the_subspace_fit_exactly_and_an_orthogonal_part_is_the_residual)
{
    static double X[NDOF], U[NDOF * R], x[NDOF * (T + 1)], v[NDOF * (T + 1)];
    unsigned seed = 7;
    for (int i = 0; i < NDOF; i++) X[i] = 2 * rnd(&seed);
    for (int i = 0; i < NDOF * R; i++) U[i] = rnd(&seed);
    /* n: a unit vector orthogonal to U's columns (Gram-Schmidt of a random one, twice) */
    double n[NDOF];
    for (int i = 0; i < NDOF; i++) n[i] = rnd(&seed);
    double *Q = malloc(sizeof(double) * NDOF * R);
    memcpy(Q, U, sizeof(double) * NDOF * R);
    for (int j = 0; j < R; j++) {
        for (int k = 0; k < j; k++) {
            double d = 0;
            for (int i = 0; i < NDOF; i++) d += Q[NDOF * k + i] * Q[NDOF * j + i];
            for (int i = 0; i < NDOF; i++) Q[NDOF * j + i] -= d * Q[NDOF * k + i];
        }
        double l = 0;
        for (int i = 0; i < NDOF; i++) l += Q[NDOF * j + i] * Q[NDOF * j + i];
        for (int i = 0; i < NDOF; i++) Q[NDOF * j + i] /= sqrt(l);
    }
    for (int pass = 0; pass < 2; pass++)
        for (int j = 0; j < R; j++) {
            double d = 0;
            for (int i = 0; i < NDOF; i++) d += Q[NDOF * j + i] * n[i];
            for (int i = 0; i < NDOF; i++) n[i] -= d * Q[NDOF * j + i];
        }
    double nn = 0;
    for (int i = 0; i < NDOF; i++) nn += n[i] * n[i];
    for (int i = 0; i < NDOF; i++) n[i] /= sqrt(nn);
    free(Q);

    rk_fom_frames F = {.ndof = NDOF, .T = T, .x = x, .v = v};
    double amp[T + 1];
    for (int pass = 0; pass < 2; pass++) {
        double sum_sq = 0;
        for (int s = 0; s <= T; s++) {
            amp[s] = pass ? 0.1 * (s + 1) : 0;
            for (int i = 0; i < NDOF; i++) x[NDOF * s + i] = X[i] + amp[s] * n[i];
            for (int j = 0; j < R; j++) {
                double q = sin(1.0 + j + 0.3 * s);
                for (int i = 0; i < NDOF; i++) x[NDOF * s + i] += U[NDOF * j + i] * q;
            }
            if (s > 0) sum_sq += amp[s] * amp[s];
        }
        rk_error err;
        rk_compare_method m = {0};
        CHECK_OK(rk_compare_basis_fit(U, NDOF, R, X, &F, &m, &err));
        double L = rk_points_diagonal(X, NV), want = sum_sq / ((double)T * NV) / (L * L);
        printf("# pass %d: basis fit %.6e, expected %.6e\n", pass, m.fit_normalized_mse, want);
        if (pass == 0) CHECK(m.fit_normalized_mse < 1e-28, "frames in the span: residual %g", m.fit_normalized_mse);
        else CHECK_CLOSE(m.fit_normalized_mse, want, 1e-12 * want);
    }
}

TEST(dependent_columns_are_refused)
{
    static double X[NDOF], U[NDOF * 2], x[NDOF * 2], v[NDOF * 2];
    for (int i = 0; i < NDOF; i++) U[i] = U[NDOF + i] = i % 3 ? 1 : 0;
    rk_fom_frames F = {.ndof = NDOF, .T = 1, .x = x, .v = v};
    rk_error err;
    rk_compare_method m = {0};
    CHECK(rk_compare_basis_fit(U, NDOF, 2, X, &F, &m, &err) != 0 && strstr(err.msg, "dependent"), "accepted: %s",
          err.msg);
}

int main(void)
{
    RUN(frames_in_the_subspace_fit_exactly_and_an_orthogonal_part_is_the_residual);
    RUN(dependent_columns_are_refused);
    return test_finish();
}
