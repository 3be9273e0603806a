/* Continuous collision detection of one stencil (contact.h): additive CCD (Li, Kaufman and Jiang
 * 2021, "Codimensional Incremental Potential Contact", Sec. 4.1, Alg. 1). The displacements are
 * made relative (their mean removed); l_p bounds how fast the distance can shrink per unit of
 * time; the stencil then advances by steps s (d - xi) / l_p, each of which provably cannot
 * reach contact, until the distance falls below (1 - s) of the start's. The time reached is a
 * conservative time of impact: along the step, no closer than 10% of the start's gap. */
#include "contact/pairs_impl.h"

#include "util/util.h"

#include <math.h>

/* s in Alg. 1: each advance covers this fraction of the distance bound, and the advance stops
 * once the gap falls below 1 - s of the start's. */
#define CCD_RESCALING 0.9
/* More advances than this means the stencil is grinding along at a tiny gap: report an impact
 * at the time reached, which stays conservative. */
#define CCD_MAX_ADVANCES 100000

static double norm3(const double *a)
{
    return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

/* The squared distance of the stencil at x, by its closest feature; edge-edge stencils that come
 * out at or below the thickness through rounding of nearly parallel lines use the endpoints. */
static double stencil_distance2(int edge_edge, const double *const x[4], double xi)
{
    rk_distance_case c = edge_edge ? rk_edge_edge_case(x) : rk_point_triangle_case(x);
    double d2 = rk_contact_distance2(c, x, NULL, NULL);
    if (edge_edge && d2 <= xi * xi) {
        for (int i = 0; i < 2; i++)
            for (int j = 2; j < 4; j++) {
                double e[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
                d2 = i + j == 2 ? e[0] * e[0] + e[1] * e[1] + e[2] * e[2]
                                : fmin(d2, e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
            }
    }
    return d2;
}

int rk_ccd_stencil(int edge_edge, const double *const x[4], const double *const dx[4], double xi, double tmax,
                   double *toi)
{
    double p[4][3], mean[3] = {0, 0, 0}, y[4][3];
    for (int k = 0; k < 4; k++)
        for (int a = 0; a < 3; a++) mean[a] += dx[k][a] / 4;
    for (int k = 0; k < 4; k++)
        for (int a = 0; a < 3; a++) p[k][a] = dx[k][a] - mean[a];
    /* l_p: point-triangle |p_0| + max |p_t|; edge-edge max |p_a| + max |p_b| */
    double lp = edge_edge ? fmax(norm3(p[0]), norm3(p[1])) + fmax(norm3(p[2]), norm3(p[3]))
                          : norm3(p[0]) + fmax(norm3(p[1]), fmax(norm3(p[2]), norm3(p[3])));
    for (int k = 0; k < 4; k++)
        for (int a = 0; a < 3; a++) y[k][a] = x[k][a];
    const double *yk[4] = {y[0], y[1], y[2], y[3]};
    double d2 = stencil_distance2(edge_edge, yk, xi), d = sqrt(d2);
    *toi = 0;
    if (!(d > xi)) return 1; /* already touching */
    if (lp == 0) return 0;   /* rigidly translating together: the distance never changes */
    double gap = (1 - CCD_RESCALING) * (d2 - xi * xi) / (d + xi), t = 0;
    for (int it = 0; it < CCD_MAX_ADVANCES; it++) {
        double step = CCD_RESCALING * (d2 - xi * xi) / ((d + xi) * lp);
        for (int k = 0; k < 4; k++)
            for (int a = 0; a < 3; a++) y[k][a] += step * p[k][a];
        d2 = stencil_distance2(edge_edge, yk, xi);
        d = sqrt(d2);
        if (t > 0 && (d2 - xi * xi) / (d + xi) < gap) break;
        t += step;
        if (t > tmax) return 0;
    }
    *toi = t;
    return 1;
}

double rk_contact_max_step(rk_contact *c, const double *x, const double *dx, const double *odx, rk_error *err)
{
    double alpha = 1, t0 = rk_now();
    /* points against (still) planes: keep 10% of each distance */
    for (int k = 0; k < c->nobstacles; k++) {
        if (c->obstacles[k].kind != RK_OBSTACLE_PLANE) continue;
        const double *n = &c->oplane[6 * k + 3];
        for (int i = 0; i < c->nv; i++) {
            int v = c->vertex[i];
            double d = rk_contact_plane_distance(c, k, &x[3 * v]);
            double rate = n[0] * dx[3 * v] + n[1] * dx[3 * v + 1] + n[2] * dx[3 * v + 2];
            if (d > 0 && rate < 0 && 0.9 * d < -rate * alpha) alpha = 0.9 * d / -rate;
        }
    }
    rk_contact_set cand = {0};
    rk_motion_frame f = {x, dx, c->ox, odx};
    if (rk_contact_candidates(c, &f, 0, &cand, err)) {
        rk_contact_set_free(&cand);
        return -1;
    }
    double t1 = rk_now();
    c->stats.seconds_broad += t1 - t0;
    static const double still[3] = {0, 0, 0};
    for (int i = 0; i < cand.n; i++) {
        const rk_contact_pair *p = &cand.pairs[i];
        const double *pts[4], *d[4];
        rk_contact_stencil(c, p, x, c->ox, pts);
        for (int k = 0; k < 4; k++) {
            int id = p->id[k];
            d[k] = id >= 0 ? &dx[3 * id] : odx ? &odx[3 * (-1 - id)] : still;
        }
        double toi;
        c->stats.ccd_calls++;
        if (rk_ccd_stencil(p->kind == RK_PAIR_EDGE_EDGE, pts, d, p->xi, alpha, &toi)) alpha = fmin(alpha, toi);
    }
    c->stats.seconds_ccd += rk_now() - t1;
    rk_contact_set_free(&cand);
    return alpha;
}
