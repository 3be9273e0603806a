/* Prescribed vertices: their targets in time, and their removal from the Newton system. */
#include "fom/fom_impl.h"

#include <math.h>

void rk_prescribed_transform(const rk_prescribed *p, double t, double R[9], double shift[3])
{
    rk_motion(p->kind, p->axis, p->center, p->rate, p->velocity, t, R, shift);
}

void rk_fom_prescribe(const rk_fom *s, double t, double *x)
{
    const double *X = s->fem->X;
    for (int g = 0; g < s->opt.nprescribed; g++) {
        const rk_prescribed *p = &s->opt.prescribed[g];
        double R[9], shift[3];
        rk_prescribed_transform(p, t, R, shift);
        for (int j = 0; j < p->count; j++) {
            int v = p->verts[j];
            const double *Xv = &X[3 * v];
            for (int i = 0; i < 3; i++)
                x[3 * v + i] = R[3 * i] * Xv[0] + R[3 * i + 1] * Xv[1] + R[3 * i + 2] * Xv[2] + shift[i];
        }
    }
}

void rk_fom_eliminate(const rk_fom *s, rk_sparse *H)
{
    if (!H || (s->opt.nprescribed == 0 && !s->impl->nobs)) return;
    const char *fixed = s->impl->prescribed_dof;
    for (int j = 0; j < H->n; j++)
        for (int k = H->colptr[j]; k < H->colptr[j + 1]; k++) {
            int i = H->rowind[k];
            if (fixed[i] || fixed[j]) H->val[k] = i == j ? 1.0 : 0.0;
        }
}
