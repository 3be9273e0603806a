/* Friction in the runtime on the analytic incline: a stiff block resting on a plane, either gravity
 * tilted by theta over a level plane or the plane itself tilted by theta under plain gravity (the
 * block turned onto it: the plane's friction and barrier along a normal that is no axis). With
 * tan theta < mu it sticks (drift along the slope under 1e-4 m over
 * 1 s); with tan theta > mu it slides with a = g (sin theta - mu cos theta) within 1%, fitted from
 * the shown vertices' mean trajectory over the second half second (backward Euler under a constant
 * force moves the mean exactly quadratically in time). The reduced simulator (precompute/rom) steps
 * the same baked model beside it as the reference (test_pipeline_friction checks it and the full
 * order against the same law). Float and double (test_runtime_incline_double). */
#include <unistd.h>

#include "runtime_fixture.h"
#include "rom/rom.h"
#include "trajectory_fit.h"

#ifdef ROMRT_DOUBLE
#define ASSET_REAL ROMBIN_REAL_F64
#else
#define ASSET_REAL ROMBIN_REAL_F32
#endif

#define G 9.81
#define STEPS 100 /* of 0.01 s */

typedef struct {
    double drift, accel; /* along the slope: over the run (m); fitted (m/s^2) */
    long newton;
} incline_motion;

/* The mean of the shown vertices along the downhill direction d. */
static double mean_along(const double *xyz, int n, const double d[3])
{
    double s = 0;
    for (int i = 0; i < n; i++) s += xyz[3 * i] * d[0] + xyz[3 * i + 1] * d[1] + xyz[3 * i + 2] * d[2];
    return s / n;
}

/* The 10 x 5 x 10 cm block turned by -theta about z, so its bottom face lies on the plane through
 * the origin with normal (sin theta, cos theta, 0), then lifted dhat / 2 off it: a MEDIT file the
 * scene loads (the scene format turns no mesh). */
static int write_turned_block(double theta, const char *path, rk_error *err)
{
    rk_mesh b;
    double size[3] = {0.1, 0.05, 0.1}, c = cos(theta), s = sin(theta);
    int cells[3] = {2, 1, 2};
    if (rk_mesh_box(size, cells, &b, err)) return -1;
    for (int v = 0; v < b.nv; v++) {
        double *X = &b.X[3 * v], x = X[0], y = X[1];
        X[0] = c * x + s * y + 5e-4 * s;
        X[1] = -s * x + c * y + 5e-4 * c;
    }
    int rc = rk_mesh_write(path, &b, NULL, err);
    rk_mesh_free(&b);
    return rc;
}

static void motion_of(const double *x, long newton, incline_motion *out)
{
    out->drift = x[STEPS] - x[0];
    out->accel = fit_acceleration(x, STEPS / 2, STEPS, 0.01);
    out->newton = newton;
}

/* The block on the incline (tilted: the plane, else gravity), baked and stepped by the runtime (*rt)
 * and the reduced simulator (*rom). */
static int run_incline(double mu, double tan_theta, double eps_v, int tilted, incline_motion *rt, incline_motion *rom,
                       double *gap, rk_error *err)
{
    double theta = atan(tan_theta), ct = cos(theta), st = sin(theta);
    double down[3] = {tilted ? ct : 1, tilted ? -st : 0, 0}; /* downhill, along the plane */
    char json[2048], mesh[256], path[128];
    /* a 10 x 5 x 10 cm block of stiff rubber resting at dhat / 2 over the plane */
    if (tilted) {
        static int count;
        snprintf(path, sizeof path, "%s/romkit_incline_%ld_%d.mesh", tl_tmpdir(), (long)getpid(), count++);
        if (write_turned_block(theta, path, err)) return -1;
        snprintf(mesh, sizeof mesh, "{\"file\": \"%s\"}", path);
    } else {
        snprintf(mesh, sizeof mesh, "{\"box\": {\"size\": [0.1, 0.05, 0.1], \"cells\": [2, 1, 2]}, \"translate\": [0, 5e-4, 0]}");
    }
    snprintf(json, sizeof json,
             "{\"objects\": [{\"mesh\": %s,"
             "  \"material\": {\"model\": \"neohookean\", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1000}}],"
             " \"gravity\": [%.17g, %.17g, 0],"
             " \"obstacles\": [{\"plane\": {\"point\": [0, 0, 0], \"normal\": [%.17g, %.17g, 0]}}],"
             " \"contact\": {\"dhat\": 1e-3, \"friction\": %.17g, \"eps_v\": %.17g},"
             " \"time\": {\"step\": 0.01, \"duration\": 1.0}, \"rom\": {\"basis\": \"modes\", \"size\": 12}}",
             mesh, tilted ? 0 : G * st, tilted ? -G : -G * ct, tilted ? st : 0, tilted ? ct : 1, mu, eps_v);
    rt_fixture f;
    romrt_error rerr;
    rk_rom s;
    int rc = rt_fixture_open(&f, json, ASSET_REAL, err, &rerr), have_rom = 0;
    if (tilted) unlink(path); /* read by the scene build, inside rt_fixture_open */
    int n = rc ? 0 : romrt_shown_count(f.m);
    double xs[STEPS + 1], xq[STEPS + 1], *ref = calloc((size_t)3 * n + 3, sizeof(double)), *xd = calloc((size_t)3 * n + 3, sizeof(double));
    romrt_real *xyz = calloc((size_t)3 * n + 3, sizeof(romrt_real));
    long rt_newton = 0;
    *gap = 0;
    if (!rc) {
        rc = rk_rom_init(&s, &f.R.model, NULL, f.v0, err);
        have_rom = !rc;
    }
    for (int k = 0; !rc && k <= STEPS; k++) {
        if (k > 0) {
            romrt_step_info info;
            if (romrt_step(f.m, &rerr) != ROMRT_OK) {
                rc = rk_fail(err, "runtime step %d: %s", k, rerr.message);
                break;
            }
            info.size = sizeof info;
            romrt_last_step(f.m, &info, NULL);
            rt_newton += info.newton_iterations;
            if (rk_rom_step(&s, err)) {
                rc = -1;
                break;
            }
        }
        romrt_positions(f.m, xyz, 3 * (size_t)n, 3, NULL);
        for (int i = 0; i < 3 * n; i++) xd[i] = (double)xyz[i];
        rt_fixture_reference(&f, s.q, ref);
        xs[k] = mean_along(xd, n, down);
        xq[k] = mean_along(ref, n, down);
        for (int i = 0; i < 3 * n; i++) *gap = fmax(*gap, fabs(xd[i] - ref[i]));
    }
    if (!rc) {
        motion_of(xs, rt_newton, rt);
        motion_of(xq, s.stats.newton_iterations, rom);
    }
    if (have_rom) rk_rom_free(&s);
    rt_fixture_close(&f);
    free(ref), free(xd), free(xyz);
    return rc;
}

static void check_incline(double mu, int tilted)
{
    rk_error err = {{0}};
    incline_motion rest, slide, rest_ref, slide_ref;
    double t_rest = 0.5 * mu, t_slide = 1.5 * mu + 0.05, gap_rest, gap_slide;
    CHECK_OK(run_incline(mu, t_rest, 1e-5, tilted, &rest, &rest_ref, &gap_rest, &err));
    CHECK_OK(run_incline(mu, t_slide, 1e-3, tilted, &slide, &slide_ref, &gap_slide, &err));
    double th = atan(t_slide), expect = G * (sin(th) - mu * cos(th));
    printf("# %s runtime, %s, mu %.1f: at rest (tan %.3f) drift %.2e m over 1 s (reduced %.2e), %ld Newton iterations; "
           "sliding (tan %.3f) a %.5f vs %.5f m/s^2 (%+.4f%%; reduced %.5f, %+.4f%%), %ld Newton iterations; "
           "largest runtime - reduced gap %.2e m (rest) %.2e m (sliding)\n",
           sizeof(romrt_real) == 4 ? "float" : "double", tilted ? "tilted plane" : "tilted gravity", mu, t_rest, rest.drift, rest_ref.drift, rest.newton, t_slide,
           slide.accel, expect, 100 * (slide.accel / expect - 1), slide_ref.accel, 100 * (slide_ref.accel / expect - 1),
           slide.newton, gap_rest, gap_slide);
    CHECK(fabs(rest.drift) < 1e-4, "mu %g, tan theta %g: the block drifted %g m", mu, t_rest, rest.drift);
    CHECK(fabs(slide.accel / expect - 1) < 0.01, "mu %g, tan theta %g: acceleration %.6g, expected %.6g (%+.3f%%)", mu,
          t_slide, slide.accel, expect, 100 * (slide.accel / expect - 1));
    CHECK(fabs(rest_ref.drift) < 1e-4 && fabs(slide_ref.accel / expect - 1) < 0.01,
          "the reduced reference: drift %g m, acceleration %.6g of %.6g", rest_ref.drift, slide_ref.accel, expect);
}

TEST(runtime_block_on_an_incline_mu_0_1) { check_incline(0.1, 0); }
TEST(runtime_block_on_an_incline_mu_0_5) { check_incline(0.5, 0); }
TEST(runtime_block_on_a_tilted_plane_mu_0_1) { check_incline(0.1, 1); }
TEST(runtime_block_on_a_tilted_plane_mu_0_5) { check_incline(0.5, 1); }

int main(void)
{
    RUN(runtime_block_on_an_incline_mu_0_1);
    RUN(runtime_block_on_an_incline_mu_0_5);
    RUN(runtime_block_on_a_tilted_plane_mu_0_1);
    RUN(runtime_block_on_a_tilted_plane_mu_0_5);
    return test_finish();
}
