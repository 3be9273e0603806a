/* The feasible step (contact.h): every candidate stencil's additive CCD (rk_ccd_stencil,
 * physics/contact_impl.h, shared with the runtime) over the broad phase's swept boxes, and the
 * points against planes. */
#include "contact/pairs_impl.h"

#include "util/util.h"

#include <math.h>

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
    int cached = rk_contact_step_candidates_cached(c, &f, &cand, err);
    if (cached < 0 || (!cached && rk_contact_candidates(c, &f, 0, &cand, err))) {
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
