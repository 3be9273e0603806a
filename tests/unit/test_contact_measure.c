/* A run's contact measures (precompute/contact/measure.c), what romkit fom and romkit run report as
 * contact.*: known distances to a plane, a sphere, a box and a second object measured to 1e-12;
 * constructed intersections (interpenetrating objects, a corner behind a plane) counted by the
 * exact test; and the tally over frames (sums, frames with a crossing, the smallest distance). */
#include "contact/contact.h"
#include "testlib.h"
#include "two_boxes.h"
#include "util/util.h"

/* One or two 1 m cubes (one cell each): B sits `gap` above A's top face, shifted (0.2, 0.3). */
typedef struct {
    rk_mesh mesh;
    int first[3];
    rk_contact c;
} cubes;

static int make_cubes(cubes *s, int two, double gap, const rk_obstacle *obs, int nobs, rk_error *err)
{
    memset(s, 0, sizeof *s);
    double size[3] = {1, 1, 1}, shift[3] = {0.2, 0.3, 1 + gap};
    int cells[3] = {1, 1, 1};
    if (two_boxes(size, cells, shift, two, &s->mesh, s->first, err)) return -1;
    rk_contact_options o;
    rk_contact_default_options(&o);
    o.dhat = 0.5; /* wide: min_distance looks this far for pairs */
    o.kappa = 1;
    return rk_contact_init(&s->c, &s->mesh, two ? s->first : NULL, two ? 2 : 1, obs, nobs, &o, 1.0, err);
}

static void free_cubes(cubes *s)
{
    rk_contact_free(&s->c);
    rk_mesh_free(&s->mesh);
}

/* The measures of the cubes at rest: crossings and the smallest distance. */
static int measure_rest(cubes *s, int *crossings, double *d, rk_error *err)
{
    return rk_contact_measure(&s->c, s->mesh.X, crossings, d, err);
}

TEST(known_distances_are_measured_to_1e_12)
{
    rk_error err;
    cubes s;
    int crossings;
    double d;
    rk_obstacle plane = {.kind = RK_OBSTACLE_PLANE, .point = {0, 0, -0.0123}, .normal = {0, 0, 2}};
    CHECK_OK(make_cubes(&s, 0, 0, &plane, 1, &err));
    CHECK_OK(measure_rest(&s, &crossings, &d, &err));
    CHECK(crossings == 0, "%d crossings above a plane", crossings);
    CHECK(fabs(d - 0.0123) <= 1e-12, "plane: %.17g, expected 0.0123", d);
    free_cubes(&s);

    /* a sphere's distance is its center's less its radius (its thickness xi) */
    rk_obstacle sphere = {.kind = RK_OBSTACLE_SPHERE, .center = {0.5, 0.4, -0.3}, .radius = 0.1};
    CHECK_OK(make_cubes(&s, 0, 0, &sphere, 1, &err));
    CHECK_OK(measure_rest(&s, &crossings, &d, &err));
    CHECK(crossings == 0 && fabs(d - 0.2) <= 1e-12, "sphere: %d crossings, %.17g, expected 0.2", crossings, d);
    free_cubes(&s);

    rk_obstacle box = {.kind = RK_OBSTACLE_BOX, .min = {1.04, 0.2, 0.2}, .max = {1.5, 0.8, 0.8}};
    CHECK_OK(make_cubes(&s, 0, 0, &box, 1, &err));
    CHECK_OK(measure_rest(&s, &crossings, &d, &err));
    CHECK(crossings == 0 && fabs(d - 0.04) <= 1e-12, "box: %d crossings, %.17g, expected 0.04", crossings, d);
    free_cubes(&s);

    CHECK_OK(make_cubes(&s, 1, 0.0371, NULL, 0, &err));
    CHECK_OK(measure_rest(&s, &crossings, &d, &err));
    CHECK(crossings == 0 && fabs(d - 0.0371) <= 1e-12, "two cubes: %d crossings, %.17g, expected 0.0371", crossings, d);
    free_cubes(&s);
}

TEST(intersections_are_found_exactly)
{
    rk_error err;
    cubes s;
    int crossings;
    double d;
    /* B sunk 0.1 into A: its side edges pass through A's top face */
    CHECK_OK(make_cubes(&s, 1, -0.1, NULL, 0, &err));
    CHECK_OK(measure_rest(&s, &crossings, &d, &err));
    CHECK(crossings > 0, "two interpenetrating cubes: no crossing found");
    /* touching counts: B exactly on A's top face */
    free_cubes(&s);
    CHECK_OK(make_cubes(&s, 1, 0, NULL, 0, &err));
    CHECK_OK(measure_rest(&s, &crossings, &d, &err));
    CHECK(crossings > 0 && d == 0, "two touching cubes: %d crossings at distance %g", crossings, d);
    free_cubes(&s);
    /* a tilted plane (normal (1, 1, 1)) 1e-9 beyond the corner (0, 0, 0): that corner alone is behind it */
    double p = 1e-9 / sqrt(3.0);
    rk_obstacle plane = {.kind = RK_OBSTACLE_PLANE, .point = {p, p, p}, .normal = {1, 1, 1}};
    CHECK_OK(make_cubes(&s, 0, 0, &plane, 1, &err));
    CHECK_OK(measure_rest(&s, &crossings, &d, &err));
    CHECK(crossings == 1 && d < 0 && fabs(d + 1e-9) <= 1e-12, "a corner behind a plane: %d crossings at %g", crossings, d);
    free_cubes(&s);
}

TEST(the_tally_sums_crossings_and_keeps_the_closest_frame)
{
    rk_error err;
    cubes s;
    CHECK_OK(make_cubes(&s, 1, 0.0371, NULL, 0, &err));
    rk_contact_tally t;
    rk_contact_tally_init(&t);
    CHECK(t.frames == 0 && isinf(t.min_distance), "a fresh tally");
    int crossings;
    double d;
    double *x = calloc(3 * (size_t)s.mesh.nv, sizeof(double));
    memcpy(x, s.mesh.X, sizeof(double) * 3 * s.mesh.nv);
    CHECK_OK(rk_contact_measure(&s.c, x, &crossings, &d, &err));
    rk_contact_tally_add(&t, crossings, d);
    for (int v = s.first[1]; v < s.first[2]; v++) x[3 * v + 2] -= 0.0371 + 0.05; /* B sinks 5 cm into A */
    CHECK_OK(rk_contact_measure(&s.c, x, &crossings, &d, &err));
    int sunk = crossings;
    rk_contact_tally_add(&t, crossings, d);
    for (int v = s.first[1]; v < s.first[2]; v++) x[3 * v + 2] += 0.0371 + 0.05 - 0.02; /* back out, 2 cm above */
    CHECK_OK(rk_contact_measure(&s.c, x, &crossings, &d, &err));
    rk_contact_tally_add(&t, crossings, d);
    CHECK(sunk > 0 && t.frames == 3 && t.intersecting_frames == 1 && t.intersections == sunk,
          "frames %ld, intersecting %ld, crossings %ld (the sunk frame: %d)", t.frames, t.intersecting_frames,
          t.intersections, sunk);
    CHECK(t.min_distance <= 0.0171 + 1e-12 && t.min_distance >= 0, "min_distance %.17g", t.min_distance);
    rk_contact_tally_add(&t, 0, NAN);
    CHECK(isnan(t.min_distance), "a frame that could not be measured is hidden by the others");
    free(x);
    free_cubes(&s);
}

int main(void)
{
    RUN(known_distances_are_measured_to_1e_12);
    RUN(intersections_are_found_exactly);
    RUN(the_tally_sums_crossings_and_keeps_the_closest_frame);
    return test_finish();
}
