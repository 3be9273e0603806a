/* A Newton matrix kept across the adaptive linear ROM's steps (issue 33), as the fixed basis keeps
 * one (step.c, romrt_set_hessian_reuse): the quadratic decoder's basis moves every step, U = B C
 * with C R x r (alrom.c), so a factor kept from an earlier step is in that step's coordinates q_old
 * and is carried into the new step's q before it serves. The basis moves little from one step to
 * the next (the paper's Eq. 16 interpolates between two nearby points of the Grassmannian), so
 * the new basis is nearly a combination of the old: U_new ~ U_old T with T the M-orthogonal
 * projection's coefficients, T = M_old^-1 U_old^T M U_new = M_old^-1 (W_F C_old)^T C_new (an
 * R r^2 product over K-space: W_F = B^T W B over the free rows, no pass over the vertices). The
 * kept matrix H_old = s M_old + K_old (s the inertia and damping weight, K_old the elastic and
 * contact Hessian it was built with) becomes
 *
 *   H = s M_new + T^T K_old T = T^T H_old T + s (M_new - T^T M_old T),
 *
 * the inertia exact in the new basis (it dominates the matrix at small steps) and the stiffness
 * carried. The added term is the mass of U_new off span(U_old), positive semi-definite, so H is
 * positive definite where H_old was. The Newton residual is always the new basis' exact gradient
 * (step.c evaluates it at every iteration), so a carried matrix changes the path, not where
 * Newton stops: step.c's guards replace it with a fresh one wherever its steps stop halving or
 * its line search has to shorten one. */
#include <string.h>

#include "runtime/alrom_impl.h"

void rt_alrom_keep_note(romrt_model *m)
{
    rt_alrom *al = &m->al;
    size_t r = (size_t)m->r, R = r + (size_t)al->pairs, i, k;
    if (al->decoder) return;
    for (k = 0; k < R; k++) /* by K-space row (r contiguous): the carry's product runs along them */
        for (i = 0; i < r; i++) al->wcs_keep[k * r + i] = al->wcs[i * R + k];
    memcpy(al->m_keep, al->M, sizeof(romrt_real) * r * r);
}

int rt_alrom_keep_carry(romrt_model *m, romrt_real w_inertia)
{
    rt_alrom *al = &m->al;
    int r = m->r, R = r + al->pairs, i, j, k;
    double *X = al->keep_work, *T = X + r * r, *F = T + r * r, *Y = F + r * r;
    double s = (double)w_inertia + (al->damping > 0 ? (double)al->damping / (double)m->h : 0);
    const romrt_real *U = m->H;
    if (al->decoder || m->hessian_age < 0 || m->hessian_age >= rt_reuse_steps(m) || m->hessian_w != w_inertia) return -1;
    for (j = 0; j < r; j++) { /* X = U_old^T M U_new = (W_F C_old)^T C_new, a column at a time as
                                * r independent sums (the compiler's vector lanes; dot products in
                                * order would not be) */
        const double *b = al->cs + (size_t)R * (size_t)j;
        double *x = X + (size_t)r * (size_t)j;
        for (i = 0; i < r; i++) x[i] = 0;
        for (k = 0; k < R; k++) {
            const double *a = al->wcs_keep + (size_t)r * (size_t)k, bk = b[k];
            for (i = 0; i < r; i++) x[i] += a[i] * bk;
        }
    }
    for (k = 0; k < r * r; k++) F[k] = (double)al->m_keep[k];
    if (rt_cholesky_wide(r, F)) return -1;
    memcpy(T, X, sizeof(double) * (size_t)r * (size_t)r); /* T = M_old^-1 X */
    for (j = 0; j < r; j++) rt_cholesky_solve_wide(r, F, T + (size_t)r * (size_t)j);
    for (j = 0; j < r; j++) /* Y = U_h T, H_old = U_h^T U_h (the kept factor, upper) */
        for (i = 0; i < r; i++) {
            double y = 0;
            for (k = i; k < r; k++) y += (double)U[i + r * k] * T[k + r * j];
            Y[i + r * j] = y;
        }
    for (j = 0; j < r; j++) /* F = Y^T Y + s (M_new - X^T T), upper triangle */
        for (i = 0; i <= j; i++) {
            double a = 0, p = 0;
            for (k = 0; k < r; k++) {
                a += Y[k + r * i] * Y[k + r * j];
                p += X[k + r * i] * T[k + r * j];
            }
            F[i + r * j] = a + s * ((double)al->M[i + r * j] - p);
        }
    for (j = 0; j < r; j++)
        for (i = 0; i <= j; i++) m->H[i + r * j] = (romrt_real)F[i + r * j];
    return rt_cholesky(r, m->H) ? -1 : 0;
}
