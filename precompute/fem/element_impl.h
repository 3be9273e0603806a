/* Private to precompute/fem: building the shared sparsity pattern (the gather and scatter between
 * global vectors and a tet's 12 dofs, which other stages use, are fem.h's). */
#ifndef RK_FEM_ELEMENT_H
#define RK_FEM_ELEMENT_H

#include "fem/fem.h"

/* Builds f->pattern (colptr, rowind) and f->slot from f->tets. */
int rk_fem_build_pattern(rk_fem *f, rk_error *err);

#endif
