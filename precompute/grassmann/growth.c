/* What one adaptive step does to a perturbation of the state (issue 33, grassmann.h): the step
 * map (u, v) -> (u', v') with its basis update (encoder, Jacobian, history, Grassmann point),
 * differentiated by finite differences along a power iteration, in the energy norm
 * |(du, dv)|^2 = dv^T M dv + du^T K du (M the mass, K the rest stiffness, the free dofs). That is
 * the norm implicit Euler dissipates for a fixed basis and linear elasticity (the step's
 * optimality U^T (M (v' - v) / h + K u') = 0 gives E' - E = -1/2 |v' - v|_M^2 - h^2/2 |v'|_K^2
 * on the difference of two runs), so a growth above 1 is the basis' own doing. */
#include "grassmann/grassmann.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double energy_norm(const rk_sparse *M, const rk_sparse *K, const double *du, const double *dv)
{
    return sqrt(fmax(0, rk_sparse_dot(M, dv, dv)) + fmax(0, rk_sparse_dot(K, du, du)));
}

int rk_alrom_step_growth(rk_alrom *A, rk_alrom *pre, rk_alrom *probe, const rk_sparse *M, const rk_sparse *K, int ndir,
                         double eps, uint64_t *seed, double *growth, rk_error *err)
{
    int n = 3 * A->fom.fem->nv;
    rk_fom_view view;
    rk_fom_view_get(&A->fom, &view);
    double *buf = malloc(sizeof(double) * 4 * (size_t)n);
    if (!buf) return rk_fail(err, "out of memory for the growth measurement");
    double *du = buf, *dv = du + n, *x = dv + n, *v = x + n;
    for (int i = 0; i < n; i++) {
        du[i] = view.prescribed[i] ? 0 : rk_uniform(seed) - 0.5;
        dv[i] = view.prescribed[i] ? 0 : rk_uniform(seed) - 0.5;
    }
    /* the state's own size sets the perturbation's (at rest: 1) */
    for (int i = 0; i < n; i++) x[i] = A->fom.x[i] - A->fom.fem->X[i];
    double size = energy_norm(M, K, x, A->fom.v);
    size = eps * (size > 0 ? size : 1);
    rk_alrom_copy_state(pre, A);
    int rc = rk_alrom_step(A, err);
    *growth = 0;
    for (int k = 0; k < ndir && !rc; k++) {
        double d = energy_norm(M, K, du, dv);
        if (!(d > 0)) break;
        for (int i = 0; i < n; i++) {
            x[i] = pre->fom.x[i] + size / d * du[i];
            v[i] = pre->fom.v[i] + size / d * dv[i];
        }
        rk_alrom_copy_state(probe, pre);
        rk_alrom_set_state(probe, x, v, NULL, NULL, pre->fom.t);
        if ((rc = rk_alrom_step(probe, err))) break;
        /* the next direction: what this one became (a power iteration toward the dominant one) */
        for (int i = 0; i < n; i++) {
            du[i] = probe->fom.x[i] - A->fom.x[i];
            dv[i] = probe->fom.v[i] - A->fom.v[i];
        }
        *growth = fmax(*growth, energy_norm(M, K, du, dv) / size);
    }
    free(buf);
    return rc ? rk_error_prefix(err, "the growth measurement") : 0;
}
