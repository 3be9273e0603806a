/* An app's sphere, capsule or box (romrt_set_collider) on an asset with a collision surface:
 * the shape as the scene's obstacle of that kind is baked (precompute/contact/collision.c,
 * obstacle_geometry) - a sphere its centre with thickness r, a capsule its segment (along its
 * local x) with thickness r, a box its 8 corners (bit a of a corner's index: +h on axis a) and
 * the same 12 outward triangles - as an rt_mesh in the runtime's own storage (m->shapes, in the
 * arena: contact_load.c), placed and moved as an app mesh is (mesh_collider.c, mesh_move.c).
 * Its contact is then the obstacles' (the point-triangle and edge-edge barrier with thickness,
 * Li et al. 2020 Eq. 6-8; additive CCD; lagged friction), exact between the shape and the
 * collision surface's triangles, where the vertex path (colliders.c) sees only the surface's
 * vertices and lets a shape thinner than an edge pass between them. */
#include <string.h>

#include "runtime/romrt_impl.h"

static const int32_t box_tris[36] = RK_BOX_TRIANGLES; /* physics.h: the obstacles' own */

/* A storage that no placed collider reads (there is one more than the slots: if all the others
 * are read, the last is not). */
static rt_shape *free_shape(romrt_model *m)
{
    int s, k, used;
    for (s = 0; s < RT_SHAPES - 1; s++) {
        for (used = 0, k = 0; k < ROMRT_MAX_COLLIDERS; k++)
            used |= m->colliders[k].active && m->colliders[k].mesh == &m->shapes[s].mesh;
        if (!used) break;
    }
    return &m->shapes[s];
}

/* The shape's mesh in its own frame into S (shape: pose, radius, half length, half extents). */
static void build(rt_shape *S, int kind, const romrt_real *shape)
{
    rt_mesh *M = &S->mesh;
    int i, a;
    memset(M, 0, sizeof *M);
    memset(S->X, 0, sizeof S->X);
    M->X = S->X, M->tri = S->tri, M->edges = S->edges, M->node = S->node, M->item = S->item;
    M->bounds = S->bounds.r, M->x = S->x;
    if (kind == ROMRT_COLLIDER_BOX) {
        M->nv = 8, M->nt = 12;
        for (i = 0; i < 8; i++)
            for (a = 0; a < 3; a++) S->X[3 * i + a] = (i >> a) & 1 ? shape[14 + a] : -shape[14 + a];
        memcpy(S->tri, box_tris, sizeof box_tris);
    } else if (kind == ROMRT_COLLIDER_CAPSULE && shape[13] > 0) {
        M->nv = 2, M->ne = 1;
        S->X[0] = -shape[13], S->X[3] = shape[13];
        S->edges[0] = 0, S->edges[1] = 1;
        M->xi = shape[12];
    } else { /* a sphere, or a capsule of no length */
        M->nv = 1;
        M->xi = shape[12];
    }
    M->dx = M->x + 3 * (size_t)M->nv, M->x0 = M->dx + 3 * (size_t)M->nv, M->cache = M->x0 + 3 * (size_t)M->nv;
    rt_mesh_build(M);
}

romrt_status rt_shape_place(romrt_model *m, int slot, int kind, const romrt_real *shape, romrt_error *err)
{
    rt_shape *S = free_shape(m);
    build(S, kind, shape);
    return rt_mesh_place(m, slot, &S->mesh, kind, shape, err);
}
