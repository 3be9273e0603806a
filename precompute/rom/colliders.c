/* An application's colliders in the reduced simulator (rom.h): planes, spheres, capsules and
 * boxes (physics.h) against the collision vertices x_v = X_v + U_v q, with the scene planes'
 * barrier kappa b(d, dhat) on each vertex's signed distance and, with contact.friction, the
 * smoothed Coulomb friction lagged like the contact stage's (IPC Sec. 5). On a model with a
 * collision surface the spheres, capsules and boxes are obstacles of the contact model instead
 * (collider_obstacles.c; `exact`) and the functions here pass them by. The runtime steps the
 * same model in C99 (runtime/colliders.c, shape_collider.c); the parity tests hold the two
 * together. */
#include "rom/rom_impl.h"

#include <cblas.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "physics/physics.h"

static const char *const kind_names[] = {"plane", "sphere", "capsule", "box"};

static int same_shape(const rk_rom_collider *c, const rk_collider *n)
{
    if (c->kind != n->kind) return 0;
    for (int i = 12; i < RK_COLLIDER_REALS; i++)
        if (c->now[i] != n->shape[i]) return 0;
    return 1;
}

int rk_rom_set_collider(rk_rom *s, int slot, const rk_collider *c, rk_error *err)
{
    if (slot < 0 || slot >= RK_MAX_COLLIDERS)
        return rk_fail(err, "collider slot %d: slots are 0 to %d", slot, RK_MAX_COLLIDERS - 1);
    if (s->model->lift_handle)
        return rk_fail(err, "collider %d: a model with a lifted moving group (clamp \"lifted\") takes no colliders "
                       "yet (its prescribed coordinates cannot give way to them)", slot);
    switch (rk_collider_check(c->kind, c->shape)) {
    case 0: break;
    case RK_COLLIDER_NOT_FINITE: return rk_fail(err, "collider %d: a number is not finite", slot);
    case RK_COLLIDER_UNKNOWN_KIND: return rk_fail(err, "collider %d: unknown kind %d", slot, (int)c->kind);
    case RK_COLLIDER_BAD_SIZE:
        return rk_fail(err, "collider %d (%s): its radius, half length or half extents must be positive", slot,
                       kind_names[c->kind]);
    default: return rk_fail(err, "collider %d: its rotation is not orthonormal", slot);
    }
    rk_rom_collider *k = &s->colliders[slot];
    if (k->active && same_shape(k, c)) { /* a move: made over the next steps */
        memcpy(k->target, c->shape, sizeof k->target);
        if (k->exact) rk_contact_pose_obstacle(&s->model->contact, k->obstacle, c->shape);
        return 0;
    }
    const rk_rom_model *m = s->model;
    rk_rom_contact_positions(s, s->q);
    for (int i = 0; i < m->ncv; i++) {
        double d = rk_collider_distance(c->kind, c->shape, &s->x[3 * m->cv[i]], NULL, NULL);
        if (!(d > 0))
            return rk_fail(err, "collider %d (%s) would overlap the body (vertex %d is %.3g m inside): place it "
                           "clear of the body, then move it", slot, kind_names[c->kind], m->cv[i], -d);
    }
    /* on a collision surface a sphere, capsule or box is an obstacle (collider_obstacles.c); a
     * plane stays on the vertices (exact for a plane), as in the runtime */
    int exact = m->surface && c->kind != RK_COLLIDER_PLANE;
    if ((exact || (k->active && k->exact)) && rk_rom_collider_obstacles(s, slot, exact ? c : NULL, err)) return -1;
    if (!exact) rk_rom_collider_take(s, slot, c, 0);
    return 0;
}

void rk_rom_collider_take(rk_rom *s, int slot, const rk_collider *c, int exact)
{
    rk_rom_collider *k = &s->colliders[slot];
    s->ncolliders += !k->active;
    k->active = 1;
    k->exact = exact;
    k->kind = c->kind;
    memcpy(k->now, c->shape, sizeof k->now);
    memcpy(k->target, c->shape, sizeof k->now);
    memcpy(k->start, c->shape, sizeof k->now);
    memcpy(k->lag, c->shape, sizeof k->now);
}

int rk_rom_remove_collider(rk_rom *s, int slot, rk_error *err)
{
    if (slot < 0 || slot >= RK_MAX_COLLIDERS)
        return rk_fail(err, "collider slot %d: slots are 0 to %d", slot, RK_MAX_COLLIDERS - 1);
    if (s->colliders[slot].active && s->colliders[slot].exact && rk_rom_collider_obstacles(s, slot, NULL, err)) return -1;
    s->ncolliders -= s->colliders[slot].active;
    s->colliders[slot].active = 0;
    return 0;
}

/* R v + p: a point of the collider's own frame in the world. */
static void to_world(const double *shape, const double v[3], double x[3])
{
    for (int i = 0; i < 3; i++) x[i] = shape[i] + shape[3 + 3 * i] * v[0] + shape[4 + 3 * i] * v[1] + shape[5 + 3 * i] * v[2];
}

/* One vertex against one collider: the barrier on its distance, and friction lagged at xl
 * (collider at c->lag) on the slip since the step began (xs), the collider's surface carried
 * from c->start to c->now; each as a gradient and a 3 x 3 block in the vertex's position, with
 * the collider's own point it acts through (for the derivatives along the collider's path). */
typedef struct {
    double E;
    int barrier, friction;         /* which act */
    double gb[3], Bb[9], cb[3];    /* barrier: gradient, block, closest point (collider frame) */
    double gf[3], Bf[9], cf[3];    /* friction: the same at the lagged closest point */
} vertex_terms;

static void vertex_energy(const rk_rom_model *m, const rk_rom_collider *c, int friction, const double *x,
                          const double *xs, const double *xl, vertex_terms *t)
{
    double dhat = m->contact_options.dhat, kappa = m->contact_options.kappa, n[3], f1, f2;
    double d = rk_collider_distance(c->kind, c->now, x, n, t->cb);
    memset(t, 0, offsetof(vertex_terms, cb));
    memset(t->gf, 0, sizeof t->gf + sizeof t->Bf);
    t->friction = 0;
    if (!(d > 0)) {
        t->E = INFINITY;
        return;
    }
    if (d < dhat) {
        t->barrier = 1;
        t->E += kappa * rk_barrier_distance(d, dhat, &f1, &f2);
        for (int a = 0; a < 3; a++) {
            t->gb[a] = kappa * f1 * n[a];
            for (int b = 0; b < 3; b++) t->Bb[3 * a + b] = kappa * f2 * n[a] * n[b]; /* curvature left out: physics.h */
        }
    }
    if (!friction) return;
    double nl[3], T[6];
    double dl = rk_collider_distance(c->kind, c->lag, xl, nl, t->cf);
    if (!(dl > 0 && dl < dhat)) return;
    rk_barrier_distance(dl, dhat, &f1, &f2);
    double scale = m->contact_options.friction * kappa * fabs(f1), was[3], is[3], rel[3], u[2], f1y, M[4];
    rk_tangent_basis(nl, T);
    to_world(c->start, t->cf, was);
    to_world(c->now, t->cf, is);
    for (int a = 0; a < 3; a++) rel[a] = x[a] - xs[a] - (is[a] - was[a]);
    u[0] = T[0] * rel[0] + T[1] * rel[1] + T[2] * rel[2];
    u[1] = T[3] * rel[0] + T[4] * rel[1] + T[5] * rel[2];
    t->friction = 1;
    t->E += scale * rk_friction_smoothed(u, m->contact_options.eps_v * m->h, &f1y, M);
    for (int a = 0; a < 3; a++) {
        t->gf[a] = scale * f1y * (T[a] * u[0] + T[3 + a] * u[1]);
        for (int b = 0; b < 3; b++)
            t->Bf[3 * a + b] = scale * (T[a] * (M[0] * T[b] + M[1] * T[3 + b]) + T[3 + a] * (M[2] * T[b] + M[3] * T[3 + b]));
    }
}

double rk_rom_colliders_energy(rk_rom *s, const double *q, int friction, double *g, double *H)
{
    const rk_rom_model *m = s->model;
    double E = 0, B[9];
    vertex_terms t;
    rk_rom_contact_positions(s, q);
    if (g) rk_rom_clear_vertex_gradient(s);
    rk_rom_reduce_ctx ctx = {.m = m, .H = H, .JB = s->jb};
    for (int k = 0; k < RK_MAX_COLLIDERS && isfinite(E); k++) {
        const rk_rom_collider *c = &s->colliders[k];
        if (!c->active || c->exact) continue; /* an obstacle's terms are the contact stage's */
        for (int i = 0; i < m->ncv && isfinite(E); i++) {
            int v = m->cv[i];
            vertex_energy(m, c, friction, &s->x[3 * v], &s->xs[3 * v], &s->xl[3 * v], &t);
            E += t.E;
            if (!(t.barrier || t.friction)) continue;
            for (int a = 0; a < 3 && g; a++) s->gx[3 * v + a] += t.gb[a] + t.gf[a];
            for (int a = 0; a < 9; a++) B[a] = t.Bb[a] + t.Bf[a];
            if (H) rk_rom_reduce_block(&ctx, &v, 1, B);
        }
    }
    if (g && isfinite(E)) rk_rom_pull_vertex_gradient(s, g);
    return isfinite(E) ? E : INFINITY;
}

/* g_s += g . w, H_ss += w^T B w, H_qs += J^T B w for a term acting through the collider's point
 * `local` (w = -its velocity on the path: moving the collider is moving the vertex back). */
static void along_path(const rk_rom_model *m, int i, const double *from, const double *to, double sk,
                       const double *local, const double *gx, const double *B, double *gs, double *hss, double *hqs)
{
    double w[3], Bw[3];
    rk_collider_path_velocity(from, to, sk, local, w);
    for (int a = 0; a < 3; a++) w[a] = -w[a];
    for (int a = 0; a < 3; a++) Bw[a] = B[3 * a] * w[0] + B[3 * a + 1] * w[1] + B[3 * a + 2] * w[2];
    *gs += gx[0] * w[0] + gx[1] * w[1] + gx[2] * w[2];
    if (hss) *hss += w[0] * Bw[0] + w[1] * Bw[1] + w[2] * Bw[2];
    for (int a = 0; a < 3 && hqs; a++)
        cblas_daxpy(m->r, Bw[a], m->cv_rows + (size_t)(3 * i + a) * m->r, 1, hqs, 1);
}

void rk_rom_colliders_path_terms(rk_rom *s, const double *q, int slot, const double *from, double sk, double *gs,
                                 double *hss, double *hqs)
{
    const rk_rom_model *m = s->model;
    const rk_rom_collider *c = &s->colliders[slot];
    int friction = m->contact_options.friction > 0;
    vertex_terms t;
    rk_rom_contact_positions(s, q);
    for (int i = 0; i < m->ncv; i++) {
        int v = m->cv[i];
        vertex_energy(m, c, friction, &s->x[3 * v], &s->xs[3 * v], &s->xl[3 * v], &t);
        if (t.barrier) along_path(m, i, from, c->target, sk, t.cb, t.gb, t.Bb, gs, hss, hqs);
        if (t.friction) along_path(m, i, from, c->target, sk, t.cf, t.gf, t.Bf, gs, hss, hqs);
    }
}

double rk_rom_colliders_max_step(rk_rom *s)
{
    const rk_rom_model *m = s->model;
    double alpha = 1;
    for (int k = 0; k < RK_MAX_COLLIDERS; k++) {
        const rk_rom_collider *c = &s->colliders[k];
        for (int i = 0; c->active && !c->exact && i < m->ncv; i++) {
            int v = m->cv[i];
            alpha = fmin(alpha, rk_collider_step(c->kind, c->now, &s->x[3 * v], &s->dx[3 * v]));
        }
    }
    return alpha;
}

int rk_rom_colliders_pending(const rk_rom *s)
{
    for (int k = 0; k < RK_MAX_COLLIDERS; k++)
        if (s->colliders[k].active && !s->colliders[k].exact &&
            memcmp(s->colliders[k].now, s->colliders[k].target, sizeof s->colliders[k].now))
            return 1;
    return 0;
}

void rk_rom_colliders_friction_start(rk_rom *s)
{
    const rk_rom_model *m = s->model;
    for (int i = 0; i < m->ncv; i++) memcpy(&s->xs[3 * m->cv[i]], &s->x[3 * m->cv[i]], 3 * sizeof(double));
    for (int k = 0; k < RK_MAX_COLLIDERS; k++) memcpy(s->colliders[k].start, s->colliders[k].now, sizeof s->colliders[k].now);
}

void rk_rom_colliders_friction_lag(rk_rom *s)
{
    const rk_rom_model *m = s->model;
    for (int i = 0; i < m->ncv; i++) memcpy(&s->xl[3 * m->cv[i]], &s->x[3 * m->cv[i]], 3 * sizeof(double));
    for (int k = 0; k < RK_MAX_COLLIDERS; k++) memcpy(s->colliders[k].lag, s->colliders[k].now, sizeof s->colliders[k].now);
}
