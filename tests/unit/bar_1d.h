/* Test fixture: the weight-space eigenvalues of a bar as a 1D problem, the reference that
 * skinning eigenmodes (mesh and RKPM) are checked against: -(c u')' = lam u on [0, L] with
 * u' = 0 at both ends, c = lambda + 4 mu (freeform paper Prop. 1). */
#ifndef RK_TEST_BAR_1D_H
#define RK_TEST_BAR_1D_H

#include <math.h>

#include "physics/physics.h"
#include "fem/fem.h"

/* Smallest positive root of -c1 k1 tan(k1 a) = c2 k2 tan(k2 (L - a)), k_i = sqrt(lam / c_i): the
 * first non-constant eigenvalue of -(c u')' = lam u on [0, L], u' = 0 at both ends, c = c1 on
 * [0, a) and c2 on (a, L]. Found by scanning then bisecting the continuous form
 * g = c1 k1 sin(k1 a) cos(k2 b) + c2 k2 sin(k2 b) cos(k1 a), b = L - a. */
static inline double two_material_eigenvalue(double c1, double c2, double a, double L)
{
    double b = L - a;
    double lo = 1e-9, step = 1e-3 * fmin(c1, c2) * pow(M_PI / L, 2);
    #define G(l) (c1 * sqrt((l) / c1) * sin(sqrt((l) / c1) * a) * cos(sqrt((l) / c2) * b) + \
                  c2 * sqrt((l) / c2) * sin(sqrt((l) / c2) * b) * cos(sqrt((l) / c1) * a))
    double hi = lo + step;
    while (G(lo) * G(hi) > 0) { lo = hi; hi += step; }
    for (int it = 0; it < 200; it++) {
        double mid = 0.5 * (lo + hi);
        if (G(lo) * G(mid) <= 0) hi = mid; else lo = mid;
    }
    #undef G
    return 0.5 * (lo + hi);
}

static inline double lame_sum(rk_material m)
{
    double mu, lambda;
    rk_lame(m.young, m.poisson, &mu, &lambda);
    return lambda + 4 * mu;
}

#endif
