/* Projected Newton on the reduced incremental potential: the full-order Newton (fom/newton.c) in
 * r dimensions, with a dense Cholesky (LAPACK dpotrf) in place of CHOLMOD. */
#include "rom/rom_impl.h"

#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <string.h>

#define ARMIJO_C 1e-4
#define MAX_HALVINGS 40
#define ENERGY_NOISE 1e-13 /* as in fom/newton.c: decreases below this are round-off */

static int all_finite(const double *a, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(a[i])) return 0;
    return 1;
}

/* d = -H^-1 g by Cholesky of H (upper triangle, overwritten). */
static int solve(double *H, int r, const double *g, double *d, int it, rk_error *err)
{
    for (int i = 0; i < r; i++) d[i] = -g[i];
    int info = LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'U', r, H, r);
    if (info != 0)
        return rk_fail(err, "Newton iteration %d: the %d x %d reduced Newton matrix is not positive definite "
                       "(pivot %d); the basis may have dependent columns", it, r, r, info);
    LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'U', r, 1, H, r, d, r);
    return 0;
}

int rk_rom_newton(rk_rom *s, const rk_rom_terms *T, double tol_d, int *converged, rk_error *err)
{
    rk_rom_model *m = s->model;
    int r = m->r;
    double *q = s->q, *g = s->work + RK_ROM_WORK_G * (size_t)r, *d = s->work + RK_ROM_WORK_D * (size_t)r;
    double *trial = s->work + RK_ROM_WORK_TRIAL * (size_t)r, *tmp = s->work + RK_ROM_WORK_TMP * (size_t)r;
    double *H = s->work + RK_ROM_WORK_VECTORS * (size_t)r;
    *converged = 0;
    for (int it = 0; it < m->newton_max_iter; it++) {
        double magnitude;
        double E = rk_rom_potential(s, T, q, g, H, &magnitude);
        if (!isfinite(E) || !all_finite(g, r))
            return rk_fail(err, "reduced incremental potential is not finite at Newton iteration %d", it);
        if (solve(H, r, g, d, it, err)) return -1;
        s->stats.newton_iterations++;
        if (!all_finite(d, r)) return rk_fail(err, "Newton direction is not finite at iteration %d", it);
        /* Size of the step as an RMS displacement: sqrt(d^T M_r d / total mass). */
        cblas_dsymv(CblasColMajor, CblasUpper, r, 1.0, m->M, r, d, 1, 0.0, tmp, 1);
        if (sqrt(fmax(cblas_ddot(r, d, 1, tmp, 1), 0.0) / m->mass) <= tol_d) {
            *converged = 1;
            return 0;
        }
        double gd = cblas_ddot(r, g, 1, d, 1);
        double alpha = m->ncontacts ? rk_rom_contact_max_step(m, q, d) : 1.0;
        int accepted = 0;
        for (int k = 0; k <= MAX_HALVINGS && !accepted; k++) {
            if (k > 0) {
                alpha *= 0.5;
                s->stats.line_search_halvings++;
            }
            for (int i = 0; i < r; i++) trial[i] = q[i] + alpha * d[i];
            double Et = rk_rom_potential(s, T, trial, NULL, NULL, NULL);
            accepted = Et <= E + ARMIJO_C * alpha * gd || (isfinite(Et) && Et - E <= ENERGY_NOISE * magnitude);
        }
        if (!accepted) return 0;
        memcpy(q, trial, sizeof(double) * r);
    }
    return 0;
}
