/* The scene's moving obstacles solved for with the body (contact.h, rk_obstacle_way): over a step
 * their vertices go on straight lines from where they are to where their motions put them at the
 * step's end, x_o(s) = from + s D, and a simulator makes the progress s one more Newton unknown,
 * pulled to 1 by w/2 (1 - s)^2 - lambda (1 - s) with w = RK_COLLIDER_PULL m L^2 / h^2 (L the
 * longest D_o) and lambda raised in rounds of the method of multipliers (IPC's moving obstacles
 * as unknowns, Li et al. 2020, Sec. 4.6, with one unknown instead of 3 per obstacle vertex). The
 * reduced simulator (precompute/rom/obstacle_solve.c) and the adaptive one (precompute/adaptive)
 * share these pieces; the runtime does the same in float (runtime/contact_progress.c). */
#include "contact/contact.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "physics/physics.h"

int rk_obstacle_way_init(rk_obstacle_way *p, const rk_contact *c, double t, double mass, double h, rk_error *err)
{
    memset(p, 0, sizeof *p);
    p->onv = c->onv;
    p->short_by = INFINITY; /* the first round is no test: it may fall short by any amount */
    size_t m = 3 * (size_t)c->onv + 1;
    p->from = rk_calloc(m, sizeof(double), err);
    p->way = rk_calloc(m, sizeof(double), err);
    p->odx = rk_calloc(m, sizeof(double), err);
    if (!p->from || !p->way || !p->odx) {
        rk_obstacle_way_free(p);
        return -1;
    }
    memcpy(p->from, c->ox, sizeof(double) * 3 * (size_t)c->onv);
    rk_contact_obstacles_at(c, t, p->way);
    double L2 = 0;
    for (int o = 0; o < c->onv; o++) {
        double d2 = 0;
        for (int a = 0; a < 3; a++) {
            p->way[3 * o + a] -= p->from[3 * o + a];
            d2 += p->way[3 * o + a] * p->way[3 * o + a];
        }
        L2 = fmax(L2, d2);
    }
    p->L = sqrt(L2);
    p->w = RK_COLLIDER_PULL * mass * L2 / (h * h);
    return L2 > 0;
}

void rk_obstacle_way_free(rk_obstacle_way *p)
{
    free(p->from), free(p->way), free(p->odx);
    p->from = p->way = p->odx = NULL;
}

void rk_obstacle_way_place(const rk_obstacle_way *p, rk_contact *c, double s)
{
    for (int i = 0; i < 3 * p->onv; i++) c->ox[i] = p->from[i] + s * p->way[i];
}

double rk_obstacle_way_pull(const rk_obstacle_way *p, double s, double *gs, double *hss)
{
    double cs = 1 - s;
    if (gs) *gs += p->lambda - p->w * cs;
    if (hss) *hss += p->w;
    return 0.5 * p->w * cs * cs - p->lambda * cs;
}

double rk_obstacle_way_gradient(const rk_obstacle_way *p, const double *og)
{
    double gs = 0;
    for (int i = 0; i < 3 * p->onv; i++) gs += og[i] * p->way[i];
    return gs;
}

int rk_obstacle_way_block(const rk_obstacle_way *p, const int *id, int np, const double *B, double *BD, double *hss)
{
    int dim = 3 * np, any = 0;
    double D[12] = {0};
    for (int k = 0; k < np; k++)
        for (int a = 0; a < 3 && id[k] < 0; a++) D[3 * k + a] = p->way[3 * (-1 - id[k]) + a], any = 1;
    if (!any) return 0;
    for (int i = 0; i < dim; i++) {
        BD[i] = 0;
        for (int k = 0; k < dim; k++) BD[i] += B[dim * i + k] * D[k];
    }
    for (int i = 0; i < dim; i++) *hss += D[i] * BD[i];
    return 1;
}

double rk_obstacle_way_max_step(rk_obstacle_way *p, rk_contact *c, const double *x, const double *dx, double s,
                                double ds, rk_error *err)
{
    double alpha = 1;
    if (ds > 0) alpha = fmin(alpha, (1 - s) / ds);
    if (ds < 0) alpha = fmin(alpha, s / -ds);
    rk_obstacle_way_place(p, c, s);
    for (int i = 0; i < 3 * p->onv; i++) p->odx[i] = ds * p->way[i];
    double ccd = rk_contact_max_step(c, x, dx, p->odx, err);
    return fmin(alpha, ccd >= 0 ? ccd : 0);
}

double rk_obstacle_way_step_norm(const rk_obstacle_way *p, double ds)
{
    return fabs(ds) * p->L;
}

int rk_obstacle_way_round(rk_obstacle_way *p, double s, double tol)
{
    double short_by = 1 - s;
    if (short_by * p->L <= tol || short_by > 0.5 * p->short_by) return 0;
    p->short_by = short_by;
    p->lambda -= p->w * short_by;
    return 1;
}

int rk_obstacle_way_arrive(rk_obstacle_way *p, rk_contact *c, const double *x, const double *still, double s,
                           double t, double tol, int *behind, rk_error *err)
{
    rk_obstacle_way_place(p, c, s);
    *behind = 1;
    if ((1 - s) * p->L > tol) return 0;
    for (int i = 0; i < 3 * p->onv; i++) p->odx[i] = (1 - s) * p->way[i]; /* the rest of the way */
    double last = rk_contact_max_step(c, x, still, p->odx, err);
    if (last < 0) return -1;
    if (last >= 1) {
        rk_contact_set_time(c, t);
        *behind = 0;
    }
    return 0;
}
