/* The barrier potential of the contact pairs (contact.h; IPC, Li et al. 2020, Eq. 6-8): kappa
 * sum_k m_k b(s_k, s_hat) on s = d^2 - xi^2 with s_hat = dhat^2 + 2 xi dhat (activation at d - xi =
 * dhat), m_k the edge-edge mollifier; gradients and PSD-projected Hessians per pair. */
#include "contact/pairs_impl.h"

#include <math.h>
#include <string.h>

#include "util/util.h"

/* Projects the Hessian H (12 x 12) to PSD on the points that take part (a non-zero row) and are
 * degrees of freedom (mesh vertices, and obstacle vertices when moving obstacles are: dofs_obs):
 * points outside the closest feature drop out, so a point-point pair projects a 6 x 6 block. The
 * other rows and columns are zeroed. */
static void project_on_dofs(const rk_contact_pair *p, int dofs_obs, double *H)
{
    int keep[12], n = 0;
    for (int k = 0; k < 4; k++) {
        int used = 0;
        for (int a = 0; a < 3 && (p->id[k] >= 0 || dofs_obs); a++)
            for (int j = 0; j < 12; j++) used |= H[12 * (3 * k + a) + j] != 0;
        for (int a = 0; a < 3 && used; a++) keep[n++] = 3 * k + a;
    }
    double B[144];
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) B[n * i + j] = H[12 * keep[i] + keep[j]];
    rk_project_psd(n, B);
    memset(H, 0, 144 * sizeof(double));
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) H[12 * keep[i] + keep[j]] = B[n * i + j];
}

/* One pair's energy, gradient (12) and Hessian (144), unscaled by kappa. +INFINITY on contact. */
static double pair_potential(const rk_contact *c, const rk_contact_pair *p, const double *x, double *g, double *H,
                             double *dist)
{
    const double *pts[4];
    rk_contact_stencil(c, p, x, c->ox, pts);
    double gd[12], Hd[144];
    int ee = p->kind == RK_PAIR_EDGE_EDGE;
    rk_distance_case k = ee ? rk_edge_edge_case(pts) : rk_point_triangle_case(pts);
    double d2 = rk_contact_distance2(k, pts, g ? gd : NULL, H ? Hd : NULL);
    double dhat = c->opt.dhat, s = d2 - p->xi * p->xi, shat = dhat * dhat + 2 * p->xi * dhat;
    *dist = sqrt(d2) - p->xi;
    if (!(s > 0)) return INFINITY;
    if (s >= shat) {
        if (g) memset(g, 0, 12 * sizeof(double));
        if (H) memset(H, 0, 144 * sizeof(double));
        return 0;
    }
    double b1, b2, b = rk_barrier(s, shat, &b1, &b2);
    double m = 1, gm[12] = {0}, Hm[144] = {0};
    if (ee && p->eps > 0) m = rk_edge_edge_mollifier(pts, p->eps, g ? gm : NULL, H ? Hm : NULL);
    if (g)
        for (int i = 0; i < 12; i++) g[i] = m * b1 * gd[i] + b * gm[i];
    if (H) {
        for (int i = 0; i < 12; i++)
            for (int j = 0; j < 12; j++)
                H[12 * i + j] = m * (b2 * gd[i] * gd[j] + b1 * Hd[12 * i + j]) + b1 * (gd[i] * gm[j] + gm[i] * gd[j]) +
                                b * Hm[12 * i + j];
        if (!c->exact_hessian) project_on_dofs(p, c->obstacle_dofs, H);
    }
    return m * b;
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
