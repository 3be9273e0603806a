/* Friction against the analytic block on an incline (IPC's smoothed, lagged Coulomb friction):
 * gravity tilted by theta against a ground plane is the incline. With tan theta < mu the block
 * stays (drift under 1e-4 m over 1 s); with tan theta > mu it slides with acceleration
 * g (sin theta - mu cos theta), measured from its mean velocity between 0.5 and 1 s (backward
 * Euler gains exactly h a of velocity per step under a constant force). Full order, and the
 * reduced simulator on a modes basis (its rigid modes carry the sliding). */
#include "scene_run.h"
#include "rom/rom.h"

#define G 9.81

typedef struct {
    double drift;        /* mean displacement along the slope over the run (m) */
    double accel;        /* from the mean velocity at 0.5 s and at the end (m/s^2) */
    long newton;
} incline_result;

/* Mass-weighted mean of x[3 v] over the vertices. */
static double mean_x(const scene_run *r, const double *x)
{
    double m = 0, s = 0;
    for (int v = 0; v < r->sim.mesh.nv; v++) {
        m += r->sim.fem.vertex_mass[v];
        s += r->sim.fem.vertex_mass[v] * x[3 * v];
    }
    return s / m;
}

/* The mean over the reduced model's vertices of x[3 v] (the reduced positions X + U q). */
static double reduced_mean_x(const scene_run *r, const rk_scene_rom *R, const double *q, int velocity, double *x)
{
    int n = 3 * r->sim.mesh.nv;
    double *origin = calloc((size_t)n, sizeof(double)); /* velocities: U v from 0 */
    rk_rom_positions(R->basis.U, n, R->basis.r, velocity ? origin : r->sim.mesh.X, q, x);
    free(origin);
    return mean_x(r, x);
}

/* The same scene stepped by the reduced simulator (rom: the scene's first rom entry). */
static int run_incline_reduced(scene_run *r, incline_result *out, rk_error *err)
{
    rk_scene_rom R;
    rk_rom rom;
    if (rk_scene_rom_build(&r->scene, &r->sim, &r->scene.entries[0], NULL, 0, &R, err)) return -1;
    double *x = calloc(3 * (size_t)r->sim.mesh.nv, sizeof(double));
    int rc = rk_rom_init(&rom, &R.model, NULL, NULL, err);
    double x0 = reduced_mean_x(r, &R, rom.q, 0, x), v_half = 0;
    for (int step = 1; !rc && step <= r->sim.steps; step++) {
        rc = rk_rom_step(&rom, err);
        if (step == r->sim.steps / 2) v_half = reduced_mean_x(r, &R, rom.v, 1, x);
    }
    if (!rc) {
        out->drift = reduced_mean_x(r, &R, rom.q, 0, x) - x0;
        out->accel = (reduced_mean_x(r, &R, rom.v, 1, x) - v_half) / (0.5 * r->sim.steps * 0.01);
        out->newton = rom.stats.newton_iterations;
    }
    rk_rom_free(&rom);
    rk_scene_rom_free(&R);
    free(x);
    return rc;
}

static int run_incline(double mu, double tan_theta, double eps_v, int reduced, incline_result *out, rk_error *err)
{
    double theta = atan(tan_theta);
    char json[1024];
    /* a 10 x 5 x 10 cm block of stiff rubber resting at dhat / 2 over the plane y = 0 */
    snprintf(json, sizeof json,
             "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.1, 0.05, 0.1], \"cells\": [2, 1, 2]},"
             "   \"translate\": [0, 5e-4, 0]},"
             "  \"material\": {\"model\": \"neohookean\", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1000}}],"
             " \"gravity\": [%.17g, %.17g, 0],"
             " \"obstacles\": [{\"plane\": {\"point\": [0, 0, 0], \"normal\": [0, 1, 0]}}],"
             " \"contact\": {\"dhat\": 1e-3, \"friction\": %g, \"eps_v\": %g},"
             " \"time\": {\"step\": 0.01, \"duration\": 1.0}, \"rom\": {\"basis\": \"modes\", \"size\": 12}}",
             G * sin(theta), -G * cos(theta), mu, eps_v);
    scene_run r;
    if (scene_run_open(&r, json, err)) return -1;
    if (reduced) {
        int rc = run_incline_reduced(&r, out, err);
        scene_run_close(&r);
        return rc;
    }
    double x0 = mean_x(&r, r.fom.x), v_half = 0;
    for (int step = 1; step <= r.sim.steps; step++) {
        if (rk_fom_step(&r.fom, err)) {
            scene_run_close(&r);
            return -1;
        }
        if (step == r.sim.steps / 2) v_half = mean_x(&r, r.fom.v);
    }
    out->drift = mean_x(&r, r.fom.x) - x0;
    out->accel = (mean_x(&r, r.fom.v) - v_half) / (0.5 * r.sim.steps * 0.01);
    out->newton = r.fom.stats.newton_iterations;
    scene_run_close(&r);
    return 0;
}

static void check_incline(double mu, int reduced)
{
    rk_error err;
    incline_result rest, slide;
    double t_rest = 0.5 * mu, t_slide = 1.5 * mu + 0.05;
    CHECK_OK(run_incline(mu, t_rest, 1e-5, reduced, &rest, &err));
    CHECK_OK(run_incline(mu, t_slide, 1e-3, reduced, &slide, &err));
    double th = atan(t_slide), expect = G * (sin(th) - mu * cos(th));
    printf("# %s, mu %.1f: at rest (tan %.3f): drift %.2e m over 1 s, %ld Newton iterations; sliding (tan %.3f): "
           "a %.4f vs %.4f m/s^2 (%.2f%%), %ld Newton iterations\n",
           reduced ? "reduced (modes 12)" : "full order", mu, t_rest, rest.drift, rest.newton, t_slide, slide.accel, expect, 100 * (slide.accel / expect - 1),
           slide.newton);
    CHECK(fabs(rest.drift) < 1e-4, "mu %g, tan theta %g: the block drifted %g m", mu, t_rest, rest.drift);
    CHECK(fabs(slide.accel / expect - 1) < 0.02, "mu %g, tan theta %g: acceleration %g, expected %g", mu, t_slide,
          slide.accel, expect);
}

TEST(block_on_an_incline_mu_0_1) { check_incline(0.1, 0); }
TEST(block_on_an_incline_mu_0_5) { check_incline(0.5, 0); }
TEST(reduced_block_on_an_incline_mu_0_1) { check_incline(0.1, 1); }
TEST(reduced_block_on_an_incline_mu_0_5) { check_incline(0.5, 1); }

int main(void)
{
    RUN(block_on_an_incline_mu_0_1);
    RUN(block_on_an_incline_mu_0_5);
    RUN(reduced_block_on_an_incline_mu_0_1);
    RUN(reduced_block_on_an_incline_mu_0_5);
    return test_finish();
}
