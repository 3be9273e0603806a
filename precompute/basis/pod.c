/* Proper orthogonal decomposition: the mass-weighted SVD of snapshot displacements. */
#include "basis/basis.h"

#include <stdlib.h>
#include <string.h>

int rk_basis_pod(const double *D, int n, int T, const rk_sparse *M, int max_r, double tol,
                 rk_basis *b, rk_error *err)
{
    memset(b, 0, sizeof *b);
    int rows = 3 * n, k = rows < T ? rows : T;
    if (max_r > k)
        return rk_fail(err, "POD: asked for %d modes from %d snapshots of %d vertices (at most %d)",
                       max_r, T, n, k);
    b->type = RK_BASIS_POD;
    b->n = n;
    b->values = rk_calloc((size_t)k, sizeof(double), err);
    b->U = rk_calloc((size_t)rows * (max_r > 0 ? max_r : 1), sizeof(double), err);
    if (!b->values || !b->U ||
        rk_mass_pca(D, rows, T, M, max_r, tol, b->U, &b->r, b->values, err)) {
        rk_basis_free(b);
        return rk_error_prefix(err, "POD");
    }
    b->nvalues = k;
    return 0;
}
