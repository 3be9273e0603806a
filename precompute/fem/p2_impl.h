/* The P2 tet's shape functions and quadrature, shared by the linear static solve (p2.c) and the
 * nonlinear element kernels (p2_elastic.c). */
#ifndef RK_FEM_P2_IMPL_H
#define RK_FEM_P2_IMPL_H

/* The gradients (3 x 10, node by node) of the ten shape functions at barycentric point L, given
 * the constant gradients dL (4 x 3) of the barycentric coordinates. */
void rk_p2_shape_gradients(const double L[4], const double dL[12], double dN[30]);
void rk_p2_shape_values(const double L[4], double N[10]);
/* Point q (0..3) of the 4-point rule of degree 2 (each weight a quarter of the volume). */
void rk_p2_quadrature_point(int q, double L[4]);

#endif
