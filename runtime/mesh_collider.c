/* An app's triangle mesh collider (romrt.h, romrt_set_mesh_collider): placed in a collider slot
 * at a rigid pose, its world positions kept in its index (mesh_index.c), its contact the baked
 * obstacles' (contact*.c: the same stencils, barrier, friction and CCD, thickness 0).
 *
 * A move to a new pose is the scene's scripted obstacles' rule (contact_progress.c): each vertex
 * goes on a straight line to where the pose puts it, at a progress that the step solves for with
 * the body, so the barrier pushes the body ahead of the mesh and CCD filters the joint motion;
 * where the body cannot give way the mesh stops short, as the other colliders do, and goes on at
 * the next step. A straight line per vertex rather than the pose's screw: CCD is exact on it, and
 * the pose is reached exactly at its end (a rotation moves the vertices through chords of their
 * arcs on the way, a shape that is never touched): mesh_move.c. The app's spheres, capsules and
 * boxes on an asset with a collision surface are such meshes too, over the runtime's own storage
 * (shape_collider.c), placed by rt_mesh_place as an app's mesh is. */
#include <math.h>
#include <string.h>

#include "runtime/romrt_impl.h"

/* Whether segment pq and triangle abc share a point, in this precision (the sign tests of the
 * exact predicate in precompute/contact/intersect.c, not exact: a zero counts as a crossing, so
 * near-touching configurations are refused too). */
static romrt_real orient(const romrt_real *a, const romrt_real *b, const romrt_real *c, const romrt_real *d)
{
    romrt_real u[3], v[3], w[3];
    int i;
    for (i = 0; i < 3; i++) u[i] = a[i] - d[i], v[i] = b[i] - d[i], w[i] = c[i] - d[i];
    return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
}

static int segment_triangle(const romrt_real *p, const romrt_real *q, const romrt_real *a, const romrt_real *b,
                            const romrt_real *c)
{
    romrt_real sp = orient(a, b, c, p), sq = orient(a, b, c, q), s1, s2, s3;
    if ((sp > 0 && sq > 0) || (sp < 0 && sq < 0)) return 0;
    s1 = orient(p, q, a, b), s2 = orient(p, q, b, c), s3 = orient(p, q, c, a);
    return !((s1 > 0 || s2 > 0 || s3 > 0) && (s1 < 0 || s2 < 0 || s3 < 0));
}

typedef struct {
    const romrt_model *m;
    const rt_mesh *M;
    const uint32_t *ids; /* the body's edge (2) or triangle (3), collision vertex ids */
} cross_ctx;

static int edge_through_mesh(const uint32_t *t, void *ctx)
{
    const cross_ctx *c = (const cross_ctx *)ctx;
    return segment_triangle(c->m->ocx + 3 * (size_t)c->ids[0], c->m->ocx + 3 * (size_t)c->ids[1], c->M->x + 3 * (size_t)t[0],
                            c->M->x + 3 * (size_t)t[1], c->M->x + 3 * (size_t)t[2]);
}

static int mesh_edge_through(const uint32_t *e, void *ctx)
{
    const cross_ctx *c = (const cross_ctx *)ctx;
    return segment_triangle(c->M->x + 3 * (size_t)e[0], c->M->x + 3 * (size_t)e[1], c->m->ocx + 3 * (size_t)c->ids[0],
                            c->m->ocx + 3 * (size_t)c->ids[1], c->m->ocx + 3 * (size_t)c->ids[2]);
}

/* Whether the mesh where it is crosses the body's collision surface at q: an edge of either
 * through a triangle of the other, the boxes culled by the mesh's BVH. The barrier only sees
 * pairs within dhat, so a mesh placed through the body would otherwise be taken. */
static int crosses_body(romrt_model *m, const rt_mesh *M)
{
    cross_ctx c;
    romrt_real box[6];
    int i, k, a;
    c.m = m, c.M = M;
    rt_obstacles_positions(m, m->q, 0);
    for (i = 0; i < m->ncedge + m->nctri; i++) {
        int edge = i < m->ncedge, n = edge ? 2 : 3;
        c.ids = edge ? m->cedges + 2 * (size_t)i : m->ctris + 3 * (size_t)(i - m->ncedge);
        for (a = 0; a < 3; a++) box[a] = (romrt_real)INFINITY, box[3 + a] = -(romrt_real)INFINITY;
        for (k = 0; k < n; k++)
            for (a = 0; a < 3; a++) {
                romrt_real x = m->ocx[3 * (size_t)c.ids[k] + a];
                if (x < box[a]) box[a] = x;
                if (x > box[3 + a]) box[3 + a] = x;
            }
        if (rt_mesh_query(M, box, edge ? ROMBIN_ITEM_TRIANGLE : ROMBIN_ITEM_EDGE, edge ? edge_through_mesh : mesh_edge_through, &c))
            return 1;
    }
    return 0;
}

void rt_mesh_leave(romrt_model *m, int slot)
{
    m->colliders[slot].mesh = 0;
    m->nmeshes--;
    m->cache_valid = 0; /* the pair list and friction's may name its vertices */
    m->nfric = 0;
}

romrt_status rt_mesh_place(romrt_model *m, int slot, rt_mesh *M, int kind, const romrt_real *shape, romrt_error *err)
{
    rt_collider *k = &m->colliders[slot], before;
    int placed;
    /* placed at once, clear of the body: its pairs at the body's q must all be apart */
    before = *k;
    placed = k->active && k->mesh;
    rt_mesh_world(M, shape, M->x);
    memcpy(M->x0, M->x, sizeof(romrt_real) * 3 * (size_t)M->nv);
    memset(M->dx, 0, sizeof(romrt_real) * 3 * (size_t)M->nv);
    rt_mesh_refit(M, 0);
    M->part = M->part_start = M->moving = 0;
    k->active = 1;
    k->kind = kind;
    k->mesh = M;
    m->nmeshes += !placed;
    m->cache_valid = 0;
    m->nfric = 0;
    m->obs_overflow = 0;
    if (m->alrom) rt_alrom_take_collision_vertices(m); /* their positions current */
    if (crosses_body(m, M) || !isfinite(rt_obstacles_energy(m, m->q, 0, 0, 0, 0))) {
        int overflow = m->obs_overflow;
        *k = before;
        m->nmeshes -= !placed;
        m->cache_valid = 0;
        m->obs_overflow = 0;
        if (overflow)
            return rt_fail_n(err, ROMRT_E_LIMIT, ROMBIN_OBHD,
                             kind == ROMRT_COLLIDER_MESH ? "romrt_set_mesh_collider: more contact pairs than the asset's capacity of "
                                                         : "romrt_set_collider: more contact pairs than the asset's capacity of ",
                             (uint64_t)m->pair_cap, " (bake with a larger rom.asset.contact_pairs)");
        return rt_fail(err, ROMRT_E_ARGUMENT, 0,
                       kind == ROMRT_COLLIDER_MESH
                           ? "romrt_set_mesh_collider: it would touch or cross the body: place it clear, then move it"
                           : "romrt_set_collider: it would touch or cross the body: place it clear, then move it");
    }
    m->ncolliders += !before.active;
    m->hessian_age = -1; /* a kept Newton matrix lacks the mesh's terms */
    memcpy(k->now, shape, sizeof k->now);
    memcpy(k->target, shape, sizeof k->target);
    memcpy(k->start, shape, sizeof k->start);
    memcpy(k->lag, shape, sizeof k->lag);
    return ROMRT_OK;
}

romrt_status romrt_set_mesh_collider(romrt_model *m, size_t slot, const romrt_mesh *mesh, const romrt_real position[3],
                                     const romrt_real rotation[9], romrt_error *err)
{
    romrt_real shape[RT_COLLIDER_REALS];
    rt_collider *k;
    rt_mesh *M;
    int i;
    if (!m || !mesh || !position || !rotation)
        return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_set_mesh_collider: no model, mesh, position or rotation (NULL)");
    if (slot >= ROMRT_MAX_COLLIDERS)
        return rt_fail_n(err, ROMRT_E_ARGUMENT, 0, "romrt_set_mesh_collider: slot ", (uint64_t)slot, " is out of range");
    if (m->lift) /* as the reduced simulator (precompute/rom/colliders.c) */
        return rt_fail(err, ROMRT_E_UNSUPPORTED, ROMBIN_LIFT, "a lifted moving group cannot give way to a collider "
                       "(bake with rom.clamp \"dirichlet\" to use colliders)");
    if (!romrt_takes_colliders(m))
        return rt_fail(err, ROMRT_E_UNSUPPORTED, ROMBIN_CVTX,
                       "the asset has no collision vertices (baked with \"colliders\": false or before rombin 1.1)");
    if (!m->surface)
        return rt_fail(err, ROMRT_E_UNSUPPORTED, ROMBIN_OBHD,
                       "romrt_set_mesh_collider: the asset has no collision surface (baked with \"colliders\": \"vertices\" "
                       "or before rombin 1.10)");
    for (i = 0; i < 3; i++) shape[i] = position[i];
    for (i = 0; i < 9; i++) shape[3 + i] = rotation[i];
    for (i = 12; i < RT_COLLIDER_REALS; i++) shape[i] = 1; /* a unit sphere's size: only the pose is checked */
    switch (RT_PHYS(collider_check)(RK_COLLIDER_SPHERE, shape)) {
    case 0: break;
    case RK_COLLIDER_NOT_FINITE: return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_set_mesh_collider: a number of the pose is not finite");
    default: return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_set_mesh_collider: the rotation is not orthonormal");
    }
    for (i = 12; i < RT_COLLIDER_REALS; i++) shape[i] = 0;
    if (!rt_mesh_index_of(mesh))
        return rt_fail(err, ROMRT_E_ARGUMENT, 0,
                       "romrt_set_mesh_collider: the index was not built for this mesh (romrt_mesh_index_build with these "
                       "positions, triangles and counts)");
    M = (rt_mesh *)mesh->index;
    if (!(k = &m->colliders[slot])->active || k->mesh != M) { /* a placement: the app's arrays checked again */
        romrt_status st = rt_mesh_check(mesh, 1, err);
        if (st) return st;
    }
    for (i = 0; i < ROMRT_MAX_COLLIDERS; i++)
        if ((size_t)i != slot && m->colliders[i].active && m->colliders[i].mesh == M)
            return rt_fail_n(err, ROMRT_E_ARGUMENT, 0, "romrt_set_mesh_collider: the index is placed in slot ", (uint64_t)i,
                             " already: one index per placed mesh");
    k = &m->colliders[slot];
    if (k->active && k->mesh == M) { /* a move: made by the next step */
        memcpy(k->target, shape, sizeof shape);
        m->hessian_age = -1; /* a kept Newton matrix is dropped by a collider's move (romrt.h) */
        return ROMRT_OK;
    }
    return rt_mesh_place(m, (int)slot, M, ROMRT_COLLIDER_MESH, shape, err);
}

