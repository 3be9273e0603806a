/* The one sparse Cholesky (fem.h, rk_chol) on matrices with known answers: tridiag(-1, 2, -1)
 * (positive definite: solves to round-off, and again after new values), the same shifted by -1.5
 * (indefinite: reported as such with the column, then solved as LDL^T), and the path graph's
 * Laplacian (singular: the factorization stops short or ends on a round-off pivot, which
 * rk_chol_minor or rk_chol_rcond says). */
#include <math.h>
#include <string.h>

#include "fem/fem.h"
#include "testlib.h"

enum { N = 50 };

/* Upper CSC of tridiag(-1, d, -1) with the first and last diagonal entries set to end. */
static void tridiag(rk_sparse *S, int colptr[N + 1], int rowind[2 * N], double val[2 * N], double d, double end)
{
    int k = 0;
    for (int j = 0; j < N; j++) {
        colptr[j] = k;
        if (j > 0) rowind[k] = j - 1, val[k++] = -1;
        rowind[k] = j, val[k++] = j == 0 || j == N - 1 ? end : d;
    }
    colptr[N] = k;
    *S = (rk_sparse){.n = N, .nnz = k, .colptr = colptr, .rowind = rowind, .val = val};
}

/* |A x - b|_inf for the tridiagonal A above. */
static double residual(const double *x, const double *b, double d, double end)
{
    double worst = 0;
    for (int i = 0; i < N; i++) {
        double ax = (i == 0 || i == N - 1 ? end : d) * x[i] - (i > 0 ? x[i - 1] : 0) - (i < N - 1 ? x[i + 1] : 0);
        worst = fmax(worst, fabs(ax - b[i]));
    }
    return worst;
}

TEST(positive_definite_solves_to_round_off_and_refactors_new_values)
{
    rk_error err;
    int colptr[N + 1], rowind[2 * N];
    double val[2 * N], b[N], x[N];
    rk_sparse S;
    tridiag(&S, colptr, rowind, val, 2, 2);
    for (int i = 0; i < N; i++) b[i] = sin(i + 1.0);
    rk_chol c;
    memset(&c, 0, sizeof c);
    CHECK_OK(rk_chol_analyze(&c, &S, &err));
    CHECK_OK(rk_chol_factor(&c, &err));
    CHECK_OK(rk_chol_solve(&c, b, x, &err));
    CHECK(residual(x, b, 2, 2) < 1e-10, "residual %g", residual(x, b, 2, 2));
    CHECK(rk_chol_minor(&c) == N && rk_chol_rcond(&c) > 0, "minor %d, rcond %g", rk_chol_minor(&c), rk_chol_rcond(&c));
    /* new values on the same pattern: a numeric refactorization, and b and x may alias */
    for (int k = 0; k < S.nnz; k++) val[k] *= 2;
    CHECK_OK(rk_chol_factor(&c, &err));
    memcpy(x, b, sizeof x);
    CHECK_OK(rk_chol_solve(&c, x, x, &err));
    for (int i = 0; i < N; i++) b[i] /= 2; /* 2 A x = b */
    CHECK(residual(x, b, 2, 2) < 1e-10, "after refactoring: residual %g", residual(x, b, 2, 2));
    rk_chol_free(&c);
    CHECK(!c.started && !c.L, "freed");
}

TEST(indefinite_is_reported_then_solved_as_ldlt)
{
    rk_error err;
    int colptr[N + 1], rowind[2 * N];
    double val[2 * N], b[N], x[N];
    rk_sparse S;
    /* eigenvalues 2 - 2 cos(k pi / 51) - 1.5 straddle 0, none within 1e-3 of it */
    tridiag(&S, colptr, rowind, val, 0.5, 0.5);
    for (int i = 0; i < N; i++) b[i] = cos(0.3 * i);
    rk_chol c;
    memset(&c, 0, sizeof c);
    CHECK_OK(rk_chol_analyze(&c, &S, &err));
    CHECK(rk_chol_factor(&c, &err) == RK_CHOL_NOT_POSDEF && strstr(err.msg, "not positive definite (CHOLMOD stopped at column"),
          "indefinite: %s", err.msg);
    CHECK_OK(rk_chol_indefinite(&c, &err));
    CHECK_OK(rk_chol_solve(&c, b, x, &err));
    CHECK(residual(x, b, 0.5, 0.5) < 1e-8, "LDL^T residual %g", residual(x, b, 0.5, 0.5));
    rk_chol_free(&c);
}

TEST(a_zero_pivot_stops_the_factorization_short)
{
    rk_error err;
    int colptr[N + 1], rowind[2 * N];
    double val[2 * N];
    rk_sparse S;
    /* the path graph's Laplacian (tridiag(-1, 2, -1), 1 at both ends): (1, ..., 1) is its null space */
    tridiag(&S, colptr, rowind, val, 2, 1);
    rk_chol c;
    memset(&c, 0, sizeof c);
    CHECK_OK(rk_chol_analyze(&c, &S, &err));
    int rc = rk_chol_factor(&c, &err);
    CHECK(rc == RK_CHOL_NOT_POSDEF || rk_chol_minor(&c) < N || rk_chol_rcond(&c) < 1e-12,
          "singular: rc %d, minor %d, rcond %g", rc, rk_chol_minor(&c), rk_chol_rcond(&c));
    rk_chol_free(&c);
}

int main(void)
{
    RUN(positive_definite_solves_to_round_off_and_refactors_new_values);
    RUN(indefinite_is_reported_then_solved_as_ldlt);
    RUN(a_zero_pivot_stops_the_factorization_short);
    return test_finish();
}
