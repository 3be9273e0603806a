/* Private to precompute/basis: the rest stiffness K and the mass M of a FEM model restricted to
 * its free degrees of freedom (constrained vertices removed), the system every eigen-basis of a
 * mesh starts from. */
#ifndef RK_BASIS_FREE_SYSTEM_H
#define RK_BASIS_FREE_SYSTEM_H

#include "fem/fem.h"
#include "util/util.h"

typedef struct {
    int ndof;       /* 3 nv */
    int nfree;
    int *keep;      /* ndof: index among the free dofs, or -1 */
    rk_sparse K, M; /* nfree x nfree */
    rk_sparse Mfull;/* ndof x ndof mass (for mass-weighted products on full vectors) */
} rk_free_system;

/* constrained: nv flags (non-zero = the vertex is prescribed), or NULL for a free object. */
int rk_free_system_init(rk_free_system *s, const rk_fem *f, const unsigned char *constrained,
                        int lumped, rk_error *err);
/* Full vector (ndof) from a free one (nfree): zeros at constrained dofs. */
void rk_free_system_expand(const rk_free_system *s, const double *xfree, double *xfull);
/* Free vector from a full one. */
void rk_free_system_gather(const rk_free_system *s, const double *xfull, double *xfree);
void rk_free_system_free(rk_free_system *s);

/* The `count` smallest modes of (K, M): values ascending, U full vectors (ndof x count) with
 * zeros at constrained dofs, *nzero the rigid ones. */
int rk_free_system_modes(const rk_free_system *s, int count, double *values, double *U, int *nzero,
                         rk_error *err);

#endif
