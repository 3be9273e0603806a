/* Ground planes: the IPC log barrier (Li et al. 2020) on vertex-plane distances, and the step
 * filter that keeps every line-search trial on the positive side. */
#include "fem/element_impl.h"

#include <math.h>
#include <stddef.h>

static double plane_distance(const rk_plane *p, const double *x)
{
    return p->normal[0] * (x[0] - p->point[0]) + p->normal[1] * (x[1] - p->point[1]) +
           p->normal[2] * (x[2] - p->point[2]);
}

static double barrier(double d, double dhat) { return rk_barrier(d, dhat, NULL, NULL); }
static double barrier_d1(double d, double dhat)
{
    double d1;
    rk_barrier(d, dhat, &d1, NULL);
    return d1;
}
static double barrier_d2(double d, double dhat)
{
    double d2;
    rk_barrier(d, dhat, NULL, &d2);
    return d2;
}

double rk_barrier_energy(const rk_fem *f, const rk_obstacles *o, const double *x)
{
    double E = 0;
    for (int k = 0; k < o->count; k++)
        for (int v = 0; v < f->nv; v++) {
            double d = plane_distance(&o->planes[k], &x[3 * v]);
            if (!(d > 0)) return INFINITY; /* crossed (or NaN) */
            if (d < o->dhat) E += o->kappa * f->vertex_mass[v] * barrier(d, o->dhat);
        }
    return E;
}

void rk_barrier_add_gradient(const rk_fem *f, const rk_obstacles *o, const double *x, double scale,
                             double *g)
{
    for (int k = 0; k < o->count; k++) {
        const double *n = o->planes[k].normal;
        for (int v = 0; v < f->nv; v++) {
            double d = plane_distance(&o->planes[k], &x[3 * v]);
            if (!(d > 0 && d < o->dhat)) continue;
            double c = scale * o->kappa * f->vertex_mass[v] * barrier_d1(d, o->dhat);
            for (int i = 0; i < 3; i++) g[3 * v + i] += c * n[i];
        }
    }
}

void rk_barrier_add_hessian(const rk_fem *f, const rk_obstacles *o, const double *x, double scale,
                            rk_sparse *H)
{
    for (int k = 0; k < o->count; k++) {
        const double *n = o->planes[k].normal;
        for (int v = 0; v < f->nv; v++) {
            double d = plane_distance(&o->planes[k], &x[3 * v]);
            if (!(d > 0 && d < o->dhat)) continue;
            double c = scale * o->kappa * f->vertex_mass[v] * barrier_d2(d, o->dhat);
            for (int j = 0; j < 3; j++)
                for (int i = 0; i <= j; i++) H->val[rk_fem_diag_slot(H, v, i, j)] += c * n[i] * n[j];
        }
    }
}

double rk_planes_max_step(const rk_obstacles *o, int nv, const double *x, const double *dx)
{
    double alpha = 1;
    for (int k = 0; k < o->count; k++) {
        const double *n = o->planes[k].normal;
        for (int v = 0; v < nv; v++) {
            double d = plane_distance(&o->planes[k], &x[3 * v]);
            double rate = n[0] * dx[3 * v] + n[1] * dx[3 * v + 1] + n[2] * dx[3 * v + 2];
            /* d + alpha rate >= 0.1 d; a vertex already on the wrong side cannot be helped */
            if (d > 0 && rate < 0 && 0.9 * d < -rate * alpha) alpha = 0.9 * d / -rate;
        }
    }
    return alpha;
}
