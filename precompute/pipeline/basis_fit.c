/* The basis fitting residual (FreeForm paper, Sec. 9.1, Eq. 36 and Tables 6-7): each reference
 * frame fitted by the subspace in plain least squares over the vertices, q_t* = argmin |X + U q -
 * x_t|^2, and the fitted frames measured as a free run is. It bounds what any simulation in that
 * subspace can reach, so a method's error splits into its basis's share (this) and its dynamics'
 * (the rest). */
#include "pipeline/method.h"

#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int rk_compare_basis_fit(const double *U, int ndof, int r, const double *X, const rk_fom_frames *ref, rk_compare_method *m,
                         rk_error *err)
{
    int T = ref->T;
    if (r <= 0 || r > ndof) return rk_fail(err, "basis fit: %d columns for %d unknowns", r, ndof);
    double *A = rk_calloc((size_t)ndof * r, sizeof(double), err);
    double *B = rk_calloc((size_t)ndof * T, sizeof(double), err);
    double *x = rk_calloc((size_t)ndof, sizeof(double), err);
    int rc = -1;
    if (!A || !B || !x) goto out;
    memcpy(A, U, sizeof(double) * ndof * r);
    for (int s = 0; s < T; s++)
        for (int i = 0; i < ndof; i++) B[(size_t)ndof * s + i] = ref->x[(size_t)ndof * (s + 1) + i] - X[i];
    /* QR (dgels), all frames as right-hand sides at once: the coefficients land in B's first r rows */
    lapack_int info = LAPACKE_dgels(LAPACK_COL_MAJOR, 'N', ndof, r, T, A, ndof, B, ndof);
    if (info != 0) {
        rk_fail(err, "basis fit: least squares failed (LAPACK dgels info %d: %s)", (int)info,
                info > 0 ? "the basis has dependent columns" : "bad argument");
        goto out;
    }
    /* dgels reports only an exactly zero pivot; a column dependent to round-off leaves a tiny one */
    double rmax = 0;
    for (int j = 0; j < r; j++) rmax = fmax(rmax, fabs(A[(size_t)ndof * j + j]));
    for (int j = 0; j < r; j++)
        if (!(fabs(A[(size_t)ndof * j + j]) > 1e-12 * rmax)) {
            rk_fail(err, "basis fit: the basis has dependent columns (column %d of %d)", j, r);
            goto out;
        }
    rk_run_error e;
    rk_run_error_init(&e, X, ndof / 3);
    for (int s = 0; s < T; s++) {
        rk_rom_positions(U, ndof, r, X, B + (size_t)ndof * s, x);
        rk_run_error_add(&e, x, ref->x + (size_t)ndof * (s + 1));
    }
    m->fit_normalized_mse = rk_normalized_mse(&e);
    rc = 0;
out:
    free(A);
    free(B);
    free(x);
    return rc;
}
