/* precompute/contact rk_points_march: a point cloud's contact surface that follows the capture
 * (issue 30: within the points' spacing s of them), checked from its output alone:
 *   - closed and 2-manifold: every directed edge once and its reverse once, the faces around
 *     every vertex one fan;
 *   - no edge meets a face it shares no vertex with (the exact segment-triangle test,
 *     rk_segment_triangle_intersect, as rk_contact_intersections runs it);
 *   - every point inside (the parity of a long segment's exact crossings, against every face) or
 *     outside by at most RK_PROXY_OUTSIDE s, its distance to every face by brute force, and the
 *     report's count of those that are not agrees;
 *   - the vertices' distances to their nearest point (brute force over a bucket grid): on the donut
 *     capture at the default voxel (1/40 of its diagonal, g = 10 s), median and 95th percentile
 *     within s (the voxel surface moved in, rk_points_proxy: 0.50 s and 2.39 s), with at most 1.5
 *     times the voxel surface's triangles;
 *   - the slivers tidied (rk_march_tidy): at most 5% of the triangles under RK_MARCH_SLIVER
 *     (untidied, the donut had 31%), none on the solid lattice; the face centroids' distance to
 *     the points is printed (the surface between the vertices; the tidy left it as it was);
 * on one point, a solid lattice, a noisy sphere shell at a capped voxel, the donut splat capture,
 * the pedestal scan;
 * bad input fails. */
#include "contact/contact.h"
#include "contact/points_proxy_impl.h" /* the voxel surface: the triangle budget's base */
#include "surface_checks.h"
#include "testlib.h"
#include "util/util.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>


typedef struct {
    int faces;
    double median_s, p95_s, max_s; /* surface vertex -> nearest point, in s */
    int outside;                   /* points outside by more than RK_PROXY_OUTSIDE s */
    double max_outside_s;          /* the farthest point outside, in s */
    double min_quality;            /* the worst triangle's 4 sqrt(3) area / sum of squared edges (1: equilateral) */
    double min_edge_s;             /* the shortest edge, in s */
    int slivers;                   /* triangles of quality under RK_MARCH_SLIVER */
    double centroid_p95_s, centroid_max_s; /* face centroid -> nearest point, in s (the surface between vertices) */
    int collapsed, flipped;        /* the report's tidy counts */
} march_stats;

#define FAIL_IF(cond, ...)                   \
    do {                                     \
        if (cond) {                          \
            snprintf(why, len, __VA_ARGS__); \
            rc = -1;                         \
            goto done;                       \
        }                                    \
    } while (0)

/* Every check above on rk_points_march of (X, n) with lattice edge h and spacing s. */
static int check_march(const double *X, int n, double h, double s, march_stats *st, char *why, size_t len)
{
    rk_error err;
    rk_surface S;
    rk_points_march_report rep;
    memset(st, 0, sizeof *st);
    int rc = 0;
    double *boxes = NULL, *dist = NULL;
    bucket B = {0};
    if (rk_points_march(X, n, h, s, &S, &rep, &err)) {
        snprintf(why, len, "rk_points_march: %s", err.msg);
        return -1;
    }
    int nf = S.nf, *tris = S.tris;
    const double *x = S.X;
    st->faces = nf;
    st->min_quality = 1;
    for (int f = 0; f < nf; f++) {
        double nrm[3], u[3], v[3], l2 = 0;
        const int *t = tris + 3 * f;
        for (int d = 0; d < 3; d++) u[d] = x[3 * t[1] + d] - x[3 * t[0] + d], v[d] = x[3 * t[2] + d] - x[3 * t[0] + d];
        nrm[0] = u[1] * v[2] - u[2] * v[1], nrm[1] = u[2] * v[0] - u[0] * v[2], nrm[2] = u[0] * v[1] - u[1] * v[0];
        for (int k = 0; k < 3; k++)
            for (int d = 0; d < 3; d++) l2 += (x[3 * t[(k + 1) % 3] + d] - x[3 * t[k] + d]) * (x[3 * t[(k + 1) % 3] + d] - x[3 * t[k] + d]);
        double q = 2 * sqrt(3.0) * sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]) / l2;
        st->min_quality = fmin(st->min_quality, q);
        st->slivers += q < RK_MARCH_SLIVER;
        for (int k = 0; k < 3; k++) {
            double e2 = 0;
            for (int d = 0; d < 3; d++) e2 += (x[3 * t[(k + 1) % 3] + d] - x[3 * t[k] + d]) * (x[3 * t[(k + 1) % 3] + d] - x[3 * t[k] + d]);
            st->min_edge_s = f == 0 && k == 0 ? sqrt(e2) / s : fmin(st->min_edge_s, sqrt(e2) / s);
        }
    }
    st->collapsed = rep.collapsed, st->flipped = rep.flipped;
    FAIL_IF(nf < 4, "%d triangles", nf);
    for (int k = 0; k < 3 * nf; k++) FAIL_IF(tris[k] < 0 || tris[k] >= S.nv, "triangle vertex %d of %d", tris[k], S.nv);
    int fans;
    boxes = malloc(sizeof(double) * 6 * (size_t)nf);
    FAIL_IF(!boxes, "out of memory");
    if (surface_closed_manifold(tris, nf, S.nv, &fans, why, len) || surface_crosses_itself(x, tris, nf, boxes, why, len)) {
        rc = -1;
        goto done;
    }
    /* every point inside (parity along (1, 0.00123, 0.00071), every face whose box can meet the
     * segment) or within RK_PROXY_OUTSIDE s of a face */
    double hi0 = -INFINITY, maxout = 0;
    for (int f = 0; f < nf; f++) hi0 = fmax(hi0, boxes[6 * f + 3]);
    for (int i = 0; i < n; i++) {
        const double *p = X + 3 * i;
        double L = 1.1 * (hi0 - p[0]) + h, q[3] = {p[0] + L, p[1] + 0.00123 * L, p[2] + 0.00071 * L};
        int crossings = 0;
        for (int f = 0; f < nf; f++) {
            const double *b = boxes + 6 * f;
            if (b[3] < p[0] || b[4] < p[1] || b[1] > q[1] || b[5] < p[2] || b[2] > q[2]) continue;
            const int *t = tris + 3 * f;
            crossings += rk_segment_triangle_intersect(p, q, x + 3 * t[0], x + 3 * t[1], x + 3 * t[2]);
        }
        if (crossings % 2 == 1) continue;
        double near = INFINITY;
        for (int f = 0; f < nf; f++) {
            const int *t = tris + 3 * f;
            near = fmin(near, triangle_distance(p, x + 3 * t[0], x + 3 * t[1], x + 3 * t[2]));
        }
        maxout = fmax(maxout, near);
        if (near > RK_PROXY_OUTSIDE * s) st->outside++;
    }
    st->max_outside_s = maxout / s;
    FAIL_IF(st->outside != rep.outside_points, "%d points outside by more than s, the report says %d", st->outside, rep.outside_points);
    FAIL_IF(st->outside > 0, "%d points outside by more than s (the farthest %.3f s)", st->outside, st->max_outside_s);
    /* the vertices' distances to the points */
    bucket_init(&B, X, n, 4 * h);
    dist = malloc(sizeof(double) * (size_t)S.nv);
    for (int v = 0; v < S.nv; v++) {
        dist[v] = bucket_nearest(&B, x + 3 * v, -1) / s;
        FAIL_IF(!(dist[v] < INFINITY), "vertex %d is farther than %g from every point", v, 4 * h);
    }
    qsort(dist, (size_t)S.nv, sizeof *dist, rk_cmp_double);
    st->median_s = dist[S.nv / 2], st->p95_s = dist[(int)(0.95 * S.nv)], st->max_s = dist[S.nv - 1];
    /* the faces' centroids (what vertex distances do not see: a face bridging a hollow) */
    free(dist);
    dist = malloc(sizeof(double) * (size_t)nf);
    FAIL_IF(!dist, "out of memory");
    for (int f = 0; f < nf; f++) {
        double c[3];
        for (int d = 0; d < 3; d++) c[d] = (x[3 * tris[3 * f] + d] + x[3 * tris[3 * f + 1] + d] + x[3 * tris[3 * f + 2] + d]) / 3;
        dist[f] = fmin(bucket_nearest(&B, c, -1), 4 * h) / s;
    }
    qsort(dist, (size_t)nf, sizeof *dist, rk_cmp_double);
    st->centroid_p95_s = dist[(int)(0.95 * nf)], st->centroid_max_s = dist[nf - 1];
done:
    free(S.X), free(S.tris), free(boxes), free(dist), free(B.key);
    return rc;
}

static void print_stats(const char *what, int n, double g, double s, const march_stats *st)
{
    printf("  %s: %d points, g %.3g, s %.3g: %d triangles; vertices median %.3f s, 95th percentile %.3f s, worst %.3f s; "
           "farthest point outside %.3f s; worst triangle quality %.2g, %d under %g, shortest edge %.3g s (%d collapsed, "
           "%d flipped); face centroids 95th percentile %.3f s, worst %.3f s\n",
           what, n, g, s, st->faces, st->median_s, st->p95_s, st->max_s, st->max_outside_s, st->min_quality, st->slivers,
           RK_MARCH_SLIVER, st->min_edge_s, st->collapsed, st->flipped, st->centroid_p95_s, st->centroid_max_s);
}

/* The voxel surface's triangles at voxel g (rk_points_proxy's; the budget's base). */
static int voxel_faces(const double *X, int n, double g)
{
    rk_error err;
    rk_mesh L;
    double lo[3];
    int *tris = NULL, nf = 0;
    if (rk_proxy_lattice(X, n, g, &L, lo, &err) || rk_mesh_boundary(&L, &tris, &nf, &err)) return -1;
    free(tris);
    rk_mesh_free(&L);
    return nf;
}

TEST(one_point_is_a_small_closed_surface)
{
    double X[3] = {0.1, -0.2, 0.3};
    march_stats st;
    char why[256];
    int rc = check_march(X, 1, 0.1, 0.05, &st, why, sizeof why);
    print_stats("one point", 1, 0.1, 0.05, &st);
    CHECK(rc == 0, "%s", why);
    CHECK(st.max_s <= 0.5 * 1.001, "a vertex %.3f s off the point (s / 2 expected)", st.max_s);
}

/* A solid lattice cloud (8 x 6 x 5 points 1 cm apart) at the default voxel g = 2 s: its flat sides
 * wrapped within the spacing too, every point inside. */
TEST(a_lattice_is_wrapped_within_its_spacing)
{
    double X[3 * 240], s = 0.01;
    int n = 0;
    for (int k = 0; k < 5; k++)
        for (int j = 0; j < 6; j++)
            for (int i = 0; i < 8; i++, n++) X[3 * n] = s * i, X[3 * n + 1] = s * j, X[3 * n + 2] = s * k;
    march_stats st;
    char why[256];
    int rc = check_march(X, n, RK_MARCH_LATTICE * 2 * s, s, &st, why, sizeof why);
    print_stats("lattice", n, 2 * s, s, &st);
    CHECK(rc == 0, "%s", why);
    CHECK(st.median_s <= 0.55 && st.p95_s <= 1.0, "vertices %.3f s (median), %.3f s (95th percentile) off", st.median_s, st.p95_s);
    /* untidied: 84 of its 432 faces under RK_MARCH_SLIVER, the worst 0.026 */
    CHECK(st.slivers == 0 && st.collapsed > 0, "%d slivers left, %d edges collapsed", st.slivers, st.collapsed);
}

/* A triangle as its smallest vertex first, its winding kept (so a flipped face differs). */
static void rotate_min_first(int *t)
{
    while (t[0] > t[1] || t[0] > t[2]) {
        int a = t[0];
        t[0] = t[1], t[1] = t[2], t[2] = a;
    }
}

static int by_triangle(const void *a, const void *b) { return memcmp(a, b, 3 * sizeof(int)); }

/* rk_points_march_mesh (what a scene's cloud collides through): its ghost cones' rk_mesh_boundary
 * is exactly the march surface, each triangle wound as the surface has it, over the points then
 * the surface's vertices (a cone face left over, or a flipped one, would fail). Two lattices apart
 * (two components coned to one apex). */
TEST(the_ghost_cones_bound_exactly_the_march_surface)
{
    double X[3 * 240], s = 0.01;
    int n = 0;
    for (int k = 0; k < 4; k++)
        for (int j = 0; j < 5; j++)
            for (int i = 0; i < 6; i++, n++)
                X[3 * n] = s * i + (k >= 2 ? 0.2 : 0), X[3 * n + 1] = s * j, X[3 * n + 2] = s * (k % 2);
    rk_error err = {{0}};
    rk_surface S;
    rk_mesh m;
    rk_points_march_report rep, rep2;
    int *tris = NULL, nf = -1;
    CHECK_OK(rk_points_march(X, n, RK_MARCH_LATTICE * 2 * s, s, &S, &rep, &err));
    CHECK_OK(rk_points_march_mesh(X, n, RK_MARCH_LATTICE * 2 * s, s, &m, &rep2, &err));
    CHECK_OK(rk_mesh_boundary(&m, &tris, &nf, &err));
    CHECK(m.nv == n + S.nv && m.nt == 0 && m.nghost == S.nf && nf == S.nf, "vertices %d (%d + %d), ghosts %d, boundary %d of %d",
          m.nv, n, S.nv, m.nghost, nf, S.nf);
    int same = nf == S.nf && memcmp(m.X + 3 * (size_t)n, S.X, sizeof(double) * 3 * (size_t)S.nv) == 0;
    for (int f = 0; same && f < nf; f++) {
        for (int k = 0; k < 3; k++) S.tris[3 * f + k] += n;
        rotate_min_first(S.tris + 3 * f), rotate_min_first(tris + 3 * f);
    }
    if (same) {
        qsort(S.tris, (size_t)nf, 3 * sizeof(int), by_triangle);
        qsort(tris, (size_t)nf, 3 * sizeof(int), by_triangle);
        same = memcmp(S.tris, tris, sizeof(int) * 3 * (size_t)nf) == 0;
    }
    CHECK(same, "the boundary differs from the march surface (%d triangles, %d faces)", S.nf, nf);
    printf("# two lattices: %d triangles, boundary of %d ghost cones the same\n", S.nf, m.nghost);
    free(tris);
    rk_surface_free(&S);
    rk_mesh_free(&m);
}

/* n splats on a sphere of radius R, a Fibonacci spiral of spacing about h, each pushed off the
 * sphere by up to h / 2 and sideways by up to 0.15 h (test_contact_points_proxy's noisy shell). */
/* X (n points, freed here) wrapped with voxel g (the lattice edge RK_MARCH_LATTICE g) and spacing s:
 * every check of check_march, the vertices' median within 0.55 s and 95th percentile within s,
 * and with budget at most 1.5 times the voxel surface's triangles. */
static void check_wrapped(const char *what, double *X, int n, double g, double s, int budget)
{
    march_stats st;
    char why[256];
    int rc = check_march(X, n, RK_MARCH_LATTICE * g, s, &st, why, sizeof why);
    print_stats(what, n, g, s, &st);
    int voxel = budget ? voxel_faces(X, n, g) : 0;
    free(X);
    CHECK(rc == 0, "%s: %s", what, why);
    CHECK(st.median_s <= 0.55 && st.p95_s <= 1.0, "%s: vertices %.3f s (median), %.3f s (95th percentile) off", what,
          st.median_s, st.p95_s);
    CHECK(!budget || st.faces <= 1.5 * voxel, "%s: %d triangles (the voxel surface has %d)", what, st.faces, voxel);
    /* the slivers tidied (rk_march_tidy): untidied, 31% of the donut's faces were under
     * RK_MARCH_SLIVER (2,674 of 8,556), 17% of the dense shell's */
    CHECK(st.slivers <= 0.05 * st.faces, "%s: %d of %d triangles under quality %g", what, st.slivers, st.faces, RK_MARCH_SLIVER);
}

static double *jittered_shell(int n, double R, double h, uint64_t *rng)
{
    double *X = malloc(sizeof(double) * 3 * (size_t)n);
    for (int i = 0; i < n; i++) {
        double z = 1 - 2 * (i + 0.5) / n, r = sqrt(1 - z * z), th = i * M_PI * (3 - sqrt(5.0)), rr = R + (rk_uniform(rng) - 0.5) * h;
        X[3 * i] = r * cos(th) * rr + (rk_uniform(rng) - 0.5) * 0.3 * h;
        X[3 * i + 1] = r * sin(th) * rr + (rk_uniform(rng) - 0.5) * 0.3 * h;
        X[3 * i + 2] = z * rr + (rk_uniform(rng) - 0.5) * 0.3 * h;
    }
    return X;
}

/* A dense noisy shell (12,000 splats, radius 0.1) at the capped voxel g = 10 s: within s. */
TEST(a_dense_shell_is_wrapped_within_its_spacing)
{
    uint64_t rng = 4242;
    int n = 12000;
    double R = 0.1, hh = sqrt(4 * M_PI * R * R / n), *X = jittered_shell(n, R, hh, &rng);
    double s = median_spacing(X, n, 4 * hh), g = 10 * s;
    check_wrapped("dense shell", X, n, g, s, 1);
}

/* The donut splat capture at the default voxel (1/40 of its diagonal, about 10 s): the voxel
 * surface moved in (rk_points_proxy) left its 95th percentile vertex 2.39 s off. */
TEST(the_donut_capture_is_wrapped_within_its_spacing)
{
    rk_error err;
    double *X = NULL;
    int n = 0;
    CHECK_OK(rk_points_load(test_data("meshes/donut_3dgs.ply"), &X, &n, &err));
    double g = rk_points_diagonal(X, n) / 40, s = median_spacing(X, n, g);
    check_wrapped("donut", X, n, g, s, 1);
}

/* The pedestal scan (points 1 cm apart) at twice that, the default voxel. */
TEST(a_scan_is_wrapped_within_its_spacing)
{
    rk_error err;
    double *X = NULL;
    int n = 0;
    CHECK_OK(rk_points_load(test_data("meshes/pedestal_points.ply"), &X, &n, &err));
    double g = 0.02, s = median_spacing(X, n, g);
    check_wrapped("pedestal", X, n, g, s, 0);
}

TEST(bad_input_fails)
{
    rk_error err;
    rk_surface S;
    rk_points_march_report rep;
    double X[6] = {0, 0, 0, 1, 1, 1}, bad[4] = {0, -0.1, NAN, INFINITY};
    CHECK(rk_points_march(X, 0, 0.1, 0.05, &S, &rep, &err) != 0, "no points accepted");
    for (int k = 0; k < 4; k++) {
        CHECK(rk_points_march(X, 2, bad[k], 0.05, &S, &rep, &err) != 0, "lattice edge %g accepted", bad[k]);
        CHECK(rk_points_march(X, 2, 0.1, bad[k], &S, &rep, &err) != 0 && strstr(err.msg, "spacing"), "spacing %g: %s", bad[k], err.msg);
    }
    CHECK(rk_points_march(X, 2, 1e-9, 0.05, &S, &rep, &err) != 0 && strstr(err.msg, "too small"), "lattice 1e-9: %s", err.msg);
    double nan_point[6] = {0, 0, 0, 1, NAN, 1};
    CHECK(rk_points_march(nan_point, 2, 0.1, 0.05, &S, &rep, &err) != 0 && strstr(err.msg, "point 1"), "a NaN point: %s", err.msg);
    CHECK(S.X == NULL && S.tris == NULL, "a failed call left a surface");
}

int main(void)
{
    RUN(one_point_is_a_small_closed_surface);
    RUN(a_lattice_is_wrapped_within_its_spacing);
    RUN(the_ghost_cones_bound_exactly_the_march_surface);
    RUN(a_dense_shell_is_wrapped_within_its_spacing);
    RUN(the_donut_capture_is_wrapped_within_its_spacing);
    RUN(a_scan_is_wrapped_within_its_spacing);
    RUN(bad_input_fails);
    return test_finish();
}
