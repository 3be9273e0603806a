/* An app's triangle mesh as a collider (runtime/mesh_index.c, mesh_collider.c, mesh_move.c over
 * the obstacles' contact code). Compiled twice: float (a float32 asset) and double
 * (test_runtime_mesh_collider_double, a float64 asset).
 *  - two objects dropped onto each other into a mesh bowl (an OBJ written here), the bowl baked
 *    as a mesh obstacle and, in a second asset without it, handed to the runtime as an app mesh
 *    at the identity pose: the same trajectory (1e-10 of the largest displacement in double);
 *    in both, no edge of the surfaces crosses a triangle (the exact segment-triangle test of
 *    precompute/contact, every frame: between the objects, and against the bowl) and the least
 *    distance stays above 0;
 *  - a 3200-triangle spiky terrain the app sweeps up into the two objects, turning: no crossing
 *    by the exact test in any frame, the objects pushed ahead;
 *  - a terrain baked rising at 1 m/s (OBMO) and the same terrain as an app mesh moved 1 cm before
 *    each step: one path (the move rule is the scripted obstacles'), 1e-10 in double; and two halves
 *    rising at 1 and 0.5 m/s, two moving obstacles against two app meshes moved at once;
 *  - bad meshes, indices and poses refused with ROMRT_E_ARGUMENT by name, nothing placed;
 *  - the cost of a 3200- and a 20,000-triangle terrain (index build, a resting step). */
#include "runtime_fixture.h"

#include <time.h>
#include <unistd.h>

#include "contact/contact.h"
#include "physics/physics.h"

#ifdef ROMRT_DOUBLE
#define PARITY_TOL 1e-10
#define ASSET_REAL ROMBIN_REAL_F64
#define NEWTON_TOL "1e-11"
#define PRECISION "double"
#else
/* float: the two BVHs (the bake's and the index's) give the stencils in different orders, and
 * the rounding of the barrier's sum in another order moved the bowl's path by 1.4e-3 of the
 * displacement (1.7e-15 in double); test_runtime_obstacles' twisting box allows 5e-3 for the same */
#define PARITY_TOL 5e-3
#define ASSET_REAL ROMBIN_REAL_F32
#define NEWTON_TOL "1e-7"
#define PRECISION "float"
#endif

/* A mesh in double (the test's) and in the runtime's reals (the app's copy it hands over). */
typedef struct {
    int nv, nt;
    double *X;
    int32_t *T;
    romrt_real *Xr;
    romrt_mesh mesh;
} app_mesh;

static void app_mesh_free(app_mesh *a)
{
    free(a->X), free(a->T), free(a->Xr), free(a->mesh.index);
    memset(a, 0, sizeof *a);
}

/* A heightfield of n x n cells over [-w, w]^2: height(x, z, i, j). */
typedef double (*height_fn)(double x, double z, int i, int j);

static void heightfield(app_mesh *a, int n, double w, height_fn h)
{
    a->nv = (n + 1) * (n + 1), a->nt = 2 * n * n;
    a->X = calloc((size_t)3 * a->nv, sizeof(double));
    a->T = calloc((size_t)3 * a->nt, sizeof(int32_t));
    a->Xr = calloc((size_t)3 * a->nv, sizeof(romrt_real));
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            double x = -w + 2 * w * i / n, z = -w + 2 * w * j / n, *p = a->X + 3 * (j * (n + 1) + i);
            p[0] = x, p[1] = h(x, z, i, j), p[2] = z;
        }
    for (int j = 0, t = 0; j < n; j++)
        for (int i = 0; i < n; i++, t += 2) {
            int32_t v = j * (n + 1) + i, *T = a->T + 3 * t;
            T[0] = v, T[1] = v + n + 1, T[2] = v + 1, T[3] = v + 1, T[4] = v + n + 1, T[5] = v + n + 2;
        }
    for (int k = 0; k < 3 * a->nv; k++) a->Xr[k] = (romrt_real)a->X[k];
    a->mesh.positions = a->Xr, a->mesh.triangles = a->T, a->mesh.vertex_count = a->nv, a->mesh.triangle_count = a->nt;
    if (romrt_mesh_index_size((size_t)a->nv, (size_t)a->nt, &a->mesh.index_bytes, NULL)) a->mesh.index_bytes = 16;
    a->mesh.index = aligned_alloc(16, (a->mesh.index_bytes + 15) / 16 * 16);
}

static double bowl_height(double x, double z, int i, int j)
{
    (void)i, (void)j;
    return 2.5 * (x * x + z * z);
}

static double spiky_height(double x, double z, int i, int j)
{
    unsigned s = (unsigned)(i * 7919 + j * 104729 + 12345) * 1103515245u + 12345u;
    (void)x, (void)z;
    return i % 4 == 2 && j % 4 == 2 ? 0.03 : 0.015 * (double)((s >> 8) & 0xFFFF) / 65536.0;
}

/* The mesh as an OBJ, exact in double. */
static int write_obj(const char *path, const app_mesh *a)
{
    FILE *fp = fopen(path, "w");
    if (!fp) return -1;
    for (int v = 0; v < a->nv; v++) fprintf(fp, "v %.17g %.17g %.17g\n", a->X[3 * v], a->X[3 * v + 1], a->X[3 * v + 2]);
    for (int t = 0; t < a->nt; t++) fprintf(fp, "f %d %d %d\n", a->T[3 * t] + 1, a->T[3 * t + 1] + 1, a->T[3 * t + 2] + 1);
    return fclose(fp);
}

/* Two boxes dropped onto each other (the upper one faster and drifting; a box mesh spans translate
 * to translate + size), `obstacles` the scene's, kappa (0: the contact stage's own). */
static const char *two_boxes(double kappa, const char *obstacles, double gravity)
{
    static char json[4096];
    char k[64] = "";
    if (kappa > 0) snprintf(k, sizeof k, ", \"kappa\": %.17g", kappa);
    snprintf(json, sizeof json,
             "{\"objects\": ["
             "  {\"mesh\": {\"box\": {\"size\": [0.1, 0.04, 0.1], \"cells\": [2, 1, 2]}, \"translate\": [-0.05, 0.035, -0.05]},"
             "   \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000},"
             "   \"velocity\": [0, -1, 0]},"
             "  {\"mesh\": {\"box\": {\"size\": [0.06, 0.06, 0.06], \"cells\": [2, 2, 2]}, \"translate\": [-0.03, 0.1, -0.02]},"
             "   \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000},"
             "   \"velocity\": [0.2, -1.5, 0]}],"
             " \"gravity\": [0, %g, 0], \"obstacles\": [%s], \"contact\": {\"dhat\": 0.002, \"friction\": 0.2%s},"
             " \"time\": {\"step\": 0.01, \"duration\": 0.4}, \"newton\": {\"tolerance\": " NEWTON_TOL "},"
             " \"rom\": {\"basis\": \"modes\", \"size\": 16, \"asset\": {\"contact_pairs\": 30000}}}",
             gravity, obstacles, k);
    return json;
}

static int boxes_apart(const double *p, const double *q, int np, const double *a, const double *b, const double *c)
{
    for (int k = 0; k < 3; k++) {
        double lo = fmin(a[k], fmin(b[k], c[k])), hi = fmax(a[k], fmax(b[k], c[k]));
        if (fmax(p[k], np > 1 ? q[k] : p[k]) < lo || fmin(p[k], np > 1 ? q[k] : p[k]) > hi) return 1;
    }
    return 0;
}

/* The mesh in the world at pose (R, p). */
static void placed(const app_mesh *a, const double *R, const double *p, double *y)
{
    for (int v = 0; v < a->nv; v++)
        for (int i = 0; i < 3; i++)
            y[3 * v + i] = R[3 * i] * a->X[3 * v] + R[3 * i + 1] * a->X[3 * v + 1] + R[3 * i + 2] * a->X[3 * v + 2] + p[i];
}

/* The body's surface against the mesh at y: crossings by the exact test (body edges through mesh
 * triangles, mesh edges through body triangles) and, when least, the least point-triangle and
 * edge-edge distance. */
static int mesh_crossings(const rt_surface *b, const app_mesh *a, const double *y, double *least)
{
    int count = 0;
    for (int t = 0; t < b->nt; t++) {
        const double *p[3];
        for (int k = 0; k < 3; k++) p[k] = b->x + 3 * b->tris[3 * t + k];
        for (int o = 0; o < a->nt; o++) {
            const double *q[3] = {y + 3 * a->T[3 * o], y + 3 * a->T[3 * o + 1], y + 3 * a->T[3 * o + 2]};
            for (int k = 0; k < 3; k++) {
                const double *e0 = p[k], *e1 = p[(k + 1) % 3], *f0 = q[k], *f1 = q[(k + 1) % 3];
                if (!boxes_apart(e0, e1, 2, q[0], q[1], q[2])) count += rk_segment_triangle_intersect(e0, e1, q[0], q[1], q[2]);
                if (!boxes_apart(f0, f1, 2, p[0], p[1], p[2])) count += rk_segment_triangle_intersect(f0, f1, p[0], p[1], p[2]);
                if (least) {
                    const double *pt[4] = {p[k], q[0], q[1], q[2]}, *tp[4] = {q[k], p[0], p[1], p[2]};
                    const double *ee[4] = {e0, e1, f0, f1};
                    *least = fmin(*least, sqrt(rk_contact_distance2(rk_point_triangle_case(pt), pt, NULL, NULL)));
                    *least = fmin(*least, sqrt(rk_contact_distance2(rk_point_triangle_case(tp), tp, NULL, NULL)));
                    *least = fmin(*least, sqrt(rk_contact_distance2(rk_edge_edge_case(ee), ee, NULL, NULL)));
                }
            }
        }
    }
    return count;
}

static double seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static const romrt_real identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};

TEST(two_objects_in_a_mesh_bowl_baked_or_app_mesh_same_path_no_crossing)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture A, B;
    app_mesh bowl = {0};
    char path[64], obstacle[160];
    const romrt_real zero[3] = {0, 0, 0};
    heightfield(&bowl, 20, 0.2, bowl_height);
    snprintf(path, sizeof path, "%s/romkit_bowl_%d.obj", tl_tmpdir(), (int)getpid());
    CHECK(write_obj(path, &bowl) == 0, "cannot write %s", path);
    snprintf(obstacle, sizeof obstacle, "{\"mesh\": {\"file\": \"%s\"}}", path);
    CHECK_OK(rt_fixture_open(&A, two_boxes(0, obstacle, -9.81), ASSET_REAL, &err, &rerr));
    double kappa = A.R.model.contact.kappa;
    CHECK_OK(rt_fixture_open(&B, two_boxes(kappa, "", -9.81), ASSET_REAL, &err, &rerr));
    remove(path);
    CHECK(romrt_mesh_index_build(&bowl.mesh, &rerr) == ROMRT_OK, "index: %s", rerr.message);
    CHECK(romrt_set_mesh_collider(B.m, 3, &bowl.mesh, zero, identity, &rerr) == ROMRT_OK, "place: %s", rerr.message);
    rt_surface a, b;
    rt_surface_init(&a, A.m), rt_surface_init(&b, B.m);
    double *xa = calloc((size_t)3 * A.sim.mesh.nv, sizeof(double)), *xb = calloc((size_t)3 * B.sim.mesh.nv, sizeof(double));
    double worst = 0, scale = 0, least_a = INFINITY, least_b = INFINITY, lowest = INFINITY, between = INFINITY;
    int cross_a = 0, cross_b = 0, steps = 40, rc = 0;
    double time_a = 0, time_b = 0;
    for (int k = 0; k < steps && !rc; k++) {
        int c = 0;
        double d = INFINITY;
        double t0 = seconds(), t1;
        if (romrt_step(A.m, &rerr) != ROMRT_OK || ((t1 = seconds()), romrt_step(B.m, &rerr)) != ROMRT_OK) {
            rc = rk_fail(&err, "step %d: %s", k, rerr.message);
            break;
        }
        time_a += t1 - t0, time_b += seconds() - t1;
        rt_surface_read(&a, A.m), rt_surface_read(&b, B.m);
        for (int i = 0; i < 3 * a.n; i++) {
            worst = fmax(worst, fabs(a.x[i] - b.x[i]));
            scale = fmax(scale, fabs(a.x[i] - A.sim.mesh.X[3 * (int)A.vmap[i / 3] + i % 3]));
        }
        for (int i = 0; i < b.n; i++) lowest = fmin(lowest, b.x[3 * i + 1]);
        /* A: everything by the contact stage's measure (the bowl is its obstacle) */
        rt_fixture_positions(&A, xa);
        rc = rk_contact_measure(&A.R.model.contact, xa, &c, &d, &err);
        cross_a += c, least_a = fmin(least_a, d);
        /* B: the objects by the measure, the app's bowl by the brute force above */
        rt_fixture_positions(&B, xb);
        c = 0, d = INFINITY;
        if (!rc) rc = rk_contact_measure(&B.R.model.contact, xb, &c, &d, &err);
        cross_b += c, least_b = fmin(least_b, d), between = fmin(between, d);
        cross_b += mesh_crossings(&b, &bowl, bowl.X, &least_b);
    }
    printf("# bowl (%s): baked against app mesh %.3g of the largest displacement %.3g m (tol %g); crossings %d / %d;"
           " least distance %.3g / %.3g m (objects %.3g m); lowest point y = %.4f; %.2f / %.2f ms a step\n",
           PRECISION, worst / scale, scale, PARITY_TOL, cross_a, cross_b, least_a, least_b, between, lowest,
           1e3 * time_a / steps, 1e3 * time_b / steps);
    CHECK(rc == 0, "%s", err.msg);
    CHECK(cross_a == 0 && cross_b == 0, "crossings: %d with the baked bowl, %d with the app's", cross_a, cross_b);
    CHECK(least_a > 0 && least_b > 0, "least distance %.3g / %.3g", least_a, least_b);
    CHECK(least_b < 0.002 && between < 0.002, "the objects should touch the bowl and each other (%.3g, %.3g)", least_b, between);
    CHECK(worst / scale <= PARITY_TOL, "baked and app bowl differ by %.3g of the displacement", worst / scale);
    rt_surface_free(&a), rt_surface_free(&b);
    free(xa), free(xb);
    app_mesh_free(&bowl);
    rt_fixture_close(&A), rt_fixture_close(&B);
}

/* Rotation by angle about z. */
static void turn_z(double angle, double *R)
{
    double c = cos(angle), s = sin(angle);
    double M[9] = {c, -s, 0, s, c, 0, 0, 0, 1};
    memcpy(R, M, sizeof M);
}


TEST(a_terrain_swept_up_into_two_objects_never_crosses)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture F;
    app_mesh ter = {0};
    heightfield(&ter, 40, 0.15, spiky_height); /* 3200 triangles */
    CHECK_OK(rt_fixture_open(&F, two_boxes(0, "", -9.81), ASSET_REAL, &err, &rerr));
    double t0 = seconds();
    CHECK(romrt_mesh_index_build(&ter.mesh, &rerr) == ROMRT_OK, "index: %s", rerr.message);
    double build = seconds() - t0;
    rt_surface b;
    rt_surface_init(&b, F.m);
    double *y = calloc((size_t)3 * ter.nv, sizeof(double)), R[9], p[3] = {0, -0.04, 0}, lowest0 = INFINITY, lowest = INFINITY;
    romrt_real Rr[9], pr[3];
    rt_surface_read(&b, F.m);
    for (int i = 0; i < b.n; i++) lowest0 = fmin(lowest0, b.x[3 * i + 1]);
    for (int k = 0; k < 9; k++) Rr[k] = identity[k];
    for (int k = 0; k < 3; k++) pr[k] = (romrt_real)p[k];
    CHECK(romrt_set_mesh_collider(F.m, 0, &ter.mesh, pr, Rr, &rerr) == ROMRT_OK, "place: %s", rerr.message);
    int crossed = 0, behind = 0, steps = 30, rc = 0;
    double stepping = 0;
    for (int k = 1; k <= steps && !rc; k++) {
        /* up 1.5 m/s, turning to 8 degrees about z: into the falling boxes */
        p[1] = -0.04 + 0.015 * k;
        turn_z(0.14 * k / steps, R);
        for (int i = 0; i < 9; i++) Rr[i] = (romrt_real)R[i];
        for (int i = 0; i < 3; i++) pr[i] = (romrt_real)p[i];
        if (romrt_set_mesh_collider(F.m, 0, &ter.mesh, pr, Rr, &rerr) != ROMRT_OK) {
            rc = rk_fail(&err, "move %d: %s", k, rerr.message);
            break;
        }
        t0 = seconds();
        if (romrt_step(F.m, &rerr) != ROMRT_OK) {
            rc = rk_fail(&err, "step %d: %s", k, rerr.message);
            break;
        }
        stepping += seconds() - t0;
        romrt_step_info info;
        info.size = sizeof info;
        romrt_last_step(F.m, &info, NULL);
        behind += info.colliders_behind;
        rt_surface_read(&b, F.m);
        /* the mesh where the runtime has it: at the pose, or short of it on the straight lines */
        placed(&ter, R, p, y);
        if (!info.colliders_behind) crossed += mesh_crossings(&b, &ter, y, NULL);
        lowest = INFINITY; /* at the last step */
        for (int i = 0; i < b.n; i++) lowest = fmin(lowest, b.x[3 * i + 1]);
    }
    printf("# terrain of %d triangles swept up at 1.5 m/s into two boxes (%s): %d crossings, %d steps behind, lowest"
           " point from %.4f to %.4f m at the end; index %.2f ms, %.2f ms a step\n",
           ter.nt, PRECISION, crossed, behind, lowest0, lowest, 1e3 * build, 1e3 * stepping / steps);
    CHECK(rc == 0, "%s", err.msg);
    CHECK(crossed == 0, "%d crossings of the swept terrain", crossed);
    CHECK(behind < steps, "the terrain should reach its poses");
    CHECK(lowest > lowest0 + 0.2, "the terrain should push the boxes up ahead of it (lowest point %.4f)", lowest);
    rt_surface_free(&b);
    free(y);
    app_mesh_free(&ter);
    rt_fixture_close(&F);
}

/* The move rule is the scripted obstacles': a terrain baked rising at 1 m/s (OBMO's translate) and
 * the same terrain as an app mesh the app puts 1 cm higher before each step take one path. */
TEST(an_app_mesh_moved_as_a_baked_obstacle_moves_takes_its_path)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture A, B;
    app_mesh ter = {0};
    char path[64], obstacle[200];
    heightfield(&ter, 20, 0.15, spiky_height);
    for (int v = 0; v < ter.nv; v++) ter.X[3 * v + 1] -= 0.04, ter.Xr[3 * v + 1] = (romrt_real)ter.X[3 * v + 1];
    snprintf(path, sizeof path, "%s/romkit_rising_%d.obj", tl_tmpdir(), (int)getpid());
    CHECK(write_obj(path, &ter) == 0, "cannot write %s", path);
    snprintf(obstacle, sizeof obstacle, "{\"mesh\": {\"file\": \"%s\"}, \"translate\": {\"velocity\": [0, 1, 0]}}", path);
    CHECK_OK(rt_fixture_open(&A, two_boxes(0, obstacle, -9.81), ASSET_REAL, &err, &rerr));
    CHECK_OK(rt_fixture_open(&B, two_boxes(A.R.model.contact.kappa, "", -9.81), ASSET_REAL, &err, &rerr));
    remove(path);
    CHECK(romrt_mesh_index_build(&ter.mesh, &rerr) == ROMRT_OK, "index: %s", rerr.message);
    romrt_real p[3] = {0, 0, 0};
    CHECK(romrt_set_mesh_collider(B.m, 1, &ter.mesh, p, identity, &rerr) == ROMRT_OK, "place: %s", rerr.message);
    rt_surface a, b;
    rt_surface_init(&a, A.m), rt_surface_init(&b, B.m);
    double worst = 0, scale = 0, *y = calloc((size_t)3 * ter.nv, sizeof(double)), R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    int steps = 30, rc = 0, crossed = 0, behind = 0;
    for (int k = 1; k <= steps && !rc; k++) {
        romrt_step_info info;
        p[1] = (romrt_real)(0.01 * k);
        if (romrt_set_mesh_collider(B.m, 1, &ter.mesh, p, identity, &rerr) != ROMRT_OK || romrt_step(A.m, &rerr) != ROMRT_OK ||
            romrt_step(B.m, &rerr) != ROMRT_OK) {
            rc = rk_fail(&err, "step %d: %s", k, rerr.message);
            break;
        }
        info.size = sizeof info;
        romrt_last_step(B.m, &info, NULL);
        behind += info.colliders_behind;
        rt_surface_read(&a, A.m), rt_surface_read(&b, B.m);
        for (int i = 0; i < 3 * a.n; i++) {
            worst = fmax(worst, fabs(a.x[i] - b.x[i]));
            scale = fmax(scale, fabs(a.x[i] - A.sim.mesh.X[3 * (int)A.vmap[i / 3] + i % 3]));
        }
        double shift[3] = {0, (double)p[1], 0};
        placed(&ter, R, shift, y);
        crossed += mesh_crossings(&b, &ter, y, NULL);
    }
    printf("# terrain rising at 1 m/s (%s): baked (OBMO) against app mesh %.3g of the largest displacement %.3g m"
           " (tol %g), %d crossings, %d steps behind\n",
           PRECISION, worst / scale, scale, PARITY_TOL, crossed, behind);
    CHECK(rc == 0, "%s", err.msg);
    CHECK(crossed == 0 && behind == 0, "%d crossings, %d steps behind", crossed, behind);
    CHECK(scale > 0.05, "the terrain should carry the boxes up (largest displacement %.3g m)", scale);
    CHECK(worst / scale <= PARITY_TOL, "baked and app terrain differ by %.3g of the displacement", worst / scale);
    rt_surface_free(&a), rt_surface_free(&b);
    free(y);
    app_mesh_free(&ter);
    rt_fixture_close(&A), rt_fixture_close(&B);
}

/* Two halves of the terrain, side by side under the lower box, rising at 1 and 0.5 m/s: baked as two
 * moving obstacles (each its own progress unknown, contact_progress.c) and handed over as two app
 * meshes moved before each step (the same rule, mesh_move.c): one path, no crossing, none behind. */
TEST(two_app_meshes_moved_at_once_take_the_baked_obstacles_paths)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture A, B;
    app_mesh half[2] = {{0}};
    char path[2][64], obstacles[400];
    const double rate[2] = {1.0, 0.5};
    for (int h = 0; h < 2; h++) {
        heightfield(&half[h], 10, 0.075, spiky_height);
        for (int v = 0; v < half[h].nv; v++) {
            half[h].X[3 * v] += h ? 0.075 : -0.075, half[h].X[3 * v + 1] -= 0.04;
            for (int a = 0; a < 2; a++) half[h].Xr[3 * v + a] = (romrt_real)half[h].X[3 * v + a];
        }
        snprintf(path[h], sizeof path[h], "%s/romkit_half%d_%d.obj", tl_tmpdir(), h, (int)getpid());
        CHECK(write_obj(path[h], &half[h]) == 0, "cannot write %s", path[h]);
    }
    snprintf(obstacles, sizeof obstacles,
             "{\"mesh\": {\"file\": \"%s\"}, \"translate\": {\"velocity\": [0, %g, 0]}},"
             "{\"mesh\": {\"file\": \"%s\"}, \"translate\": {\"velocity\": [0, %g, 0]}}",
             path[0], rate[0], path[1], rate[1]);
    CHECK_OK(rt_fixture_open(&A, two_boxes(0, obstacles, -9.81), ASSET_REAL, &err, &rerr));
    CHECK_OK(rt_fixture_open(&B, two_boxes(A.R.model.contact.kappa, "", -9.81), ASSET_REAL, &err, &rerr));
    remove(path[0]), remove(path[1]);
    romrt_real p[2][3] = {{0, 0, 0}, {0, 0, 0}};
    for (int h = 0; h < 2; h++) {
        CHECK(romrt_mesh_index_build(&half[h].mesh, &rerr) == ROMRT_OK, "index: %s", rerr.message);
        CHECK(romrt_set_mesh_collider(B.m, (size_t)h + 1, &half[h].mesh, p[h], identity, &rerr) == ROMRT_OK, "place: %s",
              rerr.message);
    }
    rt_surface a, b;
    rt_surface_init(&a, A.m), rt_surface_init(&b, B.m);
    double worst = 0, scale = 0, R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    double *y = calloc((size_t)3 * half[0].nv, sizeof(double));
    int steps = 25, rc = 0, crossed = 0, behind = 0;
    for (int k = 1; k <= steps && !rc; k++) {
        romrt_step_info info;
        for (int h = 0; h < 2 && !rc; h++) {
            p[h][1] = (romrt_real)(0.01 * rate[h] * k);
            if (romrt_set_mesh_collider(B.m, (size_t)h + 1, &half[h].mesh, p[h], identity, &rerr) != ROMRT_OK)
                rc = rk_fail(&err, "step %d, mesh %d: %s", k, h, rerr.message);
        }
        if (rc || romrt_step(A.m, &rerr) != ROMRT_OK || romrt_step(B.m, &rerr) != ROMRT_OK) {
            if (!rc) rc = rk_fail(&err, "step %d: %s", k, rerr.message);
            break;
        }
        info.size = sizeof info;
        romrt_last_step(B.m, &info, NULL);
        behind += info.colliders_behind;
        rt_surface_read(&a, A.m), rt_surface_read(&b, B.m);
        for (int i = 0; i < 3 * a.n; i++) {
            worst = fmax(worst, fabs(a.x[i] - b.x[i]));
            scale = fmax(scale, fabs(a.x[i] - A.sim.mesh.X[3 * (int)A.vmap[i / 3] + i % 3]));
        }
        for (int h = 0; h < 2; h++) {
            double shift[3] = {0, (double)p[h][1], 0};
            placed(&half[h], R, shift, y);
            crossed += mesh_crossings(&b, &half[h], y, NULL);
        }
    }
    printf("# two terrain halves rising at 1 and 0.5 m/s (%s): baked (OBMO) against two app meshes %.3g of the largest"
           " displacement %.3g m (tol %g), %d crossings, %d steps behind\n",
           PRECISION, worst / scale, scale, PARITY_TOL, crossed, behind);
    CHECK(rc == 0, "%s", err.msg);
    CHECK(crossed == 0 && behind == 0, "%d crossings, %d steps behind", crossed, behind);
    CHECK(scale > 0.05, "the terrain should carry the boxes up (largest displacement %.3g m)", scale);
    CHECK(worst / scale <= PARITY_TOL, "baked and app terrains differ by %.3g of the displacement", worst / scale);
    rt_surface_free(&a), rt_surface_free(&b);
    free(y);
    app_mesh_free(&half[0]), app_mesh_free(&half[1]);
    rt_fixture_close(&A), rt_fixture_close(&B);
}

TEST(bad_meshes_and_poses_are_refused_by_name_and_place_nothing)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture F;
    app_mesh a = {0};
    const romrt_real far[3] = {0, -1, 0};
    romrt_real touching[3];
    romrt_real bent[9] = {1, 0, 0, 0, 1, 0.1, 0, 0, 1};
    heightfield(&a, 4, 0.3, bowl_height);
    CHECK_OK(rt_fixture_open(&F, two_boxes(0, "", -9.81), ASSET_REAL, &err, &rerr));
#define REFUSED(call, what)                                                                                            \
    do {                                                                                                               \
        romrt_status st_ = (call);                                                                                     \
        printf("# %s: %s\n", #call, rerr.message);                                                                     \
        CHECK(st_ == ROMRT_E_ARGUMENT && strstr(rerr.message, what), "%s: status %d, \"%s\" (want \"%s\")", #call, st_, \
              rerr.message, what);                                                                                     \
    } while (0)
    romrt_limits lim;
    lim.size = sizeof lim;
    size_t bytes = 1;
    CHECK(romrt_get_limits(&lim, &rerr) == ROMRT_OK && lim.mesh_max_count == (size_t)1 << 24 && lim.collider_slots > 0,
          "limits: %s", rerr.message);
    REFUSED(romrt_mesh_index_size(0, 3, &bytes, &rerr), "0 vertices");
    REFUSED(romrt_mesh_index_size(3, lim.mesh_max_count + 1, &bytes, &rerr), "triangles");
    CHECK(bytes == 1, "a refused size wrote %zu", bytes);
    REFUSED(romrt_set_mesh_collider(F.m, 0, &a.mesh, far, identity, &rerr), "not built");
    a.Xr[3 * 7 + 1] = (romrt_real)NAN;
    REFUSED(romrt_mesh_index_build(&a.mesh, &rerr), "vertex 7");
    a.Xr[3 * 7 + 1] = 0;
    a.T[3 * 5 + 1] = a.nv;
    REFUSED(romrt_mesh_index_build(&a.mesh, &rerr), "triangle 5");
    a.T[3 * 5 + 1] = a.T[3 * 5];
    REFUSED(romrt_mesh_index_build(&a.mesh, &rerr), "triangle 5 names one vertex twice");
    a.T[3 * 5 + 1] = a.T[3 * 5] + 1;
    a.mesh.triangle_count = 0;
    REFUSED(romrt_mesh_index_build(&a.mesh, &rerr), "triangle count 0");
    a.mesh.triangle_count = a.nt;
    a.mesh.index_bytes -= 8;
    REFUSED(romrt_mesh_index_build(&a.mesh, &rerr), "romrt_mesh_index_size asks");
    a.mesh.index_bytes += 8;
    a.mesh.index = (char *)a.mesh.index + 4;
    REFUSED(romrt_mesh_index_build(&a.mesh, &rerr), "aligned");
    a.mesh.index = (char *)a.mesh.index - 4;
    CHECK(romrt_mesh_index_build(&a.mesh, &rerr) == ROMRT_OK, "a good mesh: %s", rerr.message);
    romrt_real nan_pose[3] = {0, (romrt_real)NAN, 0};
    REFUSED(romrt_set_mesh_collider(F.m, 0, &a.mesh, nan_pose, identity, &rerr), "not finite");
    REFUSED(romrt_set_mesh_collider(F.m, 0, &a.mesh, far, bent, &rerr), "orthonormal");
    REFUSED(romrt_set_mesh_collider(F.m, lim.collider_slots, &a.mesh, far, identity, &rerr), "slot");
    a.mesh.vertex_count--;
    REFUSED(romrt_set_mesh_collider(F.m, 0, &a.mesh, far, identity, &rerr), "not built");
    a.mesh.vertex_count++;
    /* the app's arrays changed after the build: checked again when placed */
    a.Xr[3 * 9 + 2] = (romrt_real)INFINITY;
    REFUSED(romrt_set_mesh_collider(F.m, 0, &a.mesh, far, identity, &rerr), "romrt_set_mesh_collider: the position of vertex 9");
    a.Xr[3 * 9 + 2] = (romrt_real)a.X[3 * 9 + 2];
    int32_t kept = a.T[3 * 2 + 2];
    a.T[3 * 2 + 2] = -1;
    REFUSED(romrt_set_mesh_collider(F.m, 0, &a.mesh, far, identity, &rerr), "triangle 2 names a vertex out of range, at corner 2");
    a.T[3 * 2 + 2] = kept;
    /* the bowl's centre vertex (0, 0, 0) on a vertex of the body: refused, and the slot stays
     * empty (a step is free) */
    romrt_real *shown = calloc((size_t)3 * romrt_shown_count(F.m), sizeof(romrt_real));
    romrt_positions(F.m, shown, 3 * (size_t)(romrt_shown_count(F.m)), 3, NULL);
    for (int k = 0; k < 3; k++) touching[k] = shown[k];
    free(shown);
    CHECK(a.X[3 * 12] == 0 && a.X[3 * 12 + 1] == 0 && a.X[3 * 12 + 2] == 0, "vertex 12 is the bowl's centre");
    REFUSED(romrt_set_mesh_collider(F.m, 0, &a.mesh, touching, identity, &rerr), "touch or cross the body");
    /* the bowl's bottom through the middle of the lower box, no vertex on it: crossing, refused */
    const romrt_real through[3] = {0, 0.05, 0};
    REFUSED(romrt_set_mesh_collider(F.m, 0, &a.mesh, through, identity, &rerr), "touch or cross the body");
    romrt_step_info info;
    CHECK(romrt_step(F.m, &rerr) == ROMRT_OK, "a step after the refusal: %s", rerr.message);
    info.size = sizeof info;
    romrt_last_step(F.m, &info, NULL);
    CHECK(info.colliders_behind == 0, "nothing should be placed");
    CHECK(romrt_set_mesh_collider(F.m, 0, &a.mesh, far, identity, &rerr) == ROMRT_OK, "placed far: %s", rerr.message);
    REFUSED(romrt_set_mesh_collider(F.m, 1, &a.mesh, far, identity, &rerr), "slot 0 already");
    CHECK(romrt_remove_collider(F.m, 0, &rerr) == ROMRT_OK && romrt_step(F.m, &rerr) == ROMRT_OK, "removed: %s", rerr.message);
    rt_fixture_close(&F);
    /* an asset without a collision surface (one object over a plane, baked with the collision
     * vertices alone) takes no mesh */
    CHECK_OK(rt_fixture_open(&F,
                             "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.1, 0.1, 0.1], \"cells\": [1, 1, 1]}},"
                             "  \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000}}],"
                             " \"obstacles\": [{\"plane\": {\"point\": [0, -0.1, 0], \"normal\": [0, 1, 0]}}],"
                             " \"time\": {\"step\": 0.01, \"duration\": 0.1},"
                             " \"rom\": {\"basis\": \"modes\", \"size\": 6, \"asset\": {\"colliders\": \"vertices\"}}}",
                             ASSET_REAL, &err, &rerr));
    romrt_status st = romrt_set_mesh_collider(F.m, 0, &a.mesh, far, identity, &rerr);
    printf("# no collision surface: %s\n", rerr.message);
    CHECK(st == ROMRT_E_UNSUPPORTED && strstr(rerr.message, "collision surface"), "status %d: %s", st, rerr.message);
    rt_fixture_close(&F);
    app_mesh_free(&a);
}

/* The cost of an app terrain under a resting object: the index, and a step with the box on it. */
static void terrain_cost(int n)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture F;
    app_mesh ter = {0};
    const romrt_real p[3] = {0, -0.031, 0};
    heightfield(&ter, n, 0.15, spiky_height);
    CHECK_OK(rt_fixture_open(&F, two_boxes(0, "", -9.81), ASSET_REAL, &err, &rerr));
    double t0 = seconds();
    CHECK(romrt_mesh_index_build(&ter.mesh, &rerr) == ROMRT_OK, "index: %s", rerr.message);
    double build = seconds() - t0;
    CHECK(romrt_set_mesh_collider(F.m, 0, &ter.mesh, p, identity, &rerr) == ROMRT_OK, "place: %s", rerr.message);
    int steps = 30, rc = 0;
    t0 = seconds();
    for (int k = 0; k < steps && !rc; k++)
        if (romrt_step(F.m, &rerr) != ROMRT_OK) rc = rk_fail(&err, "step %d: %s", k, rerr.message);
    double stepping = (seconds() - t0) / steps;
    /* the same steps with the mesh sliding along x by 1 mm a step (refits and moves) */
    t0 = seconds();
    for (int k = 0; k < steps && !rc; k++) {
        romrt_real q[3] = {(romrt_real)(0.001 * (k + 1)), p[1], 0};
        if (romrt_set_mesh_collider(F.m, 0, &ter.mesh, q, identity, &rerr) != ROMRT_OK || romrt_step(F.m, &rerr) != ROMRT_OK)
            rc = rk_fail(&err, "moving step %d: %s", k, rerr.message);
    }
    double moving = (seconds() - t0) / steps;
    printf("# app terrain of %d triangles (%s): index %zu bytes (%.0f a triangle), built in %.2f ms; two boxes landing"
           " on it %.2f ms a step, with the terrain moving %.2f ms\n",
           ter.nt, PRECISION, ter.mesh.index_bytes, (double)ter.mesh.index_bytes / ter.nt, 1e3 * build, 1e3 * stepping,
           1e3 * moving);
    CHECK(rc == 0, "%s", err.msg);
    app_mesh_free(&ter);
    rt_fixture_close(&F);
}

TEST(cost_of_a_3200_and_a_20000_triangle_terrain)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture F;
    int steps = 30, rc = 0;
    /* the same boxes landing on a plane where the terrain's tips are: what the terrain adds */
    CHECK_OK(rt_fixture_open(&F, two_boxes(0, "{\"plane\": {\"point\": [0, -0.001, 0], \"normal\": [0, 1, 0]}}", -9.81),
                             ASSET_REAL, &err, &rerr));
    double t0 = seconds();
    for (int k = 0; k < steps && !rc; k++)
        if (romrt_step(F.m, &rerr) != ROMRT_OK) rc = rk_fail(&err, "step %d: %s", k, rerr.message);
    printf("# the two boxes landing on a plane (%s): %.2f ms a step\n", PRECISION, 1e3 * (seconds() - t0) / steps);
    CHECK(rc == 0, "%s", err.msg);
    rt_fixture_close(&F);
    terrain_cost(40);
    terrain_cost(100);
}

int main(void)
{
    RUN(two_objects_in_a_mesh_bowl_baked_or_app_mesh_same_path_no_crossing);
    RUN(a_terrain_swept_up_into_two_objects_never_crosses);
    RUN(an_app_mesh_moved_as_a_baked_obstacle_moves_takes_its_path);
    RUN(two_app_meshes_moved_at_once_take_the_baked_obstacles_paths);
    RUN(bad_meshes_and_poses_are_refused_by_name_and_place_nothing);
    RUN(cost_of_a_3200_and_a_20000_triangle_terrain);
    return test_finish();
}
