/* Linear modes: K v = lambda M v over the free degrees of freedom, K the rest stiffness (linear
 * elasticity, each element's own Lame parameters), M consistent or lumped. */
#include "basis/basis.h"
#include "basis/free_system_impl.h"

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

int rk_free_system_modes(const rk_free_system *s, int count, double *values, double *U, int *nzero,
                         rk_error *err)
{
    if (count < 1 || count >= s->nfree)
        return rk_fail(err, "asked for %d linear modes, the object has %d free degrees of freedom "
                       "(at most %d modes)", count, s->nfree, s->nfree - 1);
    double *vec = rk_calloc((size_t)s->nfree * count, sizeof(double), err);
    if (!vec) return -1;
    if (rk_eigs_smallest(&s->K, &s->M, count, NAN, values, vec, err)) {
        free(vec);
        return rk_error_prefix(err, "linear modes");
    }
    for (int j = 0; j < count; j++)
        rk_free_system_expand(s, vec + (size_t)j * s->nfree, U + (size_t)j * s->ndof);
    free(vec);
    *nzero = rk_count_zero_eigenvalues(values, count, rk_sparse_trace(&s->K) / rk_sparse_trace(&s->M));
    return 0;
}

int rk_basis_modes(const rk_fem *f, const unsigned char *constrained, int lumped, int count,
                   rk_basis *b, rk_error *err)
{
    memset(b, 0, sizeof *b);
    rk_free_system sys;
    if (rk_free_system_init(&sys, f, constrained, lumped, err)) return -1;
    int rc = -1;
    b->type = RK_BASIS_MODES;
    b->n = f->nv;
    b->r = b->nvalues = count;
    b->values = rk_calloc((size_t)(count > 0 ? count : 1), sizeof(double), err);
    b->U = rk_calloc((size_t)sys.ndof * (count > 0 ? count : 1), sizeof(double), err);
    if (b->values && b->U) rc = rk_free_system_modes(&sys, count, b->values, b->U, &b->nzero, err);
    rk_free_system_free(&sys);
    if (rc) rk_basis_free(b);
    return rc;
}
