/* Preconditioned conjugate gradients (solver.h, rk_pcg): Hestenes-Stiefel with the preconditioned
 * residual, stopping on the true recurrence residual relative to |b|. */
#include "solver/solver.h"

#include <math.h>
#include <string.h>

static double dot(int n, const double *a, const double *b)
{
    double s = 0;
    for (int i = 0; i < n; i++) s += a[i] * b[i];
    return s;
}

int rk_pcg(const rk_pcg_problem *p, const double *b, double *x, double tol, int max_iter, double *work,
           double *relres)
{
    int n = p->n;
    double *r = work, *z = work + n, *d = work + 2 * (size_t)n, *Ad = work + 3 * (size_t)n;
    double bnorm = sqrt(dot(n, b, b));
    if (relres) *relres = 0;
    if (bnorm == 0) {
        memset(x, 0, sizeof(double) * (size_t)n);
        return 0;
    }
    p->apply(p->ctx, x, Ad);
    for (int i = 0; i < n; i++) r[i] = b[i] - Ad[i];
    double rnorm = sqrt(dot(n, r, r));
    int it = 0;
    if (rnorm > tol * bnorm) {
        if (p->precondition) p->precondition(p->ctx, r, z);
        else memcpy(z, r, sizeof(double) * (size_t)n);
        memcpy(d, z, sizeof(double) * (size_t)n);
        double rz = dot(n, r, z);
        while (it < max_iter) {
            p->apply(p->ctx, d, Ad);
            double dAd = dot(n, d, Ad);
            if (!(dAd > 0)) break; /* not positive definite along d: keep what we have */
            double alpha = rz / dAd;
            for (int i = 0; i < n; i++) {
                x[i] += alpha * d[i];
                r[i] -= alpha * Ad[i];
            }
            it++;
            rnorm = sqrt(dot(n, r, r));
            if (rnorm <= tol * bnorm) break;
            if (p->precondition) p->precondition(p->ctx, r, z);
            else memcpy(z, r, sizeof(double) * (size_t)n);
            double rz_new = dot(n, r, z);
            double beta = rz_new / rz;
            rz = rz_new;
            for (int i = 0; i < n; i++) d[i] = z[i] + beta * d[i];
        }
    }
    if (relres) *relres = rnorm / bnorm;
    return it;
}
