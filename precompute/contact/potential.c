/* The barrier potential of the contact pairs (contact.h; IPC, Li et al. 2020, Eq. 6-8): kappa
 * sum_k m_k b(s_k, s_hat) on s = d^2 - xi^2 with s_hat = dhat^2 + 2 xi dhat (activation at d - xi =
 * dhat), m_k the edge-edge mollifier; gradients and PSD-projected Hessians per pair. */
#include "contact/pairs_impl.h"

#include <math.h>
#include <string.h>

#include "util/util.h"

/* One pair's energy, gradient (12) and Hessian (144), unscaled by kappa: rk_pair_barrier, the
 * Hessian PSD-projected on the points that are degrees of freedom (mesh vertices, and obstacle
 * vertices when moving obstacles are). +INFINITY on contact. */
static double pair_potential(const rk_contact *c, const rk_contact_pair *p, const double *x, double *g, double *H,
                             double *dist)
{
    const double *pts[4];
    rk_contact_stencil(c, p, x, c->ox, pts);
    double e = rk_pair_barrier(p->kind == RK_PAIR_EDGE_EDGE, pts, p->xi, c->opt.dhat, p->eps, g, H, dist);
    if (H && e > 0 && isfinite(e) && !c->exact_hessian) {
        int dof[4];
        for (int k = 0; k < 4; k++) dof[k] = p->id[k] >= 0 || c->obstacle_dofs;
        rk_pair_project(dof, H);
    }
    return e;
}

/* A point against a plane: the point barrier of physics.h on the signed distance, +INFINITY behind it. */
static double plane_potential(const rk_contact *c, const rk_contact_pair *p, const double *x, double *g, double *H,
                              double *dist)
{
    const double *n = &c->oplane[6 * p->id[1] + 3];
    double d = rk_contact_plane_distance(c, p->id[1], &x[3 * p->id[0]]), f1, f2;
    *dist = d;
    if (!(d > 0)) return INFINITY;
    double b = rk_barrier_distance(d, c->opt.dhat, &f1, &f2);
    if (g)
        for (int i = 0; i < 3; i++) g[i] = f1 * n[i];
    if (H)
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) H[3 * i + j] = f2 * n[i] * n[j];
    return b;
}

double rk_contact_energy(rk_contact *c, const rk_contact_set *s, const double *x, double *g, double *og,
                         rk_hessian_sink sink, void *ctx, double *min_distance)
{
    double t0 = rk_now(), E = 0, closest = INFINITY, kappa = c->kappa;
    double gl[12], Hl[144];
    for (int i = 0; i < s->n && isfinite(E); i++) {
        const rk_contact_pair *p = &s->pairs[i];
        int plane = p->kind == RK_PAIR_POINT_PLANE, np = plane ? 1 : 4;
        double dist;
        double e = plane ? plane_potential(c, p, x, g || og ? gl : NULL, sink ? Hl : NULL, &dist)
                         : pair_potential(c, p, x, g || og ? gl : NULL, sink ? Hl : NULL, &dist);
        closest = fmin(closest, dist);
        E += kappa * e;
        if (!isfinite(e)) break;
        if (e == 0) continue;
        for (int k = 0; k < np; k++) {
            double *to = p->id[k] >= 0 ? (g ? &g[3 * p->id[k]] : NULL) : (og && !plane ? &og[3 * (-1 - p->id[k])] : NULL);
            for (int a = 0; a < 3 && to; a++) to[a] += kappa * gl[3 * k + a];
        }
        if (sink) {
            int dim = 3 * np;
            for (int k = 0; k < dim * dim; k++) Hl[k] *= kappa;
            sink(ctx, p->id, np, Hl);
        }
    }
    if (min_distance) *min_distance = closest;
    c->stats.seconds_potential += rk_now() - t0;
    return isfinite(E) ? E : INFINITY;
}

void rk_contact_point_energy(const rk_contact *c, const rk_contact_set *s, const double *x, double *e)
{
    for (int i = 0; i < s->n; i++) {
        const rk_contact_pair *p = &s->pairs[i];
        int plane = p->kind == RK_PAIR_POINT_PLANE, np = plane ? 1 : 4, mesh = 0;
        double dist;
        double b = c->kappa * (plane ? plane_potential(c, p, x, NULL, NULL, &dist) : pair_potential(c, p, x, NULL, NULL, &dist));
        if (b == 0) continue;
        for (int k = 0; k < np; k++) mesh += p->id[k] >= 0;
        for (int k = 0; k < np; k++)
            if (p->id[k] >= 0) e[p->id[k]] += b / mesh;
    }
}
