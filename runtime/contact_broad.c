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
 * Both take the collision surface's stencils against itself from contact_surface.c. */
#include <math.h>

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

/* Item it's obstacle vertices (1 to 3). */
static int item_points(const romrt_model *m, uint32_t it, uint32_t ids[3])
{
    uint32_t index = it >> 2;
    switch (it & 3) {
    case ROMBIN_ITEM_VERTEX:
        ids[0] = index;
        return 1;
    case ROMBIN_ITEM_EDGE:
        ids[0] = m->oedges[2 * (size_t)index], ids[1] = m->oedges[2 * (size_t)index + 1];
        return 2;
    default:
        ids[0] = m->otris[3 * (size_t)index], ids[1] = m->otris[3 * (size_t)index + 1], ids[2] = m->otris[3 * (size_t)index + 2];
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

/* An obstacle item's box over ox (and ox + odx when swept), grown by grow + its thickness. */
static void item_box(const romrt_model *m, uint32_t it, romrt_real grow, int swept, romrt_real *b)
{
    uint32_t ids[3];
    int n = item_points(m, it, ids), k, a;
    box_empty(b);
    for (k = 0; k < n; k++) {
        const romrt_real *p = m->ox + 3 * (size_t)ids[k];
        box_add(b, p);
        if (swept) {
            romrt_real e[3];
            for (a = 0; a < 3; a++) e[a] = p[a] + m->odx[3 * (size_t)ids[k] + a];
            box_add(b, e);
        }
    }
    box_grow(b, grow + m->obs_xi[4 * (size_t)m->overt_obs[ids[0]]]);
}

void rt_obstacles_refit(romrt_model *m, int swept)
{
    int k, i;
    uint32_t j;
    RT_PROF_BEGIN(RT_PROF_BROAD);
    for (k = 0; k < m->nobs; k++) {
        const uint32_t *o = m->obs + ROMBIN_OBST_COUNT * (size_t)k;
        int root = (int)o[ROMBIN_OBST_ROOT];
        for (i = root + (int)o[ROMBIN_OBST_NODES] - 1; i >= root; i--) { /* children after parents */
            const uint32_t *nd = m->onodes + 3 * (size_t)i;
            romrt_real *b = m->obounds + 6 * (size_t)i, ib[6];
            box_empty(b);
            if (nd[0] == 0) {
                box_add(b, m->obounds + 6 * (size_t)nd[1]), box_add(b, m->obounds + 6 * (size_t)nd[1] + 3);
                box_add(b, m->obounds + 6 * (size_t)nd[2]), box_add(b, m->obounds + 6 * (size_t)nd[2] + 3);
                continue;
            }
            for (j = nd[1]; j < nd[1] + nd[2]; j++) {
                /* the vertices' obstacle is this one (checked at open), so overt_obs is not needed yet */
                uint32_t ids[3];
                int n = item_points(m, m->oitems[j], ids), p, a;
                box_empty(ib);
                for (p = 0; p < n; p++) {
                    const romrt_real *x = m->ox + 3 * (size_t)ids[p];
                    box_add(ib, x);
                    if (swept) {
                        romrt_real e[3];
                        for (a = 0; a < 3; a++) e[a] = x[a] + m->odx[3 * (size_t)ids[p] + a];
                        box_add(ib, e);
                    }
                }
                box_grow(ib, m->obs_xi[4 * (size_t)k]);
                box_add(b, ib), box_add(b, ib + 3);
            }
        }
    }
    RT_PROF_END(RT_PROF_BROAD);
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

/* Obstacle k's items of `type` whose boxes touch the object primitive's (ids, size): stencils. */
static int traverse(romrt_model *m, const query *Q, int k, int type, const uint32_t *ids, int size)
{
    const uint32_t *o = m->obs + ROMBIN_OBST_COUNT * (size_t)k;
    uint32_t stack[STACK];
    int top = 0, a;
    romrt_real ob[6], wide[6], ib[6];
    object_box(m, ids, size, Q->grow, Q->swept, ob);
    for (a = 0; a < 6; a++) wide[a] = ob[a];
    /* node boxes hold the items' thickness but not grow: the query takes it (and a rounding margin) */
    box_grow(wide, Q->grow + RT_K(1e-6) * (Q->grow + RT_FABS(ob[0]) + RT_FABS(ob[3])));
    stack[top++] = o[ROMBIN_OBST_ROOT];
    while (top > 0) {
        uint32_t i = stack[--top], j;
        const uint32_t *nd = m->onodes + 3 * (size_t)i;
        if (!overlap(wide, m->obounds + 6 * (size_t)i)) continue;
        if (nd[0] == 0) {
            stack[top++] = nd[1], stack[top++] = nd[2];
            continue;
        }
        for (j = nd[1]; j < nd[1] + nd[2]; j++) {
            uint32_t it = m->oitems[j], p[3];
            int32_t id[4];
            if ((int)(it & 3) != type) continue;
            item_box(m, it, Q->grow, Q->swept, ib);
            if (!overlap(ob, ib)) continue;
            item_points(m, it, p);
            if (type == ROMBIN_ITEM_TRIANGLE) /* object point, obstacle triangle */
                id[0] = (int32_t)ids[0], id[1] = -1 - (int32_t)p[0], id[2] = -1 - (int32_t)p[1], id[3] = -1 - (int32_t)p[2];
            else if (type == ROMBIN_ITEM_VERTEX) /* obstacle point, object triangle */
                id[0] = -1 - (int32_t)p[0], id[1] = (int32_t)ids[0], id[2] = (int32_t)ids[1], id[3] = (int32_t)ids[2];
            else /* object edge, obstacle edge */
                id[0] = (int32_t)ids[0], id[1] = (int32_t)ids[1], id[2] = -1 - (int32_t)p[0], id[3] = -1 - (int32_t)p[1];
            if (Q->visit) {
                Q->visit(m, type == ROMBIN_ITEM_EDGE, id, Q->ctx);
                continue;
            }
            if (rt_contact_keep(m, type == ROMBIN_ITEM_EDGE, id, Q->grow)) return -1;
        }
    }
    return 0;
}

static int stencils(romrt_model *m, const query *Q)
{
    int k, i;
    uint32_t v;
    for (k = 0; k < m->nobs; k++) {
        const uint32_t *o = m->obs + ROMBIN_OBST_COUNT * (size_t)k;
        if (o[ROMBIN_OBST_TRIANGLES])
            for (v = 0; v < (uint32_t)m->ncv; v++)
                if (traverse(m, Q, k, ROMBIN_ITEM_TRIANGLE, &v, 1)) return -1;
        for (i = 0; i < m->nctri; i++)
            if (traverse(m, Q, k, ROMBIN_ITEM_VERTEX, m->ctris + 3 * (size_t)i, 3)) return -1;
        if (o[ROMBIN_OBST_EDGES])
            for (i = 0; i < m->ncedge; i++)
                if (traverse(m, Q, k, ROMBIN_ITEM_EDGE, m->cedges + 2 * (size_t)i, 2)) return -1;
    }
    return Q->surface ? rt_surface_stencils(m, Q->grow, Q->swept, Q->visit, Q->ctx) : 0;
}

/* The largest distance a collision vertex or obstacle vertex has moved since the gather. */
static romrt_real moved_since_cache(const romrt_model *m)
{
    romrt_real m2 = 0, d2, e;
    int i, a;
    for (i = 0; i < m->ncv; i++) {
        for (d2 = 0, a = 0; a < 3; a++) e = m->ocx[3 * (size_t)i + a] - m->cache_x[3 * (size_t)i + a], d2 += e * e;
        if (d2 > m2) m2 = d2;
    }
    for (i = 0; i < m->onv; i++) {
        for (d2 = 0, a = 0; a < 3; a++) e = m->ox[3 * (size_t)i + a] - m->cache_ox[3 * (size_t)i + a], d2 += e * e;
        if (d2 > m2) m2 = d2;
    }
    return RT_SQRT(m2);
}

int rt_obstacles_gather(romrt_model *m)
{
    query Q;
    int i;
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
    m->cache_valid = 1;
    return 0;
}

void rt_obstacles_swept(romrt_model *m, int surface, rt_stencil_visit visit, void *ctx)
{
    query Q;
    Q.grow = 0, Q.swept = 1, Q.surface = surface, Q.visit = visit, Q.ctx = ctx;
    RT_PROF_BEGIN(RT_PROF_BROAD);
    (void)stencils(m, &Q);
    RT_PROF_END(RT_PROF_BROAD);
}
