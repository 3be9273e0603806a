/* The weight-space eigenproblem shared by mesh and RKPM skinning eigenmodes (freeform paper
 * Eq. 15): argmin tr(c^T H_w c) subject to c^T M c = I, i.e. the smallest generalized
 * eigenvectors of H_w v = lambda M v. Free weights: the first is the constant one (eigenvalue 0).
 * Clamped weights (zero on a fixed region, Dirichlet): no weight is free of energy. */
#include "basis/basis.h"

#include <math.h>

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
