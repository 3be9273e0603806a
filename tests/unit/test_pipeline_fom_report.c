/* rk_scene_fom_measure and rk_fom_report (fom_report.h), the library side of romkit fom: a box in
 * free fall under backward Euler moves exactly as the discrete recursion says (v_{k+1} = v_k + h g,
 * x_{k+1} = x_k + h v_{k+1}: after n steps h^2 g n (n + 1) / 2, kinetic energy M (n h g)^2 / 2, no
 * strain), the caller's frame callback sees every frame, and the report carries those numbers;
 * the same box dropped on a plane reports contact (no crossing, a positive gap) and a box alone
 * reports none. */
#include <math.h>
#include <string.h>

#include "pipeline/fom_report.h"
#include "testlib.h"

#define BOX "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1, 0.5, 0.5], \"cells\": [4, 2, 2]}}," \
            " \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.3, \"density\": 800}}]," \
            " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": 0.01, \"duration\": 0.1}"

static int count_frame(void *ctx, int step, rk_fom *fom, double seconds, rk_error *err)
{
    int *n = ctx;
    if (step != *n) return rk_fail(err, "frame %d arrived as the %d-th", step, *n);
    ++*n;
    return 0;
}

static double number(const cJSON *o, const char *a, const char *b)
{
    const cJSON *j = cJSON_GetObjectItem(o, a);
    if (b) j = cJSON_GetObjectItem(j, b);
    return cJSON_IsNumber(j) ? j->valuedouble : NAN;
}

TEST(free_fall_is_the_backward_euler_recursion_and_the_report_says_so)
{
    rk_error err;
    rk_scene s;
    rk_scene_sim sim;
    rk_fom_measure m;
    CHECK_OK(rk_scene_parse(BOX "}", "box.json", &s, &err));
    CHECK_OK(rk_scene_build(&s, &sim, &err));
    int frames = 0;
    CHECK_OK(rk_scene_fom_measure(&sim, count_frame, &frames, &m, &err));
    int n = m.steps;
    double h = 0.01, g = 9.81, fall = h * h * g * n * (n + 1) / 2, mass = 800 * 0.25, v = n * h * g;
    printf("# %d steps: fell %.9f m (recursion %.9f), kinetic %.9g J (%.9g), contact %d\n", n, m.max_displacement,
           fall, m.kinetic_energy, 0.5 * mass * v * v, m.contact);
    CHECK(n == 10 && frames == n + 1, "%d steps, %d frames", n, frames);
    CHECK(fabs(m.max_displacement / fall - 1) < 1e-6, "fell %.9g m, the recursion %.9g", m.max_displacement, fall);
    CHECK(fabs(m.kinetic_energy / (0.5 * mass * v * v) - 1) < 1e-6, "kinetic %.9g J", m.kinetic_energy);
    CHECK(fabs(m.time - n * h) < 1e-12 && m.inverted == 0 && m.max_inverted == 0 && fabs(m.min_det_F - 1) < 1e-6,
          "t %g, inverted %d, min det F %g", m.time, m.inverted, m.min_det_F);
    CHECK(m.elastic_energy < 1e-9 * m.kinetic_energy, "a translation stores %g J", m.elastic_energy);
    CHECK(!m.contact && fabs(m.x[1] - sim.mesh.X[1] + fall) < 1e-6, "contact %d; vertex 0 y %g", m.contact, m.x[1]);
    cJSON *r = rk_fom_report(&sim, &m, 1.5);
    CHECK(number(r, "steps", NULL) == n && number(r, "vertices", NULL) == sim.mesh.nv &&
              number(r, "final", "max_displacement") == m.max_displacement &&
              number(r, "final", "kinetic_energy") == m.kinetic_energy && number(r, "seconds", "total") == 1.5 &&
              number(r, "newton_iterations", NULL) == (double)m.stats.newton_iterations,
          "the report's numbers differ from the measurement");
    CHECK(!cJSON_GetObjectItem(r, "contact"), "a lone box reports contact");
    cJSON_Delete(r);
    rk_fom_measure_free(&m);
    rk_scene_sim_free(&sim);
    rk_scene_free(&s);
}

TEST(a_box_dropped_on_a_plane_reports_its_contact)
{
    rk_error err;
    rk_scene s;
    rk_scene_sim sim;
    rk_fom_measure m;
    CHECK_OK(rk_scene_parse(BOX ", \"obstacles\": [{\"plane\": {\"point\": [0, -0.04, 0], \"normal\": [0, 1, 0]}}]}",
                            "box.json", &s, &err));
    CHECK_OK(rk_scene_build(&s, &sim, &err));
    CHECK_OK(rk_scene_fom_measure(&sim, NULL, NULL, &m, &err));
    printf("# on a plane: closest %.3g m, %ld crossings, %ld CCD calls\n", m.tally.min_distance, m.tally.intersections,
           m.contact_stats.ccd_calls);
    CHECK(m.contact && m.tally.intersections == 0 && m.tally.min_distance > 0 && m.tally.min_distance < 0.01,
          "contact %d, %ld crossings, closest %g", m.contact, m.tally.intersections, m.tally.min_distance);
    cJSON *r = rk_fom_report(&sim, &m, 0);
    CHECK(number(r, "contact", "min_distance") == m.tally.min_distance && number(r, "contact", "intersections") == 0,
          "contact.* in the report");
    cJSON_Delete(r);
    rk_fom_measure_free(&m);
    rk_scene_sim_free(&sim);
    rk_scene_free(&s);
}

static int stop_at_3(void *ctx, int step, rk_fom *fom, double seconds, rk_error *err)
{
    return step == 3 ? rk_fail(err, "stopped at frame %d", step) : 0;
}

TEST(a_failing_frame_stops_the_run_with_its_error)
{
    rk_error err;
    rk_scene s;
    rk_scene_sim sim;
    rk_fom_measure m;
    CHECK_OK(rk_scene_parse(BOX "}", "box.json", &s, &err));
    CHECK_OK(rk_scene_build(&s, &sim, &err));
    CHECK(rk_scene_fom_measure(&sim, stop_at_3, NULL, &m, &err) != 0 && strstr(err.msg, "stopped at frame 3"),
          "error: %s", err.msg);
    CHECK(m.x == NULL, "a failed measurement keeps its positions");
    rk_scene_sim_free(&sim);
    rk_scene_free(&s);
}

int main(void)
{
    RUN(free_fall_is_the_backward_euler_recursion_and_the_report_says_so);
    RUN(a_box_dropped_on_a_plane_reports_its_contact);
    RUN(a_failing_frame_stops_the_run_with_its_error);
    return test_finish();
}
