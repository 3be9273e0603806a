/* Elastic energy, gradient and Hessian assembled from the physics/ tet kernels. */
#include "fem/element_impl.h"

#include <math.h>

double rk_fem_energy(const rk_fem *f, const double *x)
{
    double E = 0;
    for (int t = 0; t < f->nt; t++) {
        double xe[12];
        rk_fem_gather(f, t, x, xe);
        E += rk_tet_energy(f->model[t], f->mu[t], f->lambda[t], xe, &f->Dm_inv[9 * t], f->vol[t]);
    }
    return isfinite(E) ? E : INFINITY; /* a NaN or infinite term poisons the sum */
}

void rk_fem_add_gradient(const rk_fem *f, const double *x, double scale, double *g)
{
    for (int t = 0; t < f->nt; t++) {
        double xe[12], ge[12] = {0};
        rk_fem_gather(f, t, x, xe);
        rk_tet_gradient(f->model[t], f->mu[t], f->lambda[t], xe, &f->Dm_inv[9 * t], f->vol[t], ge);
        rk_fem_scatter_vector(f, t, ge, scale, g);
    }
}

void rk_fem_add_hessian(const rk_fem *f, const double *x, double scale, int project, rk_sparse *H)
{
    for (int t = 0; t < f->nt; t++) {
        double xe[12], He[144];
        rk_fem_gather(f, t, x, xe);
        rk_tet_hessian(f->model[t], f->mu[t], f->lambda[t], xe, &f->Dm_inv[9 * t], f->vol[t], He, project);
        rk_fem_scatter_block(f, t, He, scale, H->val);
    }
}

void rk_fem_add_rest_stiffness(const rk_fem *f, double scale, rk_sparse *K)
{
    rk_fem_add_hessian(f, f->X, scale, 0, K);
}
