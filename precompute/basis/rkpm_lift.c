/* The lifting field of a moving prescribed region (basis.h, rk_lift; rom.clamp "lifted", issue 37).
 * A Dirichlet condition that moves, x = T(t) X on the region R_1 while the region R_0 stays put, is
 * the clamp's homogeneous problem plus a lifting: one known field w_L with w_L = 1 on R_1 and 0 on
 * R_0, carrying T, and weights that vanish on both (the usual splitting of an inhomogeneous
 * essential condition, u = u_L + u_0, e.g. Hughes, The Finite Element Method, Sec. 1.4; Kantorovich's
 * way for non-interpolating shape functions as in rkpm_clamp.c). Then
 *
 *   x(q, t) = X + w_L(X) (T(t) X - X) + U q,
 *
 * and w_L (T X - X) = w_L [R - I | s] [X; 1] is exactly one more linear-blend-skinning handle
 * (Eq. 1 of the freeform paper) whose 12 coordinates are prescribed, vec(R(t) - I) and s(t).
 *
 * Which w_L: the relative distance w_L = d_0 / (d_0 + d_1) (d_k the distance to R_k), not the
 * weight-space harmonic (H_w) solve. Any w_L with the right boundary values gives the same exact
 * boundary; the rest of it is the subspace's to correct, and the eigen-weights (Eq. 15 with both
 * regions as boundary) are the H_w-optimal corrections. On a bar between two end faces the
 * relative distance is the linear ramp along it, the angle profile of Saint-Venant torsion and the
 * axial profile of a pulled bar, so the eigen-weights start from the leading term; it needs no
 * assembly (it is evaluated anywhere from the two regions, like the clamp's mask), and its
 * gradient is analytic. It is Lipschitz, smooth wherever both distances are (inside the bar's
 * section; not across a medial axis of a region, where the eigen-weights must absorb a kink). */
#include "basis/rkpm_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void rk_lift_free(rk_lift *L)
{
    rkpm_clamp_free(&L->zero);
    rkpm_clamp_free(&L->one);
    memset(L, 0, sizeof *L);
}

int rk_lift_init(rk_lift *L, const double *X, int n, const unsigned char *zero, const unsigned char *one,
                 const int *tets, int nt, rk_error *err)
{
    memset(L, 0, sizeof *L);
    int ones = 0;
    for (int i = 0; i < n; i++) {
        if (one[i] && zero && zero[i])
            return rk_fail(err, "lifting: point %d is both in the region held still and in the moving one", i);
        ones += one[i] != 0;
    }
    if (ones == 0) return rk_fail(err, "lifting: no point is in the moving region");
    double diag = rk_points_diagonal(X, n);
    if (!(diag > 0)) return rk_fail(err, "lifting: the %d points span no volume", n);
    /* the regions' hash cells (their `rise`): a twentieth of the object, a few pieces each */
    if (rkpm_region_build(&L->one, X, n, one, tets, nt, diag / 20, err) ||
        (zero && rkpm_region_build(&L->zero, X, n, zero, tets, nt, diag / 20, err))) {
        rk_lift_free(L);
        return rk_error_prefix(err, "lifting");
    }
    L->range = 2 * diag;
    return 0;
}

double rk_lift_at(const rk_lift *L, const double X[3], double grad[3])
{
    grad[0] = grad[1] = grad[2] = 0;
    if (L->zero.n == 0) return 1;
    double g0[3], g1[3];
    double d0 = rkpm_region_distance(&L->zero, X, L->range, g0), d1 = rkpm_region_distance(&L->one, X, L->range, g1);
    if (d1 <= 0) return 1;
    if (d0 <= 0) return 0;
    double s = d0 + d1;
    /* d/dX d0 / (d0 + d1) = (d1 grad d0 - d0 grad d1) / (d0 + d1)^2 */
    for (int k = 0; k < 3; k++) grad[k] = (d1 * g0[k] - d0 * g1[k]) / (s * s);
    return d0 / s;
}

int rk_rkpm_set_lift(rk_rkpm *k, rk_lift *L, int column, rk_error *err)
{
    rk_lift_free(&k->lift);
    k->lift = *L;
    memset(L, 0, sizeof *L);
    if (column < 0) {
        rk_lift_free(&k->lift);
        return rk_fail(err, "lifting: column %d", column);
    }
    k->lift_column = column + 1;
    return 0;
}
