/* The app's spheres, capsules and boxes (romrt_set_collider) on an asset with a collision surface
 * collide as the scene's obstacles of those kinds do (runtime/shape_collider.c over the obstacles'
 * contact code), not on the surface's vertices. Compiled twice: float (a float32 asset) and
 * double (test_runtime_shape_colliders_double, a float64 asset).
 *  - a thin capsule, a small sphere and a box turned onto an edge, each driven down into the top
 *    face of a coarse block (its top face's vertices 10 cm apart) between them: the shape's core never
 *    crosses the surface (the exact segment-triangle test of precompute/contact: the capsule's
 *    segment, the box's edges and the surface's edges through the box's faces, and the path of
 *    the shape's centre from where it started), the face pushed down ahead of it; on the vertex
 *    path every one of them went through (the face's vertices far from it); a capsule placed
 *    through the face is refused;
 *  - two objects dropped onto a sphere, a capsule and a box, baked as the scene's obstacles in
 *    one asset and placed as the app's colliders in another: the same path (1e-10 of the largest
 *    displacement in double), with contact and friction;
 *  - friction on the analytic incline (test_runtime_incline's law, gravity tilted by theta) with
 *    an app box as the ground: the block sticks below tan theta = mu (drift under 1e-4 m over
 *    1 s) and slides with a = g (sin theta - mu cos theta) within 1% above it. */
#include "runtime_fixture.h"
#include "trajectory_fit.h"

#include "contact/contact.h"
#include "physics/physics.h"

#ifdef ROMRT_DOUBLE
#define PARITY_TOL 1e-10
#define ASSET_REAL ROMBIN_REAL_F64
#define NEWTON_TOL "1e-11"
#define PRECISION "double"
#else
/* float: the two BVHs give the stencils in other orders, so the barrier's sum rounds otherwise
 * (as test_runtime_mesh_collider's bowl, 1.4e-3 there) */
#define PARITY_TOL 5e-3
#define ASSET_REAL ROMBIN_REAL_F32
#define NEWTON_TOL "1e-7"
#define PRECISION "float"
#endif

/* Segment pq through the body's triangles: how many it crosses (exact test). */
static int segment_crossings(const rt_surface *b, const double *p, const double *q)
{
    int count = 0;
    for (int t = 0; t < b->nt; t++)
        count += rk_segment_triangle_intersect(p, q, b->x + 3 * b->tris[3 * t], b->x + 3 * b->tris[3 * t + 1],
                                               b->x + 3 * b->tris[3 * t + 2]);
    return count;
}

/* The least distance from point p to the body's triangles. */
static double point_distance(const rt_surface *b, const double *p)
{
    double least = INFINITY;
    for (int t = 0; t < b->nt; t++) {
        const double *pt[4] = {p, b->x + 3 * b->tris[3 * t], b->x + 3 * b->tris[3 * t + 1], b->x + 3 * b->tris[3 * t + 2]};
        least = fmin(least, sqrt(rk_contact_distance2(rk_point_triangle_case(pt), pt, NULL, NULL)));
    }
    return least;
}

/* The least distance from segment pq to the body's edges and triangles. */
static double segment_distance(const rt_surface *b, const double *p, const double *q)
{
    double least = fmin(point_distance(b, p), point_distance(b, q));
    for (int t = 0; t < b->nt; t++)
        for (int k = 0; k < 3; k++) {
            const double *ee[4] = {p, q, b->x + 3 * b->tris[3 * t + k], b->x + 3 * b->tris[3 * t + (k + 1) % 3]};
            least = fmin(least, sqrt(rk_contact_distance2(rk_edge_edge_case(ee), ee, NULL, NULL)));
        }
    return least;
}

static const int box_tris[36] = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};

/* A box collider's corners in the world (bit a of the index: +h on axis a). */
static void box_corners(const romrt_collider *c, double *y)
{
    for (int i = 0; i < 8; i++) {
        double X[3];
        for (int a = 0; a < 3; a++) X[a] = (i >> a) & 1 ? c->half_extents[a] : -c->half_extents[a];
        for (int a = 0; a < 3; a++)
            y[3 * i + a] = c->position[a] + c->rotation[3 * a] * X[0] + c->rotation[3 * a + 1] * X[1] + c->rotation[3 * a + 2] * X[2];
    }
}

/* The box's edges through the body's triangles and the body's edges through the box's. */
static int box_crossings(const rt_surface *b, const romrt_collider *c)
{
    double y[24];
    int count = 0;
    box_corners(c, y);
    for (int f = 0; f < 12; f++)
        for (int k = 0; k < 3; k++) {
            const double *p = y + 3 * box_tris[3 * f + k], *q = y + 3 * box_tris[3 * f + (k + 1) % 3];
            count += segment_crossings(b, p, q);
        }
    for (int t = 0; t < b->nt; t++)
        for (int k = 0; k < 3; k++) {
            const double *p = b->x + 3 * b->tris[3 * t + k], *q = b->x + 3 * b->tris[3 * t + (k + 1) % 3];
            for (int f = 0; f < 12; f++)
                count += rk_segment_triangle_intersect(p, q, y + 3 * box_tris[3 * f], y + 3 * box_tris[3 * f + 1],
                                                       y + 3 * box_tris[3 * f + 2]);
        }
    return count;
}

/* The least distance between the box's edges and the body's, the box's corners and the body's
 * triangles, and the body's vertices and the box's faces. */
static double box_distance(const rt_surface *b, const romrt_collider *c)
{
    double y[24], least = INFINITY;
    box_corners(c, y);
    for (int f = 0; f < 12; f++)
        for (int k = 0; k < 3; k++)
            least = fmin(least, segment_distance(b, y + 3 * box_tris[3 * f + k], y + 3 * box_tris[3 * f + (k + 1) % 3]));
    for (int i = 0; i < b->n; i++)
        for (int f = 0; f < 12; f++) {
            const double *pt[4] = {b->x + 3 * i, y + 3 * box_tris[3 * f], y + 3 * box_tris[3 * f + 1], y + 3 * box_tris[3 * f + 2]};
            least = fmin(least, sqrt(rk_contact_distance2(rk_point_triangle_case(pt), pt, NULL, NULL)));
        }
    return least;
}

/* A block of 20 cm, 2 x 1 x 2 cells (its top face's vertices 10 cm apart), its bottom held. With
 * self-contact on, or by default with nothing to touch (ROMBIN 1.10), the asset holds its collision
 * surface (OBHD, CEDG, CTRI); with "colliders": "vertices" only the vertices (CVTX). */
#define BLOCK_SCENE(contact, asset)                                                                                               \
    "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.2, 0.2, 0.2], \"cells\": [2, 1, 2]}, \"translate\": [-0.1, 0, -0.1]}," \
    "  \"material\": {\"model\": \"neohookean\", \"young\": 2e4, \"poisson\": 0.3, \"density\": 1000},"                   \
    "  \"fixed\": [{\"box\": [[-1, -1, -1], [1, 0.001, 1]]}]}],"                                                                \
    " \"gravity\": [0, 0, 0], \"contact\": {\"dhat\": 0.001, \"friction\": 0.2" contact "},"                                     \
    " \"time\": {\"step\": 0.01, \"duration\": 0.05}, \"newton\": {\"tolerance\": " NEWTON_TOL "},"                            \
    " \"rom\": {\"basis\": \"modes\", \"size\": 12, \"asset\": {" asset "}}}"

typedef struct {
    int crossings, arrived, placed;
    double least, top;   /* least distance of the core to the surface less its radius; the face's lowest y */
} drive_result;

/* The collider at c driven down by `depth` into the block's top face over 10 steps, then held
 * until it arrives (at most 30 more): crossings and distances in every frame where it is at its
 * pose (not colliders_behind). */
static int drive(rt_fixture *F, romrt_collider c, double depth, drive_result *out, rk_error *err)
{
    romrt_error rerr;
    rt_surface b;
    double y0 = c.position[1], start[3] = {c.position[0], c.position[1] + 0.05, c.position[2]};
    int rc = 0;
    memset(out, 0, sizeof *out);
    out->least = INFINITY;
    out->top = INFINITY;
    if (romrt_reset(F->m, &rerr) != ROMRT_OK || romrt_set_collider(F->m, 0, &c, &rerr) != ROMRT_OK)
        return rk_fail(err, "place: %s", rerr.message);
    out->placed = 1;
    rt_surface_init(&b, F->m);
    for (int k = 1; k <= 40 && !rc; k++) {
        romrt_step_info info;
        c.position[1] = (romrt_real)(y0 - depth * (k < 10 ? k : 10) / 10);
        if (romrt_set_collider(F->m, 0, &c, &rerr) != ROMRT_OK || romrt_step(F->m, &rerr) != ROMRT_OK) {
            rc = rk_fail(err, "step %d: %s", k, rerr.message);
            break;
        }
        info.size = sizeof info;
        romrt_last_step(F->m, &info, NULL);
        if (info.colliders_behind) continue;
        rt_surface_read(&b, F->m);
        double p[3], q[3], centre[3], d;
        for (int a = 0; a < 3; a++) centre[a] = c.position[a];
        out->crossings += segment_crossings(&b, start, centre); /* the core's path from outside */
        if (c.kind == ROMRT_COLLIDER_BOX) {
            out->crossings += box_crossings(&b, &c);
            d = box_distance(&b, &c);
        } else {
            for (int a = 0; a < 3; a++) p[a] = centre[a] - c.half_length * c.rotation[3 * a], q[a] = centre[a] + c.half_length * c.rotation[3 * a];
            if (c.kind == ROMRT_COLLIDER_CAPSULE) out->crossings += segment_crossings(&b, p, q);
            d = (c.kind == ROMRT_COLLIDER_CAPSULE ? segment_distance(&b, p, q) : point_distance(&b, centre)) - c.radius;
        }
        out->least = fmin(out->least, d);
        out->top = INFINITY;
        for (int i = 0; i < b.n; i++)
            if (b.x[3 * i + 1] > 0.1) out->top = fmin(out->top, b.x[3 * i + 1]);
        if (k >= 10) {
            out->arrived = 1;
            break;
        }
    }
    rt_surface_free(&b);
    return rc;
}

/* The three shapes driven into the block's face on the asset `scene` bakes: through the surface's
 * triangles (exact) nothing crosses; on its vertices alone at least one shape goes through. */
static void thin_shapes(const char *scene, const char *label, int exact)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture F;
    printf("# %s\n", label);
    CHECK_OK(rt_fixture_open(&F, scene, ASSET_REAL, &err, &rerr));
    const double s = sqrt(0.5);
    romrt_collider cap = {ROMRT_COLLIDER_CAPSULE, {0.02f, 0.21f, -0.01f}, {1, 0, 0, 0, 1, 0, 0, 0, 1}, 0.003f, 0.03f, {0, 0, 0}};
    romrt_collider ball = {ROMRT_COLLIDER_SPHERE, {0.04f, 0.21f, -0.01f}, {1, 0, 0, 0, 1, 0, 0, 0, 1}, 0.005f, 0, {0, 0, 0}};
    /* turned 45 degrees about z: an edge along z at its bottom */
    romrt_collider box = {ROMRT_COLLIDER_BOX, {0.03f, 0.24f, -0.01f},
                          {(romrt_real)s, (romrt_real)-s, 0, (romrt_real)s, (romrt_real)s, 0, 0, 0, 1}, 0, 0, {0.02f, 0.02f, 0.02f}};
    const romrt_collider *shapes[3] = {&cap, &ball, &box};
    const char *names[3] = {"capsule r 3 mm", "sphere r 5 mm", "box on its edge"};
    /* placed through the face between its vertices (no vertex within it): refused, nothing placed */
    romrt_collider through = cap; /* turned 45 degrees about z: its segment through the face at its middle */
    const romrt_real turned[9] = {(romrt_real)s, (romrt_real)-s, 0, (romrt_real)s, (romrt_real)s, 0, 0, 0, 1};
    memcpy(through.rotation, turned, sizeof turned);
    through.position[1] = 0.2f;
    romrt_status placed = romrt_set_collider(F.m, 0, &through, &rerr);
    printf("# a capsule placed through the face: %s\n", placed == ROMRT_OK ? "taken" : rerr.message);
    if (exact) {
        CHECK(placed == ROMRT_E_ARGUMENT, "a capsule through the face should be refused (status %d)", (int)placed);
        CHECK(romrt_set_collider(F.m, 0, &cap, &rerr) == ROMRT_OK, "the slot should still be free: %s", rerr.message);
    } else if (placed == ROMRT_OK) {
        CHECK(romrt_remove_collider(F.m, 0, &rerr) == ROMRT_OK, "removing it: %s", rerr.message);
    }
    drive_result r[3];
    int rc[3];
    for (int i = 0; i < 3; i++) {
        rc[i] = drive(&F, *shapes[i], 0.03, &r[i], &err);
        printf("# %s (%s) driven 3 cm into a face of 10 cm cells: %d crossings, least distance to the surface %.3g m"
               " past its radius, the face down to y = %.4f (rest 0.2), %s\n",
               names[i], PRECISION, r[i].crossings, r[i].least, r[i].top, r[i].arrived ? "arrived" : "still behind");
    }
    rt_fixture_close(&F);
    int through_any = 0;
    for (int i = 0; i < 3; i++) {
        CHECK(rc[i] == 0, "%s: %s", names[i], err.msg);
        through_any += r[i].crossings > 0;
        if (!exact) continue;
        CHECK(r[i].arrived, "%s: never reached its pose (the face should give way)", names[i]);
        CHECK(r[i].crossings == 0, "%s: %d crossings of the surface", names[i], r[i].crossings);
        CHECK(r[i].least > 0, "%s: the surface came within its radius (%.3g)", names[i], r[i].least);
        CHECK(r[i].top < 0.19, "%s: the face should be pushed down ahead of it (lowest top vertex %.4f)", names[i], r[i].top);
    }
    if (!exact) CHECK(through_any > 0, "on the vertices alone no shape went through the face (the test shows nothing)");
}

TEST(thin_shapes_driven_into_a_coarse_face_do_not_pass_between_its_vertices)
{
    thin_shapes(BLOCK_SCENE(", \"self\": true", ""), "self-contact: the surface baked for it", 1);
    thin_shapes(BLOCK_SCENE("", ""), "nothing to touch, the default asset: the surface baked for the app's colliders", 1);
    thin_shapes(BLOCK_SCENE("", "\"colliders\": \"vertices\""), "\"colliders\": \"vertices\": the vertices alone", 0);
}

/* Two boxes dropped onto a sphere, a capsule and a ground box (`obstacles` the scene's), kappa
 * (0: the contact stage's own). Dyadic sizes: the baked corners and the app's R X + p agree
 * exactly. */
static const char *two_boxes(double kappa, const char *obstacles)
{
    static char json[4096];
    char k[64] = "";
    if (kappa > 0) snprintf(k, sizeof k, ", \"kappa\": %.17g", kappa);
    snprintf(json, sizeof json,
             "{\"objects\": ["
             "  {\"mesh\": {\"box\": {\"size\": [0.1, 0.04, 0.1], \"cells\": [2, 1, 2]}, \"translate\": [-0.05, 0.035, -0.05]},"
             "   \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000},"
             "   \"velocity\": [0.3, -1, 0]},"
             "  {\"mesh\": {\"box\": {\"size\": [0.06, 0.06, 0.06], \"cells\": [2, 2, 2]}, \"translate\": [-0.03, 0.1, -0.02]},"
             "   \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000},"
             "   \"velocity\": [0.2, -1.5, 0]}],"
             " \"gravity\": [0, -9.81, 0], \"obstacles\": [%s], \"contact\": {\"dhat\": 0.002, \"friction\": 0.3%s},"
             " \"time\": {\"step\": 0.01, \"duration\": 0.3}, \"newton\": {\"tolerance\": " NEWTON_TOL "},"
             " \"rom\": {\"basis\": \"modes\", \"size\": 16, \"asset\": {\"contact_pairs\": 30000}}}",
             obstacles, k);
    return json;
}

TEST(sphere_capsule_and_box_as_app_colliders_take_the_baked_obstacles_path)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture A, B;
    const char *baked = "{\"sphere\": {\"center\": [0.015625, 0.015625, 0.0078125], \"radius\": 0.0078125}},"
                        "{\"capsule\": {\"a\": [-0.046875, 0.015625, -0.03125], \"b\": [0.046875, 0.015625, -0.03125],"
                        " \"radius\": 0.0078125}},"
                        "{\"box\": {\"min\": [-0.25, -0.125, -0.25], \"max\": [0.25, 0, 0.25]}}";
    CHECK_OK(rt_fixture_open(&A, two_boxes(0, baked), ASSET_REAL, &err, &rerr));
    double kappa = A.R.model.contact.kappa;
    /* B holds its collision surface too (two objects), with no obstacle: the colliders stand for them */
    CHECK_OK(rt_fixture_open(&B, two_boxes(kappa, ""), ASSET_REAL, &err, &rerr));
    romrt_collider ball = {ROMRT_COLLIDER_SPHERE, {0.015625f, 0.015625f, 0.0078125f}, {1, 0, 0, 0, 1, 0, 0, 0, 1}, 0.0078125f, 0, {0, 0, 0}};
    romrt_collider cap = {ROMRT_COLLIDER_CAPSULE, {0, 0.015625f, -0.03125f}, {1, 0, 0, 0, 1, 0, 0, 0, 1}, 0.0078125f, 0.046875f, {0, 0, 0}};
    romrt_collider ground = {ROMRT_COLLIDER_BOX, {0, -0.0625f, 0}, {1, 0, 0, 0, 1, 0, 0, 0, 1}, 0, 0, {0.25f, 0.0625f, 0.25f}};
    CHECK(romrt_set_collider(B.m, 0, &ball, &rerr) == ROMRT_OK, "sphere: %s", rerr.message);
    CHECK(romrt_set_collider(B.m, 1, &cap, &rerr) == ROMRT_OK, "capsule: %s", rerr.message);
    CHECK(romrt_set_collider(B.m, 2, &ground, &rerr) == ROMRT_OK, "box: %s", rerr.message);
    rt_surface a, b;
    rt_surface_init(&a, A.m), rt_surface_init(&b, B.m);
    double *xa = calloc((size_t)3 * A.sim.mesh.nv, sizeof(double));
    double worst = 0, scale = 0, least = INFINITY, slid = 0;
    int cross = 0, steps = 30, rc = 0;
    for (int k = 0; k < steps && !rc; k++) {
        int c = 0;
        double d = INFINITY;
        if (romrt_step(A.m, &rerr) != ROMRT_OK || romrt_step(B.m, &rerr) != ROMRT_OK) {
            rc = rk_fail(&err, "step %d: %s", k, rerr.message);
            break;
        }
        rt_surface_read(&a, A.m), rt_surface_read(&b, B.m);
        for (int i = 0; i < 3 * a.n; i++) {
            worst = fmax(worst, fabs(a.x[i] - b.x[i]));
            scale = fmax(scale, fabs(a.x[i] - A.sim.mesh.X[3 * (int)A.vmap[i / 3] + i % 3]));
        }
        slid = a.x[0] - A.sim.mesh.X[3 * (int)A.vmap[0]];
        /* A's obstacles are B's colliders: the contact stage's exact measure on A */
        rt_fixture_positions(&A, xa);
        rc = rk_contact_measure(&A.R.model.contact, xa, &c, &d, &err);
        cross += c, least = fmin(least, d);
    }
    printf("# two boxes onto a sphere, a capsule and a box (%s): baked obstacles against app colliders %.3g of the"
           " largest displacement %.3g m (tol %g); %d crossings, least distance %.3g m; a vertex moved %.3g m along x\n",
           PRECISION, worst / scale, scale, PARITY_TOL, cross, least, slid);
    CHECK(rc == 0, "%s", err.msg);
    CHECK(cross == 0 && least > 0, "crossings %d, least distance %.3g", cross, least);
    CHECK(least < 0.002, "the objects should touch the obstacles (least distance %.3g)", least);
    CHECK(worst / scale <= PARITY_TOL, "baked and app colliders differ by %.3g of the displacement", worst / scale);
    rt_surface_free(&a), rt_surface_free(&b);
    free(xa);
    rt_fixture_close(&A), rt_fixture_close(&B);
}

/* A 10 x 5 x 10 cm block resting dhat / 2 over an app box's top face (y = 0, its diagonal away
 * from the block's path), gravity tilted by theta along x, 100 steps of 0.01 s: the mean of its
 * shown vertices along x, its drift and its acceleration fitted over the second half second. */
static int incline_on_a_box(double mu, double tan_theta, double eps_v, double *drift, double *accel, rk_error *err)
{
    char json[2048];
    double th = atan(tan_theta), x[101];
    snprintf(json, sizeof json,
             "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.1, 0.05, 0.1], \"cells\": [2, 1, 2]}, \"translate\": [0, 5e-4, 0]},"
             "  \"material\": {\"model\": \"neohookean\", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1000}}],"
             " \"gravity\": [%.17g, %.17g, 0],"
             " \"contact\": {\"dhat\": 1e-3, \"friction\": %.17g, \"eps_v\": %.17g, \"self\": true},"
             " \"time\": {\"step\": 0.01, \"duration\": 1.0}, \"rom\": {\"basis\": \"modes\", \"size\": 12}}",
             9.81 * sin(th), -9.81 * cos(th), mu, eps_v);
    rt_fixture f;
    romrt_error rerr;
    romrt_collider ground = {ROMRT_COLLIDER_BOX, {0.7f, -0.0625f, 0.4f}, {1, 0, 0, 0, 1, 0, 0, 0, 1}, 0, 0, {2, 0.0625f, 0.5f}};
    int rc = rt_fixture_open(&f, json, ASSET_REAL, err, &rerr);
    if (!rc && romrt_set_collider(f.m, 0, &ground, &rerr) != ROMRT_OK) rc = rk_fail(err, "ground: %s", rerr.message);
    int n = rc ? 0 : romrt_shown_count(f.m);
    romrt_real *xyz = calloc((size_t)3 * n + 3, sizeof(romrt_real));
    for (int k = 0; !rc && k <= 100; k++) {
        if (k > 0 && romrt_step(f.m, &rerr) != ROMRT_OK) {
            rc = rk_fail(err, "step %d: %s", k, rerr.message);
            break;
        }
        romrt_positions(f.m, xyz, 3 * (size_t)n, 3, NULL);
        x[k] = 0;
        for (int i = 0; i < n; i++) x[k] += (double)xyz[3 * i] / n;
    }
    if (!rc) *drift = x[100] - x[0], *accel = fit_acceleration(x, 50, 100, 0.01);
    free(xyz);
    rt_fixture_close(&f);
    return rc;
}

TEST(a_block_on_an_app_box_sticks_and_slides_by_the_incline_law)
{
    rk_error err = {{0}};
    double mu = 0.5, t_rest = 0.5 * mu, t_slide = 1.5 * mu + 0.05, drift, a_rest, d_slide, accel;
    CHECK_OK(incline_on_a_box(mu, t_rest, 1e-5, &drift, &a_rest, &err));
    CHECK_OK(incline_on_a_box(mu, t_slide, 1e-3, &d_slide, &accel, &err));
    double th = atan(t_slide), expect = 9.81 * (sin(th) - mu * cos(th));
    printf("# incline on an app box (%s), mu %.1f: at rest (tan %.3f) drift %.2e m over 1 s; sliding (tan %.3f)"
           " a %.5f vs %.5f m/s^2 (%+.4f%%), %.3f m\n",
           PRECISION, mu, t_rest, drift, t_slide, accel, expect, 100 * (accel / expect - 1), d_slide);
    CHECK(fabs(drift) < 1e-4, "the block drifted %g m", drift);
    CHECK(fabs(accel / expect - 1) < 0.01, "acceleration %.6g, expected %.6g (%+.3f%%)", accel, expect, 100 * (accel / expect - 1));
}

int main(void)
{
    RUN(thin_shapes_driven_into_a_coarse_face_do_not_pass_between_its_vertices);
    RUN(sphere_capsule_and_box_as_app_colliders_take_the_baked_obstacles_path);
    RUN(a_block_on_an_app_box_sticks_and_slides_by_the_incline_law);
    return test_finish();
}
