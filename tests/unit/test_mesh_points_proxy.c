/* precompute/mesh rk_points_proxy: a point cloud's contact proxy, the union of the voxels of edge g
 * that hold a point, as ghost tets. Checked from its output alone, against geometry computed here:
 *   - the points come first, unchanged; no tets; ghost tets of volume g^3 / 6, six to a voxel,
 *     their corners on the voxel's corners; every corner used;
 *   - the voxels are exactly those holding a point (each point's voxel is one of them, each of
 *     them holds a point), and the corners are the voxels' distinct corners;
 *   - rk_mesh_boundary of the ghost tets is closed and consistently oriented (each directed edge
 *     matched by its reverse), its area is the voxels' exposed faces times g^2, and the volume it
 *     encloses (divergence theorem) is the voxel count times g^3;
 *   - a ray from every point crosses the boundary an odd number of times, and from points off
 *     the union an even number;
 *   - bad input fails. */
#include "mesh/mesh.h"
#include "testlib.h"
#include "util/util.h"

#include <stdint.h>

static uint64_t rng = 31337;
static double uni(void) { return rk_uniform(&rng); }

/* Integer voxel of x on the lattice of corner o and spacing g (floor). */
static void voxel_of(const double *x, const double o[3], double g, long v[3])
{
    for (int d = 0; d < 3; d++) v[d] = (long)floor((x[d] - o[d]) / g);
}

static int64_t key_of(const long v[3]) { return (int64_t)(v[0] + 4096) + 8192 * ((int64_t)(v[1] + 4096) + 8192 * (int64_t)(v[2] + 4096)); }

static int cmp64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

static int has(const int64_t *keys, int n, int64_t k) { return bsearch(&k, keys, (size_t)n, sizeof k, cmp64) != NULL; }

/* Sorts and drops duplicates; returns the count. */
static int unique64(int64_t *k, int n)
{
    qsort(k, (size_t)n, sizeof *k, cmp64);
    int m = 0;
    for (int i = 0; i < n; i++)
        if (m == 0 || k[i] != k[m - 1]) k[m++] = k[i];
    return m;
}

/* Ray from p along d against triangle (a, b, c): 1 if it crosses at t > 0 (Moller-Trumbore). */
static int ray_hits(const double *p, const double *d, const double *a, const double *b, const double *c)
{
    double e1[3], e2[3], s[3], h[3], qv[3];
    for (int k = 0; k < 3; k++) e1[k] = b[k] - a[k], e2[k] = c[k] - a[k], s[k] = p[k] - a[k];
    h[0] = d[1] * e2[2] - d[2] * e2[1], h[1] = d[2] * e2[0] - d[0] * e2[2], h[2] = d[0] * e2[1] - d[1] * e2[0];
    double det = e1[0] * h[0] + e1[1] * h[1] + e1[2] * h[2];
    if (fabs(det) < 1e-300) return 0;
    double u = (s[0] * h[0] + s[1] * h[1] + s[2] * h[2]) / det;
    if (u < 0 || u > 1) return 0;
    qv[0] = s[1] * e1[2] - s[2] * e1[1], qv[1] = s[2] * e1[0] - s[0] * e1[2], qv[2] = s[0] * e1[1] - s[1] * e1[0];
    double v = (d[0] * qv[0] + d[1] * qv[1] + d[2] * qv[2]) / det;
    if (v < 0 || u + v > 1) return 0;
    return (e2[0] * qv[0] + e2[1] * qv[1] + e2[2] * qv[2]) / det > 0;
}

static int crossings(const double *p, const rk_mesh *m, const int *tris, int nf)
{
    static const double d[3] = {0.5773, 0.4471, 0.6833}; /* generic: no lattice plane or edge along it */
    int c = 0;
    for (int f = 0; f < nf; f++)
        c += ray_hits(p, d, &m->X[3 * tris[3 * f]], &m->X[3 * tris[3 * f + 1]], &m->X[3 * tris[3 * f + 2]]);
    return c;
}

/* What the checks measured. */
typedef struct {
    int voxels, corners, faces;
    double volume_error, area_error, tet_volume_error;
} proxy_stats;

/* Every check above on the proxy of (X, n) with voxel g; expect_voxels >= 0 also checks the count.
 * Returns 0 or leaves a message in why. */
static int check_proxy(const double *X, int n, double g, int expect_voxels, proxy_stats *st, char *why, size_t len)
{
    rk_error err;
    rk_mesh m;
    memset(st, 0, sizeof *st);
#define FAIL_IF(cond, ...)                          \
    do {                                            \
        if (cond) {                                 \
            snprintf(why, len, __VA_ARGS__);        \
            rc = -1;                                \
            goto done;                              \
        }                                           \
    } while (0)
    int rc = 0, *tris = NULL, nf = 0;
    int64_t *vox = NULL, *pvox = NULL, *corner = NULL, *edges = NULL;
    if (rk_points_proxy(X, n, g, &m, &err)) {
        snprintf(why, len, "rk_points_proxy: %s", err.msg);
        return -1;
    }
    FAIL_IF(m.nt != 0, "%d tets (expected none)", m.nt);
    FAIL_IF(m.nv <= n || memcmp(m.X, X, sizeof(double) * 3 * (size_t)n) != 0, "the first %d vertices are not the points", n);
    FAIL_IF(m.nghost < 6 || m.nghost % 6 != 0, "%d ghost tets", m.nghost);
    const double *o = &m.X[3 * n]; /* a corner: the lattice's origin */
    int nv = m.nghost / 6;
    vox = calloc((size_t)m.nghost, sizeof *vox);
    unsigned char *used = calloc((size_t)m.nv, 1);
    /* each ghost tet: positive volume g^3 / 6, corners on the corners of the voxel holding its centroid */
    for (int t = 0; t < m.nghost; t++) {
        const int *T = &m.ghost[4 * t];
        double c[3] = {0, 0, 0};
        for (int k = 0; k < 4; k++) {
            if (T[k] < n || T[k] >= m.nv) {
                free(used);
                FAIL_IF(1, "ghost tet %d uses vertex %d (the corners are %d..%d)", t, T[k], n, m.nv - 1);
            }
            used[T[k]] = 1;
            for (int d = 0; d < 3; d++) c[d] += 0.25 * m.X[3 * T[k] + d];
        }
        double vol = rk_tet_signed_volume(&m.X[3 * T[0]], &m.X[3 * T[1]], &m.X[3 * T[2]], &m.X[3 * T[3]]);
        st->tet_volume_error = fmax(st->tet_volume_error, fabs(vol - g * g * g / 6) / (g * g * g / 6));
        long v[3];
        voxel_of(c, o, g, v);
        vox[t] = key_of(v);
        for (int k = 0; k < 4; k++)
            for (int d = 0; d < 3; d++) {
                double rel = (m.X[3 * T[k] + d] - o[d]) / g - v[d]; /* 0 or 1 */
                if (fabs(rel) > 1e-9 && fabs(rel - 1) > 1e-9) {
                    free(used);
                    FAIL_IF(1, "ghost tet %d: vertex %d is not a corner of its voxel (offset %g)", t, T[k], rel);
                }
            }
    }
    for (int i = n; i < m.nv; i++)
        if (!used[i]) {
            free(used);
            FAIL_IF(1, "corner vertex %d is in no ghost tet", i);
        }
    free(used);
    FAIL_IF(st->tet_volume_error > 1e-9, "a ghost tet's volume is off g^3/6 by %.3g (relative)", st->tet_volume_error);
    /* six tets to a voxel */
    qsort(vox, (size_t)m.nghost, sizeof *vox, cmp64);
    for (int i = 0; i < m.nghost; i += 6) FAIL_IF(vox[i] != vox[i + 5] || (i + 6 < m.nghost && vox[i + 6] == vox[i]), "a voxel without exactly 6 tets");
    st->voxels = unique64(vox, m.nghost);
    FAIL_IF(st->voxels != nv, "%d voxels for %d ghost tets", st->voxels, m.nghost);
    FAIL_IF(expect_voxels >= 0 && st->voxels != expect_voxels, "%d voxels, expected %d", st->voxels, expect_voxels);
    /* the voxels are those holding a point */
    pvox = calloc((size_t)n, sizeof *pvox);
    for (int i = 0; i < n; i++) {
        long v[3];
        voxel_of(&X[3 * i], o, g, v);
        pvox[i] = key_of(v);
        FAIL_IF(!has(vox, st->voxels, pvox[i]), "point %d (%g, %g, %g) is in no voxel of the proxy", i, X[3 * i], X[3 * i + 1], X[3 * i + 2]);
    }
    FAIL_IF(unique64(pvox, n) != st->voxels, "%d voxels hold points, the proxy has %d", unique64(pvox, n), st->voxels);
    /* corners: the voxels' distinct corners */
    corner = calloc(8 * (size_t)st->voxels, sizeof *corner);
    for (int i = 0; i < st->voxels; i++)
        for (int b = 0; b < 8; b++) corner[8 * i + b] = vox[i] + (b & 1) + 8192 * (((b >> 1) & 1) + 8192 * ((b >> 2) & 1));
    st->corners = unique64(corner, 8 * st->voxels);
    FAIL_IF(m.nv - n != st->corners, "%d corner vertices, the voxels have %d distinct corners", m.nv - n, st->corners);
    /* the boundary */
    if (rk_mesh_boundary(&m, &tris, &nf, &err)) FAIL_IF(1, "rk_mesh_boundary: %s", err.msg);
    int exposed = 0;
    for (int i = 0; i < st->voxels; i++) {
        static const int64_t step[3] = {1, 8192, 8192 * 8192};
        for (int d = 0; d < 3; d++) exposed += !has(vox, st->voxels, vox[i] + step[d]) + !has(vox, st->voxels, vox[i] - step[d]);
    }
    st->faces = nf;
    FAIL_IF(nf != 2 * exposed, "%d boundary triangles, the voxels expose %d faces (2 triangles each)", nf, exposed);
    double volume = 0, area = 0;
    edges = calloc(3 * (size_t)nf, sizeof *edges);
    for (int f = 0; f < nf; f++) {
        const double *a = &m.X[3 * tris[3 * f]], *b = &m.X[3 * tris[3 * f + 1]], *c = &m.X[3 * tris[3 * f + 2]];
        volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
        double u[3], w[3];
        for (int d = 0; d < 3; d++) u[d] = b[d] - a[d], w[d] = c[d] - a[d];
        double nx = u[1] * w[2] - u[2] * w[1], ny = u[2] * w[0] - u[0] * w[2], nz = u[0] * w[1] - u[1] * w[0];
        area += 0.5 * sqrt(nx * nx + ny * ny + nz * nz);
        for (int k = 0; k < 3; k++) edges[3 * f + k] = (int64_t)tris[3 * f + k] * m.nv + tris[3 * f + (k + 1) % 3];
    }
    /* closed and consistently oriented: every directed edge (a, b) as often as (b, a) */
    qsort(edges, 3 * (size_t)nf, sizeof *edges, cmp64);
    for (int e = 0; e < 3 * nf;) {
        int f = e;
        while (f < 3 * nf && edges[f] == edges[e]) f++;
        int64_t rev = (edges[e] % m.nv) * m.nv + edges[e] / m.nv;
        int64_t *lo = bsearch(&rev, edges, 3 * (size_t)nf, sizeof rev, cmp64);
        int count = 0;
        if (lo) {
            while (lo > edges && lo[-1] == rev) lo--;
            while (lo < edges + 3 * nf && *lo == rev) lo++, count++;
        }
        FAIL_IF(count != f - e, "edge %lld -> %lld appears %d times, its reverse %d: the boundary is not closed",
                (long long)(edges[e] / m.nv), (long long)(edges[e] % m.nv), f - e, count);
        e = f;
    }
    st->volume_error = fabs(volume - st->voxels * g * g * g) / (st->voxels * g * g * g);
    st->area_error = fabs(area - exposed * g * g) / (exposed * g * g);
    FAIL_IF(st->volume_error > 1e-9, "enclosed volume %.12g, voxels %d x g^3 = %.12g", volume, st->voxels, st->voxels * g * g * g);
    FAIL_IF(st->area_error > 1e-9, "area %.12g, exposed faces %d x g^2 = %.12g", area, exposed, exposed * g * g);
    /* every point is inside: odd crossings */
    for (int i = 0; i < n; i++) {
        int c = crossings(&X[3 * i], &m, tris, nf);
        FAIL_IF(c % 2 != 1, "point %d (%g, %g, %g): the ray crosses the boundary %d times", i, X[3 * i], X[3 * i + 1], X[3 * i + 2], c);
    }
    /* the centres of empty voxels next to occupied ones, and far points, are outside: even crossings */
    int probes = 0;
    for (int i = 0; i < st->voxels && probes < 200; i++)
        for (int d = 0; d < 3; d++)
            for (int s = -1; s <= 1; s += 2) {
                int64_t step = d == 0 ? 1 : d == 1 ? 8192 : 8192 * 8192, k = vox[i] + s * step;
                if (has(vox, st->voxels, k)) continue;
                long v[3] = {(long)(k % 8192) - 4096, (long)(k / 8192 % 8192) - 4096, (long)(k / 8192 / 8192) - 4096};
                double p[3];
                for (int a = 0; a < 3; a++) p[a] = o[a] + g * (v[a] + 0.37 + 0.1 * a);
                int c = crossings(p, &m, tris, nf);
                FAIL_IF(c % 2 != 0, "(%g, %g, %g), in an empty voxel, is inside (%d crossings)", p[0], p[1], p[2], c);
                probes++;
            }
    double far[3] = {o[0] - 5 * g, o[1] + 0.3 * g, o[2] + 0.2 * g};
    FAIL_IF(crossings(far, &m, tris, nf) % 2 != 0, "a point far off the cloud is inside");
done:
#undef FAIL_IF
    free(tris), free(vox), free(pvox), free(corner), free(edges);
    rk_mesh_free(&m);
    return rc;
}

TEST(one_point_is_one_voxel)
{
    double X[3] = {0.3, -1.2, 7.0};
    proxy_stats st;
    char why[256];
    CHECK(check_proxy(X, 1, 0.25, 1, &st, why, sizeof why) == 0, "%s", why);
    CHECK(st.corners == 8 && st.faces == 12, "%d corners, %d boundary triangles", st.corners, st.faces);
}

TEST(a_lattice_at_the_voxel_size_is_one_voxel_per_point)
{
    /* points at spacing g: the proxy's voxels must not merge or split them */
    int n = 4 * 3 * 2;
    double X[72], g = 0.05;
    for (int i = 0; i < n; i++) X[3 * i] = g * (i % 4) + 1, X[3 * i + 1] = g * (i / 4 % 3), X[3 * i + 2] = g * (i / 12) - 2;
    proxy_stats st;
    char why[256];
    CHECK(check_proxy(X, n, g, n, &st, why, sizeof why) == 0, "%s", why);
    CHECK(st.corners == 5 * 4 * 3 && st.faces == 2 * 2 * (4 * 3 + 3 * 2 + 4 * 2), "%d corners, %d triangles", st.corners, st.faces);
}

TEST(a_scattered_cloud_is_wrapped)
{
    /* a block, a thin rod, a diagonal chain of voxels touching only at edges and corners, and
     * strays: the union has holes, pockets and non-manifold edges between voxels */
    int n = 0;
    double *X = calloc(3 * 800, sizeof *X), g = 0.1;
    for (int i = 0; i < 500; i++, n++) X[3 * n] = 0.5 * uni(), X[3 * n + 1] = 0.3 * uni(), X[3 * n + 2] = 0.25 * uni();
    for (int i = 0; i < 150; i++, n++) X[3 * n] = 0.6 + uni(), X[3 * n + 1] = 0.12 + 0.01 * uni(), X[3 * n + 2] = 0.1 + 0.01 * uni();
    for (int i = 0; i < 8; i++, n++) X[3 * n] = -0.5 - 0.1 * i, X[3 * n + 1] = -0.5 - 0.1 * i, X[3 * n + 2] = 0.03 + 0.1 * (i % 2);
    for (int i = 0; i < 40; i++, n++) X[3 * n] = 3 * uni() - 1, X[3 * n + 1] = 2 * uni() - 1, X[3 * n + 2] = 2 * uni() + 0.5;
    proxy_stats st;
    char why[256];
    int rc = check_proxy(X, n, g, -1, &st, why, sizeof why);
    printf("# %d points, voxel %g: %d voxels, %d corners, %d boundary triangles; ghost tet volume %.3g, enclosed volume "
           "%.3g, area %.3g (relative)\n", n, g, st.voxels, st.corners, st.faces, st.tet_volume_error, st.volume_error,
           st.area_error);
    CHECK(rc == 0, "%s", why);
    free(X);
}

TEST(bad_input_fails)
{
    rk_error err;
    rk_mesh m;
    double X[6] = {0, 0, 0, 1, 1, 1};
    CHECK(rk_points_proxy(X, 0, 0.1, &m, &err) != 0, "no points accepted");
    CHECK(m.X == NULL && m.ghost == NULL, "a failed call left a mesh");
    const double bad_g[4] = {0, -0.1, NAN, INFINITY};
    for (int k = 0; k < 4; k++) CHECK(rk_points_proxy(X, 2, bad_g[k], &m, &err) != 0, "voxel %g accepted", bad_g[k]);
    CHECK(rk_points_proxy(X, 2, 1e-9, &m, &err) != 0 && strstr(err.msg, "too small"), "voxel 1e-9 for a unit cloud: %s", err.msg);
    CHECK(m.X == NULL && m.ghost == NULL, "a failed call left a mesh");
}

/* Points the lattice cannot hold: a non-finite coordinate, and one so far away that its voxel
 * index does not fit in an integer (the conversion is undefined there): refused, not wrapped. */
TEST(points_off_the_lattice_fail)
{
    rk_error err;
    rk_mesh m;
    double nan_point[6] = {0, 0, 0, 1, NAN, 1};
    CHECK(rk_points_proxy(nan_point, 2, 0.1, &m, &err) != 0, "a NaN coordinate gave a proxy of %d vertices", m.nv);
    CHECK(strstr(err.msg, "point 1") != NULL, "the message does not name point 1: %s", err.msg);
    double inf_point[6] = {0, 0, 0, INFINITY, 1, 1};
    CHECK(rk_points_proxy(inf_point, 2, 0.1, &m, &err) != 0, "an infinite coordinate gave a proxy of %d vertices", m.nv);
    double far_point[6] = {0, 0, 0, 1e300, 1, 1};
    CHECK(rk_points_proxy(far_point, 2, 0.1, &m, &err) != 0, "a point 1e300 away gave a proxy of %d vertices", m.nv);
    CHECK(m.X == NULL && m.ghost == NULL, "a failed call left a mesh");
}

int main(void)
{
    RUN(one_point_is_one_voxel);
    RUN(a_lattice_at_the_voxel_size_is_one_voxel_per_point);
    RUN(a_scattered_cloud_is_wrapped);
    RUN(bad_input_fails);
    RUN(points_off_the_lattice_fail);
    return test_finish();
}
