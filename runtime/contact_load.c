/* The obstacles' chunks (ROMBIN.md "Obstacle chunks", 1.6): OBHD's counts and ranges, OBJS,
 * OBMO, OBVX, OBED, OBTR, the BVH (OBVN, OBVB, OBIT) and the collision surface (CEDG, CTRI);
 * their scratch in the arena (the pair capacity OBHD names); at open every index in range, each
 * BVH a tree (children after their parent, one parent each, not deeper than ROMBIN_BVH_DEPTH)
 * whose leaves hold each of its obstacle's primitives once, its boxes around them, and the start
 * apart from every obstacle. A damaged chunk is refused by name. */
#include <math.h>

#include "runtime/loader_impl.h"

#define MAX_PAIRS (1u << 24)

static const char *const obstacle_chunks[] = {ROMBIN_OBJS, ROMBIN_OBMO, ROMBIN_OBVX, ROMBIN_OBED, ROMBIN_OBTR,
                                              ROMBIN_OBVN, ROMBIN_OBVB, ROMBIN_OBIT, ROMBIN_CEDG, ROMBIN_CTRI, 0};

/* A u32 chunk of a whole number of `per` records: its count. */
static romrt_status records(rt_loader *L, const char *id, uint64_t per, int *count, const uint32_t **out)
{
    rombin_chunk c;
    int found;
    romrt_status st = rt_chunk(L, id, ROMBIN_TYPE_U32, 0, 1, &c, &found);
    if (st) return st;
    if (c.raw % (4 * per) != 0 || c.raw / (4 * per) > ROMRT_MAX_TRIANGLES)
        return rt_fail_n(L->err, ROMRT_E_MODEL, id, "size is not a whole number of records of ", per, " values");
    *count = (int)(c.raw / (4 * per));
    *out = (const uint32_t *)(const void *)c.data;
    return ROMRT_OK;
}

/* The surface sweep's boxes and its three orders of the primitives, the identity to start
 * (contact_surface.c), when the surface can touch itself or another object's. */
static romrt_status rt_surface_arrays(rt_loader *L, romrt_model *m)
{
    size_t n = (size_t)m->ncv + (size_t)m->ncedge + (size_t)m->nctri, i;
    if (!m->self_contact && m->nobjects < 2) return ROMRT_OK;
    rt_scratch(L, 6 * n, &m->sboxes);
    rt_scratch_u32(L, 3 * n, &m->sorder);
    rt_scratch_u32(L, n, &m->sobj);
    rt_scratch_u32(L, (size_t)m->nobjects + 2, &m->sfirst);
    rt_scratch(L, 10 * ((size_t)m->nobjects + 1), &m->sstat);
    for (i = 0; m->sorder && i < 3 * n; i++) m->sorder[i] = (uint32_t)(i % n);
    return ROMRT_OK;
}

romrt_status rt_obstacles_arrays(rt_loader *L, romrt_model *m)
{
    rombin_chunk c;
    int found, k;
    const uint32_t *head;
    uint64_t rp = RT_PAD((size_t)m->r), n, cap;
    romrt_status st = rt_chunk(L, ROMBIN_OBHD, ROMBIN_TYPE_U32, 0, 0, &c, &found);
    m->nobs = 0;
    if (st) return st;
    if (!found) {
        for (k = 0; obstacle_chunks[k]; k++)
            if (rombin_find(&L->file, obstacle_chunks[k], &c))
                return rt_fail(L->err, ROMRT_E_MODEL, obstacle_chunks[k], "obstacle data without its header (OBHD)");
        return ROMRT_OK;
    }
    head = (const uint32_t *)(const void *)c.data;
    n = c.raw / 4;
    /* no obstacle besides planes: the collision surface touching itself (self-contact) or other
     * objects' (COBJ, read before), 1.7, or there for the app's colliders alone (its flag), 1.10 */
    if (n < ROMBIN_OBHD_COUNT || head[ROMBIN_OBHD_OBSTACLES] > ROMBIN_MAX_OBSTACLES ||
        (head[ROMBIN_OBHD_OBSTACLES] == 0 && !(head[ROMBIN_OBHD_FLAGS] & (ROMBIN_OBHD_SELF | ROMBIN_OBHD_COLLIDERS)) &&
         m->nobjects < 2))
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_OBHD,
                       "counts more obstacles than the runtime takes (64), or none with neither objects (COBJ), "
                       "self-contact nor the colliders flag");
    if (n != ROMBIN_OBHD_COUNT + (uint64_t)ROMBIN_OBST_COUNT * head[ROMBIN_OBHD_OBSTACLES])
        return rt_fail_nn(L->err, ROMRT_E_MODEL, ROMBIN_OBHD, "holds ", n, " values, its obstacle count implies ",
                          ROMBIN_OBHD_COUNT + (uint64_t)ROMBIN_OBST_COUNT * head[ROMBIN_OBHD_OBSTACLES], "");
    if (head[ROMBIN_OBHD_FLAGS] & ~(uint32_t)(ROMBIN_OBHD_SELF | ROMBIN_OBHD_COLLIDERS))
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_OBHD, "flags hold a bit this runtime does not know");
    for (k = ROMBIN_OBHD_FLAGS + 1; k < ROMBIN_OBHD_COUNT; k++)
        if (head[k]) return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_OBHD, "reserved field ", (uint64_t)k, " is not 0");
    for (k = ROMBIN_OBHD_VERTICES; k <= ROMBIN_OBHD_ITEMS; k++)
        if (head[k] > ROMRT_MAX_TRIANGLES)
            return rt_fail_n(L->err, ROMRT_E_LIMIT, ROMBIN_OBHD, "count ", (uint64_t)k, " is above the runtime's limit");
    cap = head[ROMBIN_OBHD_PAIRS];
    if (cap == 0 || cap > MAX_PAIRS)
        return rt_fail_n(L->err, ROMRT_E_LIMIT, ROMBIN_OBHD, "pair capacity ", cap, " is 0 or above 2^24");
    if (m->ncv == 0) return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_OBHD, "obstacles without collision vertices (CVTX)");
    if (!(m->dhat > 0) || !(m->kappa > 0))
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_PARM, "dhat and kappa must be positive with obstacles");
    m->surface = 1;
    m->self_contact = (head[ROMBIN_OBHD_FLAGS] & ROMBIN_OBHD_SELF) != 0;
    m->nobs = (int)head[ROMBIN_OBHD_OBSTACLES];
    m->obs = head + ROMBIN_OBHD_COUNT;
    m->onv = (int)head[ROMBIN_OBHD_VERTICES];
    m->one = (int)head[ROMBIN_OBHD_EDGES];
    m->onf = (int)head[ROMBIN_OBHD_TRIANGLES];
    m->onode = (int)head[ROMBIN_OBHD_NODES];
    m->oitem = (int)head[ROMBIN_OBHD_ITEMS];
    m->pair_cap = (int)cap;
    if (m->nobs == 0) { /* the collision surface alone */
        if (m->onv || m->one || m->onf || m->onode || m->oitem)
            return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_OBHD, "counts obstacle vertices or nodes without obstacles");
        for (k = 0; obstacle_chunks[k + 2]; k++)
            if (rombin_find(&L->file, obstacle_chunks[k], &c))
                return rt_fail(L->err, ROMRT_E_MODEL, obstacle_chunks[k], "obstacle data with no obstacle in OBHD");
        if ((st = records(L, ROMBIN_CEDG, 2, &m->ncedge, &m->cedges)) || (st = records(L, ROMBIN_CTRI, 3, &m->nctri, &m->ctris)))
            return st;
    } else if ((st = rt_reals(L, ROMBIN_OBJS, 4 * (uint64_t)m->nobs, 1, &m->obs_xi)) ||
        (st = rt_reals(L, ROMBIN_OBMO, ROMBIN_PIN_PARAMS * (uint64_t)m->nobs, 1, &m->obs_motion)) ||
        (st = rt_reals(L, ROMBIN_OBVX, 3 * (uint64_t)m->onv, 1, &m->oX)) ||
        (st = rt_u32s(L, ROMBIN_OBED, 2 * (uint64_t)m->one, 1, &m->oedges)) ||
        (st = rt_u32s(L, ROMBIN_OBTR, 3 * (uint64_t)m->onf, 1, &m->otris)) ||
        (st = rt_u32s(L, ROMBIN_OBVN, 3 * (uint64_t)m->onode, 1, &m->onodes)) ||
        (st = rt_reals(L, ROMBIN_OBVB, 6 * (uint64_t)m->onode, 1, &m->obounds_rest)) ||
        (st = rt_u32s(L, ROMBIN_OBIT, (uint64_t)m->oitem, 1, &m->oitems)) ||
        (st = records(L, ROMBIN_CEDG, 2, &m->ncedge, &m->cedges)) || (st = records(L, ROMBIN_CTRI, 3, &m->nctri, &m->ctris)))
        return st;
    if ((st = rt_surface_arrays(L, m))) return st;
    rt_scratch_u32(L, (size_t)m->onv + (size_t)m->one + (size_t)m->onf + (size_t)m->onode, &m->overt_obs);
    rt_scratch(L, 3 * (size_t)m->onv, &m->ox);
    rt_scratch(L, 3 * (size_t)m->onv, &m->ox_to);
    rt_scratch(L, 3 * (size_t)m->onv, &m->ox_from);
    rt_scratch(L, 3 * (size_t)m->onv, &m->odx);
    rt_scratch(L, 3 * (size_t)m->onv, &m->cache_ox);
    rt_scratch(L, 3 * (size_t)m->onv, &m->fox0);
    { /* the app's spheres, capsules and boxes on the obstacles' path (shape_collider.c) */
        romrt_real *shapes;
        rt_scratch(L, (RT_SHAPES * sizeof(rt_shape) + sizeof(romrt_real) - 1) / sizeof(romrt_real), &shapes);
        m->shapes = (rt_shape *)(void *)shapes;
    }
    rt_scratch(L, 6 * (size_t)m->onode, &m->obounds);
    rt_scratch(L, 3 * (size_t)m->ncv, &m->ocx);
    rt_scratch(L, 3 * (size_t)m->ncv, &m->ocdx);
    rt_scratch(L, 3 * (size_t)m->ncv, &m->cache_x);
    rt_scratch(L, 3 * (size_t)m->ncv, &m->fx0);
    rt_scratch(L, 12 * (size_t)rp, &m->pair_J);
    rt_scratch(L, 12 * (size_t)rp, &m->pair_JB);
    rt_scratch(L, (size_t)(m->r + 12) * (size_t)rp, &m->pair_H);
    rt_scratch_u32(L, 5 * (size_t)cap, (uint32_t **)(void *)&m->cand);
    rt_scratch_u32(L, 4 * (size_t)cap, (uint32_t **)(void *)&m->fric_id);
    rt_scratch(L, 11 * (size_t)cap, &m->fric);
    return ROMRT_OK;
}

/* Obstacle records: a known kind, ranges that follow each other and add up to OBHD's counts;
 * each edge's and triangle's vertices its obstacle's; its motion known. */
static romrt_status obstacle_ranges(rt_loader *L, romrt_model *m)
{
    uint64_t at[4] = {0, 0, 0, 0}, k, i, j;
    const uint32_t *o;
    romrt_status st;
    for (k = 0; k < (uint64_t)m->nobs; k++) {
        o = m->obs + ROMBIN_OBST_COUNT * k;
        if (o[ROMBIN_OBST_KIND] < 1 || o[ROMBIN_OBST_KIND] > 4)
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_OBHD, "obstacle ", k, " has an unknown kind");
        for (i = ROMBIN_OBST_NODES + 1; i < ROMBIN_OBST_COUNT; i++)
            if (o[i]) return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_OBHD, "obstacle ", k, "'s reserved field is not 0");
        if (o[ROMBIN_OBST_FIRST_VERTEX] != at[0] || o[ROMBIN_OBST_FIRST_EDGE] != at[1] ||
            o[ROMBIN_OBST_FIRST_TRIANGLE] != at[2] || o[ROMBIN_OBST_ROOT] != at[3] || o[ROMBIN_OBST_NODES] == 0 ||
            o[ROMBIN_OBST_VERTICES] == 0)
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_OBHD, "obstacle ", k,
                             "'s ranges do not follow the last one's (or it has no vertex or no BVH node)");
        at[0] += o[ROMBIN_OBST_VERTICES], at[1] += o[ROMBIN_OBST_EDGES], at[2] += o[ROMBIN_OBST_TRIANGLES];
        at[3] += o[ROMBIN_OBST_NODES];
        if (at[0] > (uint64_t)m->onv || at[1] > (uint64_t)m->one || at[2] > (uint64_t)m->onf || at[3] > (uint64_t)m->onode)
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_OBHD, "obstacle ", k, "'s ranges run past the counts");
        for (i = o[ROMBIN_OBST_FIRST_EDGE]; i < at[1]; i++)
            for (j = 0; j < 2; j++)
                if (m->oedges[2 * i + j] < o[ROMBIN_OBST_FIRST_VERTEX] || m->oedges[2 * i + j] >= at[0])
                    return rt_fail_nn(L->err, ROMRT_E_MODEL, ROMBIN_OBED, "edge ", i, " names vertex ",
                                      m->oedges[2 * i + j], ", not its obstacle's");
        for (i = o[ROMBIN_OBST_FIRST_TRIANGLE]; i < at[2]; i++)
            for (j = 0; j < 3; j++)
                if (m->otris[3 * i + j] < o[ROMBIN_OBST_FIRST_VERTEX] || m->otris[3 * i + j] >= at[0])
                    return rt_fail_nn(L->err, ROMRT_E_MODEL, ROMBIN_OBTR, "triangle ", i, " names vertex ",
                                      m->otris[3 * i + j], ", not its obstacle's");
    }
    if (at[0] != (uint64_t)m->onv || at[1] != (uint64_t)m->one || at[2] != (uint64_t)m->onf || at[3] != (uint64_t)m->onode)
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_OBHD, "the obstacles' ranges do not add up to its counts");
    if ((st = rt_indices_below(L, ROMBIN_CEDG, m->cedges, (uint64_t)m->ncedge, 2, 0, 2, (uint32_t)m->ncv)) ||
        (st = rt_indices_below(L, ROMBIN_CTRI, m->ctris, (uint64_t)m->nctri, 3, 0, 3, (uint32_t)m->ncv)))
        return st;
    return ROMRT_OK;
}

/* Obstacle k's BVH: nodes [root, root + count), children after their parent and inside the range,
 * leaves' items within OBIT and of the obstacle's primitives. */
static romrt_status bvh_indices(rt_loader *L, const romrt_model *m, uint64_t k, uint64_t *items)
{
    const uint32_t *o = m->obs + ROMBIN_OBST_COUNT * k;
    uint64_t root = o[ROMBIN_OBST_ROOT], end = root + o[ROMBIN_OBST_NODES], i, j;
    uint64_t lo[3], hi[3];
    lo[0] = o[ROMBIN_OBST_FIRST_VERTEX], hi[0] = lo[0] + o[ROMBIN_OBST_VERTICES];
    lo[1] = o[ROMBIN_OBST_FIRST_EDGE], hi[1] = lo[1] + o[ROMBIN_OBST_EDGES];
    lo[2] = o[ROMBIN_OBST_FIRST_TRIANGLE], hi[2] = lo[2] + o[ROMBIN_OBST_TRIANGLES];
    for (i = root; i < end; i++) {
        const uint32_t *nd = m->onodes + 3 * i;
        if (nd[0] == 0) {
            if (nd[1] <= i || nd[1] >= end || nd[2] <= i || nd[2] >= end || nd[1] == nd[2])
                return rt_fail_nn(L->err, ROMRT_E_MODEL, ROMBIN_OBVN, "node ", i, " has a child out of range: ",
                                  nd[1] <= i || nd[1] >= end ? nd[1] : nd[2], "");
        } else if (nd[0] == 1) {
            /* leaves hold OBIT in order, each its obstacle's primitives */
            if (nd[1] != *items || nd[2] == 0 || nd[2] > (uint64_t)m->oitem - *items)
                return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_OBVN, "leaf ", i, "'s items do not follow the last leaf's in OBIT");
            for (j = nd[1]; j < (uint64_t)nd[1] + nd[2]; j++) {
                uint32_t it = m->oitems[j], type = it & 3, index = it >> 2;
                if (type > 2 || index < lo[type] || index >= hi[type])
                    return rt_fail_nn(L->err, ROMRT_E_MODEL, ROMBIN_OBIT, "item ", j, " names primitive ", it,
                                      ", not its obstacle's");
            }
            *items += nd[2];
        } else {
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_OBVN, "node ", i, " is neither inner (0) nor a leaf (1)");
        }
    }
    return ROMRT_OK;
}

/* Each non-root node has one parent and a depth within ROMBIN_BVH_DEPTH; each primitive sits in
 * one leaf (marks in overt_obs's tail, free until the first step). */
static romrt_status bvh_shape(rt_loader *L, romrt_model *m, uint64_t k)
{
    const uint32_t *o = m->obs + ROMBIN_OBST_COUNT * k;
    uint64_t root = o[ROMBIN_OBST_ROOT], end = root + o[ROMBIN_OBST_NODES], i, j, c;
    uint32_t *depth = m->overt_obs + m->onv + m->one + m->onf, *seen = m->overt_obs + m->onv, base[3];
    uint64_t prims = (uint64_t)o[ROMBIN_OBST_VERTICES] + o[ROMBIN_OBST_EDGES] + o[ROMBIN_OBST_TRIANGLES], held = 0;
    base[0] = 0, base[1] = 0, base[2] = (uint32_t)m->one; /* seen: edges, then triangles */
    for (i = root; i < end; i++) depth[i] = 0;
    depth[root] = 1;
    for (i = root; i < end; i++) {
        const uint32_t *nd = m->onodes + 3 * i;
        if (depth[i] == 0) return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_OBVN, "node ", i, " is not reached from its root");
        if (nd[0] == 0) {
            for (c = 1; c < 3; c++) {
                if (depth[nd[c]] != 0)
                    return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_OBVN, "node ", (uint64_t)nd[c], " has two parents");
                if (depth[i] >= ROMBIN_BVH_DEPTH)
                    return rt_fail_n(L->err, ROMRT_E_LIMIT, ROMBIN_OBVN, "obstacle ", k, "'s BVH is deeper than 48 levels");
                depth[nd[c]] = depth[i] + 1;
            }
            continue;
        }
        for (j = nd[1]; j < (uint64_t)nd[1] + nd[2]; j++) {
            uint32_t it = m->oitems[j], type = it & 3, index = it >> 2;
            /* seen: vertices' marks in overt_obs itself are set later; edges and triangles here */
            uint32_t *mark = type == ROMBIN_ITEM_VERTEX ? &m->overt_obs[index] : &seen[base[type] + index];
            if (*mark == 0xFFFFFFFFu)
                return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_OBIT, "item ", j, " names a primitive another leaf holds");
            *mark = 0xFFFFFFFFu;
            held++;
        }
    }
    if (held != prims)
        return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_OBIT, "obstacle ", k, "'s leaves miss some of its primitives");
    return ROMRT_OK;
}

/* Each node's stored box holds its leaves' primitives at rest (grown by the thickness) and its
 * children's boxes, to a rounding tolerance: the runtime refits its own boxes (obounds) from the
 * vertices, so these are checked, not used. */
static romrt_status bvh_boxes(rt_loader *L, romrt_model *m)
{
    int i, a;
    romrt_real tol = 0;
    for (i = 0; i < 3 * m->onv; i++)
        if (RT_FABS(m->oX[i]) > tol) tol = RT_FABS(m->oX[i]);
    for (i = 0; i < m->nobs; i++) {
        if (!(m->obs_xi[4 * i] >= 0) || m->obs_xi[4 * i + 1] != 0 || m->obs_xi[4 * i + 2] != 0 || m->obs_xi[4 * i + 3] != 0)
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_OBJS, "obstacle ", (uint64_t)i,
                             "'s thickness is negative or its reserved values are not 0");
        if (m->obs_xi[4 * i] > tol) tol = m->obs_xi[4 * i];
    }
    tol *= RT_K(1e-5);
    rt_obstacles_refit(m, 0); /* ox = oX here: the boxes at rest */
    for (i = 0; i < m->onode; i++) {
        const romrt_real *s = m->obounds_rest + 6 * (size_t)i, *b = m->obounds + 6 * (size_t)i;
        for (a = 0; a < 3; a++)
            if (!(s[a] <= s[3 + a]) || s[a] > b[a] + tol || s[3 + a] < b[3 + a] - tol)
                return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_OBVB, "node ", (uint64_t)i,
                                 "'s box does not hold what is below it");
    }
    return ROMRT_OK;
}

romrt_status rt_obstacles_contents(rt_loader *L, romrt_model *m)
{
    romrt_status st;
    uint64_t k, items = 0;
    int i;
    if (!m->surface) return ROMRT_OK;
    if ((st = obstacle_ranges(L, m))) return st;
    for (k = 0; k < (uint64_t)m->nobs; k++)
        if ((st = bvh_indices(L, m, k, &items))) return st;
    if (items != (uint64_t)m->oitem) return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_OBIT, "holds items no leaf names");
    if (!L->arena) return ROMRT_OK; /* the rest reads converted reals and writes scratch */
    for (k = 0; k < (uint64_t)m->nobs; k++)
        if ((st = rt_check_motion(L, ROMBIN_OBMO, "obstacle ", k, m->obs_motion + ROMBIN_PIN_PARAMS * k)) ||
            (st = bvh_shape(L, m, k)))
            return st;
    for (k = 0; k < (uint64_t)m->nobs; k++) { /* every vertex's obstacle (the marks above are spent) */
        const uint32_t *o = m->obs + ROMBIN_OBST_COUNT * k;
        for (i = (int)o[ROMBIN_OBST_FIRST_VERTEX]; i < (int)(o[ROMBIN_OBST_FIRST_VERTEX] + o[ROMBIN_OBST_VERTICES]); i++)
            m->overt_obs[i] = (uint32_t)k;
        if (m->obs_motion[ROMBIN_PIN_PARAMS * k] == 0) continue;
        /* each moving obstacle is its own progress unknown in a step's joint solve (contact_progress.c):
         * the Newton matrix has room for this many */
        if (m->nmovers == ROMRT_MAX_MOVING_OBSTACLES)
            return rt_fail_n(L->err, ROMRT_E_LIMIT, ROMBIN_OBMO, "obstacle ", k,
                             " moves: more moving obstacles than this runtime's ROMRT_MAX_MOVING_OBSTACLES");
        m->movers[m->nmovers++] = (int)k;
        m->obs_moving = 1;
    }
    for (i = 0; i < 3 * m->onv; i++) m->ox[i] = m->oX[i];
    if ((st = bvh_boxes(L, m))) return st;
    rt_obstacles_at(m, 0.0);
    m->cache_valid = 0;
    if (!isfinite(rt_obstacles_energy(m, m->q, 0, 0, 0, 0)))
        return m->obs_overflow
                   ? rt_fail(L->err, ROMRT_E_LIMIT, ROMBIN_OBHD, "the start has more obstacle pairs than the pair capacity")
                   : rt_fail(L->err, ROMRT_E_MODEL, m->nobs ? ROMBIN_OBVX : ROMBIN_CTRI,
                             "the start touches or crosses an obstacle, or two parts of the collision surface touch");
    return ROMRT_OK;
}
