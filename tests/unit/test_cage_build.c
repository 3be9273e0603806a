/* precompute/cage: the exact point-in-tet test, the embedding (containing tet, barycentrics, points
 * outside reported), and cages around closed surfaces that hold every original vertex. */
#include "cage/cage.h"
#include "icosphere.h"
#include "testlib.h"

static const double A[3] = {0, 0, 0}, B[3] = {1, 0, 0}, C[3] = {0, 1, 0}, D[3] = {0, 0, 1};

TEST(point_in_tet_is_exact_on_faces)
{
    double inside[3] = {0.1, 0.2, 0.3}, on_face[3] = {1.0 / 3, 1.0 / 3, 0}, on_slanted[3] = {0.5, 0.25, 0.25};
    double beyond[3] = {0.5, 0.25, nextafter(0.25, 1)}, below[3] = {0.2, 0.2, -1e-300};
    CHECK(rk_point_in_tet(inside, A, B, C, D), "interior point not inside");
    CHECK(rk_point_in_tet(inside, A, C, B, D), "interior point not inside the inverted tet");
    CHECK(rk_point_in_tet(on_face, A, B, C, D), "a point on the face z = 0 counts as inside");
    CHECK(rk_point_in_tet(on_slanted, A, B, C, D), "a point exactly on x + y + z = 1 counts as inside");
    CHECK(!rk_point_in_tet(beyond, A, B, C, D), "one rounding unit beyond x + y + z = 1 is outside");
    CHECK(!rk_point_in_tet(below, A, B, C, D), "1e-300 below z = 0 is outside");
}

TEST(embeds_points_and_reports_the_outside_ones)
{
    rk_error err;
    double X[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    int tets[4] = {0, 1, 2, 3};
    rk_mesh m = {.nv = 4, .nt = 1, .X = X, .tets = tets};
    double P[9] = {0.1, 0.2, 0.3, 2, 0, 0, 0.25, 0.25, -0.5};
    rk_embedding e;
    CHECK_OK(rk_cage_embed(&m, P, 3, &e, &err));
    CHECK(e.outside == 2, "2 points are outside, %d reported", e.outside);
    CHECK(e.tet[0] == 0 && e.distance[0] == 0, "the first point is inside");
    double sum = 0, x[3] = {0, 0, 0};
    for (int k = 0; k < 4; k++) {
        sum += e.bary[k];
        for (int i = 0; i < 3; i++) x[i] += e.bary[k] * X[3 * k + i];
    }
    CHECK_CLOSE(sum, 1, 1e-15);
    for (int i = 0; i < 3; i++) CHECK_CLOSE(x[i], P[i], 1e-15);
    /* (2, 0, 0) is 1 from vertex B; (0.25, 0.25, -0.5) is 0.5 below the face z = 0 */
    CHECK_CLOSE(e.distance[1], 1, 1e-15);
    CHECK_CLOSE(e.distance[2], 0.5, 1e-15);
    CHECK_CLOSE(e.worst_distance, 1, 1e-15);
    CHECK(e.worst_point == 1, "worst point %d", e.worst_point);
    for (int p = 1; p < 3; p++) {
        double s = 0;
        for (int k = 0; k < 4; k++) {
            CHECK(e.bary[4 * p + k] >= 0 && e.bary[4 * p + k] <= 1, "clamped barycentric %g", e.bary[4 * p + k]);
            s += e.bary[4 * p + k];
        }
        CHECK_CLOSE(s, 1, 1e-15);
    }
    CHECK_CLOSE(e.bary[4 * 1 + 1], 1, 1e-15); /* (2, 0, 0) clamps onto B */
    rk_embedding_free(&e);
}

/* Every vertex of a closed surface of a few thousand vertices is inside its cage, by the exact
 * test, and the cage keeps to its tet budget. */
TEST(cage_holds_every_vertex_of_a_sphere)
{
    rk_error err;
    rk_surface s = {0};
    CHECK_OK(icosphere(4, 0.5, &s, &err)); /* 2562 vertices, 5120 triangles */
    CHECK(s.nv == 2562, "icosphere has %d vertices", s.nv);
    rk_cage_options o = {.max_tets = 3000};
    rk_cage_report rep;
    rk_mesh cage;
    CHECK_OK(rk_cage_build(&s, &o, &cage, &rep, &err));
    CHECK(cage.nt <= 3000 && cage.nt == rep.tets, "cage has %d tets (report %d), at most 3000", cage.nt, rep.tets);
    CHECK(rep.triangles < s.nf, "the cage's surface (%d triangles) is simpler than the sphere's", rep.triangles);
    CHECK(rep.outside == 0, "%d vertices outside (worst %g)", rep.outside, rep.worst_distance);
    rk_embedding e;
    CHECK_OK(rk_cage_embed(&cage, s.X, s.nv, &e, &err));
    int inside = 0;
    for (int i = 0; i < s.nv; i++) {
        const int *v = cage.tets + 4 * e.tet[i];
        inside += rk_point_in_tet(s.X + 3 * i, cage.X + 3 * v[0], cage.X + 3 * v[1], cage.X + 3 * v[2], cage.X + 3 * v[3]);
    }
    CHECK(inside == s.nv && e.outside == 0, "%d of %d vertices inside (%d reported outside)", inside, s.nv, e.outside);
    /* the cage stays close: its volume a little above the sphere's */
    double vol = 0, sphere = rk_surface_volume(&s);
    for (int t = 0; t < cage.nt; t++) {
        const int *v = cage.tets + 4 * t;
        vol += rk_tet_signed_volume(cage.X + 3 * v[0], cage.X + 3 * v[1], cage.X + 3 * v[2], cage.X + 3 * v[3]);
    }
    CHECK(vol > sphere && vol < 1.15 * sphere, "cage volume %g against the sphere's %g", vol, sphere);
    rk_embedding_free(&e);
    rk_mesh_free(&cage);
    rk_surface_free(&s);
}

TEST(refuses_a_tiny_budget)
{
    rk_error err;
    rk_surface s = {0};
    CHECK_OK(icosphere(1, 1, &s, &err));
    rk_cage_options o = {.max_tets = 10};
    rk_mesh cage;
    CHECK(rk_cage_build(&s, &o, &cage, NULL, &err) != 0, "a 10-tet budget was accepted");
    CHECK(strstr(err.msg, "max_tets") && strstr(err.msg, "100"), "message: %s", err.msg);
    CHECK(cage.nt == 0 && cage.X == NULL, "nothing is left on failure");
    rk_surface_free(&s);
}

int main(void)
{
    RUN(point_in_tet_is_exact_on_faces);
    RUN(embeds_points_and_reports_the_outside_ones);
    RUN(cage_holds_every_vertex_of_a_sphere);
    RUN(refuses_a_tiny_budget);
    return test_finish();
}
