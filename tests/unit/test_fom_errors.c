/* precompute/fom: failures say what and where (step number, vertex, group); unconverged steps
 * are counted, not fatal; options are checked at init. */
#include "fom/fom.h"
#include "testlib.h"
#include "fem_body.h"

typedef fem_body body;

static int make_body(body *b, rk_error *err)
{
    return fem_body_box(b, 1.0, 0.3, 0.3, 4, 1, 1, (rk_material){RK_MAT_NEOHOOKEAN, 1e5, 0.3, 1000.0}, err);
}

static void free_body(body *b) { fem_body_free(b); }

TEST(nan_state_fails_with_the_step_number)
{
    rk_error err;
    body b;
    CHECK_OK(make_body(&b, &err));
    rk_fom_options opt;
    rk_fom_default_options(&opt);
    opt.gravity[1] = -9.81;
    rk_fom s;
    CHECK_OK(rk_fom_init(&s, &b.f, &opt, &err));
    for (int k = 0; k < 3; k++) CHECK_OK(rk_fom_step(&s, &err));
    s.v[7] = NAN; /* what a blow-up leaves behind */
    CHECK(rk_fom_step(&s, &err) != 0, "a NaN velocity went unnoticed");
    CHECK(strstr(err.msg, "step 4") && strstr(err.msg, "vertex 2") && strstr(err.msg, "not finite"), "message: %s",
          err.msg);
    CHECK(s.stats.steps == 3, "failed step counted: %ld", s.stats.steps);
    rk_fom_free(&s);
    free_body(&b);
}

TEST(unconverged_steps_are_counted)
{
    rk_error err;
    body b;
    CHECK_OK(make_body(&b, &err));
    rk_fom_options opt;
    rk_fom_default_options(&opt);
    opt.newton_max_iter = 1;
    rk_fom s;
    CHECK_OK(rk_fom_init(&s, &b.f, &opt, &err));
    for (int v = 0; v < b.f.nv; v++) s.x[3 * v] *= 1.5; /* far from equilibrium: one iteration is not enough */
    for (int k = 0; k < 5; k++) CHECK_OK(rk_fom_step(&s, &err));
    CHECK(s.stats.unconverged_steps >= 1 && s.stats.newton_iterations == 5, "%ld unconverged, %ld iterations",
          s.stats.unconverged_steps, s.stats.newton_iterations);
    rk_fom_free(&s);
    opt.newton_max_iter = 50;
    CHECK_OK(rk_fom_init(&s, &b.f, &opt, &err));
    for (int v = 0; v < b.f.nv; v++) s.x[3 * v] *= 1.5;
    for (int k = 0; k < 5; k++) CHECK_OK(rk_fom_step(&s, &err));
    CHECK(s.stats.unconverged_steps == 0, "%ld unconverged with 50 iterations", s.stats.unconverged_steps);
    CHECK(s.stats.seconds_factor > 0 && s.stats.seconds_assemble > 0 && s.stats.seconds_total >= s.stats.seconds_factor,
          "timers not kept");
    rk_fom_free(&s);
    free_body(&b);
}

/* rk_fom_init with `opt` must fail and say `want`. */
static int init_fails(const rk_fem *f, const rk_fom_options *opt, const char *want, char *msg)
{
    rk_error err;
    rk_fom s;
    int rc = rk_fom_init(&s, f, opt, &err);
    snprintf(msg, 1024, "%s", rc ? err.msg : "(no error)");
    if (!rc) rk_fom_free(&s);
    return rc != 0 && strstr(err.msg, want) != NULL;
}

TEST(bad_options_are_rejected_at_init)
{
    rk_error err;
    body b;
    CHECK_OK(make_body(&b, &err));
    char msg[1024];
    rk_fom_options opt;
    rk_fom_default_options(&opt);
    opt.h = 0;
    CHECK(init_fails(&b.f, &opt, "time step", msg), "%s", msg);

    rk_fom_default_options(&opt);
    rk_obstacle ground = {.kind = RK_OBSTACLE_PLANE, .point = {0, 0, 0.05}, .normal = {0, 0, 1}}; /* the bottom layer is below it */
    opt.obstacles = &ground;
    opt.nobstacles = 1;
    opt.contact.dhat = 1e-3;
    CHECK(init_fails(&b.f, &opt, "behind a plane", msg), "%s", msg);

    rk_fom_default_options(&opt);
    int a[2] = {0, 1}, c[2] = {3, 1};
    rk_prescribed two[2] = {{.kind = RK_MOTION_FIXED, .count = 2, .verts = a},
                            {.kind = RK_MOTION_FIXED, .count = 2, .verts = c}};
    opt.nprescribed = 2;
    opt.prescribed = two;
    CHECK(init_fails(&b.f, &opt, "vertex 1 is already prescribed", msg), "%s", msg);

    two[1] = (rk_prescribed){.kind = RK_MOTION_TWIST, .count = 2, .verts = c}; /* zero axis */
    CHECK(init_fails(&b.f, &opt, "group 1: twist needs a non-zero axis", msg), "%s", msg);

    c[0] = b.f.nv;
    two[1] = (rk_prescribed){.kind = RK_MOTION_FIXED, .count = 2, .verts = c};
    CHECK(init_fails(&b.f, &opt, "out of range", msg), "%s", msg);
    free_body(&b);
}

TEST(static_solve_of_a_free_loaded_body_is_refused)
{
    rk_error err;
    body b;
    CHECK_OK(make_body(&b, &err));
    rk_fom_options opt;
    rk_fom_default_options(&opt);
    opt.gravity[2] = -9.81;
    rk_fom s;
    CHECK_OK(rk_fom_init(&s, &b.f, &opt, &err));
    CHECK(rk_fom_static(&s, &err) != 0 && strstr(err.msg, "no equilibrium"), "message: %s", err.msg);
    rk_fom_free(&s);
    free_body(&b);
}

TEST(prescribed_vertex_driven_through_a_plane_fails_with_the_step)
{
    rk_error err;
    body b;
    CHECK_OK(make_body(&b, &err));
    int v0 = 0;
    rk_prescribed down = {.kind = RK_MOTION_TRANSLATE, .count = 1, .verts = &v0, .velocity = {0, 0, -1}};
    rk_obstacle ground = {.kind = RK_OBSTACLE_PLANE, .point = {0, 0, -0.025}, .normal = {0, 0, 1}};
    rk_fom_options opt;
    rk_fom_default_options(&opt);
    opt.nprescribed = 1;
    opt.prescribed = &down;
    opt.obstacles = &ground;
    opt.nobstacles = 1;
    opt.contact.dhat = 1e-3;
    rk_fom s;
    CHECK_OK(rk_fom_init(&s, &b.f, &opt, &err));
    CHECK_OK(rk_fom_step(&s, &err));
    CHECK_OK(rk_fom_step(&s, &err));
    /* the third step would take the prescribed vertex 0.005 m below the plane: CCD stops it short,
     * and the motion cannot go on */
    CHECK(rk_fom_step(&s, &err) != 0, "vertex driven through the plane");
    CHECK(strstr(err.msg, "step 3") && strstr(err.msg, "cannot go on"), "message: %s", err.msg);
    rk_fom_free(&s);
    free_body(&b);
}

int main(void)
{
    RUN(nan_state_fails_with_the_step_number);
    RUN(unconverged_steps_are_counted);
    RUN(bad_options_are_rejected_at_init);
    RUN(static_solve_of_a_free_loaded_body_is_refused);
    RUN(prescribed_vertex_driven_through_a_plane_fails_with_the_step);
    return test_finish();
}
