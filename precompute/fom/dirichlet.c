/* Prescribed vertices: their targets in time, and their removal from the Newton system. */
#include "fom/impl.h"

#include <math.h>

/* Rodrigues: r rotated by angle about unit axis k = r cos + (k x r) sin + k (k.r)(1 - cos). */
static void rotate(const double k[3], double angle, const double r[3], double out[3])
{
    double c = cos(angle), sn = sin(angle), kr = k[0] * r[0] + k[1] * r[1] + k[2] * r[2];
    double kxr[3] = {k[1] * r[2] - k[2] * r[1], k[2] * r[0] - k[0] * r[2], k[0] * r[1] - k[1] * r[0]};
    for (int i = 0; i < 3; i++) out[i] = r[i] * c + kxr[i] * sn + k[i] * kr * (1 - c);
}

void rk_fom_prescribe(const rk_fom *s, double t, double *x)
{
    const double *X = s->fem->X;
    for (int g = 0; g < s->opt.nprescribed; g++) {
        const rk_prescribed *p = &s->opt.prescribed[g];
        for (int j = 0; j < p->count; j++) {
            int v = p->verts[j];
            const double *Xv = &X[3 * v];
            double *xv = &x[3 * v];
            if (p->kind == RK_MOTION_TWIST) {
                double r[3] = {Xv[0] - p->center[0], Xv[1] - p->center[1], Xv[2] - p->center[2]}, rr[3];
                rotate(p->axis, p->rate * t, r, rr);
                for (int i = 0; i < 3; i++) xv[i] = p->center[i] + rr[i];
            } else if (p->kind == RK_MOTION_TRANSLATE) {
                for (int i = 0; i < 3; i++) xv[i] = Xv[i] + p->velocity[i] * t;
            } else {
                for (int i = 0; i < 3; i++) xv[i] = Xv[i];
            }
        }
    }
}

int rk_fom_check_planes(const rk_fom *s, const double *x, rk_error *err)
{
    const rk_obstacles *ob = &s->opt.obstacles;
    for (int g = 0; g < s->opt.nprescribed; g++) {
        const rk_prescribed *p = &s->opt.prescribed[g];
        for (int j = 0; j < p->count; j++)
            for (int k = 0; k < ob->count; k++) {
                const rk_plane *pl = &ob->planes[k];
                const double *xv = &x[3 * p->verts[j]];
                double d = 0;
                for (int i = 0; i < 3; i++) d += pl->normal[i] * (xv[i] - pl->point[i]);
                if (!(d > 0))
                    return rk_fail(err, "prescribed vertex %d is driven onto or through plane %d (distance %g m)",
                                   p->verts[j], k, d);
            }
    }
    return 0;
}

void rk_fom_eliminate(const rk_fom *s, double *g, rk_sparse *H)
{
    if (s->opt.nprescribed == 0) return;
    const char *fixed = s->impl->prescribed_dof;
    if (g)
        for (int i = 0; i < s->impl->n; i++)
            if (fixed[i]) g[i] = 0;
    if (!H) return;
    for (int j = 0; j < H->n; j++)
        for (int k = H->colptr[j]; k < H->colptr[j + 1]; k++) {
            int i = H->rowind[k];
            if (fixed[i] || fixed[j]) H->val[k] = i == j ? 1.0 : 0.0;
        }
}
