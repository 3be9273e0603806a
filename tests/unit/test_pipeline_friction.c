/* Friction against the analytic block on an incline (IPC's smoothed, lagged Coulomb friction):
 * gravity tilted by theta against a ground plane is the incline. With tan theta < mu the block
 * stays (drift under 1e-4 m over 1 s); with tan theta > mu it slides with acceleration
 * g (sin theta - mu cos theta), measured from its mean velocity between 0.5 and 1 s (backward
 * Euler gains exactly h a of velocity per step under a constant force). */
#include "scene_run.h"

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

static int run_incline(double mu, double tan_theta, double eps_v, incline_result *out, rk_error *err)
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
             " \"time\": {\"step\": 0.01, \"duration\": 1.0}}",
             G * sin(theta), -G * cos(theta), mu, eps_v);
    scene_run r;
    if (scene_run_open(&r, json, err)) return -1;
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

static void check_incline(double mu)
{
    rk_error err;
    incline_result rest, slide;
    double t_rest = 0.5 * mu, t_slide = 1.5 * mu + 0.05;
    CHECK_OK(run_incline(mu, t_rest, 1e-5, &rest, &err));
    CHECK_OK(run_incline(mu, t_slide, 1e-3, &slide, &err));
    double th = atan(t_slide), expect = G * (sin(th) - mu * cos(th));
    printf("# mu %.1f: at rest (tan %.3f): drift %.2e m over 1 s, %ld Newton iterations; sliding (tan %.3f): "
           "a %.4f vs %.4f m/s^2 (%.2f%%), %ld Newton iterations\n",
           mu, t_rest, rest.drift, rest.newton, t_slide, slide.accel, expect, 100 * (slide.accel / expect - 1),
           slide.newton);
    CHECK(fabs(rest.drift) < 1e-4, "mu %g, tan theta %g: the block drifted %g m", mu, t_rest, rest.drift);
    CHECK(fabs(slide.accel / expect - 1) < 0.02, "mu %g, tan theta %g: acceleration %g, expected %g", mu, t_slide,
          slide.accel, expect);
}

TEST(block_on_an_incline_mu_0_1) { check_incline(0.1); }
TEST(block_on_an_incline_mu_0_5) { check_incline(0.5); }

int main(void)
{
    RUN(block_on_an_incline_mu_0_1);
    RUN(block_on_an_incline_mu_0_5);
    return test_finish();
}
