/* The scene's obstacles other than planes (ROMBIN.md "Obstacle chunks"): the contact stage's own
 * obstacle geometry (precompute/contact/collision.c: a sphere is its centre with a thickness, a
 * capsule its segment, a box its 8 corners and 12 triangles, a mesh its vertices and triangles,
 * edges from the triangles), regrouped by obstacle, each with a BVH over its primitives at rest;
 * and the object's collision surface over the collision vertices. The runtime then gathers the
 * same stencils the reduced simulator does (object points against obstacle triangles, obstacle
 * points against object triangles, edges against edges, and, between objects or with
 * self-contact, the surface's own). With no obstacle but several objects or self-contact, OBHD
 * (counts 0, the pair capacity, the self flag) and the surface alone (1.7); and so, by default,
 * with nothing of those either (1.10): the app's spheres, capsules, boxes and meshes then collide
 * with the surface's triangles exactly, where on the collision vertices alone ("colliders":
 * "vertices") a shape thinner than an edge passes between them. The runtime leaves a surface with
 * nothing on it out of the step (rt_surface_on), so until the app places a collider the step is
 * what it was. */
#include "asset/bake_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define LEAF_ITEMS 4

typedef struct {
    const rk_contact *c;
    const int *edges;     /* this obstacle's edges (global obstacle vertex ids), 2 per edge */
    double xi;
    int first_edge, first_tri; /* where they start in OBED, OBTR */
    int *items;           /* scratch: encoded items being split */
    double *centre;       /* 3 per item (by position in items) */
    uint32_t *nodes;      /* 3 per node, grows */
    double *bounds;       /* 6 per node */
    uint32_t *out_items;
    int nnodes, nout, cap;
    int depth;
} bvh_build;

/* The box of item `it` at rest, grown by the obstacle's thickness. */
static void item_box(const bvh_build *b, int it, double *box)
{
    const rk_contact *c = b->c;
    int ids[3], n = 0, index = it >> 2;
    switch (it & 3) {
    case ROMBIN_ITEM_VERTEX: ids[n++] = index; break;
    case ROMBIN_ITEM_EDGE:
        ids[n++] = b->edges[2 * (index - b->first_edge)], ids[n++] = b->edges[2 * (index - b->first_edge) + 1];
        break;
    default:
        for (int k = 0; k < 3; k++) ids[n++] = c->ofaces[3 * index + k];
    }
    for (int a = 0; a < 3; a++) box[a] = INFINITY, box[3 + a] = -INFINITY;
    for (int k = 0; k < n; k++)
        for (int a = 0; a < 3; a++) {
            double x = c->oX[3 * ids[k] + a];
            box[a] = fmin(box[a], x - b->xi);
            box[3 + a] = fmax(box[3 + a], x + b->xi);
        }
}

/* An item's centre along the split axis, and the item: sorted by the centre (ties by the item,
 * so the order never depends on qsort's). */
typedef struct {
    double at;
    int item;
} keyed;

static int cmp_keyed(const void *pa, const void *pb)
{
    const keyed *a = pa, *b = pb;
    if (a->at != b->at) return a->at < b->at ? -1 : 1;
    return (a->item > b->item) - (a->item < b->item);
}

/* Node over items[lo, hi): a leaf of at most LEAF_ITEMS, else split at the median along the
 * longest axis of the items' centres. Children come after their parent (preorder). */
static int build(bvh_build *b, int lo, int hi, int depth, rk_error *err)
{
    if (depth >= (int)ROMBIN_BVH_DEPTH) return rk_fail(err, "obstacle BVH deeper than %u levels", ROMBIN_BVH_DEPTH);
    if (depth > b->depth) b->depth = depth;
    int node = b->nnodes++;
    double *box = b->bounds + 6 * node, ib[6];
    for (int a = 0; a < 3; a++) box[a] = INFINITY, box[3 + a] = -INFINITY;
    for (int i = lo; i < hi; i++) {
        item_box(b, b->items[i], ib);
        for (int a = 0; a < 3; a++) box[a] = fmin(box[a], ib[a]), box[3 + a] = fmax(box[3 + a], ib[3 + a]);
    }
    if (hi - lo <= LEAF_ITEMS) {
        b->nodes[3 * node] = 1, b->nodes[3 * node + 1] = (uint32_t)b->nout, b->nodes[3 * node + 2] = (uint32_t)(hi - lo);
        for (int i = lo; i < hi; i++) b->out_items[b->nout++] = (uint32_t)b->items[i];
        return 0;
    }
    double cmin[3] = {INFINITY, INFINITY, INFINITY}, cmax[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = lo; i < hi; i++) {
        item_box(b, b->items[i], ib);
        for (int a = 0; a < 3; a++) {
            double m = 0.5 * (ib[a] + ib[3 + a]);
            b->centre[3 * i + a] = m;
            cmin[a] = fmin(cmin[a], m), cmax[a] = fmax(cmax[a], m);
        }
    }
    int axis = 0;
    for (int a = 1; a < 3; a++)
        if (cmax[a] - cmin[a] > cmax[axis] - cmin[axis]) axis = a;
    /* sort by centre along the axis */
    int n = hi - lo;
    keyed *key = rk_calloc((size_t)n, sizeof *key, err);
    if (!key) return -1;
    for (int i = 0; i < n; i++) key[i].at = b->centre[3 * (lo + i) + axis], key[i].item = b->items[lo + i];
    qsort(key, (size_t)n, sizeof *key, cmp_keyed);
    for (int i = 0; i < n; i++) b->items[lo + i] = key[i].item;
    free(key);
    int mid = lo + n / 2;
    b->nodes[3 * node] = 0;
    b->nodes[3 * node + 1] = (uint32_t)b->nnodes;
    if (build(b, lo, mid, depth + 1, err)) return -1;
    b->nodes[3 * node + 2] = (uint32_t)b->nnodes;
    return build(b, mid, hi, depth + 1, err);
}

static double triangle_area(const double *a, const double *b, const double *c)
{
    double u[3], v[3], n[3];
    for (int k = 0; k < 3; k++) u[k] = b[k] - a[k], v[k] = c[k] - a[k];
    n[0] = u[1] * v[2] - u[2] * v[1], n[1] = u[2] * v[0] - u[0] * v[2], n[2] = u[0] * v[1] - u[1] * v[0];
    return 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

/* The runtime's pair capacity (ROMBIN.md OBHD): the asset option, or four times the busiest
 * gather the model has seen, at least twice the collision surface's primitives, at least 256;
 * plus, for each obstacle with triangles, its primitives under as much of it as the object's
 * surface can cover (its primitives times the object's area over its own, at most all of
 * them): a coarse object lying flat on a fine ground mesh has a candidate per ground primitive
 * beneath it, far more than its own primitives (4,000 against 2,308 for a slab on a 40 x 40 grid). */
static int pair_capacity(const rk_contact *c, const rk_asset_options *o, const int *prims, const double *area, int nobs,
                         int alone)
{
    /* a surface there for the app's colliders alone: two pairs per vertex of it, at least 256 (a
     * box's face pressed on a whole face of a coarse block, 18 vertices, takes 127: its corners,
     * edges and triangles against every primitive there, test_runtime_colliders; an app's terrain
     * under a whole face of the body about as many as the face has vertices; a larger need is
     * reported by status, naming rom.asset.contact_pairs), so the arena of a small asset stays
     * small: 80 bytes a pair in float, and the obstacles' rule (below) put 120 KB on the Cortex-M
     * test's 70 KB arena */
    if (alone) {
        double n = 2.0 * c->nv;
        if (o->contact_pairs > 0) n = o->contact_pairs;
        return n < 256 && o->contact_pairs <= 0 ? 256 : n > (double)(1 << 24) ? 1 << 24 : (int)n;
    }
    double own = 0;
    for (int t = 0; t < c->nf; t++)
        own += triangle_area(&c->X[3 * c->faces[3 * t]], &c->X[3 * c->faces[3 * t + 1]], &c->X[3 * c->faces[3 * t + 2]]);
    double cap = 2.0 * ((double)c->nv + c->ne + c->nf);
    if (4.0 * (double)c->stats.max_pairs > cap) cap = 4.0 * (double)c->stats.max_pairs;
    if (cap < 256) cap = 256;
    for (int k = 0; k < nobs; k++)
        if (area[k] > 0) cap += prims[k] * fmin(1.0, own / area[k]);
    if (o->contact_pairs > 0) cap = o->contact_pairs;
    return cap > (double)(1 << 24) ? 1 << 24 : (int)ceil(cap);
}

int rk_bake_obstacles(const rk_rom_model *m, const rk_fem *fem, const rk_asset_options *o, rombin_writer *w,
                      rk_error *err)
{
    rk_contact own;
    const rk_contact *c = &m->contact;
    int for_colliders = o->colliders == RK_COLLIDERS_SURFACE && m->ncv > 0;
    if (!m->has_contact && !(for_colliders && m->colliders_contact)) { /* a model built by another stage */
        if (!for_colliders) return 0;
        if (rk_rom_colliders_surface(m, fem, &own, err)) return -1;
        c = &own;
    }
    int nobs = 0, nobjects = 0;
    for (int k = 0; k < c->nobstacles; k++) nobs += c->obstacles[k].kind != RK_OBSTACLE_PLANE;
    for (int i = 0; i < c->nv; i++)
        if (c->object[c->vertex[i]] + 1 > nobjects) nobjects = c->object[c->vertex[i]] + 1;
    /* the surface touches other objects' (COBJ, bake_objects.c) or itself: OBHD, CEDG and CTRI
     * without obstacles (1.7); or the app's colliders may touch it (1.10) */
    int surface_pairs = nobjects > 1 || c->opt.self, alone = nobs == 0 && !surface_pairs; /* for the colliders */
    if ((alone && !for_colliders) || nobs > (int)ROMBIN_MAX_OBSTACLES) {
        if (c == &own) rk_contact_free(&own);
        return nobs ? rk_fail(err, "at most %u obstacles besides planes, the scene has %d", ROMBIN_MAX_OBSTACLES, nobs) : 0;
    }
    /* each moving obstacle is its own progress unknown in the runtime's joint solve, whose Newton
     * matrix has room for RK_MAX_MOVING_OBSTACLES (runtime/contact_progress.c) */
    for (int k = 0, moving = 0; k < c->nobstacles; k++)
        if (c->obstacles[k].kind != RK_OBSTACLE_PLANE && c->obstacles[k].motion != RK_MOTION_FIXED &&
            ++moving > RK_MAX_MOVING_OBSTACLES)
            return rk_fail(err, "obstacle %d moves: the runtime takes at most %d moving obstacles besides planes", k,
                           RK_MAX_MOVING_OBSTACLES);
    int nitems_all = c->onv + c->one + c->onf;
    /* sizes: a BVH of n items has at most 2 n / 1 nodes (leaves of 1..LEAF_ITEMS, binary splits) */
    size_t headn = ROMBIN_OBHD_COUNT + (size_t)ROMBIN_OBST_COUNT * nobs;
    uint32_t *head = calloc(headn, sizeof(uint32_t)), *nodes = calloc(6 * (size_t)nitems_all + 6, sizeof(uint32_t));
    uint32_t *items = calloc((size_t)nitems_all + 1, sizeof(uint32_t));
    double *thick = calloc(4 * (size_t)nobs + 4, sizeof(double)), *motion = calloc((size_t)ROMBIN_PIN_PARAMS * nobs + 1, sizeof(double));
    double *bounds = calloc(12 * (size_t)nitems_all + 12, sizeof(double));
    int *edges = calloc(2 * (size_t)c->one + 2, sizeof(int)), *work = calloc((size_t)nitems_all + 1, sizeof(int));
    double *centre = calloc(3 * (size_t)nitems_all + 3, sizeof(double));
    int *cedges = calloc(2 * (size_t)c->ne + 2, sizeof(int)), *ctris = calloc(3 * (size_t)c->nf + 3, sizeof(int));
    int *prims = calloc((size_t)nobs + 1, sizeof(int)), rc = -1;
    double *area = calloc((size_t)nobs + 1, sizeof(double));
    if (!head || !nodes || !items || !thick || !motion || !bounds || !edges || !work || !centre || !cedges || !ctris ||
        !prims || !area) {
        rk_fail(err, "out of memory for the obstacle chunks");
        goto done;
    }
    bvh_build b = {.c = c, .items = work, .centre = centre, .nodes = nodes, .bounds = bounds, .out_items = items};
    int j = 0, ne = 0, vfirst = 0, tfirst = 0;
    for (int k = 0; k < c->nobstacles; k++) {
        const rk_obstacle *ob = &c->obstacles[k];
        if (ob->kind == RK_OBSTACLE_PLANE) continue;
        int nv = 0, nt = 0, e0 = ne;
        while (vfirst + nv < c->onv && c->overt_obstacle[vfirst + nv] == k) nv++;
        while (tfirst + nt < c->onf && c->overt_obstacle[c->ofaces[3 * (tfirst + nt)]] == k) nt++;
        for (int e = 0; e < c->one; e++)
            if (c->overt_obstacle[c->oedges[2 * e]] == k) edges[2 * ne] = c->oedges[2 * e], edges[2 * ne + 1] = c->oedges[2 * e + 1], ne++;
        uint32_t *rec = head + ROMBIN_OBHD_COUNT + (size_t)ROMBIN_OBST_COUNT * j;
        rec[ROMBIN_OBST_KIND] = (uint32_t)ob->kind;
        rec[ROMBIN_OBST_FIRST_VERTEX] = (uint32_t)vfirst, rec[ROMBIN_OBST_VERTICES] = (uint32_t)nv;
        rec[ROMBIN_OBST_FIRST_EDGE] = (uint32_t)e0, rec[ROMBIN_OBST_EDGES] = (uint32_t)(ne - e0);
        rec[ROMBIN_OBST_FIRST_TRIANGLE] = (uint32_t)tfirst, rec[ROMBIN_OBST_TRIANGLES] = (uint32_t)nt;
        rec[ROMBIN_OBST_ROOT] = (uint32_t)b.nnodes;
        thick[4 * j] = c->othick[k];
        rk_prescribed p = {.kind = ob->motion, .rate = ob->rate};
        memcpy(p.axis, ob->axis, sizeof p.axis), memcpy(p.center, ob->motion_center, sizeof p.center);
        memcpy(p.velocity, ob->velocity, sizeof p.velocity);
        rk_bake_motion_params(&p, motion + (size_t)ROMBIN_PIN_PARAMS * j);
        int n = 0;
        for (int v = 0; v < nv; v++) work[n++] = (vfirst + v) << 2 | ROMBIN_ITEM_VERTEX;
        for (int e = e0; e < ne; e++) work[n++] = e << 2 | ROMBIN_ITEM_EDGE;
        for (int t = 0; t < nt; t++) work[n++] = (tfirst + t) << 2 | ROMBIN_ITEM_TRIANGLE;
        b.edges = edges + 2 * e0, b.first_edge = e0, b.xi = c->othick[k];
        int before = b.nnodes;
        if (build(&b, 0, n, 0, err)) goto done;
        rec[ROMBIN_OBST_NODES] = (uint32_t)(b.nnodes - before);
        prims[j] = n;
        for (int t = tfirst; t < tfirst + nt; t++)
            area[j] += triangle_area(&c->oX[3 * c->ofaces[3 * t]], &c->oX[3 * c->ofaces[3 * t + 1]], &c->oX[3 * c->ofaces[3 * t + 2]]);
        vfirst += nv, tfirst += nt, j++;
    }
    head[ROMBIN_OBHD_PAIRS] = (uint32_t)pair_capacity(c, o, prims, area, nobs, alone);
    if (vfirst != c->onv || tfirst != c->onf || ne != c->one) {
        rk_fail(err, "the obstacles' vertices or triangles are not grouped by obstacle");
        goto done;
    }
    for (int e = 0; e < c->ne; e++)
        for (int k = 0; k < 2; k++) cedges[2 * e + k] = m->cv_of[c->edges[2 * e + k]];
    for (int t = 0; t < c->nf; t++)
        for (int k = 0; k < 3; k++) ctris[3 * t + k] = m->cv_of[c->faces[3 * t + k]];
    head[ROMBIN_OBHD_OBSTACLES] = (uint32_t)nobs;
    head[ROMBIN_OBHD_VERTICES] = (uint32_t)c->onv;
    head[ROMBIN_OBHD_EDGES] = (uint32_t)c->one;
    head[ROMBIN_OBHD_TRIANGLES] = (uint32_t)c->onf;
    head[ROMBIN_OBHD_NODES] = (uint32_t)b.nnodes;
    head[ROMBIN_OBHD_ITEMS] = (uint32_t)b.nout;
    head[ROMBIN_OBHD_FLAGS] = c->opt.self ? ROMBIN_OBHD_SELF : alone ? ROMBIN_OBHD_COLLIDERS : 0;
    rc = rombin_add_u32(w, ROMBIN_OBHD, 1, head, headn, err) ? -1 : 0;
    if (!rc && nobs > 0)
        rc = rombin_add_reals(w, ROMBIN_OBJS, 1, thick, 4 * (size_t)nobs, err) ||
         rombin_add_reals(w, ROMBIN_OBMO, 1, motion, (size_t)ROMBIN_PIN_PARAMS * nobs, err) ||
         rombin_add_reals(w, ROMBIN_OBVX, 1, c->oX, 3 * (size_t)c->onv, err) ||
         rk_bake_add_u32s(w, ROMBIN_OBED, 1, edges, 2 * (size_t)c->one, err) ||
         rk_bake_add_u32s(w, ROMBIN_OBTR, 1, c->ofaces, 3 * (size_t)c->onf, err) ||
         rombin_add_u32(w, ROMBIN_OBVN, 1, nodes, 3 * (size_t)b.nnodes, err) ||
         rombin_add_reals(w, ROMBIN_OBVB, 1, bounds, 6 * (size_t)b.nnodes, err) ||
         rombin_add_u32(w, ROMBIN_OBIT, 1, items, (size_t)b.nout, err)
             ? -1 : 0;
    if (!rc)
        rc = rk_bake_add_u32s(w, ROMBIN_CEDG, 1, cedges, 2 * (size_t)c->ne, err) ||
                     rk_bake_add_u32s(w, ROMBIN_CTRI, 1, ctris, 3 * (size_t)c->nf, err)
                 ? -1 : 0;
done:
    free(head), free(nodes), free(items), free(thick), free(motion), free(bounds), free(edges), free(work), free(centre);
    free(cedges), free(ctris), free(prims), free(area);
    if (c == &own) rk_contact_free(&own);
    return rc;
}
