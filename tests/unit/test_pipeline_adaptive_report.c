/* rk_adaptive_report (method_adaptive_subspace.h), romkit adaptive's report, on a short run of a
 * sagging beam: its counts are the simulator's own, seconds_per_step is the median of the step
 * times given, and contact.* appears exactly when a closest distance is given. */
#include <math.h>
#include <string.h>

#include "pipeline/method_adaptive_subspace.h"
#include "testlib.h"

#define BEAM "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [5, 1, 1], \"cells\": [10, 2, 2]}}," \
             " \"material\": {\"model\": \"neohookean\", \"young\": 5e6, \"poisson\": 0.45, \"density\": 1000}," \
             " \"fixed\": [{\"box\": [[-1, -1, -1], [0.5, 2, 2]]}]}]," \
             " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": 0.01, \"duration\": 0.05}," \
             " \"rom\": {\"method\": \"adaptive_subspace\", \"basis\": \"modes\", \"size\": 8}}"

static double num(const cJSON *o, const char *a, const char *b)
{
    const cJSON *j = cJSON_GetObjectItem(o, a);
    if (b) j = cJSON_GetObjectItem(j, b);
    return cJSON_IsNumber(j) ? j->valuedouble : NAN;
}

TEST(the_report_is_the_simulators_counts)
{
    rk_error err;
    rk_scene s;
    rk_scene_sim sim;
    rk_adaptive ad = {0};
    CHECK_OK(rk_scene_parse(BEAM, "beam.json", &s, &err));
    CHECK_OK(rk_scene_build(&s, &sim, &err));
    CHECK_OK(rk_scene_adaptive_init(&s, &sim, &s.entries[0], NULL, 0, &ad, NULL, &err));
    double secs[5] = {0.5, 0.1, 0.4, 0.2, 0.3}; /* given, not measured: median 0.3 */
    for (int k = 0; k < 5; k++) CHECK_OK(rk_adaptive_step(&ad, &err));
    cJSON *r = rk_adaptive_report(&sim, &ad, secs, 5, NULL, NULL);
    printf("# 5 steps: %ld Newton iterations, at most %d columns and %d enriched vertices\n",
           (long)ad.stats.newton_iterations, ad.stats.max_modes, ad.stats.max_nodes);
    CHECK(num(r, "steps", NULL) == 5 && num(r, "vertices", NULL) == sim.mesh.nv && num(r, "tets", NULL) == sim.mesh.nt,
          "sizes");
    CHECK(num(r, "seconds_per_step", NULL) == 0.3, "seconds_per_step %g", num(r, "seconds_per_step", NULL));
    CHECK(num(r, "newton_iterations", NULL) == (double)ad.stats.newton_iterations && ad.stats.newton_iterations >= 5 &&
              num(r, "adaptive", "max_modes") == ad.stats.max_modes &&
              num(r, "adaptive", "subdomains") == ad.opt.subdomains &&
              num(r, "seconds", "simulate") == ad.stats.seconds_total,
          "the simulator's counts");
    CHECK(!cJSON_GetObjectItem(r, "contact"), "contact without a distance");
    cJSON_Delete(r);
    rk_contact_tally tally; /* two frames: 3 crossings at 0.25 m, then none at 0.5 m */
    rk_contact_tally_init(&tally);
    rk_contact_tally_add(&tally, 3, 0.25);
    rk_contact_tally_add(&tally, 0, 0.5);
    r = rk_adaptive_report(&sim, &ad, secs, 5, &tally, NULL);
    CHECK(num(r, "contact", "min_distance") == 0.25 && num(r, "contact", "intersections") == 3 &&
              num(r, "contact", "intersecting_frames") == 1 && num(r, "contact", "frames") == 2,
          "contact.*");
    cJSON_Delete(r);
    rk_adaptive_free(&ad);
    rk_scene_sim_free(&sim);
    rk_scene_free(&s);
}

int main(void)
{
    RUN(the_report_is_the_simulators_counts);
    return test_finish();
}
