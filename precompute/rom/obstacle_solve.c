/* The scene's moving obstacles solved for with the body (rom_impl.h): over a step their vertices
 * go on straight lines from where they are to where their motions put them at the step's end,
 * x_o(s) = x_o^from + s D_o, and the progress s is one more unknown beside q, pulled to 1 by
 * w/2 (1 - s)^2, as the app's moved colliders are (collider_solve.c; IPC's moving obstacles as
 * unknowns, Li et al. 2020, Sec. 4.6). The barrier pushes the body ahead of them within one
 * Newton solve and CCD filters the joint motion, so an obstacle moving fast arrives in one step;
 * where the body cannot give way (pinned), it stops short with a bounded force and goes on next
 * step. Safe moves (rk_contact_advance: CCD's fraction with the body still, then a solve) need one
 * move per closing of the gap the barrier holds the body at: ~700 moves a step for a box thrown
 * into a terrain rising at 1 m/s, and in the float runtime over 1000.
 *
 * The contact terms depend on s through the obstacle points alone: the contact stage gives their
 * gradient (og) and each pair's block with the obstacle points as degrees of freedom
 * (obstacle_dofs, its PSD projection over all four points), and contact.c's sink turns those into
 * d/ds, d2/ds2 and d2/dq ds through D. w = RK_COLLIDER_PULL m L^2 / h^2, L the longest D_o: the
 * obstacles fall short by about a h^2 / 1000 (m) when pushing the body at acceleration a.
 * The runtime does the same (runtime/contact_progress.c). */
#include "rom/rom_impl.h"

#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "physics/physics.h"

typedef struct {
    rk_rom *s;
    const rk_rom_terms *T;
    rk_error failure;
    int r, n;
    double w, L, lambda;       /* the pull, the longest way, the pull's multiplier */
    double *from, *way;        /* 3 onv */
    double *H;                 /* n x n Newton matrix (column-major) */
    double *Hr;                /* r x r */
} obstacle_problem;

static void place(obstacle_problem *p, double sk)
{
    rk_contact *c = &p->s->model->contact;
    for (int i = 0; i < 3 * c->onv; i++) c->ox[i] = p->from[i] + sk * p->way[i];
}

static double energy(void *ctx, const double *y, double *g, int hessian, double *magnitude)
{
    obstacle_problem *p = ctx;
    rk_rom *s = p->s;
    rk_contact *c = &s->model->contact;
    int r = p->r, n = p->n;
    double sk = y[r];
    place(p, sk);
    s->obs_way = p->way;
    s->obs_gs = s->obs_hss = 0;
    memset(s->obs_hqs, 0, sizeof(double) * r);
    c->obstacle_dofs = 1;
    double E = rk_rom_potential(s, p->T, y, g, hessian ? p->Hr : NULL, magnitude, &p->failure);
    c->obstacle_dofs = 0;
    s->obs_way = NULL;
    if (!isfinite(E)) return E;
    double cs = 1 - sk, e = 0.5 * p->w * cs * cs - p->lambda * cs; /* w/2 (1 - s)^2 - lambda (1 - s) */
    E += e;
    if (magnitude) *magnitude += fabs(e);
    if (g) g[r] = s->obs_gs + p->lambda - p->w * cs;
    if (hessian) {
        memset(p->H, 0, sizeof(double) * (size_t)n * n);
        for (int j = 0; j < r; j++) memcpy(p->H + (size_t)n * j, p->Hr + (size_t)r * j, sizeof(double) * r);
        for (int i = 0; i < r; i++) p->H[(size_t)n * r + i] = p->H[(size_t)n * i + r] = s->obs_hqs[i];
        p->H[(size_t)n * r + r] = s->obs_hss + p->w;
    }
    return E;
}

static int solve(void *ctx, const double *g, double *d, rk_error *err)
{
    obstacle_problem *p = ctx;
    return rk_rom_dense_solve(p->H, p->n, g, d, "the reduced model and its moving obstacles", err);
}

/* The body and the obstacles moving together, and s within [0, 1]. */
static double max_step(void *ctx, const double *y, const double *d)
{
    obstacle_problem *p = ctx;
    rk_rom *s = p->s;
    const rk_rom_model *m = s->model;
    int r = p->r;
    double alpha = 1, sk = y[r], ds = d[r];
    if (ds > 0) alpha = fmin(alpha, (1 - sk) / ds);
    if (ds < 0) alpha = fmin(alpha, sk / -ds);
    place(p, sk);
    rk_rom_contact_move(s, y, d);
    for (int i = 0; i < 3 * m->contact.onv; i++) s->odx[i] = ds * p->way[i];
    double c = rk_contact_max_step(&s->model->contact, s->x, s->dx, s->odx, &p->failure);
    alpha = fmin(alpha, c >= 0 ? c : 0);
    if (alpha > 0) alpha = fmin(alpha, rk_rom_colliders_max_step(s));
    return alpha;
}

/* The larger of the body's RMS step and the obstacles' (metres along their way). */
static double step_norm(void *ctx, const double *d)
{
    obstacle_problem *p = ctx;
    return fmax(rk_rom_step_rms(p->s, d), fabs(d[p->r]) * p->L);
}

int rk_rom_obstacles_solve(rk_rom *s, const rk_rom_terms *T, double t, int *converged, int *behind, rk_error *err)
{
    rk_rom_model *m = s->model;
    rk_contact *c = &m->contact;
    int r = m->r, onv = c->onv;
    obstacle_problem p = {.s = s, .T = T, .r = r, .n = r + 1};
    *behind = 0;
    p.from = rk_calloc(3 * (size_t)onv + 1, sizeof(double), err);
    p.way = rk_calloc(3 * (size_t)onv + 1, sizeof(double), err);
    double *y = rk_calloc((size_t)p.n, sizeof(double), err), *work = rk_calloc(RK_NEWTON_WORK(p.n), sizeof(double), err);
    p.H = rk_calloc((size_t)p.n * p.n, sizeof(double), err);
    p.Hr = rk_calloc((size_t)r * r, sizeof(double), err);
    s->obs_hqs = rk_calloc((size_t)r, sizeof(double), err);
    int rc = -1;
    if (!p.from || !p.way || !y || !work || !p.H || !p.Hr || !s->obs_hqs) goto done;
    memcpy(p.from, c->ox, sizeof(double) * 3 * (size_t)onv);
    rk_contact_obstacles_at(c, t, p.way);
    double L2 = 0;
    for (int o = 0; o < onv; o++) {
        double d2 = 0;
        for (int a = 0; a < 3; a++) {
            p.way[3 * o + a] -= p.from[3 * o + a];
            d2 += p.way[3 * o + a] * p.way[3 * o + a];
        }
        L2 = fmax(L2, d2);
    }
    if (!(L2 > 0)) { /* nothing moves this step */
        rc = rk_rom_newton(s, T, m->newton_tol, converged, err);
        goto done;
    }
    double clear = rk_rom_contact_max_step(s, s->q, NULL, t, err);
    if (clear < 0) goto done;
    if (clear >= 1) { /* the whole way is clear of the body as it is: there at once, the body after */
        rk_contact_set_time(c, t);
        rc = rk_rom_newton(s, T, m->newton_tol, converged, err);
        goto done;
    }
    p.L = sqrt(L2);
    p.w = RK_COLLIDER_PULL * m->mass * L2 / (m->h * m->h);
    memcpy(y, s->q, sizeof(double) * r); /* s = 0: the obstacles where they are */
    rk_newton_problem prob = {.n = p.n, .ctx = &p, .what = "reduced incremental potential with moving obstacles",
                              .energy = energy, .solve = solve, .max_step = max_step, .step_norm = step_norm};
    /* rounds of the method of multipliers on the pull until they arrive within the tolerance, or
     * a round does not halve the shortfall (pinned: the body cannot give way) */
    double short_by = INFINITY; /* the first round is no test: it may fall short by any amount */
    for (int round = 0; round < RK_OBSTACLE_ROUNDS; round++) {
        rk_newton_stats stats = {0};
        rc = rk_newton_solve(&prob, y, m->newton_tol, m->newton_max_iter, work, converged, &stats, err);
        s->stats.newton_iterations += stats.iterations;
        s->stats.line_search_halvings += stats.halvings;
        if (p.failure.msg[0]) {
            *err = p.failure;
            rc = -1;
        }
        if (rc || (1 - y[r]) * p.L <= m->newton_tol || 1 - y[r] > 0.5 * short_by) break;
        short_by = 1 - y[r];
        p.lambda -= p.w * short_by;
    }
    if (rc == 0) { /* the body and the obstacles where the solve left them; at t when within the
                    * solve's tolerance of it and CCD lets the last bit go */
        memcpy(s->q, y, sizeof(double) * r);
        place(&p, y[r]);
        *behind = 1;
        if ((1 - y[r]) * p.L <= m->newton_tol) {
            double last = rk_rom_contact_max_step(s, s->q, NULL, t, err);
            if (last < 0) rc = -1;
            else if (last >= 1) rk_contact_set_time(c, t), *behind = 0;
        }
    } else {
        memcpy(c->ox, p.from, sizeof(double) * 3 * (size_t)onv);
    }
done:
    free(p.from), free(p.way), free(y), free(work), free(p.H), free(p.Hr), free(s->obs_hqs);
    s->obs_hqs = NULL;
    return rc;
}
