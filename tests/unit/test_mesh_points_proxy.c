/* precompute/mesh rk_points_proxy: a point cloud's contact surface, the level set at g/2 of the
 * distance to its points. Checked from its output alone:
 *   - the points come first, unchanged; no tets; one ghost tet per triangle, apex point 0; every
 *     surface vertex used;
 *   - rk_mesh_boundary of the ghost tets gives a surface that rk_surface_check accepts: closed,
 *     edge-manifold, consistently oriented, outward (positive volume);
 *   - no edge of it crosses a triangle of it that shares no vertex with the edge (the contact
 *     stage's exact segment-triangle test);
 *   - every surface vertex is within one spacing g of a point (the bound), and off every
 *     point;
 *   - every point is inside (a ray from it crosses the surface an odd number of times) and at
 *     least 0.1 g from it; a point far off is outside;
 *   - on a lattice, a random cloud with strays, and a real Gaussian-splat capture
 *     (tests/data/meshes/donut_3dgs.ply) and scan (pedestal_points.ply), whose measures it prints;
 *   - bad input fails. */
#include "contact/contact.h"
#include "mesh/mesh.h"
#include "testlib.h"
#include "util/util.h"

#include <stdint.h>

static uint64_t rng = 31337;
static double uni(void) { return rk_uniform(&rng); }

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

static int crossings(const double *p, const double *X, const int *tris, int nf)
{
    static const double d[3] = {0.5773, 0.4471, 0.6833}; /* generic: no lattice plane or edge along it */
    int c = 0;
    for (int f = 0; f < nf; f++) c += ray_hits(p, d, &X[3 * tris[3 * f]], &X[3 * tris[3 * f + 1]], &X[3 * tris[3 * f + 2]]);
    return c;
}

/* Distance from p to triangle (a, b, c) (Ericson's closest point). */
static double point_triangle(const double *p, const double *a, const double *b, const double *c)
{
    double ab[3], ac[3], ap[3], q[3];
    for (int k = 0; k < 3; k++) ab[k] = b[k] - a[k], ac[k] = c[k] - a[k], ap[k] = p[k] - a[k];
#define DOT(u, v) ((u)[0] * (v)[0] + (u)[1] * (v)[1] + (u)[2] * (v)[2])
    double d1 = DOT(ab, ap), d2 = DOT(ac, ap), v = 0, w = 0;
    double bp[3], cp[3];
    for (int k = 0; k < 3; k++) bp[k] = p[k] - b[k], cp[k] = p[k] - c[k];
    double d3 = DOT(ab, bp), d4 = DOT(ac, bp), d5 = DOT(ab, cp), d6 = DOT(ac, cp);
    double va = d3 * d6 - d5 * d4, vb = d5 * d2 - d1 * d6, vc = d1 * d4 - d3 * d2;
    if (d1 <= 0 && d2 <= 0) v = 0, w = 0;
    else if (d3 >= 0 && d4 <= d3) v = 1, w = 0;
    else if (d6 >= 0 && d5 <= d6) v = 0, w = 1;
    else if (vc <= 0 && d1 >= 0 && d3 <= 0) v = d1 / (d1 - d3), w = 0;
    else if (vb <= 0 && d2 >= 0 && d6 <= 0) v = 0, w = d2 / (d2 - d6);
    else if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) w = (d4 - d3) / ((d4 - d3) + (d5 - d6)), v = 1 - w;
    else {
        double den = 1 / (va + vb + vc);
        v = vb * den, w = vc * den;
    }
#undef DOT
    double d = 0;
    for (int k = 0; k < 3; k++) q[k] = a[k] + v * ab[k] + w * ac[k], d += (p[k] - q[k]) * (p[k] - q[k]);
    return sqrt(d);
}

typedef struct {
    int vertices, triangles, crossings;
    double vertex_to_point;  /* max over surface vertices of the distance to the nearest point, / g */
    double vertex_closest;   /* min over surface vertices of that distance, / g */
    double point_clearance;  /* min over points of the distance to the surface, / g */
    double point_to_surface; /* max over points of the distance to the surface, / g */
} surface_stats;

/* Everything above on the surface of (X, n) at spacing g; 0 or a message in why. Brute force:
 * n and the triangles must stay in the thousands. */
static int check_surface(const double *X, int n, double g, surface_stats *st, char *why, size_t len)
{
    rk_error err;
    rk_mesh m;
    memset(st, 0, sizeof *st);
#define FAIL_IF(cond, ...)                   \
    do {                                     \
        if (cond) {                          \
            snprintf(why, len, __VA_ARGS__); \
            rc = -1;                         \
            goto done;                       \
        }                                    \
    } while (0)
    int rc = 0, *tris = NULL, nf = 0;
    unsigned char *used = NULL;
    if (rk_points_proxy(X, n, g, &m, &err)) {
        snprintf(why, len, "rk_points_proxy: %s", err.msg);
        return -1;
    }
    FAIL_IF(m.nt != 0, "%d tets (expected none)", m.nt);
    FAIL_IF(m.nv <= n || memcmp(m.X, X, sizeof(double) * 3 * (size_t)n) != 0, "the first %d vertices are not the points", n);
    used = calloc((size_t)m.nv, 1);
    for (int t = 0; t < m.nghost; t++) {
        const int *T = &m.ghost[4 * t];
        FAIL_IF(T[0] != 0, "ghost tet %d has apex %d, not point 0", t, T[0]);
        for (int k = 1; k < 4; k++) {
            FAIL_IF(T[k] < n || T[k] >= m.nv, "ghost tet %d uses vertex %d (the surface's are %d..%d)", t, T[k], n, m.nv - 1);
            used[T[k]] = 1;
        }
    }
    for (int i = n; i < m.nv; i++) FAIL_IF(!used[i], "surface vertex %d is in no triangle", i);
    if (rk_mesh_boundary(&m, &tris, &nf, &err)) FAIL_IF(1, "rk_mesh_boundary: %s", err.msg);
    FAIL_IF(nf != m.nghost, "%d boundary triangles from %d ghost tets", nf, m.nghost);
    st->vertices = m.nv - n, st->triangles = nf;
    /* the surface alone (its vertices renumbered from 0) through the surface check */
    int *local = calloc(3 * (size_t)nf, sizeof *local);
    for (int k = 0; k < 3 * nf; k++) local[k] = tris[k] - n;
    rk_surface s = {m.nv - n, nf, m.X + 3 * (size_t)n, local};
    int bad = rk_surface_check(&s, "contact surface", &err);
    free(local);
    FAIL_IF(bad, "%s", err.msg);
    /* no edge crosses a triangle it does not touch (bounding boxes first) */
    double *box = calloc(6 * (size_t)nf, sizeof *box);
    for (int f = 0; f < nf; f++)
        for (int d = 0; d < 3; d++) {
            double lo = INFINITY, hi = -INFINITY;
            for (int k = 0; k < 3; k++) lo = fmin(lo, m.X[3 * tris[3 * f + k] + d]), hi = fmax(hi, m.X[3 * tris[3 * f + k] + d]);
            box[6 * f + d] = lo, box[6 * f + 3 + d] = hi;
        }
    for (int f = 0; f < nf; f++)
        for (int e = 0; e < 3; e++) {
            int p = tris[3 * f + e], q = tris[3 * f + (e + 1) % 3];
            if (p > q) continue; /* each edge once (its other triangle has it reversed) */
            for (int t = 0; t < nf; t++) {
                const int *T = &tris[3 * t];
                if (T[0] == p || T[1] == p || T[2] == p || T[0] == q || T[1] == q || T[2] == q) continue;
                int apart = 0;
                for (int d = 0; d < 3; d++)
                    apart |= fmax(m.X[3 * p + d], m.X[3 * q + d]) < box[6 * t + d] ||
                             fmin(m.X[3 * p + d], m.X[3 * q + d]) > box[6 * t + 3 + d];
                if (!apart)
                    st->crossings += rk_segment_triangle_intersect(&m.X[3 * p], &m.X[3 * q], &m.X[3 * T[0]], &m.X[3 * T[1]],
                                                                   &m.X[3 * T[2]]) != 0;
            }
        }
    free(box);
    FAIL_IF(st->crossings != 0, "%d edges cross the surface", st->crossings);
    /* the vertices' distances to the points */
    st->vertex_closest = INFINITY;
    for (int v = n; v < m.nv; v++) {
        double best = INFINITY;
        for (int i = 0; i < n; i++) {
            double d = 0;
            for (int k = 0; k < 3; k++) d += (m.X[3 * v + k] - X[3 * i + k]) * (m.X[3 * v + k] - X[3 * i + k]);
            best = fmin(best, d);
        }
        st->vertex_to_point = fmax(st->vertex_to_point, sqrt(best) / g);
        st->vertex_closest = fmin(st->vertex_closest, sqrt(best) / g);
    }
    FAIL_IF(st->vertex_to_point > 1, "a surface vertex is %.3g g from the nearest point", st->vertex_to_point);
    FAIL_IF(!(st->vertex_closest > 0), "a surface vertex is on a point");
    /* the points: inside, off the surface */
    st->point_clearance = INFINITY;
    for (int i = 0; i < n; i++) {
        int c = crossings(&X[3 * i], m.X, tris, nf);
        FAIL_IF(c % 2 != 1, "point %d (%g, %g, %g): the ray crosses the surface %d times", i, X[3 * i], X[3 * i + 1], X[3 * i + 2], c);
        double best = INFINITY;
        for (int f = 0; f < nf; f++)
            best = fmin(best, point_triangle(&X[3 * i], &m.X[3 * tris[3 * f]], &m.X[3 * tris[3 * f + 1]], &m.X[3 * tris[3 * f + 2]]));
        st->point_clearance = fmin(st->point_clearance, best / g);
        st->point_to_surface = fmax(st->point_to_surface, best / g);
    }
    FAIL_IF(st->point_clearance < 0.1, "a point is only %.3g g inside the surface", st->point_clearance);
    double far[3] = {X[0], X[1], X[2]}; /* past the cloud's lower corner */
    for (int i = 1; i < n; i++)
        for (int k = 0; k < 3; k++) far[k] = fmin(far[k], X[3 * i + k]);
    for (int k = 0; k < 3; k++) far[k] -= (5 + 0.1 * k) * g;
    FAIL_IF(crossings(far, m.X, tris, nf) % 2 != 0, "a point far off the cloud is inside");
done:
#undef FAIL_IF
    free(tris), free(used);
    rk_mesh_free(&m);
    return rc;
}

static void report(const char *what, int n, double g, const surface_stats *st)
{
    printf("# %s: %d points, spacing %.4g m: %d vertices, %d triangles; surface -> nearest point at most %.3f g (%.3g m), "
           "at least %.3f g; points inside by %.3f g (%.3g m) to %.3f g\n",
           what, n, g, st->vertices, st->triangles, st->vertex_to_point, st->vertex_to_point * g, st->vertex_closest,
           st->point_clearance, st->point_clearance * g, st->point_to_surface);
}

TEST(one_point_is_wrapped)
{
    double X[3] = {0.3, -1.2, 7.0};
    surface_stats st;
    char why[256];
    CHECK(check_surface(X, 1, 0.25, &st, why, sizeof why) == 0, "%s", why);
    report("one point", 1, 0.25, &st);
    /* a sphere of radius g/2 to within the lattice (its edge g/2): the point is about g/2 inside */
    CHECK(st.point_clearance > 0.3 && st.point_clearance <= 0.5 + 1e-9, "the point is %.3g g inside", st.point_clearance);
    CHECK(st.triangles < 200, "%d triangles around one point", st.triangles);
}

TEST(a_lattice_at_the_spacing_is_wrapped_half_a_spacing_off)
{
    /* points at spacing g: the surface is a rounded box g/2 off the outer points */
    int n = 4 * 3 * 2;
    double X[72], g = 0.05;
    for (int i = 0; i < n; i++) X[3 * i] = g * (i % 4) + 1, X[3 * i + 1] = g * (i / 4 % 3), X[3 * i + 2] = g * (i / 12) - 2;
    surface_stats st;
    char why[256];
    CHECK(check_surface(X, n, g, &st, why, sizeof why) == 0, "%s", why);
    report("lattice 4 x 3 x 2", n, g, &st);
    CHECK(st.point_to_surface <= 0.5 + 1e-9, "an outer point is %.3g g inside", st.point_to_surface);
}

TEST(a_scattered_cloud_is_wrapped)
{
    /* a block, a thin rod, a diagonal chain of points, and strays: pockets, thin parts, and
     * components of their own */
    int n = 0;
    double *X = calloc(3 * 400, sizeof *X), g = 0.1;
    for (int i = 0; i < 250; i++, n++) X[3 * n] = 0.5 * uni(), X[3 * n + 1] = 0.3 * uni(), X[3 * n + 2] = 0.25 * uni();
    for (int i = 0; i < 60; i++, n++) X[3 * n] = 0.6 + uni(), X[3 * n + 1] = 0.12 + 0.01 * uni(), X[3 * n + 2] = 0.1 + 0.01 * uni();
    for (int i = 0; i < 8; i++, n++) X[3 * n] = -0.5 - 0.1 * i, X[3 * n + 1] = -0.5 - 0.1 * i, X[3 * n + 2] = 0.03 + 0.1 * (i % 2);
    for (int i = 0; i < 20; i++, n++) X[3 * n] = 3 * uni() - 1, X[3 * n + 1] = 2 * uni() - 1, X[3 * n + 2] = 2 * uni() + 0.5;
    surface_stats st;
    char why[256];
    int rc = check_surface(X, n, g, &st, why, sizeof why);
    report("scattered", n, g, &st);
    CHECK(rc == 0, "%s", why);
    free(X);
}

/* A real capture from tests/data/meshes, every stride-th point (the checks are brute force), at
 * the spacing the scene build gives it: the RKPM sampling's (twice the median nearest-neighbour
 * distance), at least 1/40 of the bounding-box diagonal (build.c). */
static void real_cloud(const char *file, int stride)
{
    char path[1024];
    snprintf(path, sizeof path, "tests/data/meshes/%s", file);
    rk_error err;
    double *all = NULL;
    int total = 0;
    CHECK_OK(rk_points_load(path, &all, &total, &err));
    if (!all) return;
    int n = 0;
    double *X = calloc(3 * (size_t)total, sizeof *X);
    for (int i = 0; i < total; i += stride, n++) memcpy(X + 3 * n, all + 3 * i, 3 * sizeof(double));
    double median = 0, *nn = calloc((size_t)n, sizeof *nn);
    for (int i = 0; i < n; i++) {
        double best = INFINITY;
        for (int j = 0; j < n; j++) {
            double d = 0;
            for (int k = 0; k < 3 && j != i; k++) d += (X[3 * i + k] - X[3 * j + k]) * (X[3 * i + k] - X[3 * j + k]);
            if (j != i && d > 0) best = fmin(best, d);
        }
        nn[i] = sqrt(best);
    }
    qsort(nn, (size_t)n, sizeof *nn, rk_cmp_double);
    median = nn[n / 2];
    double g = fmax(2 * median, rk_points_diagonal(X, n) / 40);
    surface_stats st;
    char why[256];
    int rc = check_surface(X, n, g, &st, why, sizeof why);
    report(file, n, g, &st);
    CHECK(rc == 0, "%s: %s", file, why);
    free(nn), free(X), free(all);
}

TEST(a_gaussian_splat_capture_is_wrapped) { real_cloud("donut_3dgs.ply", 200); }
TEST(a_scanned_cloud_is_wrapped) { real_cloud("pedestal_points.ply", 7); }

TEST(bad_input_fails)
{
    rk_error err;
    rk_mesh m;
    double X[6] = {0, 0, 0, 1, 1, 1};
    CHECK(rk_points_proxy(X, 0, 0.1, &m, &err) != 0, "no points accepted");
    CHECK(m.X == NULL && m.ghost == NULL, "a failed call left a mesh");
    const double bad_g[4] = {0, -0.1, NAN, INFINITY};
    for (int k = 0; k < 4; k++) CHECK(rk_points_proxy(X, 2, bad_g[k], &m, &err) != 0, "spacing %g accepted", bad_g[k]);
    CHECK(rk_points_proxy(X, 2, 1e-9, &m, &err) != 0 && strstr(err.msg, "too small"), "spacing 1e-9 for a unit cloud: %s", err.msg);
    CHECK(m.X == NULL && m.ghost == NULL, "a failed call left a mesh");
}

/* Points the lattice cannot hold: a non-finite coordinate, and one so far away that its lattice
 * index does not fit in an integer (the conversion is undefined there): refused, not wrapped. */
TEST(points_off_the_lattice_fail)
{
    rk_error err;
    rk_mesh m;
    double nan_point[6] = {0, 0, 0, 1, NAN, 1};
    CHECK(rk_points_proxy(nan_point, 2, 0.1, &m, &err) != 0, "a NaN coordinate gave a surface of %d vertices", m.nv);
    CHECK(strstr(err.msg, "point 1") != NULL, "the message does not name point 1: %s", err.msg);
    double inf_point[6] = {0, 0, 0, INFINITY, 1, 1};
    CHECK(rk_points_proxy(inf_point, 2, 0.1, &m, &err) != 0, "an infinite coordinate gave a surface of %d vertices", m.nv);
    double far_point[6] = {0, 0, 0, 1e300, 1, 1};
    CHECK(rk_points_proxy(far_point, 2, 0.1, &m, &err) != 0, "a point 1e300 away gave a surface of %d vertices", m.nv);
    CHECK(m.X == NULL && m.ghost == NULL, "a failed call left a mesh");
}

int main(void)
{
    RUN(one_point_is_wrapped);
    RUN(a_lattice_at_the_spacing_is_wrapped_half_a_spacing_off);
    RUN(a_scattered_cloud_is_wrapped);
    RUN(a_gaussian_splat_capture_is_wrapped);
    RUN(a_scanned_cloud_is_wrapped);
    RUN(bad_input_fails);
    RUN(points_off_the_lattice_fail);
    return test_finish();
}
