/* The collision surface against itself: the stencils between different objects' surfaces (COBJ)
 * and, with self-contact (OBHD's flag), within one surface, as the reduced simulator gathers them
 * (precompute/contact/pairs.c): collision points against collision triangles and collision edges
 * against collision edges, never two primitives that share a vertex, never two of one object
 * without self-contact. The same test on boxes (each grown by grow, over x and x + dx when swept)
 * gives the same stencils.
 *
 * The surface deforms, so nothing about it can be baked: the broad phase is a sort and sweep
 * (Baraff 1992) along the axis of the largest variance of the primitives' centres (not of their
 * range: a slab under a block spans as far in height as across, but its primitives bunch there). Each axis keeps its
 * order of the primitives in the arena, and an insertion sort brings it up to date: between two
 * calls the surface moves little, so the order is nearly sorted and the sort costs about one pass.
 * The sweep then tests only primitives whose intervals overlap on that axis. It is chosen over a
 * BVH refitted per call (a tree to traverse against itself, and a build at open) and over a
 * hashed grid (a cell size to pick for primitives of any size, the obstacles' spread included)
 * as the shortest code with no tuning; its cost is measured in docs/runtime.md. */
#include <math.h>

#include "runtime/romrt_impl.h"

/* Primitive p's collision vertices (1 to 3): points, then edges, then triangles. */
static int prim_ids(const romrt_model *m, uint32_t p, uint32_t ids[3])
{
    if (p < (uint32_t)m->ncv) {
        ids[0] = p;
        return 1;
    }
    p -= (uint32_t)m->ncv;
    if (p < (uint32_t)m->ncedge) {
        ids[0] = m->cedges[2 * (size_t)p], ids[1] = m->cedges[2 * (size_t)p + 1];
        return 2;
    }
    p -= (uint32_t)m->ncedge;
    ids[0] = m->ctris[3 * (size_t)p], ids[1] = m->ctris[3 * (size_t)p + 1], ids[2] = m->ctris[3 * (size_t)p + 2];
    return 3;
}

static uint32_t object_of(const romrt_model *m, uint32_t v)
{
    return m->cv_obj ? m->cv_obj[v] : 0;
}

/* Whether primitives a and b may touch: no shared vertex, and different objects or self-contact. */
static int allowed(const romrt_model *m, const uint32_t *a, int na, const uint32_t *b, int nb)
{
    int i, j;
    for (i = 0; i < na; i++)
        for (j = 0; j < nb; j++)
            if (a[i] == b[j]) return 0;
    return m->self_contact || object_of(m, a[0]) != object_of(m, b[0]);
}

/* The stencil of primitives a < b: point-triangle (the point first) or edge-edge (a's edge
 * first, as the precompute's a < b); 0 when their kinds make none. */
static int stencil_of(const romrt_model *m, uint32_t a, uint32_t b, int32_t id[4], int *edge_edge)
{
    uint32_t ia[3], ib[3];
    int na = prim_ids(m, a, ia), nb = prim_ids(m, b, ib), k;
    if (!((na == 1 && nb == 3) || (na == 3 && nb == 1) || (na == 2 && nb == 2)) || !allowed(m, ia, na, ib, nb))
        return 0;
    *edge_edge = na == 2;
    if (na == 3) { /* the point first */
        id[0] = (int32_t)ib[0];
        for (k = 0; k < 3; k++) id[1 + k] = (int32_t)ia[k];
        return 1;
    }
    for (k = 0; k < na; k++) id[k] = (int32_t)ia[k];
    for (k = 0; k < nb; k++) id[na + k] = (int32_t)ib[k];
    return 1;
}

int rt_surface_stencils(romrt_model *m, romrt_real grow, int swept, rt_stencil_visit visit, void *ctx)
{
    int n = m->ncv + m->ncedge + m->nctri, i, j, k, a, axis = 0, ee;
    romrt_real *B = m->sboxes, sum[3], sum2[3], var[3];
    uint32_t *ord, ids[3];
    if (!m->self_contact && m->nobjects < 2) return 0;
    for (a = 0; a < 3; a++) sum[a] = 0, sum2[a] = 0;
    for (i = 0; i < n; i++) { /* boxes, and the spread of their centres */
        romrt_real *b = B + 6 * (size_t)i;
        int np = prim_ids(m, (uint32_t)i, ids);
        for (a = 0; a < 3; a++) b[a] = (romrt_real)INFINITY, b[3 + a] = -(romrt_real)INFINITY;
        for (k = 0; k < np; k++)
            for (a = 0; a < 3; a++) {
                romrt_real x = m->ocx[3 * (size_t)ids[k] + a], e = swept ? x + m->ocdx[3 * (size_t)ids[k] + a] : x;
                if (x < b[a]) b[a] = x;
                if (x > b[3 + a]) b[3 + a] = x;
                if (e < b[a]) b[a] = e;
                if (e > b[3 + a]) b[3 + a] = e;
            }
        for (a = 0; a < 3; a++) {
            romrt_real c = (b[a] + b[3 + a]) / 2;
            b[a] -= grow, b[3 + a] += grow;
            sum[a] += c, sum2[a] += c * c;
        }
    }
    for (a = 0; a < 3; a++) var[a] = sum2[a] - sum[a] * sum[a] / (romrt_real)(n > 0 ? n : 1); /* n times it */
    for (a = 1; a < 3; a++)
        if (var[a] > var[axis]) axis = a;
    ord = m->sorder + (size_t)axis * (size_t)n;
    for (i = 1; i < n; i++) { /* insertion sort by the boxes' lower ends: nearly sorted already */
        uint32_t p = ord[i];
        romrt_real key = B[6 * (size_t)p + axis];
        for (j = i; j > 0 && B[6 * (size_t)ord[j - 1] + axis] > key; j--) ord[j] = ord[j - 1];
        ord[j] = p;
    }
    for (i = 0; i < n; i++) {
        const romrt_real *ba = B + 6 * (size_t)ord[i];
        for (j = i + 1; j < n; j++) {
            const romrt_real *bb = B + 6 * (size_t)ord[j];
            int32_t id[4];
            uint32_t p = ord[i], q = ord[j];
            if (bb[axis] > ba[3 + axis]) break; /* and every later one */
            if (ba[0] > bb[3] || ba[3] < bb[0] || ba[1] > bb[4] || ba[4] < bb[1] || ba[2] > bb[5] || ba[5] < bb[2]) continue;
            if (!stencil_of(m, p < q ? p : q, p < q ? q : p, id, &ee)) continue;
            if (visit) visit(m, ee, id, ctx);
            else if (rt_contact_keep(m, ee, id, grow)) return -1;
        }
    }
    return 0;
}
