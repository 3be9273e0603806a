/* Method adaptive_linear as a module (method.h): its keys, its run beside full order
 * (alrom_compare.c), its bake (bake_alrom.c), its report rows. */
#include "pipeline/method_adaptive_linear.h"

#include <math.h>
#include <string.h>

#include "pipeline/parse_impl.h"

_Static_assert(sizeof(rk_adaptive_linear_entry) <= RK_METHOD_OWN_BYTES, "options fit the entry's block");
_Static_assert(sizeof(rk_adaptive_linear_measures) <= RK_COMPARE_OWN_BYTES, "measures fit the result's block");

int rk_adaptive_linear_compare(rk_compare_ctx *c, const rk_rom_entry *e, rk_compare_method *m, rk_error *err);
void rk_adaptive_linear_compare_free(void *cache);

/* Checked before the shared keys: its size is r, not a basis's. */
static int check(const rk_json_ctx *c, const cJSON *e, const char *path)
{
    if (cJSON_HasObjectItem(e, "basis"))
        return rk_json_fail(c, path, "method adaptive_linear takes size (r), history, lambda and decoder; no basis");
    return 0;
}

/* The adaptive linear ROM's keys (grassmann.h; the paper's r, m, lambda). */
static int parse(const rk_json_ctx *c, const cJSON *e, const char *path, double h, rk_rom_entry *o)
{
    rk_adaptive_linear_entry *own = (rk_adaptive_linear_entry *)o->own;
    rk_alrom_default_options(&own->opt);
    if (cJSON_HasObjectItem(e, "koopman") || cJSON_HasObjectItem(e, "mesh_free") ||
        cJSON_HasObjectItem(e, "tolerance") || cJSON_HasObjectItem(e, "basis"))
        return rk_json_fail(c, path, "method adaptive_linear takes size (r), history, lambda, decoder and cubature; no "
                            "basis, tolerance, koopman or mesh_free");
    const char *decoder = NULL;
    if (rk_json_whole(c, e, path, "history", 1, 10000, &own->opt.history) ||
        rk_json_number(c, e, path, "lambda", 0, &own->opt.lambda) || rk_json_string(c, e, path, "decoder", 0, &decoder) ||
        rk_json_number(c, e, path, "ridge", 0, &own->opt.ridge) || rk_json_number(c, e, path, "budget", 0, &own->opt.budget) ||
        rk_json_whole(c, e, path, "cadence", 1, 1000, &own->opt.cadence) ||
        rk_json_whole(c, e, path, "encoder_iterations", 1, 20, &own->opt.encoder_iterations))
        return -1;
    if (!(own->opt.ridge >= 0)) return rk_json_fail(c, path, "ridge must be >= 0, got %g", own->opt.ridge);
    if (!(own->opt.budget >= 0)) return rk_json_fail(c, path, "budget must be >= 0, got %g", own->opt.budget);
    if (!(own->opt.lambda >= 0 && own->opt.lambda <= 1))
        return rk_json_fail(c, path, "lambda must be in [0, 1], got %g", own->opt.lambda);
    if (decoder && strcmp(decoder, "quadratic") && strcmp(decoder, "quadratic_pod") && strcmp(decoder, "crom"))
        return rk_json_fail(c, path, "decoder must be \"quadratic\", \"quadratic_pod\" or \"crom\", got \"%s\"", decoder);
    own->crom = decoder && !strcmp(decoder, "crom");
    own->quadratic_pod = decoder && !strcmp(decoder, "quadratic_pod");
    rk_crom_default_options(&own->crom_opt);
    char cpath[128];
    const cJSON *cr = rk_json_child(e, path, "crom", cpath, sizeof cpath);
    if (cr && !own->crom) return rk_json_fail(c, cpath, "is for decoder \"crom\"");
    if (cr) {
        static const char *const keys[] = {"encoder_width", "encoder_layers", "decoder_width", "decoder_layers",
                                           "epochs", "snapshots_per_batch", "points", "base_lr", "seed", NULL};
        rk_crom_options *co = &own->crom_opt;
        double seed = (double)co->seed;
        if (!cJSON_IsObject(cr) || rk_json_check_keys(c, cr, cpath, keys) ||
            rk_json_whole(c, cr, cpath, "encoder_width", 1, 4096, &co->encoder_width) ||
            rk_json_whole(c, cr, cpath, "encoder_layers", 1, 64, &co->encoder_layers) ||
            rk_json_whole(c, cr, cpath, "decoder_width", 1, 4096, &co->decoder_width) ||
            rk_json_whole(c, cr, cpath, "decoder_layers", 1, 64, &co->decoder_layers) ||
            rk_json_whole(c, cr, cpath, "epochs", 1, 1e6, &co->epochs) ||
            rk_json_whole(c, cr, cpath, "snapshots_per_batch", 1, 1e6, &co->snapshots_per_batch) ||
            rk_json_whole(c, cr, cpath, "points", 1, 1e8, &co->points) ||
            rk_json_number(c, cr, cpath, "base_lr", 0, &co->base_lr) || rk_json_number(c, cr, cpath, "seed", 0, &seed))
            return cJSON_IsObject(cr) ? -1 : rk_json_fail(c, cpath, "must be an object");
        if (!(co->base_lr > 0 && co->base_lr < 1)) return rk_json_fail(c, cpath, "base_lr must be in (0, 1), got %g", co->base_lr);
        if (!(seed >= 0 && seed == floor(seed))) return rk_json_fail(c, cpath, "seed must be a whole number, got %g", seed);
        co->seed = (unsigned long long)seed;
    }
    if (o->basis.size == 0) return rk_json_fail(c, path, "method adaptive_linear needs size (r, the latent coordinates)");
    return 0;
}


static void default_name(const rk_rom_entry *e, char *name, size_t size)
{
    snprintf(name, size, "adaptive_linear-%d", e->basis.size);
}

static int bake(const rk_scene *scene, const rk_rom_entry *e, const rk_bake_request *req, const rk_asset_options *ao,
                rk_baked *out, rk_error *err)
{
    if (req->snapshots)
        return rk_fail(err, "%s: method adaptive_linear trains on its entry's training list, not on --snapshots", e->path);
    return rk_scene_bake_alrom(scene, e, ao, req->training_runs, req->ntraining_runs, out, err);
}

static void report(const rk_compare_method *m, cJSON *j)
{
    const rk_adaptive_linear_measures *lm = (const void *)m->own;
    cJSON_AddNumberToObject(j, "history_share", lm->history_share);
}

static const char *const keys[] = {"history", "lambda", "ridge", "budget", "cadence", "encoder_iterations", "decoder", "crom", NULL};

const rk_method rk_method_adaptive_linear = {
    .name = "adaptive_linear",
    .kind = "adaptive_linear",
    .keys = keys,
    .measures_contact = 1,
    .check = check,
    .parse = parse,
    .default_name = default_name,
    .compare = rk_adaptive_linear_compare,
    .compare_free = rk_adaptive_linear_compare_free,
    .bake = bake,
    .report = report,
};

const rk_adaptive_linear_entry *rk_adaptive_linear_of(const rk_rom_entry *e)
{
    return rk_method_options(e, &rk_method_adaptive_linear);
}
