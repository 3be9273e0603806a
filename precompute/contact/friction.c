/* Friction (IPC, Li et al. 2020, Sec. 5): the smoothed Coulomb dissipative potential
 *   D(x) = mu sum_k lambda_k f0(|u_k|),   u_k = T_k sum_i w_ki (x_i - x_i^t)   (Eq. 9-10)
 * with the normal force lambda_k, the tangent basis T_k (2 x 3) and the closest-point weights
 * w_k lagged: fixed at the state rk_contact_friction_lag saw, for a whole Newton solve; x^t is
 * where everything was when the step began. f0 is |u| smoothed to C1 below eps_v h (Eq. 14-15),
 * so friction is static below the slip speed eps_v. */
#include "contact/pairs_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "physics/physics.h"
#include "util/util.h"

int rk_contact_friction_start(rk_contact *c, const double *x, rk_error *err)
{
    if (!c->fx0) {
        c->fx0 = rk_calloc(3 * (size_t)c->nmesh + 1, sizeof(double), err);
        c->fox0 = rk_calloc(3 * (size_t)c->onv + 1, sizeof(double), err);
        if (!c->fx0 || !c->fox0) return -1;
    }
    memcpy(c->fx0, x, sizeof(double) * 3 * (size_t)c->nmesh);
    memcpy(c->fox0, c->ox, sizeof(double) * 3 * (size_t)c->onv);
    c->nfriction = 0;
    return 0;
}

/* The lagged quantities of one pair at x, or 0 when the pair exerts no force. */
static int lag_pair(const rk_contact *c, const rk_contact_pair *p, const double *x, rk_friction_pair *f)
{
    double n[3], dhat = c->opt.dhat, b1, b2;
    memset(f, 0, sizeof *f);
    if (p->kind == RK_PAIR_POINT_PLANE) {
        const double *pn = &c->oplane[6 * p->id[1] + 3];
        double d = rk_contact_plane_distance(c, p->id[1], &x[3 * p->id[0]]);
        if (!(d > 0 && d < dhat)) return 0;
        rk_barrier_distance(d, dhat, &b1, &b2);
        f->lambda = c->kappa * fabs(b1);
        f->np = 1, f->id[0] = p->id[0], f->w[0] = 1;
        memcpy(n, pn, sizeof n);
        rk_tangent_basis(n, f->T);
        return f->lambda > 0;
    }
    const double *pts[4];
    rk_contact_stencil(c, p, x, c->ox, pts);
    f->lambda = rk_pair_friction_lag(p->kind == RK_PAIR_EDGE_EDGE, pts, p->xi, dhat, p->eps, c->kappa, f->w, f->T);
    f->np = 4;
    memcpy(f->id, p->id, sizeof f->id);
    return f->lambda > 0;
}

int rk_contact_friction_lag(rk_contact *c, const double *x, rk_error *err)
{
    c->nfriction = 0;
    if (c->opt.friction <= 0) return 0;
    if (rk_contact_gather(c, x, &c->friction_pairs, err)) return -1;
    const rk_contact_set *s = &c->friction_pairs;
    if (s->n > c->capfriction) {
        rk_friction_pair *grown = realloc(c->friction, sizeof *grown * (size_t)s->n);
        if (!grown) return rk_fail(err, "out of memory for %d friction pairs", s->n);
        c->friction = grown, c->capfriction = s->n;
    }
    for (int i = 0; i < s->n; i++) c->nfriction += lag_pair(c, &s->pairs[i], x, &c->friction[c->nfriction]);
    return 0;
}

double rk_contact_friction_energy(const rk_contact *c, const double *x, double h, double *g, double *og,
                                  rk_hessian_sink sink, void *ctx)
{
    double mu = c->opt.friction, eps = c->opt.eps_v * h, E = 0;
    for (int k = 0; k < c->nfriction; k++) {
        const rk_friction_pair *f = &c->friction[k];
        double rel[3] = {0, 0, 0}; /* sum_i w_i (x_i - x_i^t); planes stay where they are */
        for (int i = 0; i < f->np; i++) {
            int id = f->id[i];
            const double *now = id >= 0 ? &x[3 * id] : &c->ox[3 * (-1 - id)];
            const double *then = id >= 0 ? &c->fx0[3 * id] : &c->fox0[3 * (-1 - id)];
            for (int a = 0; a < 3; a++) rel[a] += f->w[i] * (now[a] - then[a]);
        }
        double gt[3], B[9], H[144]; /* d D_k / d rel; then w_i w_j B per block */
        E += rk_friction_slip(f->T, rel, eps, mu * f->lambda, gt, sink ? B : NULL);
        for (int i = 0; i < f->np; i++) {
            int id = f->id[i];
            double *to = id >= 0 ? (g ? &g[3 * id] : NULL) : (og ? &og[3 * (-1 - id)] : NULL);
            for (int a = 0; a < 3 && to; a++) to[a] += f->w[i] * gt[a];
        }
        if (!sink) continue;
        int dim = 3 * f->np;
        for (int i = 0; i < f->np; i++)
            for (int j = 0; j < f->np; j++)
                for (int a = 0; a < 3; a++)
                    for (int b = 0; b < 3; b++) H[dim * (3 * i + a) + 3 * j + b] = f->w[i] * f->w[j] * B[3 * a + b];
        sink(ctx, f->id, f->np, H);
    }
    return E;
}
