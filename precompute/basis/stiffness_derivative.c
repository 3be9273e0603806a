/* The third derivative of the elastic energy contracted with two displacements, the right-hand
 * side of the modal-derivative equation (Barbic & James 2005, Eq. 9): (H : a) b. The physics
 * layer gives exact element Hessians for every material model, so the directional derivative
 * is taken numerically, element by element, with a step scaled to each element:
 *   D(e) = (He(X + e a) - He(X - e a)) / (2e),   (H : a) = (4 D(e/2) - D(e)) / 3 + O(e^4). */
#include "basis/basis.h"

#include <math.h>
#include <string.h>

static void element_hessian(const rk_fem *f, int t, const double *xe, double *He)
{
    rk_tet_hessian(f->model[t], f->mu[t], f->lambda[t], xe, &f->Dm_inv[9 * t], f->vol[t], He, 0);
}

/* D(e) b_e for one element. */
static void central(const rk_fem *f, int t, const double *Xe, const double *ae, const double *be,
                    double e, double *out)
{
    double xp[12], xm[12], Hp[144], Hm[144];
    for (int k = 0; k < 12; k++) {
        xp[k] = Xe[k] + e * ae[k];
        xm[k] = Xe[k] - e * ae[k];
    }
    element_hessian(f, t, xp, Hp);
    element_hessian(f, t, xm, Hm);
    for (int p = 0; p < 12; p++) {
        double s = 0;
        for (int q = 0; q < 12; q++) s += (Hp[12 * p + q] - Hm[12 * p + q]) * be[q];
        out[p] = s / (2 * e);
    }
}

void rk_stiffness_derivative(const rk_fem *f, const double *a, const double *b, double *out)
{
    memset(out, 0, 3 * (size_t)f->nv * sizeof(double));
    for (int t = 0; t < f->nt; t++) {
        const int *tv = &f->tets[4 * t];
        double Xe[12], ae[12], be[12], amax = 0;
        for (int v = 0; v < 4; v++)
            for (int c = 0; c < 3; c++) {
                Xe[3 * v + c] = f->X[3 * tv[v] + c];
                ae[3 * v + c] = a[3 * tv[v] + c];
                be[3 * v + c] = b[3 * tv[v] + c];
                amax = fmax(amax, fabs(ae[3 * v + c]));
            }
        if (amax == 0) continue;
        double e = 1e-3 * cbrt(f->vol[t]) / amax;
        double d1[12], d2[12];
        central(f, t, Xe, ae, be, e, d1);
        central(f, t, Xe, ae, be, e / 2, d2);
        for (int v = 0; v < 4; v++)
            for (int c = 0; c < 3; c++) out[3 * tv[v] + c] += (4 * d2[3 * v + c] - d1[3 * v + c]) / 3;
    }
}
