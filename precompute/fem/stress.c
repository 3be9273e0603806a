/* The largest principal Cauchy stress at each vertex (FreeForm paper, Fig. 8): each tet's
 * sigma = P F^T / J from the shared physics' first Piola-Kirchhoff stress (rk_pk1; rk_cauchy_stress,
 * which romkit run --stress takes at a point cloud's points from their F too), averaged
 * over the tets around a vertex by their rest volumes, and that average's largest eigenvalue. The
 * tensor is averaged, not its eigenvalues, so a vertex between tets pulled along different axes
 * reports the stress it carries. */
#include "fem/fem.h"

#include <stdlib.h>
#include <string.h>

#include "physics/physics.h"

void rk_cauchy_stress(rk_material_model model, double mu, double lambda, const double F[9], double s[9])
{
    double P[9];
    rk_pk1(model, mu, lambda, F, P);
    double J = rk_det3(F);
    /* sigma = P F^T / J (row-major 3 x 3), symmetrized: a linear material's P F^T is not quite */
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double a = 0, b = 0;
            for (int k = 0; k < 3; k++) a += P[3 * i + k] * F[3 * j + k], b += P[3 * j + k] * F[3 * i + k];
            s[3 * i + j] = 0.5 * (a + b) / J;
        }
}

double rk_largest_principal(const double s[9])
{
    double A[9], w[3], V[9];
    memcpy(A, s, sizeof A);
    rk_sym_eig(3, A, w, V);
    return w[0] > w[1] ? (w[0] > w[2] ? w[0] : w[2]) : (w[1] > w[2] ? w[1] : w[2]);
}

int rk_fem_principal_stress(const rk_fem *f, const double *x, double *out, rk_error *err)
{
    double *sum = rk_calloc(6 * (size_t)f->nv + 1, sizeof(double), err), *vol = rk_calloc((size_t)f->nv + 1, sizeof(double), err);
    if (!sum || !vol) {
        free(sum);
        free(vol);
        return -1;
    }
    for (int t = 0; t < f->nt; t++) {
        double xt[12], F[9], s[9];
        for (int a = 0; a < 4; a++) memcpy(xt + 3 * a, x + 3 * (size_t)f->tets[4 * t + a], 3 * sizeof(double));
        rk_tet_F(xt, f->Dm_inv + 9 * (size_t)t, F);
        rk_cauchy_stress(f->model[t], f->mu[t], f->lambda[t], F, s);
        const double packed[6] = {s[0], s[4], s[8], s[1], s[2], s[5]};
        for (int a = 0; a < 4; a++) {
            int v = f->tets[4 * t + a];
            for (int k = 0; k < 6; k++) sum[6 * (size_t)v + k] += f->vol[t] * packed[k];
            vol[v] += f->vol[t];
        }
    }
    for (int v = 0; v < f->nv; v++) {
        if (!(vol[v] > 0)) { /* in no tet (a point cloud's point, a contact proxy's corner) */
            out[v] = 0;
            continue;
        }
        const double *p = sum + 6 * (size_t)v;
        double A[9] = {p[0], p[3], p[4], p[3], p[1], p[5], p[4], p[5], p[2]};
        for (int k = 0; k < 9; k++) A[k] /= vol[v];
        out[v] = rk_largest_principal(A);
    }
    free(sum);
    free(vol);
    return 0;
}
