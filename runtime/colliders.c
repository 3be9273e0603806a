/* An application's colliders (romrt.h): the reduced simulator's (precompute/rom/colliders.c and
 * collider_solve.c) in C99 and fixed memory, on the asset's collision vertices (CVTX). The
 * geometry, the step filter and friction's smoothing are physics/collider_impl.h's, shared.
 * On an asset with a collision surface only the planes take this path (a plane meets a triangle
 * mesh first at a vertex: exact there); spheres, capsules and boxes go to the obstacles'
 * (shape_collider.c). */
#include <math.h>
#include <string.h>

#include "runtime/romrt_impl.h"

int romrt_takes_colliders(const romrt_model *m)
{
    return m && m->kind == ROMRT_KIND_REDUCED && m->ncv > 0 && !m->lift;
}

static void to_shape(const romrt_collider *c, romrt_real *shape)
{
    int i;
    for (i = 0; i < 3; i++) shape[i] = c->position[i];
    for (i = 0; i < 9; i++) shape[3 + i] = c->rotation[i];
    shape[12] = c->radius;
    shape[13] = c->half_length;
    for (i = 0; i < 3; i++) shape[14 + i] = c->half_extents[i];
}

romrt_status romrt_set_collider(romrt_model *m, size_t slot, const romrt_collider *c, romrt_error *err)
{
    romrt_real shape[RT_COLLIDER_REALS], x[3];
    rt_collider *k;
    int i, same = 1;
    if (!m || !c) return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_set_collider: no model or collider (NULL)");
    if (slot >= ROMRT_MAX_COLLIDERS)
        return rt_fail_n(err, ROMRT_E_ARGUMENT, 0, "romrt_set_collider: slot ", (uint64_t)slot, " is out of range");
    if (m->lift) /* as the reduced simulator (precompute/rom/colliders.c) */
        return rt_fail(err, ROMRT_E_UNSUPPORTED, ROMBIN_LIFT, "a lifted moving group cannot give way to a collider "
                       "(bake with rom.clamp \"dirichlet\" to use colliders)");
    if (!romrt_takes_colliders(m))
        return rt_fail(err, ROMRT_E_UNSUPPORTED, ROMBIN_CVTX,
                       "the asset has no collision vertices (baked with \"colliders\": false or before rombin 1.1)");
    if (c->kind == ROMRT_COLLIDER_MESH)
        return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_set_collider: a mesh is placed by romrt_set_mesh_collider");
    to_shape(c, shape);
    switch (RT_PHYS(collider_check)((int)c->kind, shape)) {
    case 0: break;
    case RK_COLLIDER_NOT_FINITE: return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_set_collider: a number is not finite");
    case RK_COLLIDER_UNKNOWN_KIND: return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_set_collider: unknown kind");
    case RK_COLLIDER_BAD_SIZE:
        return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_set_collider: the radius, half length or half extents must be positive");
    default: return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_set_collider: the rotation is not orthonormal");
    }
    k = &m->colliders[slot];
    for (i = 12; i < RT_COLLIDER_REALS; i++) same &= k->now[i] == shape[i];
    if (k->active && k->kind == (int)c->kind && same) { /* a move: made by the next step */
        memcpy(k->target, shape, sizeof shape);
        if (k->mesh) m->hessian_age = -1; /* as an app mesh's move (romrt.h) */
        return ROMRT_OK;
    }
    if (m->alrom) rt_alrom_take_collision_vertices(m); /* their positions current */
    for (i = 0; i < m->ncv; i++) {
        rt_vertex_position(m, m->cv[i], m->q, x);
        if (!(RT_PHYS(collider_distance)((int)c->kind, shape, x, 0, 0) > 0))
            return rt_fail_n(err, ROMRT_E_ARGUMENT, 0, "romrt_set_collider: it would overlap the body at stored vertex ",
                             m->cv[i], ": place it clear, then move it");
    }
    if (m->shapes && c->kind != ROMRT_COLLIDER_PLANE) return rt_shape_place(m, (int)slot, (int)c->kind, shape, err);
    if (k->mesh) rt_mesh_leave(m, (int)slot); /* a mesh's slot taken over */
    m->ncolliders += !k->active;
    m->hessian_age = -1; /* a kept Newton matrix lacks the new collider's terms */
    k->active = 1;
    k->kind = (int)c->kind;
    memcpy(k->now, shape, sizeof shape);
    memcpy(k->target, shape, sizeof shape);
    memcpy(k->start, shape, sizeof shape);
    memcpy(k->lag, shape, sizeof shape);
    return ROMRT_OK;
}

romrt_status romrt_remove_collider(romrt_model *m, size_t slot, romrt_error *err)
{
    if (!m) return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_remove_collider: no model (NULL)");
    if (slot >= ROMRT_MAX_COLLIDERS)
        return rt_fail_n(err, ROMRT_E_ARGUMENT, 0, "romrt_remove_collider: slot ", (uint64_t)slot, " is out of range");
    if (m->colliders[slot].mesh) rt_mesh_leave(m, (int)slot);
    m->ncolliders -= m->colliders[slot].active;
    m->colliders[slot].active = 0;
    m->hessian_age = -1;
    return ROMRT_OK;
}

/* R v + p: a point of the collider's own frame in the world. */
static void to_world(const romrt_real *shape, const romrt_real v[3], romrt_real x[3])
{
    int i;
    for (i = 0; i < 3; i++) x[i] = shape[i] + shape[3 + 3 * i] * v[0] + shape[4 + 3 * i] * v[1] + shape[5 + 3 * i] * v[2];
}

/* One vertex against one collider, as precompute/rom/colliders.c's vertex_energy. */
typedef struct {
    romrt_real E;
    int barrier, friction;
    romrt_real gb[3], Bb[9], cb[3];
    romrt_real gf[3], Bf[9], cf[3];
} rt_vertex_terms;

static void vertex_terms(const romrt_model *m, const rt_collider *c, int friction, uint32_t v, const romrt_real *q,
                         rt_vertex_terms *t)
{
    romrt_real x[3], n[3], f1, f2, d;
    int a, b;
    rt_vertex_position(m, v, q, x);
    d = RT_PHYS(collider_distance)(c->kind, c->now, x, n, t->cb);
    t->E = 0;
    t->barrier = t->friction = 0;
    if (!(d > 0)) {
        t->E = (romrt_real)INFINITY;
        return;
    }
    if (d < m->dhat) {
        t->barrier = 1;
        t->E += m->kappa * RT_PHYS(barrier_distance)(d, m->dhat, &f1, &f2);
        for (a = 0; a < 3; a++) {
            t->gb[a] = m->kappa * f1 * n[a];
            for (b = 0; b < 3; b++) t->Bb[3 * a + b] = m->kappa * f2 * n[a] * n[b];
        }
    }
    if (friction) {
        romrt_real xl[3], nl[3], T[6], xs[3], was[3], is[3], rel[3], u[2], f1y, M[4], dl, scale;
        rt_vertex_position(m, v, m->q_lag, xl);
        dl = RT_PHYS(collider_distance)(c->kind, c->lag, xl, nl, t->cf);
        if (!(dl > 0 && dl < m->dhat)) return;
        RT_PHYS(barrier_distance)(dl, m->dhat, &f1, &f2);
        scale = m->mu * m->kappa * RT_FABS(f1);
        RT_PHYS(tangent_basis)(nl, T);
        rt_vertex_position(m, v, m->qt, xs);
        to_world(c->start, t->cf, was);
        to_world(c->now, t->cf, is);
        for (a = 0; a < 3; a++) rel[a] = x[a] - xs[a] - (is[a] - was[a]);
        u[0] = T[0] * rel[0] + T[1] * rel[1] + T[2] * rel[2];
        u[1] = T[3] * rel[0] + T[4] * rel[1] + T[5] * rel[2];
        t->friction = 1;
        t->E += scale * RT_PHYS(friction_smoothed)(u, m->eps_v * m->h, &f1y, M);
        for (a = 0; a < 3; a++) {
            t->gf[a] = scale * f1y * (T[a] * u[0] + T[3 + a] * u[1]);
            for (b = 0; b < 3; b++)
                t->Bf[3 * a + b] = scale * (T[a] * (M[0] * T[b] + M[1] * T[3 + b]) + T[3 + a] * (M[2] * T[b] + M[3] * T[3 + b]));
        }
    }
}

romrt_real rt_colliders_energy(romrt_model *m, const romrt_real *q, int friction, romrt_real *g, romrt_real *H, int ld)
{
    romrt_real E = 0, gx[3], B[9];
    rt_vertex_terms t;
    int k, i, a;
    for (k = 0; k < ROMRT_MAX_COLLIDERS && isfinite(E); k++) {
        const rt_collider *c = &m->colliders[k];
        if (!c->active || c->mesh) continue; /* a mesh's contact is the obstacles' (contact.c) */
        for (i = 0; i < m->ncv && isfinite(E); i++) {
            vertex_terms(m, c, friction, m->cv[i], q, &t);
            E += t.E;
            m->contact_terms += t.barrier || t.friction;
            if (!(t.barrier || t.friction) || (!g && !H)) continue;
            for (a = 0; a < 3; a++) gx[a] = (t.barrier ? t.gb[a] : 0) + (t.friction ? t.gf[a] : 0);
            for (a = 0; a < 9; a++) B[a] = (t.barrier ? t.Bb[a] : 0) + (t.friction ? t.Bf[a] : 0);
            rt_vertex_pull(m, m->cv[i], gx, B, g, H, ld);
        }
    }
    return isfinite(E) ? E : (romrt_real)INFINITY;
}

/* g_s += g . w, H_ss += w^T B w, H_qs += J^T B w for a term acting through the collider's point
 * `local`, w = minus its velocity on the path (moving the collider is moving the vertex back). */
static void along_path(const romrt_model *m, uint32_t v, const romrt_real *from, const romrt_real *to, romrt_real sk,
                       const romrt_real *local, const romrt_real *gx, const romrt_real *B, romrt_real *gs,
                       romrt_real *hss, romrt_real *hqs)
{
    romrt_real w[3], Bw[3];
    int a;
    RT_PHYS(collider_path_velocity)(from, to, sk, local, w);
    for (a = 0; a < 3; a++) w[a] = -w[a];
    for (a = 0; a < 3; a++) Bw[a] = B[3 * a] * w[0] + B[3 * a + 1] * w[1] + B[3 * a + 2] * w[2];
    *gs += gx[0] * w[0] + gx[1] * w[1] + gx[2] * w[2];
    if (hss) *hss += w[0] * Bw[0] + w[1] * Bw[1] + w[2] * Bw[2];
    if (hqs)
        for (a = 0; a < 3; a++) rt_row_axpy(m, v, a, Bw[a], hqs);
}

void rt_colliders_path_terms(romrt_model *m, const romrt_real *q, int k, romrt_real sk, romrt_real *gs, romrt_real *hss,
                             romrt_real *hqs)
{
    const rt_collider *c = &m->colliders[m->moving[k]];
    rt_vertex_terms t;
    int i;
    for (i = 0; i < m->ncv; i++) {
        vertex_terms(m, c, m->mu > 0, m->cv[i], q, &t);
        if (t.barrier) along_path(m, m->cv[i], m->move_from[k], c->target, sk, t.cb, t.gb, t.Bb, gs, hss, hqs);
        if (t.friction) along_path(m, m->cv[i], m->move_from[k], c->target, sk, t.cf, t.gf, t.Bf, gs, hss, hqs);
    }
}

romrt_real rt_colliders_max_step(romrt_model *m, const romrt_real *y, const romrt_real *d)
{
    romrt_real alpha = 1, x[3], dx[3];
    int k, i, j, a, r = m->r;
    for (j = 0; j < m->nmoving; j++) { /* no collider past either end of its path */
        romrt_real sk = y[r + j], dk = d[r + j];
        if (dk > 0 && (1 - sk) / dk < alpha) alpha = (1 - sk) / dk;
        if (dk < 0 && sk / -dk < alpha) alpha = sk / -dk;
    }
    for (i = 0; i < m->ncv && alpha > 0; i++) {
        rt_vertex_position(m, m->cv[i], y, x);
        for (a = 0; a < 3; a++) dx[a] = rt_row_dot(m, m->cv[i], a, d);
        for (k = 0; k < ROMRT_MAX_COLLIDERS; k++) {
            const rt_collider *c = &m->colliders[k];
            romrt_real s;
            int moving = -1;
            if (!c->active || c->mesh) continue;
            for (j = 0; j < m->nmoving; j++)
                if (m->moving[j] == k) moving = j;
            s = moving < 0 ? RT_PHYS(collider_step)(c->kind, c->now, x, dx)
                           : RT_PHYS(collider_joint_step)(c->kind, m->move_from[moving], c->target, y[r + moving],
                                                          d[r + moving], x, dx);
            if (s < alpha) alpha = s;
        }
    }
    return alpha;
}

void rt_colliders_lag(romrt_model *m, const romrt_real *q, int start)
{
    int k;
    memcpy(m->q_lag, q, sizeof(romrt_real) * (size_t)m->r);
    for (k = 0; k < ROMRT_MAX_COLLIDERS; k++) {
        if (start) memcpy(m->colliders[k].start, m->colliders[k].now, sizeof m->colliders[k].now);
        memcpy(m->colliders[k].lag, m->colliders[k].now, sizeof m->colliders[k].now);
    }
}

int rt_colliders_pending(const romrt_model *m)
{
    int k;
    for (k = 0; k < ROMRT_MAX_COLLIDERS; k++)
        if (m->colliders[k].active && !m->colliders[k].mesh &&
            memcmp(m->colliders[k].now, m->colliders[k].target, sizeof m->colliders[k].now))
            return 1;
    return 0;
}

void rt_colliders_begin_move(romrt_model *m, const romrt_real *q)
{
    int k, i;
    m->nmoving = 0;
    for (k = 0; k < ROMRT_MAX_COLLIDERS; k++) {
        rt_collider *c = &m->colliders[k];
        romrt_real L = 0;
        int j = m->nmoving;
        if (!c->active || c->mesh || !memcmp(c->now, c->target, sizeof c->now)) continue;
        m->moving[j] = k;
        memcpy(m->move_from[j], c->now, sizeof c->now);
        /* the path's length at the body: the farthest a collision vertex's spot travels */
        for (i = 0; i < m->ncv; i++) {
            romrt_real x[3], local[3], v[3], len;
            int a;
            rt_vertex_position(m, m->cv[i], q, x);
            for (a = 0; a < 3; a++)
                local[a] = c->now[3 + a] * (x[0] - c->now[0]) + c->now[6 + a] * (x[1] - c->now[1]) +
                           c->now[9 + a] * (x[2] - c->now[2]);
            RT_PHYS(collider_path_velocity)(c->now, c->target, 0, local, v);
            len = RT_SQRT(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
            if (len > L) L = len;
        }
        m->move_L[j] = L > RT_K(1e-12) ? L : RT_K(1e-12);
        m->move_w[j] = RT_K(RK_COLLIDER_PULL) * m->mass * m->move_L[j] * m->move_L[j] / (m->h * m->h);
        m->nmoving++;
    }
}

void rt_colliders_place(romrt_model *m, const romrt_real *y)
{
    int j;
    for (j = 0; j < m->nmoving; j++) {
        rt_collider *c = &m->colliders[m->moving[j]];
        RT_PHYS(collider_pose_at)(m->move_from[j], c->target, y[m->r + j], c->now);
    }
}

void rt_colliders_end_move(romrt_model *m, const romrt_real *y)
{
    int j, i;
    rt_colliders_place(m, y);
    for (j = 0; j < m->nmoving; j++) {
        rt_collider *c = &m->colliders[m->moving[j]];
        romrt_real ok = 1, x[3];
        /* within the solve's tolerance of the pose: there, when the last bit is safe */
        if ((1 - y[m->r + j]) * m->move_L[j] > m->tol) continue;
        for (i = 0; i < m->ncv && ok >= 1; i++) {
            rt_vertex_position(m, m->cv[i], y, x);
            ok = RT_PHYS(collider_motion_step)(c->kind, c->now, c->target, x);
        }
        if (ok >= 1) memcpy(c->now, c->target, sizeof c->now);
    }
    m->nmoving = 0;
}
