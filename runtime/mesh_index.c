/* An app's triangle mesh collider's index (romrt.h, romrt_mesh_index_build): in memory the app
 * owns, with no allocation, the mesh validated, its unique edges, and a BVH over its vertices,
 * edges and triangles in the asset's layout (ROMBIN.md "Obstacle chunks": OBVN's nodes, OBIT's
 * items index << 2 | kind), so that contact_broad.c traverses it as it does a baked obstacle's;
 * then the mesh's world positions while placed (mesh_collider.c).
 *
 * The edges: the triangles' 3 t (min, max) vertex pairs as 64-bit keys, heap sorted in the space
 * the BVH's boxes take later, duplicates dropped: every edge once, as the precompute's
 * obstacle edges are (a shared edge taken twice would count its barrier twice). The BVH: top
 * down, each node's items split at the median of their centres along the widest axis of the
 * centres' box (a quickselect in place, O(n) a level), leaves of at most 4 items as the bake's
 * (precompute/asset/bake_obstacles.c, LEAF_ITEMS): balanced, so at most log2(n / 2) + 1 deep
 * (the traversal's stack takes 48), and at most one node per item (leaves hold 2 or more). */
#include <math.h>
#include <string.h>

#include "runtime/romrt_impl.h"

#define MESH_MAGIC 0x524d4858u /* "XHMR" */
#define LEAF_ITEMS 4u
#define BUILD_STACK 64

typedef struct {
    size_t edges, node, item, bounds, x, total;
    uint32_t ne_max, items_max, nodes_max;
} layout;

static size_t up8(size_t n) { return (n + 7) / 8 * 8; }

static int plan(size_t nv, size_t nt, layout *L)
{
    size_t at = up8(sizeof(rt_mesh)), reals = sizeof(romrt_real);
    if (nv == 0 || nt == 0 || nv > ROMRT_MESH_MAX_COUNT || nt > ROMRT_MESH_MAX_COUNT) return -1;
    L->ne_max = 3u * (uint32_t)nt;
    L->items_max = (uint32_t)nv + L->ne_max + (uint32_t)nt;
    L->nodes_max = L->items_max + 1;
    L->edges = at, at += up8(4 * 2 * (size_t)L->ne_max);
    L->node = at, at += up8(4 * 3 * (size_t)L->nodes_max);
    L->item = at, at += up8(4 * (size_t)L->items_max);
    L->bounds = at, at += up8(reals * 6 * (size_t)L->nodes_max);
    L->x = at, at += up8(reals * 4 * 3 * (size_t)nv); /* x, dx, x0, cache */
    L->total = at;
    return 0;
}

romrt_status romrt_mesh_index_size(size_t vertex_count, size_t triangle_count, size_t *index_bytes, romrt_error *err)
{
    layout L;
    if (!index_bytes) return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_mesh_index_size: index_bytes is NULL");
    if (plan(vertex_count, triangle_count, &L))
        return rt_fail_nn(err, ROMRT_E_ARGUMENT, 0, "romrt_mesh_index_size: ", (uint64_t)vertex_count,
                          " vertices and ", (uint64_t)triangle_count, " triangles (each 1 to 2^24)");
    *index_bytes = L.total;
    return ROMRT_OK;
}

/* Sift key i down the heap of n keys (max-heap). */
static void sift(uint64_t *k, size_t i, size_t n)
{
    for (;;) {
        size_t c = 2 * i + 1;
        uint64_t t;
        if (c >= n) return;
        if (c + 1 < n && k[c + 1] > k[c]) c++;
        if (k[i] >= k[c]) return;
        t = k[i], k[i] = k[c], k[c] = t;
        i = c;
    }
}

/* The unique edges of the triangles into M->edges (keys: scratch of 3 nt u64). */
static void unique_edges(rt_mesh *M, uint64_t *keys)
{
    size_t n = 3 * (size_t)M->nt, i;
    uint32_t ne = 0;
    for (i = 0; i < n; i++) {
        uint32_t a = (uint32_t)M->tri[i], b = (uint32_t)M->tri[i % 3 == 2 ? i - 2 : i + 1];
        keys[i] = a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
    }
    for (i = n / 2; i-- > 0;) sift(keys, i, n);
    for (i = n; i-- > 1;) {
        uint64_t t = keys[0];
        keys[0] = keys[i], keys[i] = t;
        sift(keys, 0, i);
    }
    for (i = 0; i < n; i++)
        if (i == 0 || keys[i] != keys[i - 1]) {
            M->edges[2 * (size_t)ne] = (uint32_t)(keys[i] >> 32);
            M->edges[2 * (size_t)ne + 1] = (uint32_t)(keys[i] & 0xFFFFFFFFu);
            ne++;
        }
    M->ne = ne;
}

/* Coordinate a of item it's centre (the mean of its 1 to 3 points, in the mesh's frame). */
static romrt_real centre(const rt_mesh *M, uint32_t it, int a)
{
    uint32_t index = it >> 2;
    const romrt_real *X = M->X;
    switch (it & 3) {
    case ROMBIN_ITEM_VERTEX: return X[3 * (size_t)index + a];
    case ROMBIN_ITEM_EDGE:
        return (X[3 * (size_t)M->edges[2 * (size_t)index] + a] + X[3 * (size_t)M->edges[2 * (size_t)index + 1] + a]) / 2;
    default:
        return (X[3 * (size_t)M->tri[3 * (size_t)index] + a] + X[3 * (size_t)M->tri[3 * (size_t)index + 1] + a] +
                X[3 * (size_t)M->tri[3 * (size_t)index + 2] + a]) /
               3;
    }
}

/* Items [lo, hi) reordered so that the one at mid has its rank along a (Hoare's quickselect). */
static void select_median(const rt_mesh *M, uint32_t *items, uint32_t lo, uint32_t hi, uint32_t mid, int a)
{
    while (hi - lo > 1) {
        romrt_real pivot = centre(M, items[lo + (hi - lo) / 2], a);
        uint32_t i = lo, j = hi - 1, t;
        while (i <= j) {
            while (centre(M, items[i], a) < pivot) i++;
            while (centre(M, items[j], a) > pivot) j--;
            if (i <= j) {
                t = items[i], items[i] = items[j], items[j] = t;
                i++;
                if (j == 0) break;
                j--;
            }
        }
        /* [lo, j] <= pivot <= [i, hi) */
        if (mid <= j) hi = j + 1;
        else if (mid >= i) lo = i;
        else return;
    }
}

static void build_bvh(rt_mesh *M)
{
    uint32_t stack[BUILD_STACK][3], top = 0, n = 0, i;
    for (i = 0; i < M->nv; i++) M->item[n++] = i << 2 | ROMBIN_ITEM_VERTEX;
    for (i = 0; i < M->ne; i++) M->item[n++] = i << 2 | ROMBIN_ITEM_EDGE;
    for (i = 0; i < M->nt; i++) M->item[n++] = i << 2 | ROMBIN_ITEM_TRIANGLE;
    M->items = n;
    M->nodes = 1;
    stack[top][0] = 0, stack[top][1] = 0, stack[top][2] = n, top++; /* node, first item, end */
    while (top > 0) {
        uint32_t node, lo, hi, mid, *nd;
        romrt_real cmin[3], cmax[3], c;
        int a, axis = 0;
        top--;
        node = stack[top][0], lo = stack[top][1], hi = stack[top][2];
        nd = M->node + 3 * (size_t)node;
        if (hi - lo <= LEAF_ITEMS) {
            nd[0] = 1, nd[1] = lo, nd[2] = hi - lo;
            continue;
        }
        for (a = 0; a < 3; a++) cmin[a] = (romrt_real)INFINITY, cmax[a] = -(romrt_real)INFINITY;
        for (i = lo; i < hi; i++)
            for (a = 0; a < 3; a++) {
                c = centre(M, M->item[i], a);
                if (c < cmin[a]) cmin[a] = c;
                if (c > cmax[a]) cmax[a] = c;
            }
        for (a = 1; a < 3; a++)
            if (cmax[a] - cmin[a] > cmax[axis] - cmin[axis]) axis = a;
        mid = lo + (hi - lo) / 2;
        select_median(M, M->item, lo, hi, mid, axis);
        nd[0] = 0, nd[1] = M->nodes, nd[2] = M->nodes + 1;
        M->nodes += 2;
        stack[top][0] = nd[2], stack[top][1] = mid, stack[top][2] = hi, top++;
        stack[top][0] = nd[1], stack[top][1] = lo, stack[top][2] = mid, top++;
    }
}

romrt_status rt_mesh_check(const romrt_mesh *mesh, int placing, romrt_error *err)
{
    const char *vertex = placing ? "romrt_set_mesh_collider: the position of vertex " : "romrt_mesh_index_build: the position of vertex ";
    const char *triangle = placing ? "romrt_set_mesh_collider: triangle " : "romrt_mesh_index_build: triangle ";
    size_t i;
    int k, j;
    for (i = 0; i < 3 * mesh->vertex_count; i++)
        if (!isfinite(mesh->positions[i])) return rt_fail_n(err, ROMRT_E_ARGUMENT, 0, vertex, (uint64_t)(i / 3), " is not finite");
    for (i = 0; i < mesh->triangle_count; i++)
        for (k = 0; k < 3; k++) {
            int32_t v = mesh->triangles[3 * (size_t)i + k];
            if (v < 0 || (size_t)v >= mesh->vertex_count)
                return rt_fail_nn(err, ROMRT_E_ARGUMENT, 0, triangle, (uint64_t)i, " names a vertex out of range, at corner ",
                                  (uint64_t)k, "");
            for (j = 0; j < k; j++)
                if (mesh->triangles[3 * (size_t)i + j] == v)
                    return rt_fail_n(err, ROMRT_E_ARGUMENT, 0, triangle, (uint64_t)i, " names one vertex twice");
        }
    return ROMRT_OK;
}

romrt_status romrt_mesh_index_build(const romrt_mesh *mesh, romrt_error *err)
{
    layout L;
    rt_mesh *M;
    unsigned char *base;
    romrt_status st;
    if (!mesh || !mesh->positions || !mesh->triangles || !mesh->index)
        return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_mesh_index_build: no mesh, positions, triangles or index (NULL)");
    if (plan(mesh->vertex_count, mesh->triangle_count, &L))
        return rt_fail_nn(err, ROMRT_E_ARGUMENT, 0, "romrt_mesh_index_build: vertex count ",
                          (uint64_t)mesh->vertex_count, " or triangle count ", (uint64_t)mesh->triangle_count,
                          " is 0 or above the limits' mesh_max_count (2^24)");
    if ((size_t)mesh->index % 8 != 0)
        return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_mesh_index_build: the index is not 8-byte aligned");
    if (mesh->index_bytes < L.total)
        return rt_fail_nn(err, ROMRT_E_ARGUMENT, 0, "romrt_mesh_index_build: the index has ", (uint64_t)mesh->index_bytes,
                          " bytes, romrt_mesh_index_size asks ", (uint64_t)L.total, "");
    if ((st = rt_mesh_check(mesh, 0, err))) return st;
    base = (unsigned char *)mesh->index;
    M = (rt_mesh *)mesh->index;
    memset(M, 0, sizeof *M);
    M->nv = (uint32_t)mesh->vertex_count, M->nt = (uint32_t)mesh->triangle_count;
    M->X = mesh->positions, M->tri = mesh->triangles;
    M->edges = (uint32_t *)(void *)(base + L.edges);
    M->node = (uint32_t *)(void *)(base + L.node);
    M->item = (uint32_t *)(void *)(base + L.item);
    M->bounds = (romrt_real *)(void *)(base + L.bounds);
    M->x = (romrt_real *)(void *)(base + L.x);
    M->dx = M->x + 3 * (size_t)M->nv, M->x0 = M->dx + 3 * (size_t)M->nv, M->cache = M->x0 + 3 * (size_t)M->nv;
    rt_mesh_build(M);
    M->magic = MESH_MAGIC;
    return ROMRT_OK;
}

void rt_mesh_build(rt_mesh *M)
{
    if (M->nt) unique_edges(M, (uint64_t *)(void *)M->bounds); /* the bounds' space, free until the first refit */
    build_bvh(M);
    memcpy(M->x, M->X, sizeof(romrt_real) * 3 * (size_t)M->nv);
    memset(M->dx, 0, sizeof(romrt_real) * 3 * (size_t)M->nv);
    rt_mesh_refit(M, 0);
}

static int index_fits(const romrt_mesh *mesh)
{
    layout L;
    return plan(mesh->vertex_count, mesh->triangle_count, &L) == 0 && mesh->index_bytes >= L.total;
}

/* Whether mesh's index was built for it (its arrays and counts), for mesh_collider.c. */
int rt_mesh_index_of(const romrt_mesh *mesh)
{
    const rt_mesh *M = (const rt_mesh *)mesh->index;
    return M && (size_t)mesh->index % 8 == 0 && mesh->index_bytes >= sizeof *M && M->magic == MESH_MAGIC &&
           M->X == mesh->positions && M->tri == mesh->triangles && M->nv == (uint32_t)mesh->vertex_count &&
           M->nt == (uint32_t)mesh->triangle_count && index_fits(mesh);
}
