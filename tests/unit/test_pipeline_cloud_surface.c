/* rk_cloud_surface (precompute/pipeline/build_body.c), a cloud's contact surface as the scene build
 * takes it, on its two branches past the first march (issue 30's bound: every point inside the
 * surface or within its spacing s of it):
 *   - retried: where a point lies more than s outside the march on the lattice 1.5 g, the march on
 *     the lattice g is taken (with a warning): the mesh returned is exactly rk_points_march_mesh's
 *     at h = g, and that one has no point past s;
 *   - refused: where one still does at g, the build fails with an error naming the cloud's file
 *     and what to change.
 * The cloud: a noisy spherical shell of 1,000 points (test_contact_proxy_march's jittered shell,
 * radius 0.1 m, pushed off the sphere by up to half its spacing) at a coarse proxy_voxel of 11 s
 * (10 points up to 1.46 s outside at 1.5 g, none at g) and 11.5 s (2 points up to 1.24 s outside
 * even at g); found by a scan of proxy_voxel from s to 12 s (at the default voxel, 2 s, the shell
 * is wrapped on the first try). About 1 s of CPU. */
#include "pipeline/build_impl.h"
#include "testlib.h"
#include "util/util.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define FILE_NAME "shell_1000.ply"

/* n points on a sphere of radius R as a Fibonacci spiral, each pushed off it by up to half the
 * spiral's spacing and sideways by up to 0.15 of it. */
static double *jittered_shell(int n, double R, uint64_t seed)
{
    uint64_t rng = seed;
    double h = sqrt(4 * M_PI * R * R / n), *X = malloc(sizeof(double) * 3 * (size_t)n);
    for (int i = 0; X && i < n; i++) {
        double z = 1 - 2 * (i + 0.5) / n, r = sqrt(1 - z * z), th = i * M_PI * (3 - sqrt(5.0)), rr = R + (rk_uniform(&rng) - 0.5) * h;
        X[3 * i] = r * cos(th) * rr + (rk_uniform(&rng) - 0.5) * 0.3 * h;
        X[3 * i + 1] = r * sin(th) * rr + (rk_uniform(&rng) - 0.5) * 0.3 * h;
        X[3 * i + 2] = z * rr + (rk_uniform(&rng) - 0.5) * 0.3 * h;
    }
    return X;
}

/* The cloud as a scene object at proxy_voxel g_in_s times its spacing s (into *s). */
static void object_at(rk_scene_object *o, const double *X, int n, double g_in_s, double *s)
{
    rk_error err;
    double g;
    memset(o, 0, sizeof *o);
    strcpy(o->file, FILE_NAME);
    o->scale = 1;
    CHECK_OK(rk_cloud_proxy_spacing(o, X, n, &g, s, &err));
    o->proxy_voxel = g_in_s * *s;
}

TEST(a_point_past_s_on_the_coarse_lattice_retries_on_g)
{
    int n = 1000;
    double *X = jittered_shell(n, 0.1, 4242), s = 0;
    rk_scene_object o;
    rk_error err = {{0}};
    rk_mesh m, direct;
    rk_surface S;
    rk_points_march_report rep;
    CHECK(X != NULL, "out of memory");
    object_at(&o, X, n, 11, &s);
    double g = o.proxy_voxel;
    /* the first march leaves points past s: the branch is taken */
    CHECK_OK(rk_points_march(X, n, RK_MARCH_LATTICE * g, s, &S, &rep, &err));
    rk_surface_free(&S);
    printf("# shell, %d points, s %.4g m, g %.4g m: on the lattice 1.5 g %d points past s (the farthest %.2f s)\n", n, s, g,
           rep.outside_points, rep.max_outside / s);
    CHECK(rep.outside_points > 0, "no point past s on the lattice 1.5 g: the retry is not reached");
    CHECK_OK(rk_cloud_surface(&o, X, n, &m, &err));
    CHECK_OK(rk_points_march_mesh(X, n, g, s, &direct, &rep, &err));
    CHECK(rep.outside_points == 0, "%d points past s on the lattice g", rep.outside_points);
    CHECK(m.nv == direct.nv && m.nghost == direct.nghost && memcmp(m.X, direct.X, sizeof(double) * 3 * (size_t)m.nv) == 0 &&
              memcmp(m.ghost, direct.ghost, sizeof(int) * 4 * (size_t)m.nghost) == 0,
          "the surface (%d vertices, %d triangles) is not the march on the lattice g (%d, %d)", m.nv, m.nghost, direct.nv,
          direct.nghost);
    printf("# retried on the lattice g: %d triangles, no point past s\n", m.nghost);
    rk_mesh_free(&m);
    rk_mesh_free(&direct);
    free(X);
}

TEST(a_point_past_s_even_on_g_is_refused_naming_the_file)
{
    int n = 1000;
    double *X = jittered_shell(n, 0.1, 4242), s = 0;
    rk_scene_object o;
    rk_error err = {{0}};
    rk_mesh m;
    CHECK(X != NULL, "out of memory");
    object_at(&o, X, n, 11.5, &s);
    int rc = rk_cloud_surface(&o, X, n, &m, &err);
    printf("# shell at g = 11.5 s: %s\n", rc ? err.msg : "accepted");
    CHECK(rc != 0, "accepted");
    CHECK(strstr(err.msg, FILE_NAME) && strstr(err.msg, "even on the lattice") && strstr(err.msg, "proxy_voxel"),
          "the error does not name the file, the lattice and the remedy: %s", err.msg);
    free(X);
}

int main(void)
{
    RUN(a_point_past_s_on_the_coarse_lattice_retries_on_g);
    RUN(a_point_past_s_even_on_g_is_refused_naming_the_file);
    return test_finish();
}
