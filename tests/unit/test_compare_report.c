/* rk_compare_report (compare.h): the report romkit compare writes carries the comparison's numbers
 * (the fom row first, then each method's), a failed method's reason instead of its numbers, no
 * contact object for a scene without contact, and the caller's total seconds. */
#include <math.h>
#include <string.h>

#include "compare/compare.h"
#include "testlib.h"

#define BEAM "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [5, 1, 1], \"cells\": [10, 2, 2]}}," \
             " \"material\": {\"model\": \"neohookean\", \"young\": 5e6, \"poisson\": 0.45, \"density\": 1000}," \
             " \"fixed\": [{\"box\": [[-1, -1, -1], [0.5, 2, 2]]}]}]," \
             " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": 0.01, \"duration\": 0.2}, \"rom\": "

static const cJSON *at(const cJSON *o, const char *a, const char *b)
{
    const cJSON *j = cJSON_GetObjectItem(o, a);
    return b ? cJSON_GetObjectItem(j, b) : j;
}

TEST(the_report_carries_the_comparisons_numbers)
{
    rk_error err;
    rk_scene s;
    rk_compare_result res;
    CHECK_OK(rk_scene_parse(BEAM "[{\"basis\": \"modes\", \"size\": 6}, {\"basis\": \"modes\", \"size\": 4000}]}",
                            "beam.json", &s, &err));
    CHECK_OK(rk_compare_scene(&s, &res, &err));
    rk_scene_free(&s);
    cJSON *r = rk_compare_report(&res, 2.5);
    const cJSON *methods = at(r, "methods", NULL);
    CHECK(cJSON_GetArraySize(methods) == 3, "%d rows, expected fom and two methods", cJSON_GetArraySize(methods));
    const cJSON *fom = cJSON_GetArrayItem(methods, 0), *modes = cJSON_GetArrayItem(methods, 1),
                *bad = cJSON_GetArrayItem(methods, 2);
    CHECK(!strcmp(cJSON_GetStringValue(at(fom, "name", NULL)), "fom") &&
              at(fom, "seconds_per_step", NULL)->valuedouble == res.fom_seconds_per_step,
          "the fom row");
    const rk_compare_method *m = &res.methods[0];
    CHECK(!m->failure[0] && !strcmp(cJSON_GetStringValue(at(modes, "kind", NULL)), "reduced") &&
              !strcmp(cJSON_GetStringValue(at(modes, "basis", "type")), "modes") &&
              at(modes, "basis", "columns")->valuedouble == m->r &&
              at(modes, "normalized_mse", NULL)->valuedouble == m->normalized_mse &&
              at(modes, "relative_online_error", NULL)->valuedouble == m->relative_online_error,
          "modes-6: %s", m->failure);
    CHECK(res.methods[1].failure[0] && !strcmp(cJSON_GetStringValue(at(bad, "failure", NULL)), res.methods[1].failure) &&
              !at(bad, "basis", NULL) && !at(bad, "normalized_mse", NULL),
          "modes-4000 should fail and report only why: %s", res.methods[1].failure);
    CHECK(!at(r, "contact", NULL) && at(r, "seconds", "total")->valuedouble == 2.5 &&
              at(r, "vertices", NULL)->valuedouble == res.vertices && at(r, "reference", "refine")->valuedouble == 0,
          "top-level keys");
    cJSON_Delete(r);
    rk_compare_result_free(&res);
}

int main(void)
{
    RUN(the_report_carries_the_comparisons_numbers);
    return test_finish();
}
