/* Element inversion: the count of elements whose deformation gradient has det F <= 0. */
#include "fem/element_impl.h"

#include <math.h>

int rk_fem_inverted(const rk_fem *f, const double *x, double *min_J)
{
    int inverted = 0;
    double lowest = INFINITY;
    for (int t = 0; t < f->nt; t++) {
        double xe[12], F[9];
        rk_fem_gather(f, t, x, xe);
        rk_tet_F(xe, &f->Dm_inv[9 * t], F);
        double J = rk_det3(F);
        if (!(J > 0)) inverted++;
        if (J < lowest) lowest = J;
    }
    if (min_J) *min_J = lowest;
    return inverted;
}
