/* The weight-space eigenproblem shared by mesh and RKPM skinning eigenmodes (freeform paper
 * Eq. 15): argmin tr(c^T H_w c) subject to c^T M c = I, i.e. the smallest generalized
 * eigenvectors of H_w v = lambda M v. Free weights: the first is the constant one (eigenvalue 0).
 * Clamped weights (zero on a fixed region, Dirichlet): no weight is free of energy. */
#include "basis/basis.h"

#include <math.h>
#include <stdlib.h>

int rk_weight_eigs(const rk_sparse *Hw, const rk_sparse *Mw, int m, int clamped, double *values, double *C,
                   int *nzero, rk_error *err)
{
    if (m < 1 || m + 1 >= Hw->n)
        return rk_fail(err, "asked for %d skinning weights (plus %s) from %d unknowns (at most %d)", m,
                       clamped ? "one for the clamp's missing constant" : "the constant one", Hw->n, Hw->n - 2);
    if (rk_eigs_smallest(Hw, Mw, m + 1, NAN, values, C, err))
        return rk_error_prefix(err, "skinning eigenmodes");
    *nzero = rk_count_zero_eigenvalues(values, m + 1, rk_sparse_trace(Hw) / rk_sparse_trace(Mw));
    if (clamped) {
        if (*nzero > 0)
            return rk_fail(err, "clamped skinning eigenmodes: %d zero eigenvalue%s, so %d piece%s of the object "
                           "hold%s no fixed vertex; give each piece its own basis or fix it too", *nzero,
                           *nzero == 1 ? "" : "s", *nzero, *nzero == 1 ? "" : "s", *nzero == 1 ? "s" : "");
        return 0;
    }
    if (*nzero > 1)
        return rk_fail(err, "skinning eigenmodes: %d zero eigenvalues, so the object falls into "
                       "at least %d disconnected pieces; skinning weights need one connected "
                       "object (build one basis per piece)", *nzero, *nzero);
    if (*nzero == 0)
        return rk_fail(err, "skinning eigenmodes: the smallest eigenvalue %.3g is not zero, so "
                       "constant weights are not free of energy (a bug or a broken matrix)", values[0]);
    return 0;
}

int rk_weight_eigs_restricted(const rk_sparse *Hw, const rk_sparse *Mw, const int *keep, int nkept, int m,
                              int clamped, double *values, double *C, int *nzero, rk_error *err)
{
    rk_sparse Hf = {0}, Mf = {0};
    double *Cf = rk_calloc((size_t)nkept * (m + 1), sizeof(double), err);
    int rc = -1, n = Hw->n;
    if (Cf && !rk_sparse_restrict(Hw, keep, nkept, &Hf, err) && !rk_sparse_restrict(Mw, keep, nkept, &Mf, err) &&
        !rk_weight_eigs(&Hf, &Mf, m, clamped, values, Cf, nzero, err)) {
        for (int j = 0; j <= m; j++)
            for (int c = 0; c < n; c++) C[(size_t)n * j + c] = keep[c] >= 0 ? Cf[(size_t)nkept * j + keep[c]] : 0;
        rc = 0;
    }
    rk_sparse_free(&Hf);
    rk_sparse_free(&Mf);
    free(Cf);
    return rc;
}
