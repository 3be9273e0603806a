/* rk_mesh_refine: uniform 1:8 ("red") refinement of a tet mesh.
 *
 * Each tet (v0, v1, v2, v3) gets a vertex at the midpoint of each of its six edges. The four
 * corner tets are the parent shrunk by half about each of its vertices; the octahedron left in
 * the middle is cut into four tets around the shortest of its three diagonals (m01-m23, m02-m13,
 * m03-m12; the first of equal ones), which keeps the children closest to the parent's shape
 * (Bey 1995, Zhang 1995). The octahedron's faces are never cut, so every face of the parent is
 * split into the same four triangles whichever diagonal it takes: the refined mesh is conforming
 * because an edge's midpoint is one vertex, created once for the edge whatever tets share it.
 *
 * Edges are found per vertex: the edges (a, b), a < b, of every tet listed in a's row, each row
 * sorted and its duplicates dropped. Midpoint vertices are numbered after the old ones in the order
 * of (a, b), so the result depends only on the input (no hashing, no threads). Each child is the
 * affine image of a fixed child of the reference tet, listed below with its orientation checked
 * there, so it has its parent's orientation without a floating-point test. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/mesh_impl.h"

/* A tet's edges as local vertex pairs; local node 4 + e is the midpoint of edge e. */
static const int EDGE[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
enum { M01 = 4, M02, M03, M12, M13, M23 };

/* The four corners: the parent scaled by 1/2 about v0, v1, v2 and v3 (vertex order kept). */
static const int CORNER[4][4] = {
    {0, M01, M02, M03}, {M01, 1, M12, M13}, {M02, M12, 2, M23}, {M03, M13, M23, 3}};
/* The octahedron around each diagonal: the diagonal, then two neighbours along the ring of the
 * other four midpoints, ordered so that on the reference tet (0,0,0), (1,0,0), (0,1,0), (0,0,1)
 * each has 6 x volume +1/8, like the corners (tests/unit/test_mesh_refine.c checks it). */
static const int DIAGONAL[3][2] = {{M01, M23}, {M02, M13}, {M03, M12}};
static const int INNER[3][4][4] = {
    {{M01, M23, M02, M03}, {M01, M23, M03, M13}, {M01, M23, M13, M12}, {M01, M23, M12, M02}},
    {{M02, M13, M03, M01}, {M02, M13, M23, M03}, {M02, M13, M12, M23}, {M02, M13, M01, M12}},
    {{M03, M12, M01, M02}, {M03, M12, M02, M23}, {M03, M12, M23, M13}, {M03, M12, M13, M01}}};

/* The edges of one level: row a (a vertex) holds the b > a it shares an edge with, ascending. */
typedef struct {
    int nv;
    int *start;  /* nv + 1: row a is b[start[a] .. start[a] + count[a]) */
    int *count;  /* nv: distinct neighbours in each row */
    int *first;  /* nv: index, among all edges, of row a's first edge */
    int *b;      /* the rows */
    int nedges;
} edge_rows;

static void edge_rows_free(edge_rows *r)
{
    free(r->start);
    free(r->count);
    free(r->first);
    free(r->b);
    *r = (edge_rows){0};
}

static int cmp_int(const void *x, const void *y)
{
    int a = *(const int *)x, b = *(const int *)y;
    return (a > b) - (a < b);
}

/* Sorts v[0..n) ascending and drops repeats; returns how many are left. */
static int sort_unique(int *v, int n)
{
    if (n > 24) qsort(v, (size_t)n, sizeof *v, cmp_int);
    else
        for (int i = 1; i < n; i++)
            for (int j = i; j > 0 && v[j - 1] > v[j]; j--) {
                int s = v[j];
                v[j] = v[j - 1];
                v[j - 1] = s;
            }
    int u = 0;
    for (int i = 0; i < n; i++)
        if (u == 0 || v[i] != v[u - 1]) v[u++] = v[i];
    return u;
}

static int build_edges(const rk_mesh *m, edge_rows *r, rk_error *err)
{
    *r = (edge_rows){.nv = m->nv};
    r->start = rk_calloc((size_t)m->nv + 1, sizeof *r->start, err);
    r->count = rk_calloc((size_t)m->nv, sizeof *r->count, err);
    r->first = rk_calloc((size_t)m->nv, sizeof *r->first, err);
    r->b = rk_calloc(6 * (size_t)m->nt, sizeof *r->b, err);
    if (!r->start || !r->count || !r->first || !r->b) {
        edge_rows_free(r);
        return -1;
    }
    for (size_t t = 0; t < (size_t)m->nt; t++) {
        const int *v = m->tets + 4 * t;
        for (int e = 0; e < 6; e++) {
            int a = v[EDGE[e][0]], b = v[EDGE[e][1]];
            r->start[(a < b ? a : b) + 1]++;
        }
    }
    for (int a = 0; a < m->nv; a++) r->start[a + 1] += r->start[a];
    for (size_t t = 0; t < (size_t)m->nt; t++) {
        const int *v = m->tets + 4 * t;
        for (int e = 0; e < 6; e++) {
            int a = v[EDGE[e][0]], b = v[EDGE[e][1]];
            if (a > b) {
                int s = a;
                a = b;
                b = s;
            }
            r->b[r->start[a] + r->count[a]++] = b;
        }
    }
    long total = 0;
    for (int a = 0; a < m->nv; a++) {
        r->count[a] = sort_unique(r->b + r->start[a], r->count[a]);
        r->first[a] = (int)total;
        total += r->count[a];
    }
    if (total > RK_MESH_MAX_COUNT - (long)m->nv) {
        edge_rows_free(r);
        return rk_fail(err, "%d vertices and %ld edge midpoints are too many vertices", m->nv, total);
    }
    r->nedges = (int)total;
    return 0;
}

/* The new vertex at the midpoint of (a, b): old vertex count + the edge's index; -1 when (a, b)
 * is not an edge of the tets. */
static int midpoint_of(const edge_rows *r, int a, int b)
{
    if (a > b) {
        int s = a;
        a = b;
        b = s;
    }
    const int *row = r->b + r->start[a];
    int lo = 0, hi = r->count[a];
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (row[mid] < b) lo = mid + 1;
        else hi = mid;
    }
    return lo < r->count[a] && row[lo] == b ? r->nv + r->first[a] + lo : -1;
}

static double dist2(const double *p, const double *q)
{
    double d0 = p[0] - q[0], d1 = p[1] - q[1], d2 = p[2] - q[2];
    return d0 * d0 + d1 * d1 + d2 * d2;
}

/* The eight children of the tet v (its ten nodes given) into out[0..32). X holds the midpoints. */
static void split(const int node[10], const double *X, int *out)
{
    int best = 0;
    double len = dist2(X + 3 * (size_t)node[DIAGONAL[0][0]], X + 3 * (size_t)node[DIAGONAL[0][1]]);
    for (int d = 1; d < 3; d++) {
        double l = dist2(X + 3 * (size_t)node[DIAGONAL[d][0]], X + 3 * (size_t)node[DIAGONAL[d][1]]);
        if (l < len) {
            len = l;
            best = d;
        }
    }
    for (int c = 0; c < 4; c++)
        for (int k = 0; k < 4; k++) {
            out[4 * c + k] = node[CORNER[c][k]];
            out[16 + 4 * c + k] = node[INNER[best][c][k]];
        }
}

/* The ten nodes of tet v: its vertices, then its edges' midpoints (-1 where an edge is missing). */
static void nodes_of(const edge_rows *r, const int *v, int node[10])
{
    for (int k = 0; k < 4; k++) node[k] = v[k];
    for (int e = 0; e < 6; e++) node[4 + e] = midpoint_of(r, v[EDGE[e][0]], v[EDGE[e][1]]);
}

/* One level: in -> out (out empty on failure). */
static int refine_once(const rk_mesh *in, rk_mesh *out, rk_error *err)
{
    *out = (rk_mesh){0};
    edge_rows r;
    if (build_edges(in, &r, err)) return -1;
    size_t nv = (size_t)in->nv + (size_t)r.nedges;
    out->X = rk_calloc(3 * nv, sizeof *out->X, err);
    out->tets = rk_calloc(32 * (size_t)in->nt, sizeof *out->tets, err);
    if (in->tet_tag) out->tet_tag = rk_calloc(8 * (size_t)in->nt, sizeof *out->tet_tag, err);
    if (in->nghost) out->ghost = rk_calloc(32 * (size_t)in->nghost, sizeof *out->ghost, err);
    if (!out->X || !out->tets || (in->tet_tag && !out->tet_tag) || (in->nghost && !out->ghost)) goto fail;
    out->nv = (int)nv;
    out->nt = 8 * in->nt;
    memcpy(out->X, in->X, 3 * sizeof *in->X * (size_t)in->nv);
    for (int a = 0; a < in->nv; a++)
        for (int j = 0; j < r.count[a]; j++) {
            const double *p = in->X + 3 * (size_t)a, *q = in->X + 3 * (size_t)r.b[r.start[a] + j];
            double *mid = out->X + 3 * ((size_t)in->nv + (size_t)r.first[a] + (size_t)j);
            for (int k = 0; k < 3; k++) mid[k] = 0.5 * (p[k] + q[k]);
        }
    for (size_t t = 0; t < (size_t)in->nt; t++) {
        int node[10];
        nodes_of(&r, in->tets + 4 * t, node);
        split(node, out->X, out->tets + 32 * t);
        if (in->tet_tag)
            for (int c = 0; c < 8; c++) out->tet_tag[8 * t + c] = in->tet_tag[t];
    }
    /* Ghost tets (flat tets kept inside the body, mesh.h) are split with the same midpoints so
     * their faces still match the body's. Every edge of a ghost is expected to be a tet's. */
    for (int g = 0; g < in->nghost; g++) {
        const int *v = in->ghost + 4 * (size_t)g;
        int node[10];
        nodes_of(&r, v, node);
        for (int e = 0; e < 6; e++)
            if (node[4 + e] < 0) {
                rk_fail(err, "ghost tet %d (vertices %d %d %d %d): its edge (%d, %d) belongs to no tet, so its "
                             "midpoint would be a vertex of ghosts only",
                        g, v[0], v[1], v[2], v[3], v[EDGE[e][0]], v[EDGE[e][1]]);
                goto fail;
            }
        split(node, out->X, out->ghost + 32 * (size_t)g);
    }
    out->nghost = 8 * in->nghost;
    edge_rows_free(&r);
    return 0;
fail:
    edge_rows_free(&r);
    rk_mesh_free(out);
    return -1;
}

static int validate(const rk_mesh *m, int levels, rk_error *err)
{
    if (levels < 0 || levels > RK_MESH_REFINE_MAX_LEVELS)
        return rk_fail(err, "refine: %d levels asked for; levels run from 0 to %d (each multiplies the tets by 8)",
                       levels, RK_MESH_REFINE_MAX_LEVELS);
    if (m->nt <= 0 || m->nv <= 0 || !m->X || !m->tets)
        return rk_fail(err, "refine: the mesh has no tets (%d vertices, %d tets)", m->nv, m->nt);
    double tets = (double)m->nt;
    for (int l = 0; l < levels; l++) tets *= 8;
    if (tets > RK_MESH_REFINE_MAX_TETS)
        return rk_fail(err, "refine: %d levels would turn %d tets into %.0f, more than the %d a refinement may make",
                       levels, m->nt, tets, RK_MESH_REFINE_MAX_TETS);
    for (int pass = 0; pass < 2; pass++) {
        const int *tets_of = pass ? m->ghost : m->tets;
        int n = pass ? m->nghost : m->nt;
        for (int t = 0; t < n; t++) {
            const int *v = tets_of + 4 * (size_t)t;
            for (int k = 0; k < 4; k++) {
                if (v[k] < 0 || v[k] >= m->nv)
                    return rk_fail(err, "refine: %s %d references vertex %d, but there are %d vertices",
                                   pass ? "ghost tet" : "tet", t, v[k], m->nv);
                for (int j = 0; j < k; j++)
                    if (v[j] == v[k])
                        return rk_fail(err, "refine: %s %d (vertices %d %d %d %d) uses vertex %d twice",
                                       pass ? "ghost tet" : "tet", t, v[0], v[1], v[2], v[3], v[k]);
            }
        }
    }
    return 0;
}

int rk_mesh_refine(const rk_mesh *in, int levels, rk_mesh *out, rk_error *err)
{
    *out = (rk_mesh){0};
    if (validate(in, levels, err)) return -1;
    rk_mesh cur = {0};
    const rk_mesh *src = in;
    if (levels == 0) { /* a copy */
        cur.nv = in->nv;
        cur.nt = in->nt;
        cur.nghost = in->nghost;
        cur.X = rk_calloc(3 * (size_t)in->nv, sizeof *cur.X, err);
        cur.tets = rk_calloc(4 * (size_t)in->nt, sizeof *cur.tets, err);
        if (in->tet_tag) cur.tet_tag = rk_calloc((size_t)in->nt, sizeof *cur.tet_tag, err);
        if (in->nghost) cur.ghost = rk_calloc(4 * (size_t)in->nghost, sizeof *cur.ghost, err);
        if (!cur.X || !cur.tets || (in->tet_tag && !cur.tet_tag) || (in->nghost && !cur.ghost)) {
            rk_mesh_free(&cur);
            return -1;
        }
        memcpy(cur.X, in->X, 3 * sizeof *cur.X * (size_t)in->nv);
        memcpy(cur.tets, in->tets, 4 * sizeof *cur.tets * (size_t)in->nt);
        if (in->tet_tag) memcpy(cur.tet_tag, in->tet_tag, sizeof *cur.tet_tag * (size_t)in->nt);
        if (in->nghost) memcpy(cur.ghost, in->ghost, 4 * sizeof *cur.ghost * (size_t)in->nghost);
        *out = cur;
        return 0;
    }
    for (int l = 0; l < levels; l++) {
        rk_mesh next;
        int rc = refine_once(src, &next, err);
        if (src != in) rk_mesh_free(&cur);
        if (rc) return rk_error_prefix(err, "refine (level %d of %d)", l + 1, levels);
        cur = next;
        src = &cur;
    }
    *out = cur;
    return 0;
}
