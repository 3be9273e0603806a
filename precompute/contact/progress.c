/* The scene's moving obstacles solved for with the body (contact.h, rk_obstacle_way): over a step
 * their vertices go on straight lines from where they are to where their motions put them at the
 * step's end, x_o(s_k) = from + s_k D_o, and a simulator makes each moving obstacle's progress s_k
 * one more Newton unknown, pulled to 1 by w_k/2 (1 - s_k)^2 - lambda_k (1 - s_k) with
 * w_k = RK_COLLIDER_PULL m L_k^2 / h^2 (L_k the longest D_o of obstacle k) and lambda_k raised in
 * rounds of the method of multipliers (IPC's moving obstacles as unknowns, Li et al. 2020,
 * Sec. 4.6, with one unknown per obstacle instead of 3 per obstacle vertex). One progress per
 * obstacle rather than one for all: an obstacle that presses a pinned body stops short alone, and
 * the others arrive. The reduced simulator (precompute/rom/obstacle_solve.c) and the adaptive one
 * (precompute/adaptive) share these pieces; the runtime does the same in float
 * (runtime/contact_progress.c). */
#include "contact/contact.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "physics/physics.h"

int rk_obstacle_way_init(rk_obstacle_way *p, const rk_contact *c, double t, double mass, double h, rk_error *err)
{
    memset(p, 0, sizeof *p);
    p->onv = c->onv;
    size_t m = 3 * (size_t)c->onv + 1, no = (size_t)c->nobstacles + 1;
    p->from = rk_calloc(m, sizeof(double), err);
    p->way = rk_calloc(m, sizeof(double), err);
    p->odx = rk_calloc(m, sizeof(double), err);
    p->unit = rk_calloc((size_t)c->onv + 1, sizeof(int), err);
    p->L = rk_calloc(no, sizeof(double), err);
    p->w = rk_calloc(no, sizeof(double), err);
    p->lambda = rk_calloc(no, sizeof(double), err);
    p->short_by = rk_calloc(no, sizeof(double), err);
    p->gs = rk_calloc(no, sizeof(double), err);
    p->near = rk_calloc(no, sizeof(int), err);
    int *of = rk_calloc(no, sizeof(int), err); /* each obstacle's unknown */
    double *L2 = rk_calloc(no, sizeof(double), err);
    if (!p->from || !p->way || !p->odx || !p->unit || !p->L || !p->w || !p->lambda || !p->short_by || !p->gs ||
        !p->near || !of || !L2) {
        free(of), free(L2);
        rk_obstacle_way_free(p);
        return -1;
    }
    memcpy(p->from, c->ox, sizeof(double) * 3 * (size_t)c->onv);
    rk_contact_obstacles_at(c, t, p->way);
    for (int o = 0; o < c->onv; o++) {
        double d2 = 0;
        for (int a = 0; a < 3; a++) {
            p->way[3 * o + a] -= p->from[3 * o + a];
            d2 += p->way[3 * o + a] * p->way[3 * o + a];
        }
        int k = c->overt_obstacle[o];
        L2[k] = fmax(L2[k], d2);
    }
    /* the obstacles that move this step, in their order: the unknowns s_0.. */
    for (int k = 0; k < c->nobstacles; k++) {
        of[k] = -1;
        if (!(L2[k] > 0)) continue;
        int u = of[k] = p->n++;
        p->L[u] = sqrt(L2[k]);
        p->w[u] = RK_COLLIDER_PULL * mass * L2[k] / (h * h);
        p->short_by[u] = INFINITY; /* the first round is no test: it may fall short by any amount */
    }
    for (int o = 0; o < c->onv; o++) p->unit[o] = of[c->overt_obstacle[o]];
    free(of), free(L2);
    return p->n;
}

void rk_obstacle_way_free(rk_obstacle_way *p)
{
    free(p->from), free(p->way), free(p->odx), free(p->unit);
    free(p->L), free(p->w), free(p->lambda), free(p->short_by), free(p->gs), free(p->near);
    memset(p, 0, sizeof *p);
}

void rk_obstacle_way_place(const rk_obstacle_way *p, rk_contact *c, const double *s)
{
    for (int o = 0; o < p->onv; o++) {
        int u = p->unit[o];
        for (int a = 0; a < 3; a++) c->ox[3 * o + a] = p->from[3 * o + a] + (u >= 0 ? s[u] * p->way[3 * o + a] : 0);
    }
}

double rk_obstacle_way_pull(const rk_obstacle_way *p, const double *s, double *gs, double *hss, int ld)
{
    double E = 0;
    for (int u = 0; u < p->n; u++) {
        double cs = 1 - s[u];
        if (gs) gs[u] += p->lambda[u] - p->w[u] * cs;
        if (hss) hss[u + (size_t)ld * u] += p->w[u];
        E += 0.5 * p->w[u] * cs * cs - p->lambda[u] * cs;
    }
    return E;
}

void rk_obstacle_way_gradient(rk_obstacle_way *p, const double *og, double *gs)
{
    memset(p->gs, 0, sizeof(double) * (size_t)p->n);
    for (int o = 0; o < p->onv; o++)
        for (int a = 0; a < 3 && p->unit[o] >= 0; a++) p->gs[p->unit[o]] += og[3 * o + a] * p->way[3 * o + a];
    for (int u = 0; u < p->n; u++) gs[u] += p->gs[u];
}

int rk_obstacle_way_block(const rk_obstacle_way *p, const int *id, int np, const double *B, int *units, double *BD,
                          double *hss, int ld)
{
    int dim = 3 * np, nu = 0;
    double D[4][12];
    for (int k = 0; k < np; k++) {
        int u = id[k] < 0 ? p->unit[-1 - id[k]] : -1, j = 0;
        if (u < 0) continue;
        while (j < nu && units[j] != u) j++;
        if (j == nu) { /* a unit new to this block: its way, 0 at every other point */
            units[nu++] = u;
            memset(D[j], 0, sizeof D[j]);
        }
        for (int a = 0; a < 3; a++) D[j][3 * k + a] = p->way[3 * (-1 - id[k]) + a];
    }
    for (int j = 0; j < nu; j++) {
        double *BDj = BD + 12 * j;
        for (int i = 0; i < dim; i++) {
            BDj[i] = 0;
            for (int k = 0; k < dim; k++) BDj[i] += B[dim * i + k] * D[j][k];
        }
    }
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nu; j++)
            for (int k = 0; k < dim; k++) hss[units[i] + (size_t)ld * units[j]] += D[i][k] * BD[12 * j + k];
    return nu;
}

double rk_obstacle_way_max_step(rk_obstacle_way *p, rk_contact *c, const double *x, const double *dx, const double *s,
                                const double *ds, rk_error *err)
{
    double alpha = 1;
    for (int u = 0; u < p->n; u++) {
        if (ds[u] > 0) alpha = fmin(alpha, (1 - s[u]) / ds[u]);
        if (ds[u] < 0) alpha = fmin(alpha, s[u] / -ds[u]);
    }
    rk_obstacle_way_place(p, c, s);
    for (int o = 0; o < p->onv; o++)
        for (int a = 0; a < 3; a++) p->odx[3 * o + a] = p->unit[o] >= 0 ? ds[p->unit[o]] * p->way[3 * o + a] : 0;
    double ccd = rk_contact_max_step(c, x, dx, p->odx, err);
    return fmin(alpha, ccd >= 0 ? ccd : 0);
}

double rk_obstacle_way_step_norm(const rk_obstacle_way *p, const double *ds)
{
    double size = 0;
    for (int u = 0; u < p->n; u++) size = fmax(size, fabs(ds[u]) * p->L[u]);
    return size;
}

int rk_obstacle_way_round(rk_obstacle_way *p, const double *s, double tol)
{
    int again = 0;
    for (int u = 0; u < p->n; u++) {
        double short_by = 1 - s[u];
        if (short_by * p->L[u] <= tol || short_by > 0.5 * p->short_by[u]) continue;
        p->short_by[u] = short_by;
        p->lambda[u] -= p->w[u] * short_by;
        again = 1;
    }
    return again;
}

/* Whether the rest of the way of the units marked in near can go at once with the body still at
 * x (the others where they are): 1, 0, -1 on failure. */
static int rest_clear(rk_obstacle_way *p, rk_contact *c, const double *x, const double *still, const double *s)
{
    for (int o = 0; o < p->onv; o++) {
        int u = p->unit[o];
        for (int a = 0; a < 3; a++) p->odx[3 * o + a] = u >= 0 && p->near[u] ? (1 - s[u]) * p->way[3 * o + a] : 0;
    }
    rk_error err = {0};
    double last = rk_contact_max_step(c, x, still, p->odx, &err);
    return last < 0 ? -1 : last >= 1;
}

int rk_obstacle_way_arrive(rk_obstacle_way *p, rk_contact *c, const double *x, const double *still, const double *s,
                           double t, double tol, int *behind, rk_error *err)
{
    rk_obstacle_way_place(p, c, s);
    int nnear = 0;
    for (int u = 0; u < p->n; u++) nnear += p->near[u] = (1 - s[u]) * p->L[u] <= tol;
    *behind = 1;
    if (nnear == p->n) { /* all within the tolerance: together, when CCD lets their last bits go */
        int clear = rest_clear(p, c, x, still, s);
        if (clear < 0) return rk_fail(err, "out of memory for the moving obstacles' last move");
        if (clear) {
            rk_contact_set_time(c, t);
            *behind = 0;
            return 0;
        }
    }
    /* else each whose rest of the way CCD lets go on its own, the others where they are (those
     * gone before it at the end): near the end, or short only because the solve stopped at its
     * floor first (in float a free obstacle's s creeps by the pinned one's CCD fractions); a
     * pinned one's rest runs into the body */
    int *done = rk_calloc((size_t)p->n + 1, sizeof(int), err), ndone = 0;
    if (!done) return -1;
    for (int u = 0; u < p->n; u++) {
        memset(p->near, 0, sizeof(int) * (size_t)p->n);
        p->near[u] = 1;
        int one = rest_clear(p, c, x, still, s);
        if (one < 0) {
            free(done);
            return rk_fail(err, "out of memory for the moving obstacles' last move");
        }
        if (!one) continue;
        done[u] = 1, ndone++;
        for (int o = 0; o < p->onv; o++)
            for (int a = 0; a < 3 && p->unit[o] == u; a++) c->ox[3 * o + a] = p->from[3 * o + a] + p->way[3 * o + a];
    }
    if (ndone == p->n) { /* all there after all: exactly where the clock puts them (their planes too) */
        rk_contact_set_time(c, t);
        *behind = 0;
    } else if (ndone) { /* those there exactly where the clock puts them, the others at s */
        rk_contact_obstacles_at(c, t, p->odx);
        for (int o = 0; o < p->onv; o++)
            for (int a = 0; a < 3 && p->unit[o] >= 0 && done[p->unit[o]]; a++) c->ox[3 * o + a] = p->odx[3 * o + a];
    }
    free(done);
    return 0;
}
