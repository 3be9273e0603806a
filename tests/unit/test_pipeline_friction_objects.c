/* Friction between two objects on the analytic incline: a block resting on a fixed slab (the
 * second object, not an obstacle), gravity tilted by theta. With tan theta < mu the block sticks
 * (drift along the slope under 1e-4 m over 1 s); with tan theta > mu it slides with
 * a = g (sin theta - mu cos theta) within 1%, fitted from its centre of mass over the second half
 * second (backward Euler under a constant force moves it exactly quadratically). Full order and
 * the reduced simulator (precompute/rom, modes): the reference the runtime, which collides objects
 * through sphere proxies without friction (issue 30), is to be held to.
 *
 * The slab is one cell: its top face's vertices are its corners, far from the block. On a slab of
 * 10 cm cells (20 x 1 x 3), whose vertices pass under the block as it slides, both miss the law
 * with the scene defaults, for two reasons measured at mu 0.1 (tan theta 0.2):
 *  - the reduced simulator slides 1.35% slow: Newton's default tolerance (1e-5 of the bounding-box
 *    diagonal per second, 2e-5 m/s with this 2 m slab) leaves a momentum error of 2.4 mN a step
 *    against 481 mN of friction; "newton": {"tolerance": 1e-6} gives +0.32%, 1e-7 +0.17%;
 *  - the full order slides 2.0% slow (mu 0.5: 1.5%) and drifts 0.58 mm where it should stick,
 *    whatever Newton's tolerance; a fixed "kappa" (100, 1e4) gives -0.14%, -0.57% and 7e-6 m,
 *    2.9e-5 m of drift. With adaptive kappa the drift is all in the first 7 steps (the barrier
 *    starts soft and friction is lagged on it while the block settles from dhat / 2 to 9e-6 m),
 *    then it sticks (1e-8 m a step); sliding, every step gains the law's 0.962 m/s^2 but four
 *    (steps 53, 69, 76, 94: 0.61 to 0.94), each with a row of the block's vertices over a slab edge. */
#include "scene_run.h"
#include "rom/rom.h"
#include "incline_slab.h"
#include "trajectory_fit.h"

#define G 9.81

typedef struct {
    double drift, accel;
    long newton;
    int steps;
} incline_result;

/* The mass-weighted mean of x[3 v] over object 1's vertices (the block). */
static double block_x(const rk_scene_sim *sim, const double *x)
{
    double m = 0, s = 0;
    for (int v = sim->object_first_vertex[1]; v < sim->object_first_vertex[2]; v++) {
        m += sim->fem.vertex_mass[v];
        s += sim->fem.vertex_mass[v] * x[3 * v];
    }
    return s / m;
}

/* The same scene at full order: the block's centre of mass every step. */
static int run_full_order(const char *json, incline_result *out, rk_error *err)
{
    scene_run r;
    if (scene_run_open(&r, json, err)) return -1;
    int rc = 0, T = r.sim.steps;
    double *xs = calloc((size_t)T + 1, sizeof(double));
    xs[0] = block_x(&r.sim, r.fom.x);
    for (int k = 1; !rc && k <= T; k++) {
        rc = rk_fom_step(&r.fom, err);
        xs[k] = block_x(&r.sim, r.fom.x);
    }
    if (!rc) {
        out->drift = xs[T] - xs[0];
        out->accel = fit_acceleration(xs, T / 2, T, r.sim.options.h);
        out->newton = r.fom.stats.newton_iterations;
    }
    free(xs);
    scene_run_close(&r);
    return rc;
}

static int run_incline(double mu, double tan_theta, double eps_v, int reduced, incline_result *out, rk_error *err)
{
    char json[2048];
    incline_slab_scene(json, sizeof json, G, mu, tan_theta, eps_v);
    if (!reduced) return run_full_order(json, out, err);
    rk_scene scene;
    rk_scene_sim sim;
    rk_scene_rom R;
    rk_rom s;
    int stage = 0, rc = -1;
    double *x = NULL, *xs = NULL;
    if (rk_scene_parse(json, "test.json", &scene, err)) return -1;
    stage = 1;
    if (rk_scene_build(&scene, &sim, err)) goto out;
    stage = 2;
    if (rk_scene_rom_build(&scene, &sim, &scene.entries[0], NULL, 0, &R, err)) goto out;
    stage = 3;
    if (rk_rom_init(&s, &R.model, NULL, NULL, err)) goto out;
    stage = 4;
    int n = 3 * sim.mesh.nv;
    out->steps = sim.steps;
    x = calloc((size_t)n, sizeof(double));
    xs = calloc((size_t)sim.steps + 1, sizeof(double));
    if (!x || !xs) goto out;
    rk_rom_positions(R.basis.U, n, R.basis.r, sim.mesh.X, s.q, x);
    xs[0] = block_x(&sim, x);
    for (int k = 1; k <= sim.steps; k++) {
        if (rk_rom_step(&s, err)) goto out;
        rk_rom_positions(R.basis.U, n, R.basis.r, sim.mesh.X, s.q, x);
        xs[k] = block_x(&sim, x);
    }
    int crossings;
    double closest;
    if (rk_rom_contact_measure(&s, &crossings, &closest, err)) goto out;
    if (crossings) {
        rk_fail(err, "the block and the slab intersect at the end (%d crossings)", crossings);
        goto out;
    }
    out->drift = xs[sim.steps] - xs[0];
    out->accel = fit_acceleration(xs, sim.steps / 2, sim.steps, sim.options.h);
    out->newton = s.stats.newton_iterations;
    rc = 0;
out:
    free(x), free(xs);
    if (stage >= 4) rk_rom_free(&s);
    if (stage >= 3) rk_scene_rom_free(&R);
    if (stage >= 2) rk_scene_sim_free(&sim);
    rk_scene_free(&scene);
    return rc;
}

static void check_incline(double mu, int reduced)
{
    rk_error err = {{0}};
    incline_result rest, slide;
    double t_rest = 0.5 * mu, t_slide = 1.5 * mu + 0.05;
    CHECK_OK(run_incline(mu, t_rest, 1e-5, reduced, &rest, &err));
    CHECK_OK(run_incline(mu, t_slide, 1e-3, reduced, &slide, &err));
    double th = atan(t_slide), expect = G * (sin(th) - mu * cos(th));
    printf("# %s, block on a slab, mu %.1f: at rest (tan %.3f) drift %.2e m over 1 s, %ld Newton "
           "iterations; sliding (tan %.3f) a %.5f vs %.5f m/s^2 (%+.4f%%), %ld Newton iterations\n",
           reduced ? "reduced (modes 12)" : "full order", mu, t_rest, rest.drift, rest.newton, t_slide, slide.accel, expect, 100 * (slide.accel / expect - 1),
           slide.newton);
    CHECK(fabs(rest.drift) < 1e-4, "mu %g, tan theta %g: the block drifted %g m", mu, t_rest, rest.drift);
    CHECK(fabs(slide.accel / expect - 1) < 0.01, "mu %g, tan theta %g: acceleration %.6g, expected %.6g", mu, t_slide,
          slide.accel, expect);
}

TEST(block_on_a_slab_incline_mu_0_1) { check_incline(0.1, 0); }
TEST(block_on_a_slab_incline_mu_0_5) { check_incline(0.5, 0); }
TEST(reduced_block_on_a_slab_incline_mu_0_1) { check_incline(0.1, 1); }
TEST(reduced_block_on_a_slab_incline_mu_0_5) { check_incline(0.5, 1); }

int main(void)
{
    RUN(block_on_a_slab_incline_mu_0_1);
    RUN(block_on_a_slab_incline_mu_0_5);
    RUN(reduced_block_on_a_slab_incline_mu_0_1);
    RUN(reduced_block_on_a_slab_incline_mu_0_5);
    return test_finish();
}
