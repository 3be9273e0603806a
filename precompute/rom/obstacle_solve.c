/* The scene's moving obstacles solved for with the body (rom_impl.h): over a step their vertices
 * go on straight lines from where they are to where their motions put them at the step's end,
 * x_o(s_k) = x_o^from + s_k D_o, and each moving obstacle's progress s_k is one more unknown
 * beside q (the Newton matrix dense, r + k square), pulled to 1 by w_k/2 (1 - s_k)^2, as the app's
 * moved colliders are (collider_solve.c; IPC's moving obstacles as unknowns, Li et al. 2020,
 * Sec. 4.6). The barrier pushes the body ahead of them within one Newton solve and CCD filters the
 * joint motion, so an obstacle moving fast arrives in one step; where the body cannot give way
 * (pinned), that obstacle stops short with a bounded force and goes on next step, and the others
 * arrive. Safe moves (rk_contact_advance: CCD's fraction with the body still, then a solve) need one
 * move per closing of the gap the barrier holds the body at: ~700 moves a step for a box thrown
 * into a terrain rising at 1 m/s, and in the float runtime over 1000.
 *
 * The way, the pull, its rounds and the contact terms' derivatives in s are the contact stage's
 * (progress.c, rk_obstacle_way; the adaptive simulator shares them): the contact stage gives the
 * obstacle points' gradient (og) and each pair's block with them as degrees of freedom
 * (obstacle_dofs, its PSD projection over all four points), and contact.c's sink turns those into
 * d/ds, d2/ds2 and d2/dq ds_k through D_k. w_k = RK_COLLIDER_PULL m L_k^2 / h^2, L_k obstacle k's
 * longest D_o: the obstacles fall short by about a h^2 / 1000 (m) when pushing the body at acceleration a.
 * The runtime does the same (runtime/contact_progress.c). */
#include "rom/rom_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    rk_rom *s;
    const rk_rom_terms *T;
    rk_error failure;
    int r, k, n;               /* q's size, the progress unknowns (one per moving obstacle), r + k */
    rk_obstacle_way way;
    double *H;                 /* n x n Newton matrix (column-major) */
    double *Hr;                /* r x r */
} obstacle_problem;

static double energy(void *ctx, const double *y, double *g, int hessian, double *magnitude)
{
    obstacle_problem *p = ctx;
    rk_rom *s = p->s;
    rk_contact *c = &s->model->contact;
    int r = p->r, n = p->n, k = p->k;
    const double *sk = y + r;
    rk_obstacle_way_place(&p->way, c, sk);
    s->obs_way = &p->way;
    memset(s->obs_gs, 0, sizeof(double) * (size_t)k);
    memset(s->obs_hss, 0, sizeof(double) * (size_t)k * k);
    memset(s->obs_hqs, 0, sizeof(double) * (size_t)r * k);
    c->obstacle_dofs = 1;
    double E = rk_rom_potential(s, p->T, y, g, hessian ? p->Hr : NULL, magnitude, &p->failure);
    c->obstacle_dofs = 0;
    s->obs_way = NULL;
    if (!isfinite(E)) return E;
    double e = rk_obstacle_way_pull(&p->way, sk, s->obs_gs, s->obs_hss, k);
    E += e;
    if (magnitude) *magnitude += fabs(e);
    if (g) memcpy(g + r, s->obs_gs, sizeof(double) * (size_t)k);
    if (hessian) {
        memset(p->H, 0, sizeof(double) * (size_t)n * n);
        for (int j = 0; j < r; j++) memcpy(p->H + (size_t)n * j, p->Hr + (size_t)r * j, sizeof(double) * r);
        for (int u = 0; u < k; u++) {
            const double *hqs = s->obs_hqs + (size_t)r * u;
            for (int i = 0; i < r; i++) p->H[(size_t)n * (r + u) + i] = p->H[(size_t)n * i + r + u] = hqs[i];
            for (int v = 0; v < k; v++) p->H[(size_t)n * (r + v) + r + u] = s->obs_hss[u + (size_t)k * v];
        }
    }
    return E;
}

static int solve(void *ctx, const double *g, double *d, rk_error *err)
{
    obstacle_problem *p = ctx;
    return rk_rom_dense_solve(p->H, p->n, g, d, "the reduced model and its moving obstacles", err);
}

/* The body and the obstacles moving together, and each s_k within [0, 1]. */
static double max_step(void *ctx, const double *y, const double *d)
{
    obstacle_problem *p = ctx;
    rk_rom *s = p->s;
    int r = p->r;
    rk_rom_contact_move(s, y, d);
    double alpha = rk_obstacle_way_max_step(&p->way, &s->model->contact, s->x, s->dx, y + r, d + r, &p->failure);
    if (alpha > 0) alpha = fmin(alpha, rk_rom_colliders_max_step(s));
    return alpha;
}

/* The larger of the body's RMS step and the obstacles' (metres along their way). */
static double step_norm(void *ctx, const double *d)
{
    obstacle_problem *p = ctx;
    return fmax(rk_rom_step_rms(p->s, d), rk_obstacle_way_step_norm(&p->way, d + p->r));
}

int rk_rom_obstacles_solve(rk_rom *s, const rk_rom_terms *T, double t, int *converged, int *behind, rk_error *err)
{
    rk_rom_model *m = s->model;
    rk_contact *c = &m->contact;
    int r = m->r;
    obstacle_problem p = {.s = s, .T = T, .r = r};
    *behind = 0;
    int moving = rk_obstacle_way_init(&p.way, c, t, m->mass, m->h, err);
    if (moving < 0) return -1;
    p.k = moving, p.n = r + moving;
    double *y = rk_calloc((size_t)p.n, sizeof(double), err), *work = rk_calloc(RK_NEWTON_WORK(p.n), sizeof(double), err);
    p.H = rk_calloc((size_t)p.n * p.n, sizeof(double), err);
    p.Hr = rk_calloc((size_t)r * r, sizeof(double), err);
    s->obs_hqs = rk_calloc((size_t)r * p.k + 1, sizeof(double), err);
    s->obs_gs = rk_calloc((size_t)p.k + 1, sizeof(double), err);
    s->obs_hss = rk_calloc((size_t)p.k * p.k + 1, sizeof(double), err);
    int rc = -1;
    if (!y || !work || !p.H || !p.Hr || !s->obs_hqs || !s->obs_gs || !s->obs_hss) goto done;
    if (!moving) { /* nothing moves this step */
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
    memcpy(y, s->q, sizeof(double) * r); /* s = 0: the obstacles where they are */
    rk_newton_problem prob = {.n = p.n, .ctx = &p, .what = "reduced incremental potential with moving obstacles",
                              .energy = energy, .solve = solve, .max_step = max_step, .step_norm = step_norm};
    /* rounds of the method of multipliers on the pulls until every obstacle arrives within the
     * tolerance, or its round does not halve its shortfall (pinned: the body cannot give way) */
    for (int round = 0; round < RK_OBSTACLE_ROUNDS; round++) {
        rk_newton_stats stats = {0};
        rc = rk_newton_solve(&prob, y, m->newton_tol, m->newton_max_iter, work, converged, &stats, err);
        s->stats.newton_iterations += stats.iterations;
        s->stats.line_search_halvings += stats.halvings;
        if (p.failure.msg[0]) {
            *err = p.failure;
            rc = -1;
        }
        if (rc || !rk_obstacle_way_round(&p.way, y + r, m->newton_tol)) break;
    }
    if (rc == 0) { /* the body and the obstacles where the solve left them; each at t when within
                    * the solve's tolerance of it and CCD lets its last bit go */
        memcpy(s->q, y, sizeof(double) * r);
        rk_rom_contact_move(s, s->q, NULL);
        rc = rk_obstacle_way_arrive(&p.way, c, s->x, s->dx, y + r, t, m->newton_tol, behind, err);
    } else {
        memset(y + r, 0, sizeof(double) * (size_t)p.k);
        rk_obstacle_way_place(&p.way, c, y + r);
    }
done:
    rk_obstacle_way_free(&p.way);
    free(y), free(work), free(p.H), free(p.Hr), free(s->obs_hqs), free(s->obs_gs), free(s->obs_hss);
    s->obs_hqs = s->obs_gs = s->obs_hss = NULL;
    return rc;
}
