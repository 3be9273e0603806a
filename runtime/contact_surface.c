/* The collision surface against itself: the stencils between different objects' surfaces (COBJ)
 * and, with self-contact (OBHD's flag), within one surface, as the reduced simulator gathers them
 * (precompute/contact/pairs.c): collision points against collision triangles and collision edges
 * against collision edges, never two primitives that share a vertex, never two of one object
 * without self-contact. The same test on boxes (each grown by grow, over x and x + dx when swept)
 * gives the same stencils.
 *
 * The surface deforms, so nothing about it can be baked: the broad phase is a sort and sweep
 * (Baraff 1992) along the axis where the fewest overlaps are expected (sweep_axis). Each axis keeps its
 * order of the primitives in the arena, and an insertion sort brings it up to date: between two
 * calls the surface moves little, so the order is nearly sorted and the sort costs about one pass
 * (an axis's first sort, from the primitives' own order, is a heap sort).
 * The order groups the primitives by object, so that without self-contact only two different
 * objects' runs are swept against each other (an object's own overlaps, most of them, are never
 * visited); the sweep tests only primitives whose intervals overlap on that axis. It is chosen over a
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

/* Primitive p's object, as the boxes' pass recorded it (sobj: the sort compares it on every step). */
static uint32_t prim_object(const romrt_model *m, uint32_t p)
{
    return m->sobj[p];
}

/* Whether primitive p (object po, lower end key) goes before primitive q. */
static int before(const romrt_model *m, const romrt_real *B, int axis, uint32_t po, romrt_real key, uint32_t q)
{
    uint32_t qo = prim_object(m, q);
    return po < qo || (po == qo && key < B[6 * (size_t)q + axis]);
}

/* Heap sort of ord[0..n) by (object, lower end): the first sort of an axis, when the order is the
 * primitives' own and an insertion sort could take n^2 / 4 moves (a voxel proxy of 10^4 faces). */
static void sift(const romrt_model *m, const romrt_real *B, int axis, uint32_t *ord, int root, int n)
{
    for (;;) {
        int c = 2 * root + 1;
        uint32_t t;
        if (c >= n) return;
        if (c + 1 < n && before(m, B, axis, prim_object(m, ord[c]), B[6 * (size_t)ord[c] + axis], ord[c + 1])) c++;
        if (!before(m, B, axis, prim_object(m, ord[root]), B[6 * (size_t)ord[root] + axis], ord[c])) return;
        t = ord[root], ord[root] = ord[c], ord[c] = t;
        root = c;
    }
}

static void heap_sort(const romrt_model *m, const romrt_real *B, int axis, uint32_t *ord, int n)
{
    int i;
    uint32_t t;
    for (i = n / 2 - 1; i >= 0; i--) sift(m, B, axis, ord, i, n);
    for (i = n - 1; i > 0; i--) {
        t = ord[0], ord[0] = ord[i], ord[i] = t;
        sift(m, B, axis, ord, 0, i);
    }
}

/* Primitives p and q, whose intervals overlap on the axis: their stencil, if their boxes touch. */
static int test_pair(romrt_model *m, const romrt_real *B, uint32_t p, uint32_t q, romrt_real grow, rt_stencil_visit visit,
                     void *ctx)
{
    const romrt_real *ba = B + 6 * (size_t)p, *bb = B + 6 * (size_t)q;
    int32_t id[4];
    int ee;
    if (ba[0] > bb[3] || ba[3] < bb[0] || ba[1] > bb[4] || ba[4] < bb[1] || ba[2] > bb[5] || ba[5] < bb[2]) return 0;
    if (!stencil_of(m, p < q ? p : q, p < q ? q : p, id, &ee)) return 0;
    if (visit) {
        visit(m, ee, id, ctx);
        return 0;
    }
    return rt_contact_keep(m, ee, id, grow);
}

/* The pairs within ord[a0..a1) (one object's run, sorted by lower end). */
static int sweep_one(romrt_model *m, const romrt_real *B, int axis, const uint32_t *ord, int a0, int a1, romrt_real grow,
                     rt_stencil_visit visit, void *ctx)
{
    int i, j;
    for (i = a0; i < a1; i++)
        for (j = i + 1; j < a1 && B[6 * (size_t)ord[j] + axis] <= B[6 * (size_t)ord[i] + 3 + axis]; j++)
            if (test_pair(m, B, ord[i], ord[j], grow, visit, ctx)) return -1;
    return 0;
}

/* Whether box b (lo 3, hi 3) meets hull h (an object's sstat: lo 3, hi 3). */
static int meets(const romrt_real *b, const romrt_real *h)
{
    return !(b[0] > h[3] || b[3] < h[0] || b[1] > h[4] || b[4] < h[1] || b[2] > h[5] || b[5] < h[2]);
}

/* The pairs between two runs (objects with hulls ha and hb), each sorted by lower end: whichever
 * starts first is tested against the other run's primitives that start before it ends, then
 * dropped; each overlap once. A primitive whose box misses the other object's hull can touch none
 * of its primitives and is dropped untested (in a pile most of each object is away from each
 * neighbour, while their runs overlap along any one axis). */
static int sweep_two(romrt_model *m, const romrt_real *B, int axis, const uint32_t *ord, int a0, int a1, int b0, int b1,
                     const romrt_real *ha, const romrt_real *hb, romrt_real grow, rt_stencil_visit visit, void *ctx)
{
    int i = a0, j = b0, k;
    while (i < a1 && j < b1) {
        romrt_real la = B[6 * (size_t)ord[i] + axis], lb = B[6 * (size_t)ord[j] + axis];
        if (la <= lb) {
            if (meets(B + 6 * (size_t)ord[i], hb))
                for (k = j; k < b1 && B[6 * (size_t)ord[k] + axis] <= B[6 * (size_t)ord[i] + 3 + axis]; k++)
                    if (test_pair(m, B, ord[i], ord[k], grow, visit, ctx)) return -1;
            i++;
        } else {
            if (meets(B + 6 * (size_t)ord[j], ha))
                for (k = i; k < a1 && B[6 * (size_t)ord[k] + axis] <= B[6 * (size_t)ord[j] + 3 + axis]; k++)
                    if (test_pair(m, B, ord[k], ord[j], grow, visit, ctx)) return -1;
            j++;
        }
    }
    return 0;
}

/* The sweep's axis: the one where the fewest pairs of primitives are expected to overlap, from
 * each object's hull [lo, hi], primitive count n and mean width w on it. Two objects' primitives
 * spread evenly over their hulls overlap about n_a n_b (w_a + w_b) c / (e_a e_b) times, c the
 * hulls' common length and e their extents; one object's own, with self-contact, n^2 w / e. A
 * flat object lying on another along the axis of their contact: no common length but the contact
 * layer, where the variance of the centres or their range would sweep across both flat sides (a
 * splat donut on a block of points: most of a step). */
static int sweep_axis(const romrt_model *m, int nobj)
{
    const romrt_real *S = m->sstat;
    romrt_real est[3], tiny = (romrt_real)1e-30;
    int a, o, p, axis = 0;
    for (a = 0; a < 3; a++) {
        est[a] = 0;
        for (o = 0; o < nobj; o++) {
            const romrt_real *so = S + 10 * (size_t)o;
            romrt_real eo = so[3 + a] - so[a], wo = so[9] > 0 ? so[6 + a] / so[9] : 0;
            if (!(so[9] > 0)) continue;
            if (m->self_contact) est[a] += so[9] * so[9] * wo / (eo + tiny);
            for (p = o + 1; p < nobj; p++) {
                const romrt_real *sp = S + 10 * (size_t)p;
                romrt_real ep = sp[3 + a] - sp[a], wp = sp[9] > 0 ? sp[6 + a] / sp[9] : 0;
                romrt_real c = (so[3 + a] < sp[3 + a] ? so[3 + a] : sp[3 + a]) - (so[a] > sp[a] ? so[a] : sp[a]);
                if (sp[9] > 0 && c > 0) est[a] += so[9] * sp[9] * (wo + wp) * c / ((eo + tiny) * (ep + tiny));
            }
        }
    }
    for (a = 1; a < 3; a++)
        if (est[a] < est[axis]) axis = a;
    return axis;
}

int rt_surface_stencils(romrt_model *m, romrt_real grow, int swept, rt_stencil_visit visit, void *ctx)
{
    int n = m->ncv + m->ncedge + m->nctri, nobj = m->nobjects > 0 ? m->nobjects : 1, i, j, k, a, axis;
    romrt_real *B = m->sboxes, *S = m->sstat;
    uint32_t *ord, ids[3];
    if (!m->self_contact && m->nobjects < 2) return 0;
    for (i = 0; i < 10 * nobj; i++) S[i] = i % 10 < 3 ? (romrt_real)INFINITY : i % 10 < 6 ? -(romrt_real)INFINITY : 0;
    for (i = 0; i < n; i++) { /* boxes, and each object's hull, widths and count */
        romrt_real *b = B + 6 * (size_t)i, *so;
        int np = prim_ids(m, (uint32_t)i, ids);
        m->sobj[i] = object_of(m, ids[0]);
        so = S + 10 * (size_t)m->sobj[i];
        if (np == 1) { /* a point (they come first) */
            for (a = 0; a < 3; a++) {
                romrt_real x = m->ocx[3 * (size_t)ids[0] + a], e = swept ? x + m->ocdx[3 * (size_t)ids[0] + a] : x;
                b[a] = (e < x ? e : x) - grow, b[3 + a] = (e > x ? e : x) + grow;
            }
        } else { /* an edge or triangle: its points' boxes' union (rounding is monotone: the
                  * same bits as growing the union) */
            for (a = 0; a < 6; a++) b[a] = B[6 * (size_t)ids[0] + a];
            for (k = 1; k < np; k++)
                for (a = 0; a < 3; a++) {
                    const romrt_real *c = B + 6 * (size_t)ids[k];
                    if (c[a] < b[a]) b[a] = c[a];
                    if (c[3 + a] > b[3 + a]) b[3 + a] = c[3 + a];
                }
        }
        for (a = 0; a < 3; a++) {
            if (b[a] < so[a]) so[a] = b[a];
            if (b[3 + a] > so[3 + a]) so[3 + a] = b[3 + a];
            so[6 + a] += b[3 + a] - b[a];
        }
        so[9] += 1;
    }
    axis = sweep_axis(m, nobj);
    ord = m->sorder + (size_t)axis * (size_t)n;
    if (!(m->ssorted & (1 << axis))) { /* this axis's first use: from any order, in O(n log n) */
        heap_sort(m, B, axis, ord, n);
        m->ssorted |= 1 << axis;
    }
    for (i = 1; i < n; i++) { /* insertion sort by object, then lower end: nearly sorted already */
        uint32_t p = ord[i], po = prim_object(m, p);
        romrt_real key = B[6 * (size_t)p + axis];
        for (j = i; j > 0 && before(m, B, axis, po, key, ord[j - 1]); j--) ord[j] = ord[j - 1];
        ord[j] = p;
    }
    /* each object's run of the order: first[o] to first[o + 1] */
    for (k = 0, i = 0; k <= nobj; k++) {
        while (i < n && (int)prim_object(m, ord[i]) < k) i++;
        m->sfirst[k] = (uint32_t)i;
    }
    for (k = 0; k < nobj; k++) {
        int a0 = (int)m->sfirst[k], a1 = (int)m->sfirst[k + 1], o;
        if (m->self_contact && sweep_one(m, B, axis, ord, a0, a1, grow, visit, ctx)) return -1;
        for (o = k + 1; o < nobj; o++) /* objects whose hulls are apart have no pair */
            if (meets(S + 10 * (size_t)k, S + 10 * (size_t)o) &&
                sweep_two(m, B, axis, ord, a0, a1, (int)m->sfirst[o], (int)m->sfirst[o + 1], S + 10 * (size_t)k,
                          S + 10 * (size_t)o, grow, visit, ctx))
                return -1;
    }
    return 0;
}
