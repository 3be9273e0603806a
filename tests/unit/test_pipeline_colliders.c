/* An application's colliders in the reduced simulator (rom.h, rk_rom_set_collider): a sphere the
 * app moves into a hanging block pushes it aside, no collision vertex ever inside it; a block
 * resting on a box collider stays on it; bad colliders are refused and change nothing; on a model
 * with a collision surface (its own, or by default one for the app's shapes alone) a capsule
 * thinner than the edges, placed through the block between its vertices, is refused (the vertex
 * path, rom.asset.colliders "vertices", takes it), and the shapes come and go as obstacles of the
 * contact model. */
#include "scene_run.h"
#include "rom/rom.h"

/* A 0.2 x 0.6 x 0.2 m block hanging from its top face, and its reduced model (modes 12). */
#define HANGING                                                                                        \
    "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.2, 0.6, 0.2], \"cells\": [2, 6, 2]}},"           \
    "  \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000}," \
    "  \"fixed\": [{\"box\": [[-1, 0.599, -1], [1, 1, 1]]}]}],"                                         \
    " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": 0.01, \"duration\": 0.5},"                        \
    " \"rom\": {\"basis\": \"modes\", \"size\": 12}}"

typedef struct {
    scene_run run;
    rk_scene_rom R;
    rk_rom rom;
    double *x;
} reduced;

static int open_reduced(reduced *o, const char *json, rk_error *err)
{
    memset(o, 0, sizeof *o);
    if (scene_run_open(&o->run, json, err)) return -1;
    if (rk_scene_rom_build(&o->run.scene, &o->run.sim, &o->run.scene.entries[0], NULL, 0, &o->R, err) ||
        rk_rom_init(&o->rom, &o->R.model, NULL, NULL, err)) {
        scene_run_close(&o->run);
        return -1;
    }
    o->x = calloc(3 * (size_t)o->run.sim.mesh.nv, sizeof(double));
    return 0;
}

static void close_reduced(reduced *o)
{
    rk_rom_free(&o->rom);
    rk_scene_rom_free(&o->R);
    scene_run_close(&o->run);
    free(o->x);
}

/* The reduced positions; the least signed distance of the boundary vertices from collider c. */
static double least_distance(reduced *o, const rk_collider *c)
{
    rk_rom_positions(o->R.basis.U, 3 * o->run.sim.mesh.nv, o->R.basis.r, o->run.sim.mesh.X, o->rom.q, o->x);
    double least = INFINITY;
    for (int i = 0; i < o->R.model.ncv; i++)
        least = fmin(least, rk_collider_distance(c->kind, c->shape, &o->x[3 * o->R.model.cv[i]], NULL, NULL));
    return least;
}

static double mean_x(const reduced *o)
{
    double s = 0;
    for (int v = 0; v < o->run.sim.mesh.nv; v++) s += o->x[3 * v];
    return s / o->run.sim.mesh.nv;
}

static rk_collider sphere_at(double x, double y, double z, double radius)
{
    rk_collider c = {RK_COLLIDER_SPHERE, {x, y, z, 1, 0, 0, 0, 1, 0, 0, 0, 1, radius, 0, 0, 0, 0}};
    return c;
}

TEST(an_app_moved_sphere_pushes_a_hanging_block)
{
    rk_error err;
    reduced o;
    CHECK_OK(open_reduced(&o, HANGING, &err));
    /* beside the block's lower half, then 1 cm a step toward x = 0.1, well into where the block
     * hangs: it must swing away */
    rk_collider c = sphere_at(-0.15, 0.15, 0.1, 0.1);
    int rc = rk_rom_set_collider(&o.rom, 0, &c, &err);
    double x0 = 0, least = INFINITY, behind = 0;
    least_distance(&o, &c);
    x0 = mean_x(&o);
    for (int step = 0; step < 40 && !rc; step++) {
        c.shape[0] = fmin(-0.15 + 0.01 * (step + 1), 0.1);
        rc = rk_rom_set_collider(&o.rom, 0, &c, &err) || rk_rom_step(&o.rom, &err);
        const double *now = o.rom.colliders[0].now;
        rk_collider at = {RK_COLLIDER_SPHERE, {0}};
        memcpy(at.shape, now, sizeof at.shape);
        least = fmin(least, least_distance(&o, &at));
        behind = fmax(behind, fabs(o.rom.colliders[0].target[0] - now[0]));
    }
    double pushed = mean_x(&o) - x0, gap = o.rom.colliders[0].target[0] - o.rom.colliders[0].now[0];
    printf("# sphere pushed the hanging block %.3f m along x; closest vertex %.3g m from the sphere; the sphere at "
           "most %.3g m behind the app's pose after a step, %.3g m at the end; %ld Newton iterations\n",
           pushed, least, behind, gap, o.rom.stats.newton_iterations);
    close_reduced(&o);
    CHECK(rc == 0, "%s", err.msg);
    CHECK(least > 0, "a vertex reached the sphere (%g)", least);
    CHECK(pushed > 0.05, "the block moved only %g m", pushed);
    CHECK(fabs(gap) < 1e-12, "the sphere did not reach the app's pose (%g m short)", gap);
    CHECK(behind < 1e-5, "the sphere fell %g m behind the app's pose in a step", behind);
}

TEST(bad_colliders_are_refused_and_change_nothing)
{
    rk_error err;
    reduced o;
    CHECK_OK(open_reduced(&o, HANGING, &err));
    rk_collider c = sphere_at(0.0, 0.3, 0.1, 0.05); /* through the block's side */
    int overlap = rk_rom_set_collider(&o.rom, 0, &c, &err);
    printf("# inside the block: %s\n", err.msg);
    CHECK(overlap != 0 && strstr(err.msg, "overlap") && o.rom.ncolliders == 0, "a sphere inside the block was taken");
    c = sphere_at(0.5, 0.3, 0.1, -0.05);
    CHECK(rk_rom_set_collider(&o.rom, 1, &c, &err) != 0 && strstr(err.msg, "radius"), "a negative radius passed");
    c = sphere_at(0.5, NAN, 0.1, 0.05);
    CHECK(rk_rom_set_collider(&o.rom, 1, &c, &err) != 0 && strstr(err.msg, "finite"), "NaN passed");
    c = sphere_at(0.5, 0.3, 0.1, 0.05);
    CHECK(rk_rom_set_collider(&o.rom, RK_MAX_COLLIDERS, &c, &err) != 0, "a slot out of range was taken");
    CHECK(o.rom.ncolliders == 0, "%d colliders after refusals", o.rom.ncolliders);
    /* a good one, then a bad move of it: the good pose stays */
    CHECK_OK(rk_rom_set_collider(&o.rom, 1, &c, &err));
    rk_collider bad = c;
    bad.shape[3] = 3;
    CHECK(rk_rom_set_collider(&o.rom, 1, &bad, &err) != 0 && o.rom.colliders[1].target[3] == 1,
          "a non-rotation changed the collider");
    close_reduced(&o);
}

TEST(a_block_rests_on_a_turned_box_collider)
{
    rk_error err;
    reduced o;
    /* a free block 2 mm over a box collider whose top face is tilted 5 degrees: friction 0.5 holds it */
    CHECK_OK(open_reduced(&o,
        "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.2, 0.1, 0.2], \"cells\": [2, 1, 2]}},"
        "  \"material\": {\"model\": \"neohookean\", \"young\": 1e6, \"poisson\": 0.4, \"density\": 1000}}],"
        " \"gravity\": [0, -9.81, 0], \"contact\": {\"friction\": 0.5, \"eps_v\": 1e-5, \"dhat\": 1e-3},"
        " \"time\": {\"step\": 0.01, \"duration\": 1.0}, \"rom\": {\"basis\": \"modes\", \"size\": 12}}", &err));
    double th = 5 * 3.14159265358979 / 180, c5 = cos(th), s5 = sin(th);
    /* turned about z by -5 degrees (its local x runs down the slope); its top face, half a metre
     * above its centre, passes 2 mm under the block's lowest bottom corner (x = 0) */
    double top_center_x = 0.1 + 0.5 * s5;
    double yc = -0.002 - 0.5 * c5 - top_center_x * tan(th);
    rk_collider box = {RK_COLLIDER_BOX, {0.1, yc, 0.1, c5, s5, 0, -s5, c5, 0, 0, 0, 1, 0, 0, 1, 0.5, 1}};
    int rc = rk_rom_set_collider(&o.rom, 2, &box, &err);
    least_distance(&o, &box);
    double x0 = mean_x(&o), x_half = 0, least = INFINITY;
    for (int step = 0; step < 100 && !rc; step++) {
        rc = rk_rom_step(&o.rom, &err);
        least = fmin(least, least_distance(&o, &box));
        if (step == 49) x_half = mean_x(&o);
    }
    /* landing on the slope moves it along the normal; then it must hold */
    double landing = x_half - x0, drift = mean_x(&o) - x_half;
    printf("# block on a box tilted 5 degrees, mu 0.5: %.2e m along x while landing, then %.2e m in 0.5 s; "
           "closest %.3g m\n", landing, drift, least);
    close_reduced(&o);
    CHECK(rc == 0, "%s", err.msg);
    CHECK(least > 0 && least < 1e-3, "closest %g (it should rest within dhat)", least);
    CHECK(fabs(drift) < 1e-5, "the block slid %g m after landing", drift);
}

/* The hanging block baked with its collision vertices alone for the app's shapes. */
#define VERTEX_HANGING                                                                                 \
    "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.2, 0.6, 0.2], \"cells\": [2, 6, 2]}},"           \
    "  \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000}," \
    "  \"fixed\": [{\"box\": [[-1, 0.599, -1], [1, 1, 1]]}]}],"                                         \
    " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": 0.01, \"duration\": 0.5},"                        \
    " \"rom\": {\"basis\": \"modes\", \"size\": 12, \"asset\": {\"colliders\": \"vertices\"}}}"

/* The hanging block with a collision surface (a far sphere obstacle). */
#define SURFACE_HANGING                                                                                \
    "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.2, 0.6, 0.2], \"cells\": [2, 6, 2]}},"           \
    "  \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000}," \
    "  \"fixed\": [{\"box\": [[-1, 0.599, -1], [1, 1, 1]]}]}],"                                         \
    " \"gravity\": [0, -9.81, 0], \"obstacles\": [{\"sphere\": {\"center\": [3, 3, 3], \"radius\": 0.05}}],"  \
    " \"time\": {\"step\": 0.01, \"duration\": 0.5}, \"rom\": {\"basis\": \"modes\", \"size\": 12}}"

TEST(on_a_collision_surface_shapes_are_obstacles_and_a_thin_one_cannot_slip_between_vertices)
{
    rk_error err;
    reduced o;
    /* a 3 mm capsule along z through the block 1 cm inside its x = 0 side, at y = 0.25 (between
     * the vertices 10 cm apart: the nearest is 5.1 cm from its segment) */
    rk_collider thin = {RK_COLLIDER_CAPSULE, {0.01, 0.25, 0.1, 0, 0, -1, 0, 1, 0, 1, 0, 0, 0.003, 0.3, 0, 0, 0}};
    CHECK_OK(open_reduced(&o, VERTEX_HANGING, &err));
    CHECK(!o.R.model.surface, "the block baked for its vertices alone has a collision surface");
    CHECK_OK(rk_rom_set_collider(&o.rom, 0, &thin, &err)); /* the vertex path sees no vertex inside it */
    close_reduced(&o);
    /* by default (rom.asset.colliders true) a model with no contact of its own has the surface for
     * the app's shapes, out of the step until one is placed: the capsule through it is refused */
    CHECK_OK(open_reduced(&o, HANGING, &err));
    CHECK(o.R.model.surface && o.R.model.colliders_contact && o.R.model.contact.nobstacles == 0,
          "the default block has no surface for its colliders");
    int through = rk_rom_set_collider(&o.rom, 0, &thin, &err);
    CHECK(through != 0 && strstr(err.msg, "cross") && o.rom.ncolliders == 0 && o.R.model.contact.nobstacles == 0,
          "the thin capsule through the default block was taken");
    close_reduced(&o);
    CHECK_OK(open_reduced(&o, SURFACE_HANGING, &err));
    rk_contact *c = &o.R.model.contact;
    int scene = c->nobstacles, onv = c->onv;
    CHECK(o.R.model.surface && scene == 1, "the model has no collision surface (%d obstacles)", scene);
    int rc = rk_rom_set_collider(&o.rom, 0, &thin, &err);
    printf("# through the block between its vertices: %s\n", err.msg);
    CHECK(rc != 0 && strstr(err.msg, "cross") && o.rom.ncolliders == 0 && c->nobstacles == scene && c->onv == onv,
          "the thin capsule through the block was taken (%d obstacles)", c->nobstacles);
    /* clear of it: an obstacle with its two points, then a box in slot 1: 8 more */
    thin.shape[0] = -0.05;
    CHECK_OK(rk_rom_set_collider(&o.rom, 0, &thin, &err));
    rk_collider box = {RK_COLLIDER_BOX, {0.5, 0.3, 0.1, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0.1, 0.1, 0.1}};
    CHECK_OK(rk_rom_set_collider(&o.rom, 1, &box, &err));
    CHECK(o.rom.colliders[0].exact && o.rom.colliders[1].exact && c->nobstacles == scene + 2 && c->onv == onv + 10,
          "%d obstacles, %d obstacle vertices after a capsule and a box", c->nobstacles, c->onv);
    /* moved, the box is due at its new pose and gets there in the step */
    box.shape[0] = 0.45;
    CHECK_OK(rk_rom_set_collider(&o.rom, 1, &box, &err));
    CHECK_OK(rk_rom_step(&o.rom, &err));
    CHECK(o.rom.colliders[1].now[0] == 0.45 && c->ox[3 * (onv + 2)] == 0.35, "the box is not where it was moved (%g)",
          c->ox[3 * (onv + 2)]);
    /* a capsule of another size through the block between its vertices, in slot 0, is refused by
     * the exact test: the one there stays where it is */
    rk_collider thick = thin;
    thick.shape[0] = 0.01, thick.shape[12] = 0.004;
    double was[6];
    memcpy(was, &c->ox[3 * onv], sizeof was);
    CHECK(rk_rom_set_collider(&o.rom, 0, &thick, &err) != 0 && strstr(err.msg, "cross") && c->nobstacles == scene + 2 &&
              c->onv == onv + 10 && !memcmp(was, &c->ox[3 * onv], sizeof was) && o.rom.colliders[0].target[12] == 0.003,
          "a capsule through the block replaced the one there");
    /* slot 0 becomes a plane (the vertex path), then the box goes: the scene's obstacles alone */
    rk_collider floor = {RK_COLLIDER_PLANE, {0, -0.5, 0, 1, 0, 0, 0, 0, 1, 0, -1, 0, 0, 0, 0, 0, 0}}; /* normal +y */
    CHECK_OK(rk_rom_set_collider(&o.rom, 0, &floor, &err));
    CHECK_OK(rk_rom_remove_collider(&o.rom, 1, &err));
    CHECK(!o.rom.colliders[0].exact && o.rom.ncolliders == 1 && c->nobstacles == scene && c->onv == onv,
          "%d colliders, %d obstacles left", o.rom.ncolliders, c->nobstacles);
    CHECK_OK(rk_rom_step(&o.rom, &err));
    close_reduced(&o);
}

int main(void)
{
    RUN(an_app_moved_sphere_pushes_a_hanging_block);
    RUN(on_a_collision_surface_shapes_are_obstacles_and_a_thin_one_cannot_slip_between_vertices);
    RUN(bad_colliders_are_refused_and_change_nothing);
    RUN(a_block_rests_on_a_turned_box_collider);
    return test_finish();
}
