/* Linear modes: K v = lambda M v over the free degrees of freedom, K the rest stiffness (linear
 * elasticity, each element's own Lame parameters), M consistent or lumped. */
#include "basis/basis.h"
#include "basis/free_system.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int rk_count_zero_eigenvalues(const double *values, int count, double scale)
{
    /* Rigid modes come out at roundoff level, ~1e-16 of the spectral scale times the
     * condition of the shifted factorization; the first elastic mode of any mesh we handle is
     * far above 1e-9 of it (that would need over 30000 elements along the object). */
    int z = 0;
    while (z < count && fabs(values[z]) < 1e-9 * scale) z++;
    return z;
}

int rk_basis_modes(const rk_fem *f, const unsigned char *constrained, int lumped, int count,
                   rk_basis *b, rk_error *err)
{
    memset(b, 0, sizeof *b);
    rk_free_system sys;
    if (rk_free_system_init(&sys, f, constrained, lumped, err)) return -1;
    int rc = -1;
    double *vec = NULL;
    if (count < 1 || count >= sys.nfree) {
        rk_fail(err, "asked for %d linear modes, the object has %d free degrees of freedom (at most %d modes)",
                count, sys.nfree, sys.nfree - 1);
        goto out;
    }
    b->type = RK_BASIS_MODES;
    b->n = f->nv;
    b->r = b->nvalues = count;
    b->values = rk_calloc((size_t)count, sizeof(double), err);
    b->U = rk_calloc((size_t)sys.ndof * count, sizeof(double), err);
    vec = rk_calloc((size_t)sys.nfree * count, sizeof(double), err);
    if (!b->values || !b->U || !vec) goto out;
    if (rk_eigs_smallest(&sys.K, &sys.M, count, NAN, b->values, vec, err)) {
        rk_error_prefix(err, "linear modes");
        goto out;
    }
    for (int j = 0; j < count; j++)
        rk_free_system_expand(&sys, vec + (size_t)j * sys.nfree, b->U + (size_t)j * sys.ndof);
    b->nzero = rk_count_zero_eigenvalues(b->values, count, rk_sparse_trace(&sys.K) / rk_sparse_trace(&sys.M));
    rc = 0;
out:
    free(vec);
    rk_free_system_free(&sys);
    if (rc) rk_basis_free(b);
    return rc;
}
