/* A method added from outside the library, as a new method would be: its own file (this one) and
 * one registration line (main). The toy predicts by extrapolating frames: the free run holds the
 * start; the realigned run steps x_{t+1} = x_t + gain (x_t - x_{t-1}) from the reference's frames
 * (gain: its own scene key, kept in the entry's method-owned block). romkit compare's machinery
 * (the scene's keys, the default name, the full-order run, the errors, the per-method cache) runs
 * it through the table, beside a built-in method. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "compare/compare.h"
#include "testlib.h"

typedef struct {
    double gain;
} toy_options;

static int toy_entries_seen = -1; /* what the cache counted, read when compare frees it */

static int toy_parse(const rk_json_ctx *c, const cJSON *e, const char *path, double h, rk_rom_entry *o)
{
    toy_options *t = (toy_options *)o->own;
    t->gain = 0;
    if (rk_method_number(c, e, path, "toy_gain", &t->gain)) return -1;
    if (!(t->gain >= 0 && t->gain <= 1)) return rk_method_fail(c, path, "toy_gain must be in [0, 1]");
    return 0;
}

static int toy_compare(rk_compare_ctx *c, const rk_rom_entry *e, rk_compare_method *m, rk_error *err);

static void toy_compare_free(void *cache)
{
    toy_entries_seen = *(int *)cache;
    free(cache);
}

static int toy_bake(const rk_scene *scene, const rk_rom_entry *e, const rk_bake_request *req,
                    const rk_asset_options *ao, rk_baked *out, rk_error *err)
{
    return rk_fail(err, "%s: the toy method has no asset", e->path);
}

static const char *const toy_keys[] = {"toy_gain", NULL};
static const rk_method toy = {.name = "toy", .kind = "toy", .keys = toy_keys, .parse = toy_parse,
                              .compare = toy_compare, .compare_free = toy_compare_free, .bake = toy_bake};

static int toy_compare(rk_compare_ctx *c, const rk_rom_entry *e, rk_compare_method *m, rk_error *err)
{
    const toy_options *t = rk_method_options(e, &toy);
    const rk_fom_frames *ref = c->ref;
    int n = ref->ndof;
    if (!*c->cache && !(*c->cache = rk_calloc(1, sizeof(int), err))) return -1;
    ++*(int *)*c->cache;
    double *x = rk_calloc((size_t)n, sizeof(double), err);
    if (!x) return -1;
    rk_run_error free_run, online;
    rk_run_error_init(&free_run, c->sim->mesh.X, n / 3);
    rk_run_error_init(&online, c->sim->mesh.X, n / 3);
    for (int s = 0; s < ref->T; s++) {
        const double *now = ref->x + (size_t)n * s, *before = s ? now - n : now, *next = now + n;
        rk_run_error_add(&free_run, ref->x, next);
        for (int i = 0; i < n; i++) x[i] = now[i] + t->gain * (now[i] - before[i]);
        rk_run_error_add(&online, x, next);
    }
    free(x);
    rk_compare_record_errors(m, &free_run);
    m->relative_online_error = rk_relative_online_error(&online);
    m->seconds_per_step = 1e-9;
    return 0;
}

#define BEAM "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [5, 1, 1], \"cells\": [10, 2, 2]}}," \
             " \"material\": {\"model\": \"neohookean\", \"young\": 5e6, \"poisson\": 0.45, \"density\": 1000}," \
             " \"fixed\": [{\"box\": [[-1, -1, -1], [0.5, 2, 2]]}]}]," \
             " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": 0.01, \"duration\": 0.3}, \"rom\": "

TEST(the_toy_method_parses_its_own_keys_and_only_its_own)
{
    rk_error err;
    rk_scene s;
    CHECK_OK(rk_scene_parse(BEAM "{\"method\": \"toy\", \"size\": 3, \"toy_gain\": 0.5}}", "toy.json", &s, &err));
    CHECK(s.entries[0].method == &toy && !strcmp(s.entries[0].name, "toy-3"), "method %s, name %s",
          s.entries[0].method->name, s.entries[0].name);
    const toy_options *t = rk_method_options(&s.entries[0], &toy);
    CHECK(t && t->gain == 0.5, "gain %g", t ? t->gain : NAN);
    rk_baked b;
    rk_bake_request req = {0};
    CHECK(rk_scene_bake(&s, &s.entries[0], &req, &b, &err) && strstr(err.msg, "the toy method has no asset"),
          "bake: %s", err.msg);
    rk_scene_free(&s);
    CHECK(rk_scene_parse(BEAM "{\"basis\": \"modes\", \"size\": 3, \"toy_gain\": 0.5}}", "toy.json", &s, &err) &&
              strstr(err.msg, "toy.json: rom: toy_gain is a key of method toy"),
          "a fixed entry with the toy's key: %s", err.msg);
    CHECK(rk_scene_parse(BEAM "{\"method\": \"toy\", \"size\": 3, \"toy_gain\": 2}}", "toy.json", &s, &err) &&
              strstr(err.msg, "toy.json: rom: toy_gain must be in [0, 1]"),
          "gain 2: %s", err.msg);
    CHECK(rk_scene_parse(BEAM "{\"method\": \"toys\", \"size\": 3}}", "toy.json", &s, &err) &&
              strstr(err.msg, "\"adaptive_linear\" or \"toy\", got \"toys\""),
          "unknown method: %s", err.msg);
}

TEST(compare_runs_the_toy_through_the_table_beside_a_builtin_method)
{
    rk_error err;
    rk_scene s;
    rk_compare_result res;
    CHECK_OK(rk_scene_parse(BEAM "[{\"method\": \"toy\", \"size\": 1}, {\"method\": \"toy\", \"size\": 2, \"toy_gain\": 1},"
                            " {\"basis\": \"modes\", \"size\": 6}]}", "toy.json", &s, &err));
    toy_entries_seen = -1;
    CHECK_OK(rk_compare_scene(&s, &res, &err));
    rk_scene_free(&s);
    CHECK(res.nmethods == 3, "%d methods", res.nmethods);
    if (res.nmethods != 3) return;
    const rk_compare_method *hold = &res.methods[0], *extrapolate = &res.methods[1], *modes = &res.methods[2];
    for (int k = 0; k < 3; k++)
        printf("# %-12s %-8s nMSE %.3e online %.3e speed-up %.3g %s\n", res.methods[k].name,
               res.methods[k].method->kind, res.methods[k].normalized_mse, res.methods[k].relative_online_error,
               res.methods[k].speedup, res.methods[k].failure);
    CHECK(hold->method == &toy && extrapolate->method == &toy && !hold->failure[0] && !extrapolate->failure[0],
          "toy entries: %s / %s", hold->failure, extrapolate->failure);
    CHECK(toy_entries_seen == 2, "the toy's cache saw %d entries, expected 2 (one cache for both)", toy_entries_seen);
    /* the beam sags: holding the start is wrong, and extrapolating a smooth motion beats holding
     * each frame; the speed-up is computed by compare from the toy's step time */
    CHECK(hold->normalized_mse > 0 && isfinite(hold->normalized_mse), "hold nMSE %g", hold->normalized_mse);
    CHECK(hold->normalized_mse == extrapolate->normalized_mse, "the free runs differ: %g %g", hold->normalized_mse,
          extrapolate->normalized_mse);
    CHECK(extrapolate->relative_online_error < 0.5 * hold->relative_online_error, "online: gain 1 %g, gain 0 %g",
          extrapolate->relative_online_error, hold->relative_online_error);
    CHECK(fabs(hold->speedup * 1e-9 / res.fom_seconds_per_step - 1) < 1e-12, "speed-up %g", hold->speedup);
    CHECK(modes->method->kind && !strcmp(modes->method->kind, "reduced") && !modes->failure[0] &&
              modes->normalized_mse < hold->normalized_mse,
          "modes-6 nMSE %g against holding the start %g (%s)", modes->normalized_mse, hold->normalized_mse,
          modes->failure);
    rk_compare_result_free(&res);
}

int main(void)
{
    rk_method_register(&toy); /* the one line that adds the method */
    RUN(the_toy_method_parses_its_own_keys_and_only_its_own);
    RUN(compare_runs_the_toy_through_the_table_beside_a_builtin_method);
    return test_finish();
}
