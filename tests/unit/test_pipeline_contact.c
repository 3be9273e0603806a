/* IPC contact on the three scenes, through the scene pipeline: two soft boxes dropped
 * onto each other onto a mesh obstacle, a rod twisted until it coils on itself, a ball pressed
 * onto a bed of spikes by a moving box. Every frame is checked by the exact test (segment-triangle
 * crossings between every pair of surfaces, self and obstacles included), for a positive distance
 * and for inverted elements; then what the scene must have done (resting, coiled, pressed). */
#include "scene_run.h"

#define NEO "\"model\": \"neohookean\", \"young\": 1e5, \"density\": 1000"

typedef struct {
    int frames, worst_intersections, worst_inverted;
    double min_distance;
} frame_checks;

/* Steps the scene to its end, checking every frame (the start included). */
static int run_checked(scene_run *r, frame_checks *c, rk_error *err)
{
    *c = (frame_checks){.min_distance = INFINITY};
    for (int step = 0; step <= r->sim.steps; step++) {
        if (step > 0 && rk_fom_step(&r->fom, err)) return -1;
        if (!scene_run_finite(r)) return rk_fail(err, "non-finite state at step %d", step);
        int crossings;
        double d;
        if (rk_fom_contact_measure(&r->fom, &crossings, &d, err)) return -1;
        int inverted = rk_fem_inverted(&r->sim.fem, r->fom.x, NULL);
        c->worst_intersections = crossings > c->worst_intersections ? crossings : c->worst_intersections;
        c->worst_inverted = inverted > c->worst_inverted ? inverted : c->worst_inverted;
        c->min_distance = fmin(c->min_distance, d);
        c->frames++;
    }
    return 0;
}

/* Lowest and highest y of the vertices [first, last). */
static void y_range(const scene_run *r, int first, int last, double *lo, double *hi)
{
    *lo = INFINITY, *hi = -INFINITY;
    for (int v = first; v < last; v++) {
        *lo = fmin(*lo, r->fom.x[3 * v + 1]);
        *hi = fmax(*hi, r->fom.x[3 * v + 1]);
    }
}

static void report(const char *name, const scene_run *r, const frame_checks *c)
{
    const rk_contact_stats *st = rk_fom_contact_stats(&r->fom);
    printf("# %s: %d frames, %d tets, %ld Newton iterations (%ld steps unconverged), pairs mean %.0f max %ld, "
           "closest %.3g m, crossings %d, inverted %d\n",
           name, c->frames - 1, r->sim.mesh.nt, r->fom.stats.newton_iterations, r->fom.stats.unconverged_steps,
           st->gathers ? (double)st->pairs / (double)st->gathers : 0.0, st->max_pairs, c->min_distance,
           c->worst_intersections, c->worst_inverted);
}

#define CHECK_FRAMES(c)                                                                                    \
    do {                                                                                                  \
        CHECK((c).worst_intersections == 0, "%d surface crossings in some frame", (c).worst_intersections); \
        CHECK((c).min_distance > 0, "surfaces touched (distance %g)", (c).min_distance);                   \
        CHECK((c).worst_inverted == 0, "%d inverted elements in some frame", (c).worst_inverted);          \
    } while (0)

TEST(two_soft_boxes_dropped_onto_each_other_onto_a_mesh_obstacle)
{
    rk_error err;
    scene_run r;
    CHECK_OK(scene_run_open(&r,
        "{\"objects\": ["
        "  {\"mesh\": {\"box\": {\"size\": [0.4, 0.2, 0.4], \"cells\": [4, 2, 4]}, \"translate\": [0, 0.35, 0]},"
        "   \"material\": {" NEO ", \"poisson\": 0.4}},"
        "  {\"mesh\": {\"box\": {\"size\": [0.3, 0.2, 0.3], \"cells\": [3, 2, 3]}, \"translate\": [0.1, 0.65, 0.05]},"
        "   \"material\": {" NEO ", \"poisson\": 0.4}}],"
        " \"gravity\": [0, -9.81, 0],"
        " \"obstacles\": [{\"mesh\": {\"file\": \"tests/data/contact/ridge.obj\"}}],"
        " \"contact\": {\"dhat\": 2e-3},"
        " \"time\": {\"step\": 0.01, \"duration\": 0.6}}", &err));
    frame_checks c;
    int rc = run_checked(&r, &c, &err);
    report("stack on a ridge", &r, &c);
    double lo0, hi0, lo1, hi1;
    y_range(&r, r.sim.object_first_vertex[0], r.sim.object_first_vertex[1], &lo0, &hi0);
    y_range(&r, r.sim.object_first_vertex[1], r.sim.object_first_vertex[2], &lo1, &hi1);
    printf("# lower box y in [%.4f, %.4f], upper box y in [%.4f, %.4f]\n", lo0, hi0, lo1, hi1);
    scene_run_close(&r);
    CHECK(rc == 0, "%s", err.msg);
    CHECK_FRAMES(c);
    /* both fell (0.3 m and 0.4 m of free fall take 0.25 and 0.29 s) and landed: the lower box on
     * the plate and the 5 cm ridge, the upper one on top of the lower (it lies wholly above it) */
    CHECK(lo0 > 0 && lo0 < 0.01, "the lower box should rest on the plate (lowest y %.4f)", lo0);
    CHECK(hi0 > 0.2 && hi0 < 0.3, "the lower box should lie on the plate and ridge (highest y %.4f)", hi0);
    CHECK(lo1 > 0.15 && lo1 < hi0, "the upper box should rest on the lower one (lowest y %.4f, lower box top %.4f)",
          lo1, hi0);
}

TEST(rod_twisted_three_turns_coils_on_itself)
{
    rk_error err;
    scene_run r;
    /* a 1 m rod of 4 cm square section, one end clamped, the other screwed 3 turns while pushed
     * 0.6 m toward the clamp: it buckles into a coil whose turns press on each other */
    CHECK_OK(scene_run_open(&r,
        "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1.0, 0.04, 0.04], \"cells\": [25, 1, 1]}},"
        "  \"material\": {" NEO ", \"poisson\": 0.3},"
        "  \"fixed\": [{\"box\": [[-1, -1, -1], [0.001, 1, 1]]}],"
        "  \"moving\": [{\"box\": [[0.999, -1, -1], [2, 1, 1]],"
        "    \"twist\": {\"axis\": [1, 0, 0], \"degrees_per_second\": 720, \"center\": [1, 0.02, 0.02]},"
        "    \"translate\": {\"velocity\": [-0.4, 0, 0]}}]}],"
        " \"contact\": {\"self\": true, \"dhat\": 1e-3},"
        " \"time\": {\"step\": 0.01, \"duration\": 1.5}}", &err));
    frame_checks c;
    int rc = run_checked(&r, &c, &err);
    report("coiled rod", &r, &c);
    const rk_contact_stats *st = rk_fom_contact_stats(&r.fom);
    long max_pairs = st ? st->max_pairs : 0;
    double closest = c.min_distance;
    /* how far the rod left its axis: a coil, not a straight twisted bar */
    double off_axis = 0;
    for (int v = 0; v < r.sim.mesh.nv; v++)
        off_axis = fmax(off_axis, hypot(r.fom.x[3 * v + 1] - 0.02, r.fom.x[3 * v + 2] - 0.02));
    printf("# coil: farthest from the axis %.3f m, closest approach of the surfaces %.3g m (dhat 1e-3)\n", off_axis,
           closest);
    scene_run_close(&r);
    CHECK(rc == 0, "%s", err.msg);
    CHECK_FRAMES(c);
    CHECK(off_axis > 0.1, "the rod should buckle out of its axis (farthest %.3f m)", off_axis);
    CHECK(max_pairs > 0 && closest < 1e-3, "the coil's turns should press on each other (pairs %ld, closest %g)",
          max_pairs, closest);
}

TEST(soft_ball_pressed_onto_spikes_by_a_moving_box)
{
    rk_error err;
    scene_run r;
    /* ball radius 0.1 m resting 1 cm above 6 cm spikes; a box whose bottom starts 1 cm above the
     * ball comes down at 0.3 m/s for 0.3 s: its bottom ends at y = 0.19, squeezing the ball from
     * 0.2 m to under 0.13 m between the box and the spikes */
    CHECK_OK(scene_run_open(&r,
        "{\"objects\": [{\"mesh\": {\"file\": \"tests/data/contact/ball.obj\", \"translate\": [0, 0.17, 0],"
        "   \"quality\": 2.0}, \"material\": {" NEO ", \"poisson\": 0.4}}],"
        " \"gravity\": [0, -9.81, 0],"
        " \"obstacles\": [{\"mesh\": {\"file\": \"tests/data/contact/spikes.obj\"}},"
        "   {\"box\": {\"min\": [-0.2, 0.28, -0.2], \"max\": [0.2, 0.35, 0.2]},"
        "    \"translate\": {\"velocity\": [0, -0.3, 0]}}],"
        " \"contact\": {\"dhat\": 1e-3},"
        " \"time\": {\"step\": 0.01, \"duration\": 0.3}}", &err));
    frame_checks c;
    int rc = run_checked(&r, &c, &err);
    report("ball on spikes", &r, &c);
    double lo, hi;
    y_range(&r, 0, r.sim.mesh.nv, &lo, &hi);
    printf("# ball y in [%.4f, %.4f]: squeezed to %.3f m between the spikes' tips (0.06) and the box (0.19)\n", lo,
           hi, hi - lo);
    scene_run_close(&r);
    CHECK(rc == 0, "%s", err.msg);
    CHECK_FRAMES(c);
    /* the box reached its path's end (the augmented Lagrangian held it there, to 1e-2 dhat): the
     * ball is under it and touches it */
    CHECK(hi < 0.19 + 1e-5 && hi > 0.185, "the box should have pressed the ball to y = 0.19 (top at %.6f)", hi);
    CHECK(lo > 0 && lo < 0.06, "the spikes should dent the ball's underside (lowest point %.4f)", lo);
}

int main(void)
{
    RUN(two_soft_boxes_dropped_onto_each_other_onto_a_mesh_obstacle);
    RUN(rod_twisted_three_turns_coils_on_itself);
    RUN(soft_ball_pressed_onto_spikes_by_a_moving_box);
    return test_finish();
}
