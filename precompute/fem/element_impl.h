/* Private to precompute/fem: moving one tet's data between global vectors/matrices and its
 * 12 local dofs (a0 a1 a2 b0 ... d2), and building the shared sparsity pattern. */
#ifndef RK_FEM_ELEMENT_H
#define RK_FEM_ELEMENT_H

#include "fem/fem.h"

/* Number of upper-triangle entries of a 12x12 element block (the slot map's stride). */
#define RK_TET_SLOTS 78

/* xe = the 12 coordinates of tet t's vertices taken from x (3*nv). */
static inline void rk_fem_gather(const rk_fem *f, int t, const double *x, double xe[12])
{
    const int *v = &f->tets[4 * t];
    for (int a = 0; a < 4; a++) {
        const double *p = &x[3 * v[a]];
        xe[3 * a] = p[0];
        xe[3 * a + 1] = p[1];
        xe[3 * a + 2] = p[2];
    }
}

/* g[dof] += scale * ge[local dof] for tet t. */
static inline void rk_fem_scatter_vector(const rk_fem *f, int t, const double ge[12], double scale,
                                         double *g)
{
    const int *v = &f->tets[4 * t];
    for (int a = 0; a < 4; a++) {
        double *p = &g[3 * v[a]];
        p[0] += scale * ge[3 * a];
        p[1] += scale * ge[3 * a + 1];
        p[2] += scale * ge[3 * a + 2];
    }
}

/* val[slot] += scale * He for the 78 upper entries (p <= q, row-major) of tet t's symmetric
 * 12x12 block He (row-major). */
static inline void rk_fem_scatter_block(const rk_fem *f, int t, const double He[144], double scale,
                                        double *val)
{
    const int *s = &f->slot[RK_TET_SLOTS * t];
    for (int p = 0; p < 12; p++)
        for (int q = p; q < 12; q++) val[*s++] += scale * He[12 * p + q];
}

/* Builds f->pattern (colptr, rowind) and f->slot from f->tets. */
int rk_fem_build_pattern(rk_fem *f, rk_error *err);

#endif
