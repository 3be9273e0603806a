/* rk_points_proxy: a point cloud's contact surface (mesh.h): the level set d(x) = level of the
 * distance d to the nearest point, by marching tetrahedra (each lattice cube split by Kuhn's 6
 * tets, d linear in each), level = g/2 on a lattice of edge h = g/2, and the 4 corners of the tet
 * that holds each point taken as inside whatever d says there (they are within h sqrt 3 = 0.87 g
 * of it): so every point is enclosed, and a vertex on an edge out of such a corner sits next to it.
 * Vertices sit on the lattice edges, shared between tets and cubes alike (Kuhn's faces match
 * between neighbours), strictly inside each edge (d is never exactly level): the surface is
 * closed and 2-manifold, and each tet holds one plane piece of it (the interpolant is linear
 * there), so it does not cross itself. A finer lattice (g/4) bounds every vertex within 0.93 g of
 * a point without the corners' help, at 4.7 times the triangles (8,880 against 1,872 around a
 * 4 x 3 x 2 lattice of points): too many for the runtime's contact; test_mesh_points_proxy measures
 * the bound on this one (at most 0.87 g on the clouds it wraps). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/mesh_impl.h"

#define LEVEL 0.5 /* the surface's distance to the points, in g */
#define CELLS 2   /* lattice cubes per g */

static int cmp_i64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

static int cmp_pair(const void *a, const void *b)
{
    const int64_t *x = a, *y = b;
    return x[0] != y[0] ? (x[0] > y[0]) - (x[0] < y[0]) : (x[1] > y[1]) - (x[1] < y[1]);
}

/* Sorts and drops duplicates (items of `width` int64s); returns the new count. */
static size_t unique(int64_t *k, size_t n, size_t width)
{
    if (n == 0) return 0;
    qsort(k, n, width * sizeof *k, width == 1 ? cmp_i64 : cmp_pair);
    size_t m = 1;
    for (size_t i = 1; i < n; i++)
        if (memcmp(k + width * i, k + width * (m - 1), width * sizeof *k) != 0) memmove(k + width * m++, k + width * i, width * sizeof *k);
    return m;
}

/* The first item of k (n items of `width`, sorted) not below key (width int64s). */
static size_t find(const int64_t *k, size_t n, size_t width, const int64_t *key)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        int below = width == 1 ? k[mid] < key[0] : cmp_pair(k + 2 * mid, key) < 0;
        if (below) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

/* Kuhn's split of the unit cube: the 6 tets around the diagonal 000-111, one per axis order;
 * corner bits are x | y << 1 | z << 2. Faces on the cube's sides are cut along the diagonal
 * through the lower corner in every cube alike, so neighbouring cubes' faces match. */
static const int KUHN[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

/* Even permutations of a tet's corners (orientation kept) that put the lone corner first, or the
 * pair of corners first (indexed by the pair's bit mask). */
static const int LONE[4][4] = {{0, 1, 2, 3}, {1, 0, 3, 2}, {2, 0, 1, 3}, {3, 0, 2, 1}};
static const int PAIR[16][4] = {[3] = {0, 1, 2, 3}, [5] = {0, 2, 3, 1}, [9] = {0, 3, 1, 2},
                                [6] = {1, 2, 0, 3}, [10] = {1, 3, 2, 0}, [12] = {2, 3, 0, 1}};

#define S ((int64_t)1 << 20) /* lattice keys: i + S (j + S k) */

static int64_t key3(const int64_t c[3]) { return c[0] + S * (c[1] + S * c[2]); }

typedef struct {
    const double *X;
    int n;
    double lo[3], h, level, reach; /* reach: farther than this, d is clamped there */
    int64_t *bucket;               /* n (bucket key, point) pairs, sorted; buckets of edge reach */
} field;

/* d(x) - level, for x at least lo; d past reach is taken as reach (outside either way). */
static double value(const field *F, const double x[3])
{
    int64_t c[3];
    for (int d = 0; d < 3; d++) c[d] = (int64_t)floor((x[d] - F->lo[d]) / F->reach);
    double best = F->reach * F->reach;
    for (int dz = -1; dz <= 1; dz++)
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                int64_t b[3] = {c[0] + dx, c[1] + dy, c[2] + dz};
                if (b[0] < 0 || b[1] < 0 || b[2] < 0) continue;
                int64_t key[2] = {key3(b), -1};
                for (size_t i = find(F->bucket, (size_t)F->n, 2, key); i < (size_t)F->n && F->bucket[2 * i] == key[0]; i++) {
                    const double *p = F->X + 3 * F->bucket[2 * i + 1];
                    double d2 = 0;
                    for (int d = 0; d < 3; d++) d2 += (x[d] - p[d]) * (x[d] - p[d]);
                    best = fmin(best, d2);
                }
            }
    double f = sqrt(best) - F->level, eps = 1e-6 * F->h;
    /* never on the level: every crossing edge then has its vertex strictly inside it */
    return f < 0 ? fmin(f, -eps) : fmax(f, eps);
}

static void node_position(const field *F, int64_t k, double x[3])
{
    int64_t idx[3] = {k % S, k / S % S, k / S / S};
    for (int d = 0; d < 3; d++) x[d] = F->lo[d] + F->h * (double)idx[d];
}

typedef struct {
    int64_t *items; /* triangles: 3 edges of 2 node keys each */
    size_t n, cap;
} tri_list;

static int push_tri(tri_list *L, const int64_t e[6])
{
    if (L->n == L->cap) {
        size_t cap = L->cap ? 2 * L->cap : 1024;
        int64_t *p = realloc(L->items, sizeof(int64_t) * 6 * cap);
        if (!p) return -1;
        L->items = p, L->cap = cap;
    }
    for (int i = 0; i < 6; i++) L->items[6 * L->n + i] = e[i];
    L->n++;
    return 0;
}

static void edge(int64_t a, int64_t b, int64_t *e)
{
    e[0] = a < b ? a : b;
    e[1] = a < b ? b : a;
}

/* The surface's piece in one tet (corners k[4], positively oriented, values f[4]), oriented so
 * its normal points out of the level set (toward d > level). */
static int march(const int64_t k[4], const double f[4], tri_list *L)
{
    int mask = 0, inside = 0;
    for (int a = 0; a < 4; a++)
        if (f[a] < 0) mask |= 1 << a, inside++;
    int64_t e[12];
    if (inside == 1 || inside == 3) {
        /* the lone corner first (an even permutation): (e_ab, e_ac, e_ad) winds as face bcd,
         * its normal away from a: outward when a is inside */
        int lone = 0;
        while (((mask >> lone) & 1) != (inside == 1)) lone++;
        const int *p = LONE[lone];
        for (int j = 0; j < 3; j++) edge(k[p[0]], k[p[j + 1]], e + 2 * j);
        if (inside == 3) {
            int64_t t[2] = {e[2], e[3]};
            memcpy(e + 2, e + 4, 2 * sizeof *e);
            memcpy(e + 4, t, 2 * sizeof *e);
        }
        return push_tri(L, e);
    }
    if (inside != 2) return 0;
    /* (a, b) inside first: the quad (e_ac, e_ad, e_bd, e_bc) has its normal toward c, d */
    const int *p = PAIR[mask];
    edge(k[p[0]], k[p[2]], e), edge(k[p[0]], k[p[3]], e + 2), edge(k[p[1]], k[p[3]], e + 4),
        edge(k[p[1]], k[p[2]], e + 6);
    int64_t t1[6] = {e[0], e[1], e[2], e[3], e[4], e[5]}, t2[6] = {e[0], e[1], e[4], e[5], e[6], e[7]};
    return push_tri(L, t1) || push_tri(L, t2);
}

/* Kuhn's tets positively oriented (x right-handed): the last two corners swapped where needed. */
static void oriented_kuhn(int out[6][4])
{
    for (int t = 0; t < 6; t++) {
        double c[4][3];
        for (int a = 0; a < 4; a++)
            for (int d = 0; d < 3; d++) c[a][d] = (KUHN[t][a] >> d) & 1;
        memcpy(out[t], KUHN[t], sizeof out[t]);
        if (rk_tet_signed_volume(c[0], c[1], c[2], c[3]) < 0) out[t][2] = KUHN[t][3], out[t][3] = KUHN[t][2];
    }
}

int rk_points_proxy(const double *X, int n, double g, rk_mesh *out, rk_error *err)
{
    memset(out, 0, sizeof *out);
    if (n < 1 || !(g > 0) || !isfinite(g)) return rk_fail(err, "contact surface: %d points, spacing %g", n, g);
    for (int i = 0; i < n; i++)
        if (!isfinite(X[3 * i]) || !isfinite(X[3 * i + 1]) || !isfinite(X[3 * i + 2]))
            return rk_fail(err, "contact surface: point %d is not finite (%g, %g, %g)", i, X[3 * i], X[3 * i + 1],
                           X[3 * i + 2]);
    field F = {X, n, {0}, g / CELLS, LEVEL * g, 0, NULL};
    F.reach = F.level + F.h * sqrt(3.0);
    double hi[3];
    for (int d = 0; d < 3; d++) F.lo[d] = hi[d] = X[d];
    for (int i = 1; i < n; i++)
        for (int d = 0; d < 3; d++) F.lo[d] = fmin(F.lo[d], X[3 * i + d]), hi[d] = fmax(hi[d], X[3 * i + d]);
    for (int d = 0; d < 3; d++) {
        F.lo[d] -= F.level + 2 * F.h; /* the lattice's first nodes outside */
        /* range-checked as a double: converting anything past 2^63 to int64_t is undefined */
        if (!((hi[d] - F.lo[d]) / F.h < (double)(S - 4)))
            return rk_fail(err, "contact surface: spacing %g is too small for the cloud's extent %g", g, hi[d] - F.lo[d]);
    }
    int rc = -1;
    int64_t *cells = NULL, *nodes = NULL, *verts = NULL;
    double *fn = NULL;
    tri_list L = {0};
    int per = 2 * (int)ceil(F.level / F.h) + 2; /* cubes a side around a point that the ball can reach */
    F.bucket = malloc(sizeof(int64_t) * 2 * (size_t)n);
    cells = malloc(sizeof(int64_t) * (size_t)n * per * per * per);
    if (!F.bucket || !cells) goto oom;
    size_t ncell = 0;
    for (int i = 0; i < n; i++) {
        const double *p = X + 3 * i;
        int64_t c[3], b[3];
        for (int d = 0; d < 3; d++) {
            b[d] = (int64_t)floor((p[d] - F.lo[d]) / F.reach);
            c[d] = (int64_t)floor((p[d] - F.level - F.lo[d]) / F.h);
        }
        F.bucket[2 * i] = key3(b), F.bucket[2 * i + 1] = i;
        for (int dz = 0; dz < per; dz++)
            for (int dy = 0; dy < per; dy++)
                for (int dx = 0; dx < per; dx++) {
                    int64_t q[3] = {c[0] + dx, c[1] + dy, c[2] + dz};
                    cells[ncell++] = key3(q);
                }
    }
    qsort(F.bucket, (size_t)n, 2 * sizeof(int64_t), cmp_pair);
    ncell = unique(cells, ncell, 1);
    nodes = malloc(sizeof(int64_t) * 8 * ncell);
    if (!nodes) goto oom;
    for (size_t c = 0; c < ncell; c++)
        for (int b = 0; b < 8; b++) nodes[8 * c + b] = cells[c] + (b & 1) + S * (((b >> 1) & 1) + S * ((b >> 2) & 1));
    size_t nnode = unique(nodes, 8 * ncell, 1);
    fn = malloc(sizeof(double) * nnode);
    if (!fn) goto oom;
    for (size_t v = 0; v < nnode; v++) {
        double x[3];
        node_position(&F, nodes[v], x);
        fn[v] = value(&F, x);
    }
    /* each point's Kuhn tet all inside, whatever d's interpolant says: the point is enclosed */
    for (int i = 0; i < n; i++) {
        const double *p = X + 3 * i;
        int64_t c[3];
        double u[3];
        for (int d = 0; d < 3; d++) {
            double t = (p[d] - F.lo[d]) / F.h;
            c[d] = (int64_t)floor(t), u[d] = t - floor(t);
        }
        /* the tet of the path 0 -> 7 that adds the axes in the order of u, largest first */
        int a0 = u[0] >= u[1] && u[0] >= u[2] ? 0 : u[1] >= u[2] ? 1 : 2;
        int a2 = u[0] < u[1] && u[0] < u[2] ? 0 : u[1] < u[2] ? 1 : 2;
        if (a2 == a0) a2 = (a0 + 2) % 3;
        int path[4] = {0, 1 << a0, 7 - (1 << a2), 7};
        for (int j = 0; j < 4; j++) {
            int b = path[j];
            int64_t q[3] = {c[0] + (b & 1), c[1] + ((b >> 1) & 1), c[2] + ((b >> 2) & 1)}, k = key3(q);
            double *fv = &fn[find(nodes, nnode, 1, &k)];
            *fv = fmin(*fv, -1e-6 * F.h);
        }
    }
    int kuhn[6][4];
    oriented_kuhn(kuhn);
    for (size_t c = 0; c < ncell; c++) {
        int64_t corner[8];
        double fc[8];
        int inside = 0;
        for (int b = 0; b < 8; b++) {
            corner[b] = cells[c] + (b & 1) + S * (((b >> 1) & 1) + S * ((b >> 2) & 1));
            fc[b] = fn[find(nodes, nnode, 1, &corner[b])];
            inside += fc[b] < 0;
        }
        if (inside == 0 || inside == 8) continue;
        for (int t = 0; t < 6; t++) {
            int64_t k[4];
            double f[4];
            for (int a = 0; a < 4; a++) k[a] = corner[kuhn[t][a]], f[a] = fc[kuhn[t][a]];
            if (march(k, f, &L)) goto oom;
        }
    }
    if (L.n == 0) {
        rk_fail(err, "contact surface: no surface around %d points at spacing %g", n, g);
        goto out;
    }
    /* the crossing edges, each one vertex: where d's linear interpolant along it is level */
    verts = malloc(sizeof(int64_t) * 6 * L.n);
    if (!verts) goto oom;
    memcpy(verts, L.items, sizeof(int64_t) * 6 * L.n);
    size_t nvert = unique(verts, 3 * L.n, 2);
    if ((double)n + (double)nvert >= 2147483647.0 || L.n >= 536870911) {
        rk_fail(err, "contact surface: %zu vertices around %d points at spacing %g: too many", nvert, n, g);
        goto out;
    }
    out->nv = n + (int)nvert;
    out->X = malloc(sizeof(double) * 3 * (size_t)out->nv);
    out->nghost = (int)L.n;
    out->ghost = malloc(sizeof(int) * 4 * L.n);
    out->tets = malloc(sizeof(int));
    if (!out->X || !out->ghost || !out->tets) goto oom;
    memcpy(out->X, X, sizeof(double) * 3 * (size_t)n);
    for (size_t v = 0; v < nvert; v++) {
        double a[3], b[3];
        node_position(&F, verts[2 * v], a);
        node_position(&F, verts[2 * v + 1], b);
        double fa = fn[find(nodes, nnode, 1, &verts[2 * v])], fb = fn[find(nodes, nnode, 1, &verts[2 * v + 1])];
        double t = fa / (fa - fb); /* in (0, 1): the two values have opposite signs, neither 0 */
        for (int d = 0; d < 3; d++) out->X[3 * (n + v) + d] = a[d] + t * (b[d] - a[d]);
    }
    /* Each triangle as a ghost tet with the cloud's point 0 for apex: rk_mesh_boundary keeps the
     * faces that one tet holds, which are the triangles (opposite the apex, as wound), while each
     * side face (apex, edge) is shared by the two triangles across that edge of the closed
     * surface, and so dropped. Only those faces are read (never the tets' volumes). */
    for (size_t t = 0; t < L.n; t++) {
        int *T = out->ghost + 4 * t;
        T[0] = 0;
        for (int j = 0; j < 3; j++) T[1 + j] = n + (int)find(verts, nvert, 2, L.items + 6 * t + 2 * j);
    }
    rc = 0;
    goto out;
oom:
    rk_fail(err, "contact surface: out of memory");
out:
    if (rc) rk_mesh_free(out);
    free(F.bucket), free(cells), free(nodes), free(fn), free(verts), free(L.items);
    return rc;
}
