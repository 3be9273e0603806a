/* An application's colliders moving within a step (rom.h): each collider the app moved gets its
 * progress s along the path from where it was to where the app put it (physics.h,
 * rk_collider_pose_at) as one more unknown beside q, pulled to 1 by w/2 (1 - s)^2, and the step
 * solves for both. Moving a collider is then like IPC's moving obstacles (Sec. 4.6): the barrier
 * pushes the body ahead of it within the same Newton solve and CCD filters the joint motion, so
 * a collider moved fast still arrives in one step; where the body cannot give way (pinned), the
 * collider stops short with a bounded force and goes on next step.
 *
 * w = RK_COLLIDER_PULL m L^2 / h^2: a thousand times the inertia of the whole mass m over the
 * path's length L (how far its points travel at the body), so the collider falls short by about
 * a h^2 / 1000 (m) when pushing the body at acceleration a. Derivatives in s are those in the
 * vertices' positions times -dc/ds, the velocity of the collider's surface point on the path
 * (the barrier's closest point, friction's lagged one): a vertex-collider term depends on the
 * vertex's position relative to the collider's surface only. */
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
    int r, n, np;
    int slot[RK_MAX_COLLIDERS];
    double from[RK_MAX_COLLIDERS][RK_COLLIDER_REALS];
    double w[RK_MAX_COLLIDERS], L[RK_MAX_COLLIDERS];
    double *H;                 /* n x n Newton matrix (column-major) */
    double *Hr;                /* r x r */
} move_problem;

static double energy(void *ctx, const double *y, double *g, int hessian, double *magnitude)
{
    move_problem *p = ctx;
    rk_rom *s = p->s;
    int r = p->r, n = p->n;
    for (int k = 0; k < p->np; k++) {
        rk_rom_collider *c = &s->colliders[p->slot[k]];
        rk_collider_pose_at(p->from[k], c->target, y[r + k], c->now);
    }
    double E = rk_rom_potential(s, p->T, y, g, hessian ? p->Hr : NULL, magnitude, &p->failure);
    if (!isfinite(E)) return E;
    if (hessian) {
        memset(p->H, 0, sizeof(double) * (size_t)n * n);
        for (int j = 0; j < r; j++) memcpy(p->H + (size_t)n * j, p->Hr + (size_t)r * j, sizeof(double) * r);
    }
    for (int k = 0; k < p->np; k++) {
        double sk = y[r + k], gs = 0, hss = 0, *hqs = hessian ? p->H + (size_t)n * (r + k) : NULL;
        rk_rom_colliders_path_terms(s, y, p->slot[k], p->from[k], sk, &gs, hessian ? &hss : NULL, hqs);
        E += 0.5 * p->w[k] * (1 - sk) * (1 - sk);
        if (magnitude) *magnitude += 0.5 * p->w[k] * (1 - sk) * (1 - sk);
        if (g) g[r + k] = gs - p->w[k] * (1 - sk);
        if (hessian) {
            p->H[(size_t)n * (r + k) + r + k] = hss + p->w[k];
            for (int i = 0; i < r; i++) p->H[(size_t)n * i + r + k] = hqs[i]; /* both triangles */
        }
    }
    return E;
}

static int solve(void *ctx, const double *g, double *d, rk_error *err)
{
    move_problem *p = ctx;
    return rk_rom_dense_solve(p->H, p->n, g, d, "the reduced model and its moving colliders", err);
}

/* The body and the colliders moving together: the scene's contact as usual, every collider's
 * joint step, and no collider past either end of its path. */
static double max_step(void *ctx, const double *y, const double *d)
{
    move_problem *p = ctx;
    rk_rom *s = p->s;
    const rk_rom_model *m = s->model;
    double alpha = 1;
    for (int k = 0; k < p->np; k++) {
        double sk = y[p->r + k], dk = d[p->r + k];
        if (dk > 0) alpha = fmin(alpha, (1 - sk) / dk);
        if (dk < 0) alpha = fmin(alpha, sk / -dk);
    }
    rk_rom_contact_move(s, y, d);
    if (rk_rom_contact_on(m)) {
        double c = rk_contact_max_step(&s->model->contact, s->x, s->dx, NULL, &p->failure);
        alpha = fmin(alpha, c >= 0 ? c : 0);
    }
    for (int k = 0; k < RK_MAX_COLLIDERS; k++) {
        rk_rom_collider *c = &s->colliders[k];
        if (!c->active || c->exact) continue; /* an obstacle's CCD is the contact stage's */
        int moving = -1;
        for (int j = 0; j < p->np; j++)
            if (p->slot[j] == k) moving = j;
        for (int i = 0; i < m->ncv && alpha > 0; i++) {
            const double *x = &s->x[3 * m->cv[i]], *dx = &s->dx[3 * m->cv[i]];
            alpha = fmin(alpha, moving < 0 ? rk_collider_step(c->kind, c->now, x, dx)
                                           : rk_collider_joint_step(c->kind, p->from[moving], c->target,
                                                                    y[p->r + moving], d[p->r + moving], x, dx));
        }
    }
    return alpha;
}

/* The larger of the body's RMS step and the colliders' (metres along their paths). */
static double step_norm(void *ctx, const double *d)
{
    move_problem *p = ctx;
    double size = rk_rom_step_rms(p->s, d);
    for (int k = 0; k < p->np; k++) size = fmax(size, fabs(d[p->r + k]) * p->L[k]);
    return size;
}

int rk_rom_colliders_solve(rk_rom *s, const rk_rom_terms *T, int *converged, rk_error *err)
{
    rk_rom_model *m = s->model;
    int r = m->r;
    move_problem p = {.s = s, .T = T, .r = r};
    rk_rom_contact_positions(s, s->q);
    for (int k = 0; k < RK_MAX_COLLIDERS; k++) {
        rk_rom_collider *c = &s->colliders[k];
        if (!c->active || c->exact || !memcmp(c->now, c->target, sizeof c->now)) continue;
        p.slot[p.np] = k;
        memcpy(p.from[p.np], c->now, sizeof c->now);
        /* the path's length at the body: the farthest a collision vertex's spot travels (an upper bound) */
        double L = 0;
        for (int i = 0; i < m->ncv; i++) {
            double v[3], local[3], *x = &s->x[3 * m->cv[i]];
            for (int a = 0; a < 3; a++) /* the vertex in the collider's frame at the start */
                local[a] = c->now[3 + a] * (x[0] - c->now[0]) + c->now[6 + a] * (x[1] - c->now[1]) +
                           c->now[9 + a] * (x[2] - c->now[2]);
            rk_collider_path_velocity(c->now, c->target, 0, local, v);
            L = fmax(L, sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
        }
        p.L[p.np] = fmax(L, 1e-12);
        p.w[p.np] = RK_COLLIDER_PULL * m->mass * p.L[p.np] * p.L[p.np] / (m->h * m->h);
        p.np++;
    }
    if (p.np == 0) return 0;
    p.n = r + p.np;
    size_t n = (size_t)p.n;
    double *y = rk_calloc(n, sizeof(double), err), *work = rk_calloc(RK_NEWTON_WORK(n), sizeof(double), err);
    p.H = rk_calloc(n * n, sizeof(double), err);
    p.Hr = rk_calloc((size_t)r * r, sizeof(double), err);
    int rc = -1;
    if (y && work && p.H && p.Hr) {
        memcpy(y, s->q, sizeof(double) * r); /* s = 0: the colliders where they are */
        rk_newton_problem prob = {.n = p.n, .ctx = &p, .what = "reduced incremental potential with moving colliders",
                                  .energy = energy, .solve = solve, .max_step = max_step, .step_norm = step_norm};
        rk_newton_stats stats = {0};
        rc = rk_newton_solve(&prob, y, m->newton_tol, m->newton_max_iter, work, converged, &stats, err);
        s->stats.newton_iterations += stats.iterations;
        s->stats.line_search_halvings += stats.halvings;
        if (p.failure.msg[0]) {
            *err = p.failure;
            rc = -1;
        }
    }
    if (rc == 0) { /* the body and the colliders where the solve left them */
        memcpy(s->q, y, sizeof(double) * r);
        rk_rom_contact_positions(s, s->q);
        for (int k = 0; k < p.np; k++) {
            rk_rom_collider *c = &s->colliders[p.slot[k]];
            rk_collider_pose_at(p.from[k], c->target, y[r + k], c->now);
            /* within the solve's tolerance of the target: there, when CCD lets the last bit go */
            if ((1 - y[r + k]) * p.L[k] > m->newton_tol) continue;
            double ok = 1;
            for (int i = 0; i < m->ncv && ok >= 1; i++)
                ok = rk_collider_motion_step(c->kind, c->now, c->target, &s->x[3 * m->cv[i]]);
            if (ok >= 1) memcpy(c->now, c->target, sizeof c->now);
        }
    } else {
        for (int k = 0; k < p.np; k++) memcpy(s->colliders[p.slot[k]].now, p.from[k], sizeof p.from[k]);
    }
    free(y), free(work), free(p.H), free(p.Hr);
    return rc;
}
