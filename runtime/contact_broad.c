/* The broad phase against the obstacles: each obstacle's BVH (baked, its boxes refitted here over
 * where its vertices are) traversed with the boxes of the object's collision points, edges and
 * triangles, giving the reduced simulator's stencils (precompute/contact/pairs.c): object points
 * against obstacle triangles, obstacle points against object triangles, object edges against
 * obstacle edges. A box test on a primitive is the precompute's (its points' box grown by grow,
 * an obstacle's also by its thickness; closed intervals), so both gather the same stencils.
 *   gather  the candidates within 2 dhat (by their boxes, then their distance), kept (a Verlet
 *           list, as precompute/contact's cache) while nothing has moved dhat / 2 since: they
 *           then hold every pair within dhat
 *   swept   every stencil whose boxes over a step (x to x + dx, obstacles ox to ox + odx) touch,
 *           handed to CCD as found (nothing stored)
 * Both take the collision surface's stencils against itself from contact_surface.c. An app's
 * mesh collider (mesh_collider.c) is one more obstacle here: its BVH, built into the app's index
 * in the same layout, traversed by the same code over its world positions. */
#include <math.h>
#include <string.h>

#include "runtime/romrt_impl.h"

#define STACK (2 * ROMBIN_BVH_DEPTH + 2)

void rt_obstacles_positions(romrt_model *m, const romrt_real *q, const romrt_real *dq)
{
    int i, a;
    for (i = 0; i < m->ncv; i++) {
        rt_vertex_position(m, m->cv[i], q, m->ocx + 3 * (size_t)i);
        for (a = 0; dq && a < 3; a++) m->ocdx[3 * (size_t)i + a] = rt_row_dot(m, m->cv[i], a, dq);
    }
}

/* One obstacle's BVH as the traversal sees it: a baked obstacle's (OBVN, OBIT, OBED, OBTR over ox,
 * global obstacle vertex ids, base 0) or an app mesh's (its index, local ids, base onv + (slot <<
 * RT_MESH_SHIFT)); stencil id of its vertex v: -1 - (base + v). */
typedef struct {
    const uint32_t *nodes, *items, *edges, *tris;
    romrt_real *bounds;
    const romrt_real *x, *dx;
    romrt_real xi;
    uint32_t root, count, base;
    int has_edges, has_tris;
} bvh_view;

static void baked_view(const romrt_model *m, int k, bvh_view *V)
{
    const uint32_t *o = m->obs + ROMBIN_OBST_COUNT * (size_t)k;
    V->nodes = m->onodes, V->items = m->oitems, V->edges = m->oedges, V->tris = m->otris, V->bounds = m->obounds;
    V->x = m->ox, V->dx = m->odx, V->xi = m->obs_xi[4 * (size_t)k];
    V->root = o[ROMBIN_OBST_ROOT], V->count = o[ROMBIN_OBST_NODES], V->base = 0;
    V->has_edges = o[ROMBIN_OBST_EDGES] != 0, V->has_tris = o[ROMBIN_OBST_TRIANGLES] != 0;
}

static void mesh_view(const romrt_model *m, int slot, rt_mesh *M, bvh_view *V)
{
    V->nodes = M->node, V->items = M->item, V->edges = M->edges, V->tris = (const uint32_t *)(const void *)M->tri;
    V->bounds = M->bounds, V->x = M->x, V->dx = M->dx, V->xi = M->xi;
    V->root = 0, V->count = M->nodes, V->base = (uint32_t)m->onv + ((uint32_t)slot << RT_MESH_SHIFT);
    V->has_edges = M->ne != 0, V->has_tris = M->nt != 0;
}

/* Item it's vertices (1 to 3), in the view's ids. */
static int item_points(const bvh_view *V, uint32_t it, uint32_t ids[3])
{
    uint32_t index = it >> 2;
    switch (it & 3) {
    case ROMBIN_ITEM_VERTEX:
        ids[0] = index;
        return 1;
    case ROMBIN_ITEM_EDGE:
        ids[0] = V->edges[2 * (size_t)index], ids[1] = V->edges[2 * (size_t)index + 1];
        return 2;
    default:
        ids[0] = V->tris[3 * (size_t)index], ids[1] = V->tris[3 * (size_t)index + 1], ids[2] = V->tris[3 * (size_t)index + 2];
        return 3;
    }
}

static void box_empty(romrt_real *b)
{
    int a;
    for (a = 0; a < 3; a++) b[a] = (romrt_real)INFINITY, b[3 + a] = -(romrt_real)INFINITY;
}

static void box_add(romrt_real *b, const romrt_real *p)
{
    int a;
    for (a = 0; a < 3; a++) {
        if (p[a] < b[a]) b[a] = p[a];
        if (p[a] > b[3 + a]) b[3 + a] = p[a];
    }
}

static void box_grow(romrt_real *b, romrt_real grow)
{
    int a;
    for (a = 0; a < 3; a++) b[a] -= grow, b[3 + a] += grow;
}

static int overlap(const romrt_real *a, const romrt_real *b)
{
    return !(a[0] > b[3] || a[3] < b[0] || a[1] > b[4] || a[4] < b[1] || a[2] > b[5] || a[5] < b[2]);
}

/* An item's box over x (and x + dx when swept), grown by grow + the obstacle's thickness. */
static void item_box(const bvh_view *V, uint32_t it, romrt_real grow, int swept, romrt_real *b)
{
    uint32_t ids[3];
    int n = item_points(V, it, ids), k, a;
    box_empty(b);
    for (k = 0; k < n; k++) {
        const romrt_real *p = V->x + 3 * (size_t)ids[k];
        box_add(b, p);
        if (swept) {
            romrt_real e[3];
            for (a = 0; a < 3; a++) e[a] = p[a] + V->dx[3 * (size_t)ids[k] + a];
            box_add(b, e);
        }
    }
    box_grow(b, grow + V->xi);
}

/* The view's node boxes over x (swept: and x + dx), children before their parents. */
static void refit(const bvh_view *V, int swept)
{
    uint32_t i, j;
    for (i = V->root + V->count; i-- > V->root;) { /* children after parents */
        const uint32_t *nd = V->nodes + 3 * (size_t)i;
        romrt_real *b = V->bounds + 6 * (size_t)i, ib[6];
        box_empty(b);
        if (nd[0] == 0) {
            box_add(b, V->bounds + 6 * (size_t)nd[1]), box_add(b, V->bounds + 6 * (size_t)nd[1] + 3);
            box_add(b, V->bounds + 6 * (size_t)nd[2]), box_add(b, V->bounds + 6 * (size_t)nd[2] + 3);
            continue;
        }
        for (j = nd[1]; j < nd[1] + nd[2]; j++) {
            item_box(V, V->items[j], 0, swept, ib);
            box_add(b, ib), box_add(b, ib + 3);
        }
    }
}

void rt_obstacles_refit(romrt_model *m, int swept)
{
    bvh_view V;
    int k;
    RT_PROF_BEGIN(RT_PROF_BROAD);
    for (k = 0; k < m->nobs; k++) {
        baked_view(m, k, &V);
        refit(&V, swept);
    }
    RT_PROF_END(RT_PROF_BROAD);
}

void rt_mesh_refit(rt_mesh *M, int swept)
{
    bvh_view V;
    V.nodes = M->node, V.items = M->item, V.edges = M->edges, V.tris = (const uint32_t *)(const void *)M->tri;
    V.bounds = M->bounds, V.x = M->x, V.dx = M->dx, V.xi = M->xi, V.root = 0, V.count = M->nodes, V.base = 0;
    refit(&V, swept);
}

int rt_mesh_query(const rt_mesh *M, const romrt_real box[6], int type, int (*visit)(const uint32_t *ids, void *ctx),
                  void *ctx)
{
    bvh_view V;
    uint32_t stack[STACK];
    int top = 0;
    romrt_real ib[6];
    V.nodes = M->node, V.items = M->item, V.edges = M->edges, V.tris = (const uint32_t *)(const void *)M->tri;
    V.bounds = M->bounds, V.x = M->x, V.dx = M->dx, V.xi = M->xi, V.root = 0, V.count = M->nodes, V.base = 0;
    stack[top++] = 0;
    while (top > 0) {
        uint32_t i = stack[--top], j;
        const uint32_t *nd = M->node + 3 * (size_t)i;
        if (!overlap(box, M->bounds + 6 * (size_t)i)) continue;
        if (nd[0] == 0) {
            stack[top++] = nd[1], stack[top++] = nd[2];
            continue;
        }
        for (j = nd[1]; j < nd[1] + nd[2]; j++) {
            uint32_t it = M->item[j], p[3];
            if ((int)(it & 3) != type) continue;
            item_box(&V, it, 0, 0, ib);
            if (!overlap(box, ib)) continue;
            item_points(&V, it, p);
            if (visit(p, ctx)) return 1;
        }
    }
    return 0;
}

/* The object's primitive of `size` collision vertices ids (over ocx, and ocx + ocdx when swept):
 * its box grown by grow. */
static void object_box(const romrt_model *m, const uint32_t *ids, int size, romrt_real grow, int swept, romrt_real *b)
{
    int k, a;
    box_empty(b);
    for (k = 0; k < size; k++) {
        const romrt_real *p = m->ocx + 3 * (size_t)ids[k];
        box_add(b, p);
        if (swept) {
            romrt_real e[3];
            for (a = 0; a < 3; a++) e[a] = p[a] + m->ocdx[3 * (size_t)ids[k] + a];
            box_add(b, e);
        }
    }
    box_grow(b, grow);
}

typedef struct {
    romrt_real grow;
    int swept;              /* boxes over the step (CCD) rather than within grow (the gather) */
    int surface;            /* the collision surface against itself too (contact_surface.c) */
    rt_stencil_visit visit; /* swept: each stencil; else pushed into m->cand */
    void *ctx;
} query;

int rt_contact_keep(romrt_model *m, int edge_edge, const int32_t id[4], romrt_real grow)
{
    /* the gather keeps a stencil only within grow of its thickness: nothing farther can come within
     * dhat while nothing moves dhat / 2 (the boxes alone kept 20 times more of them over a fine
     * terrain, past any capacity sized by the collision surface) */
    const romrt_real *pts[4];
    romrt_real reach = grow + rt_obstacles_xi(m, id);
    int32_t *c;
    rt_obstacles_stencil(m, id, pts);
    if (!(RT_PHYS(contact_distance2)(edge_edge ? RT_PHYS(edge_edge_case)(pts) : RT_PHYS(point_triangle_case)(pts), pts, 0,
                                     0) < reach * reach))
        return 0;
    if (m->ncand >= m->pair_cap) {
        m->obs_overflow = 1;
        return -1;
    }
    c = m->cand + 5 * (size_t)m->ncand++;
    c[0] = edge_edge, c[1] = id[0], c[2] = id[1], c[3] = id[2], c[4] = id[3];
    return 0;
}

/* The stencil of object primitive (ids) and obstacle item it of `type` (its view ids p): kept or
 * visited. */
static int found(romrt_model *m, const query *Q, const bvh_view *V, int type, const uint32_t *ids, uint32_t it)
{
    uint32_t p[3];
    int32_t id[4];
    int a, np = item_points(V, it, p);
    for (a = 0; a < np; a++) p[a] += V->base; /* only the item's points: the rest of p is unset */
    if (type == ROMBIN_ITEM_TRIANGLE) /* object point, obstacle triangle */
        id[0] = (int32_t)ids[0], id[1] = -1 - (int32_t)p[0], id[2] = -1 - (int32_t)p[1], id[3] = -1 - (int32_t)p[2];
    else if (type == ROMBIN_ITEM_VERTEX) /* obstacle point, object triangle */
        id[0] = -1 - (int32_t)p[0], id[1] = (int32_t)ids[0], id[2] = (int32_t)ids[1], id[3] = (int32_t)ids[2];
    else /* object edge, obstacle edge */
        id[0] = (int32_t)ids[0], id[1] = (int32_t)ids[1], id[2] = -1 - (int32_t)p[0], id[3] = -1 - (int32_t)p[1];
    if (Q->visit) {
        Q->visit(m, type == ROMBIN_ITEM_EDGE, id, Q->ctx);
        return 0;
    }
    return rt_contact_keep(m, type == ROMBIN_ITEM_EDGE, id, Q->grow);
}

/* Box ob (an object primitive's, or an object's hull, grown by grow) widened to meet the node
 * boxes, which hold the items' thickness but not grow (and a rounding margin). */
static void widen(const query *Q, const romrt_real ob[6], romrt_real wide[6])
{
    int a;
    for (a = 0; a < 6; a++) wide[a] = ob[a];
    box_grow(wide, Q->grow + RT_K(1e-6) * (Q->grow + RT_FABS(ob[0]) + RT_FABS(ob[3])));
}

/* The view's items of `type` whose boxes touch the object primitive's (ids, size): stencils. */
static int traverse(romrt_model *m, const query *Q, const bvh_view *V, int type, const uint32_t *ids, int size)
{
    uint32_t stack[STACK];
    int top = 0;
    romrt_real ob[6], wide[6], ib[6];
    object_box(m, ids, size, Q->grow, Q->swept, ob);
    widen(Q, ob, wide);
    stack[top++] = V->root;
    while (top > 0) {
        uint32_t i = stack[--top], j;
        const uint32_t *nd = V->nodes + 3 * (size_t)i;
        if (!overlap(wide, V->bounds + 6 * (size_t)i)) continue;
        if (nd[0] == 0) {
            stack[top++] = nd[1], stack[top++] = nd[2];
            continue;
        }
        for (j = nd[1]; j < nd[1] + nd[2]; j++) {
            uint32_t it = V->items[j];
            if ((int)(it & 3) != type) continue;
            item_box(V, it, Q->grow, Q->swept, ib);
            if (!overlap(ob, ib)) continue;
            if (found(m, Q, V, type, ids, it)) return -1;
        }
    }
    return 0;
}

/* The items near one object: those of `type` whose boxes touch its hull (its primitives' boxes'
 * union), in the order traverse visits them, with their boxes; -1 past NEAR_CAP of them. Every
 * item a primitive's traversal finds is among them, and in the same order: the same stencils. */
#define NEAR_CAP 32
static int near_items(const query *Q, const bvh_view *V, int type, const romrt_real hull[6], uint32_t *list,
                      romrt_real *boxes)
{
    uint32_t stack[STACK];
    int top = 0, n = 0, a;
    romrt_real wide[6], ib[6];
    widen(Q, hull, wide);
    stack[top++] = V->root;
    while (top > 0) {
        uint32_t i = stack[--top], j;
        const uint32_t *nd = V->nodes + 3 * (size_t)i;
        if (!overlap(wide, V->bounds + 6 * (size_t)i)) continue;
        if (nd[0] == 0) {
            stack[top++] = nd[1], stack[top++] = nd[2];
            continue;
        }
        for (j = nd[1]; j < nd[1] + nd[2]; j++) {
            uint32_t it = V->items[j];
            if ((int)(it & 3) != type) continue;
            item_box(V, it, Q->grow, Q->swept, ib);
            if (!overlap(hull, ib)) continue;
            if (n == NEAR_CAP) return -1;
            for (a = 0; a < 6; a++) boxes[6 * (size_t)n + a] = ib[a];
            list[n++] = it;
        }
    }
    return n;
}

/* The object primitives first .. first + count - 1 of `type` (size points each, from ids) against
 * one obstacle's BVH, a run of one object's at a time (the surface lists each object's
 * primitives together): the BVH is traversed once for the run's object (its hull), and each
 * primitive is tested against the few items near it, or none (an object away from a container's
 * walls), where a traversal per primitive from the root took a fifth of the pour's step; an
 * object near more than NEAR_CAP items (a terrain) traverses per primitive. */
static int run_against(romrt_model *m, const query *Q, const bvh_view *V, int type, const uint32_t *prims, int size, int count,
                       const romrt_real *hulls)
{
    uint32_t list[NEAR_CAP], v;
    romrt_real boxes[6 * NEAR_CAP], ob[6];
    int i = 0, j, k, n;
    while (i < count) {
        const uint32_t *ids = prims ? prims + (size_t)size * i : 0;
        uint32_t o = m->cv_obj ? m->cv_obj[ids ? ids[0] : (uint32_t)i] : 0;
        for (j = i + 1; j < count && (m->cv_obj ? m->cv_obj[prims ? prims[(size_t)size * j] : (uint32_t)j] : 0) == o; j++)
            continue;
        n = near_items(Q, V, type, hulls + 10 * (size_t)o, list, boxes);
        for (; i < j && n != 0; i++) {
            const uint32_t *pid = prims ? prims + (size_t)size * i : (v = (uint32_t)i, &v);
            if (n < 0) {
                if (traverse(m, Q, V, type, pid, size)) return -1;
                continue;
            }
            object_box(m, pid, size, Q->grow, Q->swept, ob);
            for (k = 0; k < n; k++)
                if (overlap(ob, boxes + 6 * (size_t)k) && found(m, Q, V, type, pid, list[k])) return -1;
        }
        i = j;
    }
    return 0;
}

/* The object's primitives against one obstacle's BVH. */
static int against(romrt_model *m, const query *Q, const bvh_view *V, const romrt_real *hulls)
{
    if (V->has_tris && run_against(m, Q, V, ROMBIN_ITEM_TRIANGLE, 0, 1, m->ncv, hulls)) return -1;
    if (run_against(m, Q, V, ROMBIN_ITEM_VERTEX, m->ctris, 3, m->nctri, hulls)) return -1;
    if (V->has_edges && run_against(m, Q, V, ROMBIN_ITEM_EDGE, m->cedges, 2, m->ncedge, hulls)) return -1;
    return 0;
}

/* Each object's hull: its collision vertices' box (over ocx, and ocx + ocdx when swept) grown by
 * grow, at 10 reals an object (the surface sweep's sstat layout). */
static void object_hulls(const romrt_model *m, const query *Q, romrt_real *hulls)
{
    int nobj = m->nobjects > 0 ? m->nobjects : 1, i, a;
    for (i = 0; i < nobj; i++) box_empty(hulls + 10 * (size_t)i);
    for (i = 0; i < m->ncv; i++) {
        romrt_real *h = hulls + 10 * (size_t)(m->cv_obj ? m->cv_obj[i] : 0), e[3];
        const romrt_real *p = m->ocx + 3 * (size_t)i;
        box_add(h, p);
        if (Q->swept) {
            for (a = 0; a < 3; a++) e[a] = p[a] + m->ocdx[3 * (size_t)i + a];
            box_add(h, e);
        }
    }
    for (i = 0; i < nobj; i++) box_grow(hulls + 10 * (size_t)i, Q->grow);
}

static int stencils(romrt_model *m, const query *Q)
{
    bvh_view V;
    romrt_real one[10], *hulls = m->sstat ? m->sstat : one; /* the sweep's, before it fills them */
    int k;
    object_hulls(m, Q, hulls);
    for (k = 0; k < m->nobs; k++) {
        baked_view(m, k, &V);
        if (against(m, Q, &V, hulls)) return -1;
    }
    for (k = 0; k < ROMRT_MAX_COLLIDERS && m->nmeshes; k++) {
        if (!m->colliders[k].active || !m->colliders[k].mesh) continue;
        mesh_view(m, k, m->colliders[k].mesh, &V);
        if (against(m, Q, &V, hulls)) return -1;
    }
    return Q->surface ? rt_surface_stencils(m, Q->grow, Q->swept, Q->visit, Q->ctx) : 0;
}

/* The largest distance a collision vertex or obstacle vertex has moved since the gather. */
static romrt_real moved_since_cache(const romrt_model *m)
{
    romrt_real m2 = 0, d2, e;
    int i, a, k;
    for (i = 0; i < m->ncv; i++) {
        for (d2 = 0, a = 0; a < 3; a++) e = m->ocx[3 * (size_t)i + a] - m->cache_x[3 * (size_t)i + a], d2 += e * e;
        if (d2 > m2) m2 = d2;
    }
    for (i = 0; i < m->onv; i++) {
        for (d2 = 0, a = 0; a < 3; a++) e = m->ox[3 * (size_t)i + a] - m->cache_ox[3 * (size_t)i + a], d2 += e * e;
        if (d2 > m2) m2 = d2;
    }
    for (k = 0; k < ROMRT_MAX_COLLIDERS && m->nmeshes; k++) {
        const rt_mesh *M = m->colliders[k].active ? m->colliders[k].mesh : 0;
        for (i = 0; M && i < (int)M->nv; i++) {
            for (d2 = 0, a = 0; a < 3; a++) e = M->x[3 * (size_t)i + a] - M->cache[3 * (size_t)i + a], d2 += e * e;
            if (d2 > m2) m2 = d2;
        }
    }
    return RT_SQRT(m2);
}

int rt_obstacles_gather(romrt_model *m)
{
    query Q;
    int i, k;
    if (m->cache_valid && 2 * moved_since_cache(m) <= m->dhat) return 0;
    Q.grow = 2 * m->dhat, Q.swept = 0, Q.surface = 1, Q.visit = 0, Q.ctx = 0;
    m->ncand = 0;
    m->cache_valid = 0;
    RT_PROF_BEGIN(RT_PROF_BROAD);
    i = stencils(m, &Q);
    RT_PROF_END(RT_PROF_BROAD);
    if (i) return -1;
    for (i = 0; i < 3 * m->ncv; i++) m->cache_x[i] = m->ocx[i];
    for (i = 0; i < 3 * m->onv; i++) m->cache_ox[i] = m->ox[i];
    for (k = 0; k < ROMRT_MAX_COLLIDERS && m->nmeshes; k++) {
        rt_mesh *M = m->colliders[k].active ? m->colliders[k].mesh : 0;
        if (M) memcpy(M->cache, M->x, sizeof(romrt_real) * 3 * (size_t)M->nv);
    }
    m->cache_valid = 1;
    return 0;
}

void rt_obstacles_swept(romrt_model *m, int surface, romrt_real grow, rt_stencil_visit visit, void *ctx)
{
    query Q;
    Q.grow = grow, Q.swept = 1, Q.surface = surface, Q.visit = visit, Q.ctx = ctx;
    RT_PROF_BEGIN(RT_PROF_BROAD);
    (void)stencils(m, &Q);
    RT_PROF_END(RT_PROF_BROAD);
}
