/* The Koopman method as a module (method.h): an entry with a "koopman" section. Its keys, its run
 * beside full order (koopman_compare.c), its bake (the operator, and a reduced model beside it when
 * the entry has a cubature: method_fixed.c's bake), its report rows. */
#include "pipeline/method_koopman.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "pipeline/method_fixed.h"
#include "pipeline/parse_impl.h"

_Static_assert(sizeof(rk_koopman_entry) <= RK_METHOD_OWN_BYTES, "options fit the entry's block");
_Static_assert(sizeof(rk_koopman_measures) <= RK_COMPARE_OWN_BYTES, "measures fit the result's block");

int rk_koopman_compare(rk_compare_ctx *c, const rk_rom_entry *e, rk_compare_method *m, rk_error *err);

static int parse_trajectories(const rk_json_ctx *c, const cJSON *k, const char *path, rk_koopman_entry *o)
{
    char tpath[96];
    const cJSON *list = rk_json_child(k, path, "trajectories", tpath, sizeof tpath);
    if (!list) return 0;
    if (!cJSON_IsArray(list) || cJSON_GetArraySize(list) < 1 || cJSON_GetArraySize(list) > RK_KOOPMAN_MAX_TRAJECTORIES)
        return rk_json_fail(c, tpath, "must be a list of 1 to %d trajectories", RK_KOOPMAN_MAX_TRAJECTORIES);
    static const char *const tkeys[] = {"gravity", "velocity", "load_scale", NULL};
    o->ntraj = cJSON_GetArraySize(list);
    for (int i = 0; i < o->ntraj; i++) {
        const cJSON *t = cJSON_GetArrayItem(list, i);
        rk_koopman_variation *v = &o->traj[i];
        char p[128];
        snprintf(p, sizeof p, "%s[%d]", tpath, i);
        if (!cJSON_IsObject(t)) return rk_json_fail(c, p, "must be an object");
        v->load_scale = 1;
        v->has_gravity = cJSON_HasObjectItem(t, "gravity");
        v->has_velocity = cJSON_HasObjectItem(t, "velocity");
        if (rk_json_check_keys(c, t, p, tkeys) || rk_json_vector(c, t, p, "gravity", 0, 3, v->gravity) ||
            rk_json_vector(c, t, p, "velocity", 0, 3, v->velocity) ||
            rk_json_number(c, t, p, "load_scale", 0, &v->load_scale))
            return -1;
    }
    return 0;
}

/* rom[i].koopman (pipeline.h, rk_koopman_entry); h is the scene's time step. */
static int parse(const rk_json_ctx *c, const cJSON *e, const char *path, double h, rk_rom_entry *o)
{
    char kpath[64];
    rk_koopman_entry *ko = (rk_koopman_entry *)o->own;
    memset(ko, 0, sizeof *ko);
    rk_koopman_default_options(&ko->fit);
    ko->fit.h = h;
    const cJSON *k = rk_json_child(e, path, "koopman", kpath, sizeof kpath);
    if (!k) return 0;
    if (!cJSON_IsObject(k)) return rk_json_fail(c, kpath, "must be an object");
    static const char *const keys[] = {"rank", "energy", "clamp", "balance", "project", "trajectories", NULL};
    int balance = 1;
    if (rk_json_check_keys(c, k, kpath, keys) ||
        rk_json_whole(c, k, kpath, "rank", 0, 4096, &ko->fit.rank) /* 0: by energy */ ||
        rk_json_number(c, k, kpath, "energy", 0, &ko->fit.energy) || rk_json_bool(c, k, kpath, "clamp", &ko->fit.clamp) ||
        rk_json_bool(c, k, kpath, "balance", &balance) ||
        rk_json_bool(c, k, kpath, "project", &ko->project))
        return -1;
    if (!(ko->fit.energy > 0 && ko->fit.energy <= 1))
        return rk_json_fail(c, kpath, "energy must be in (0, 1], got %g", ko->fit.energy);
    ko->fit.unbalanced = !balance;
    return parse_trajectories(c, k, kpath, ko);
}


static void report(const rk_compare_method *m, cJSON *j)
{
    cJSON *k = cJSON_AddObjectToObject(j, "koopman");
    cJSON_AddNumberToObject(k, "rank", m->r);
    cJSON_AddNumberToObject(k, "max_abs_eigenvalue", ((const rk_koopman_measures *)(const void *)m->own)->max_abs_eigenvalue);
}

const rk_method rk_method_koopman = {
    .name = "koopman",
    .kind = "koopman",
    .implied_by = "koopman",
    .basis_required = 1,
    .training_needs_pod = 1,
    .reduced_model = 1,
    .table_cubature = "dmd",
    .parse = parse,
    .default_name = rk_method_basis_name,
    .compare = rk_koopman_compare,
    .bake = rk_method_bake_models,
    .report = report,
};

const rk_koopman_entry *rk_koopman_of(const rk_rom_entry *e)
{
    return rk_method_options(e, &rk_method_koopman);
}
