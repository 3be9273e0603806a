/* rk_control_report (control.h) on a hand-made result: 2 vertices, 3 frames of a target that moves
 * 0, 1 and 2 m, a full-order run off by 0, 0.01 and 0.05 m and a model off by 0, 0.1 and 0 m:
 * the scale is 2 m, the per-frame errors in % of it 0, 0.5, 2.5 and 0, 5, 0, and the counts
 * under 2 % and 6 % follow; the inputs and the Koopman numbers are the result's. */
#include <math.h>
#include <string.h>

#include "pipeline/control.h"
#include "testlib.h"

enum { NV = 2, N3 = 3 * NV, T = 3 };

static rk_rom_entry entry; /* large: static */

static const cJSON *at(const cJSON *o, const char *a, const char *b)
{
    const cJSON *j = cJSON_GetObjectItem(o, a);
    return b ? cJSON_GetObjectItem(j, b) : j;
}

TEST(errors_are_percent_of_the_targets_largest_displacement)
{
    double target[N3 * T] = {0}, fom[N3 * T], model[N3 * T], C[2] = {3, 4};
    for (int t = 0; t < T; t++) target[N3 * t + 1] = t; /* vertex 0 moves t m along y */
    memcpy(fom, target, sizeof fom);
    memcpy(model, target, sizeof model);
    fom[N3 * 1 + 3] += 0.01, fom[N3 * 2 + 3] += 0.05; /* vertex 1, along x */
    model[N3 * 1 + 5] += 0.1;
    snprintf(entry.asset.groups[0].name, sizeof entry.asset.groups[0].name, "tip");
    entry.asset.ngroups = 1;
    rk_control_options o = {.ninputs = 1, .input = {{0, 1}}, .horizon = 4, .regularize = 0.01};
    rk_control_result r = {.T = T, .inputs = 1, .trajectories = 2, .rank = 5, .follow_values = 3, .C = C,
                           .u_model = model, .u_fom = fom, .seconds_solve = 1, .max_abs_eigenvalue = 0.999};
    CHECK_CLOSE(rk_control_target_scale(target, N3, T), 2.0, 1e-15);
    double mx[3];
    cJSON *rep = rk_control_report(&entry, &o, &r, target, N3, mx);
    const cJSON *er = at(rep, "error", NULL), *fv = at(er, "fom_vs_target", NULL), *mv = at(er, "model_vs_target", NULL);
    const cJSON *per = at(fv, "per_frame_percent", NULL);
    CHECK(cJSON_GetArraySize(per) == T, "%d frames", cJSON_GetArraySize(per));
    CHECK_CLOSE(cJSON_GetArrayItem(per, 1)->valuedouble, 0.5, 1e-12);
    CHECK_CLOSE(cJSON_GetArrayItem(per, 2)->valuedouble, 2.5, 1e-12);
    CHECK_CLOSE(mx[0], 2.5, 1e-12);
    CHECK_CLOSE(mx[1], 5.0, 1e-12);
    CHECK_CLOSE(mx[2], 100 * hypot(0.01, 0.1) / 2, 1e-12); /* frame 1: they differ by (0.01, 0, 0.1) m */
    CHECK(at(fv, "frames_under_2_percent", NULL)->valueint == 2 && at(mv, "frames_under_2_percent", NULL)->valueint == 2 &&
              at(mv, "frames_under_6_percent", NULL)->valueint == 3,
          "counts under 2 %% and 6 %%");
    CHECK_CLOSE(at(er, "target_max_displacement", NULL)->valuedouble, 2.0, 1e-15);
    const cJSON *in = cJSON_GetArrayItem(at(rep, "inputs", NULL), 0);
    CHECK(!strcmp(cJSON_GetStringValue(at(in, "group", NULL)), "tip") && !strcmp(cJSON_GetStringValue(at(in, "axis", NULL)), "y"),
          "input 0");
    CHECK(at(rep, "koopman", "rank")->valueint == 5 && at(rep, "koopman", "max_abs_eigenvalue")->valuedouble == 0.999 &&
              at(rep, "seconds", "solve_per_frame")->valuedouble == 0.5 && at(rep, "vertices", NULL)->valueint == NV,
          "koopman.*, seconds.*, vertices");
    cJSON_Delete(rep);
}

int main(void)
{
    RUN(errors_are_percent_of_the_targets_largest_displacement);
    return test_finish();
}
