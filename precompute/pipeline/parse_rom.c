/* The scene's "rom" section (an object, or a list of them) into rk_rom_entry: the basis keys, the
 * cubature, the Koopman section, the asset keys (parse_asset.c), the name, the method and a
 * published reference number. Each key lands in the option struct of the stage that uses it. */
#include "pipeline/parse_impl.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static int parse_basis(const rk_json_ctx *c, const cJSON *e, const char *path, int method, rk_basis_options *o)
{
    const char *name = NULL;
    /* an adaptive subspace's candidates are skinning eigenmodes unless the entry says otherwise (Sec. 4) */
    if (rk_json_string(c, e, path, "basis", method == RK_METHOD_FIXED, &name)) return -1;
    if (!name) name = "skinning";
    rk_basis_default_options(o);
    if (rk_basis_type_parse(name, &o->type))
        return rk_json_fail(c, path, "basis must be modes, modal_derivatives, skinning, rkpm_skinning "
                            "or pod, got \"%s\"", name);
    double tol = 0;
    if (rk_json_whole(c, e, path, "size", 0, 4096, &o->size) || rk_json_number(c, e, path, "tolerance", 0, &tol) ||
        rk_json_whole(c, e, path, "modes", 0, 60, &o->modes) ||
        rk_json_whole(c, e, path, "kernels", 4, 100000, &o->kernels) ||
        rk_json_whole(c, e, path, "integration_points", 100, 1e7, &o->integration_points))
        return -1;
    if (!(tol >= 0 && tol < 1)) return rk_json_fail(c, path, "tolerance must be in (0, 1), got %g", tol);
    if (o->size == 0 && tol == 0)
        return rk_json_fail(c, path, "needs size (how many columns or weights) or tolerance (the "
                            "largest relative error of the scene's full-order frames)");
    o->tolerance = tol;
    return 0;
}

static int parse_cubature(const rk_json_ctx *c, const cJSON *e, const char *path, rk_rom_entry *o)
{
    char cpath[128];
    const cJSON *cub = rk_json_child(e, path, "cubature", cpath, sizeof cpath);
    rk_cubature_default_options(&o->cub);
    o->cubature = cub != NULL;
    if (!cub) return 0;
    if (!cJSON_IsObject(cub)) return rk_json_fail(c, cpath, "must be an object");
    static const char *const keys[] = {"tolerance", "max_points", "poses", "sample", "prune", NULL};
    if (rk_json_check_keys(c, cub, cpath, keys)) return -1;
    double tol = o->cub.tolerance;
    if (rk_json_number(c, cub, cpath, "tolerance", 0, &tol) ||
        rk_json_whole(c, cub, cpath, "max_points", 0, 1e7, &o->cub.max_points) ||
        rk_json_whole(c, cub, cpath, "poses", 1, 10000, &o->cub.poses) ||
        rk_json_whole(c, cub, cpath, "sample", 0, 1e7, &o->cub.sample) ||
        rk_json_bool(c, cub, cpath, "prune", &o->cub.prune))
        return -1;
    if (!(tol > 0 && tol < 1)) return rk_json_fail(c, cpath, "tolerance must be in (0, 1), got %g", tol);
    o->cub.tolerance = tol;
    return 0;
}

static int parse_mesh_free(const rk_json_ctx *c, const cJSON *e, const char *path, rk_rom_entry *o)
{
    char mpath[128];
    const cJSON *mf = rk_json_child(e, path, "mesh_free", mpath, sizeof mpath);
    o->mesh_free = (rk_mesh_free_options){0, RK_SAMPLING_GRID, 0, 5000, 1, 0};
    if (!mf) return 0;
    if (cJSON_IsFalse(mf)) return 0;
    o->mesh_free.enabled = 1;
    if (o->basis.type != RK_BASIS_RKPM_SKINNING)
        return rk_json_fail(c, mpath, "needs basis rkpm_skinning (its weights have gradients anywhere), not %s",
                            rk_basis_type_name(o->basis.type));
    if (cJSON_IsTrue(mf)) return 0;
    if (!cJSON_IsObject(mf)) return rk_json_fail(c, mpath, "must be true, false or an object");
    static const char *const keys[] = {"sampling", "points", "seed", "volume", NULL};
    const char *sampling = NULL;
    double seed = 1;
    if (rk_json_check_keys(c, mf, mpath, keys) || rk_json_string(c, mf, mpath, "sampling", 0, &sampling) ||
        rk_json_whole(c, mf, mpath, "points", 4, 1e7, &o->mesh_free.points) ||
        rk_json_number(c, mf, mpath, "seed", 0, &seed) || rk_json_number(c, mf, mpath, "volume", 0, &o->mesh_free.volume))
        return -1;
    if (o->mesh_free.volume < 0 || !isfinite(o->mesh_free.volume))
        return rk_json_fail(c, mpath, "volume (m^3) must be positive, got %g", o->mesh_free.volume);
    if (!(seed >= 0 && seed < 9007199254740992.0 && seed == floor(seed)))
        return rk_json_fail(c, mpath, "seed must be a whole number from 0 to 2^53, got %g", seed);
    o->mesh_free.seed = (unsigned long long)seed;
    o->mesh_free.sampling_given = sampling != NULL;
    if (!sampling || !strcmp(sampling, "grid")) o->mesh_free.sampling = RK_SAMPLING_GRID;
    else if (!strcmp(sampling, "random")) o->mesh_free.sampling = RK_SAMPLING_RANDOM;
    else if (!strcmp(sampling, "cloud")) o->mesh_free.sampling = RK_SAMPLING_CLOUD, o->basis.from_vertices = 1;
    else return rk_json_fail(c, mpath, "sampling must be grid, random or cloud, got \"%s\"", sampling);
    return 0;
}

static int parse_reference(const rk_json_ctx *c, const cJSON *e, const char *path, rk_rom_entry *o)
{
    char rpath[128];
    const cJSON *ref = rk_json_child(e, path, "reference", rpath, sizeof rpath);
    o->reference_nmse = NAN;
    o->reference_source[0] = 0;
    if (!ref) return 0;
    static const char *const keys[] = {"normalized_mse", "source", NULL};
    if (!cJSON_IsObject(ref)) return rk_json_fail(c, rpath, "must be an object");
    if (rk_json_check_keys(c, ref, rpath, keys) || rk_json_number(c, ref, rpath, "normalized_mse", 1, &o->reference_nmse))
        return -1;
    const char *src = NULL;
    if (rk_json_string(c, ref, rpath, "source", 0, &src)) return -1;
    if (src) snprintf(o->reference_source, sizeof o->reference_source, "%s", src);
    return 0;
}

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
static int parse_koopman(const rk_json_ctx *c, const cJSON *e, const char *path, double h, rk_rom_entry *o)
{
    char kpath[64];
    rk_koopman_entry *ko = &o->koop;
    memset(ko, 0, sizeof *ko);
    rk_koopman_default_options(&ko->fit);
    ko->fit.h = h;
    const cJSON *k = rk_json_child(e, path, "koopman", kpath, sizeof kpath);
    o->koopman = k != NULL;
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

static int parse_method(const rk_json_ctx *c, const cJSON *e, const char *path, rk_rom_entry *o)
{
    const char *method = NULL;
    if (rk_json_string(c, e, path, "method", 0, &method)) return -1;
    o->method = RK_METHOD_FIXED;
    if (!method || strcmp(method, "fixed") == 0) return 0;
    if (strcmp(method, "adaptive_subspace") == 0) {
        o->method = RK_METHOD_ADAPTIVE_SUBSPACE;
        return 0;
    }
    if (strcmp(method, "adaptive_linear") == 0) {
        o->method = RK_METHOD_ADAPTIVE_LINEAR;
        return 0;
    }
    return rk_json_fail(c, path, "method must be \"fixed\", \"adaptive_subspace\" or \"adaptive_linear\", got \"%s\"",
                        method);
}

/* The adaptive subspace method's keys (adaptive.h; the paper's Table 2 names them). */
static int parse_adaptive(const rk_json_ctx *c, const cJSON *e, const char *path, rk_rom_entry *o)
{
    rk_adaptive_options *a = &o->adaptive;
    rk_adaptive_default_options(a);
    o->adaptive_initial_size = 0;
    if (o->method != RK_METHOD_ADAPTIVE_SUBSPACE) return 0;
    if (cJSON_HasObjectItem(e, "cubature") || cJSON_HasObjectItem(e, "koopman") ||
        cJSON_HasObjectItem(e, "mesh_free") || cJSON_HasObjectItem(e, "tolerance"))
        return rk_json_fail(c, path, "method adaptive_subspace takes a candidate basis by size, with no cubature, "
                            "koopman, mesh_free or tolerance (it integrates every element)");
    const char *hessian = NULL;
    if (rk_json_number(c, e, path, "eps_g_modal", 0, &a->eps_g_modal) ||
        rk_json_number(c, e, path, "eps_g_nodal", 0, &a->eps_g_nodal) ||
        rk_json_number(c, e, path, "eps_e", 0, &a->eps_e) || rk_json_number(c, e, path, "eps_d", 0, &a->eps_d) ||
        rk_json_whole(c, e, path, "subdomains", 0, 1e7, &a->subdomains) ||
        rk_json_whole(c, e, path, "initial_size", 0, 1e6, &o->adaptive_initial_size) ||
        rk_json_bool(c, e, path, "downdate", &a->downdate) || rk_json_bool(c, e, path, "modal", &a->modal) ||
        rk_json_bool(c, e, path, "nodal", &a->nodal) || rk_json_number(c, e, path, "pcg_tol", 0, &a->pcg_tol) ||
        rk_json_string(c, e, path, "hessian", 0, &hessian))
        return -1;
    static const char *const positive[4] = {"eps_g_modal", "eps_g_nodal", "eps_d", "pcg_tol"};
    double values[4] = {a->eps_g_modal, a->eps_g_nodal, a->eps_d, a->pcg_tol};
    for (int k = 0; k < 4; k++)
        if (!(values[k] > 0) || !isfinite(values[k]))
            return rk_json_fail(c, path, "%s must be a positive number, got %g", positive[k], values[k]);
    if (a->pcg_tol >= 1) return rk_json_fail(c, path, "pcg_tol must be below 1, got %g", a->pcg_tol);
    if (!isfinite(a->eps_e)) return rk_json_fail(c, path, "eps_e must be finite, got %g", a->eps_e);
    if (hessian && strcmp(hessian, "bfgs") && strcmp(hessian, "exact"))
        return rk_json_fail(c, path, "hessian must be \"bfgs\" or \"exact\", got \"%s\"", hessian);
    a->exact_hessian = hessian && !strcmp(hessian, "exact");
    if (o->basis.size == 0) return rk_json_fail(c, path, "method adaptive_subspace needs size (the candidate basis)");
    return 0;
}

/* rom.training: scene files or {"scene": F} / {"snapshots": F}, resolved against the scene's folder. */
static int parse_training(const rk_json_ctx *c, const cJSON *e, const char *path, const char *scene_path,
                          rk_rom_entry *o)
{
    char tpath[128];
    const cJSON *list = rk_json_child(e, path, "training", tpath, sizeof tpath);
    o->ntraining = 0;
    if (!list) return 0;
    if (!cJSON_IsArray(list) || cJSON_GetArraySize(list) < 1 || cJSON_GetArraySize(list) > RK_MAX_TRAINING)
        return rk_json_fail(c, tpath, "must be a list of 1 to %d scene or snapshot files", RK_MAX_TRAINING);
    char dir[1024];
    snprintf(dir, sizeof dir, "%s", scene_path);
    char *slash = strrchr(dir, '/');
    if (slash) *slash = 0;
    else dir[0] = 0;
    for (int i = 0; i < cJSON_GetArraySize(list); i++) {
        const cJSON *it = cJSON_GetArrayItem(list, i);
        char ip[160];
        snprintf(ip, sizeof ip, "%s[%d]", tpath, i);
        const char *file = NULL;
        int snapshots = 0;
        if (cJSON_IsString(it)) {
            file = it->valuestring;
        } else if (cJSON_IsObject(it)) {
            static const char *const keys[] = {"scene", "snapshots", NULL};
            const char *sc = NULL, *sn = NULL;
            if (rk_json_check_keys(c, it, ip, keys) || rk_json_string(c, it, ip, "scene", 0, &sc) ||
                rk_json_string(c, it, ip, "snapshots", 0, &sn))
                return -1;
            if ((sc != NULL) == (sn != NULL)) return rk_json_fail(c, ip, "needs exactly one of 'scene' or 'snapshots'");
            file = sc ? sc : sn;
            snapshots = sn != NULL;
        } else {
            return rk_json_fail(c, ip, "must be a scene file name or an object {\"scene\": ...} or {\"snapshots\": ...}");
        }
        if (!file[0]) return rk_json_fail(c, ip, "names no file");
        o->training[i].snapshots = snapshots;
        if (file[0] == '/' || !dir[0]) snprintf(o->training[i].file, sizeof o->training[i].file, "%s", file);
        else snprintf(o->training[i].file, sizeof o->training[i].file, "%s/%s", dir, file);
        o->ntraining++;
    }
    if (o->method == RK_METHOD_FIXED && o->basis.type != RK_BASIS_POD)
        return rk_json_fail(c, tpath, "is for what trains on full-order runs: basis pod or method adaptive_linear");
    return 0;
}

/* The adaptive linear ROM's keys (grassmann.h; the paper's r, m, lambda). */
static int parse_alrom(const rk_json_ctx *c, const cJSON *e, const char *path, rk_rom_entry *o)
{
    rk_alrom_default_options(&o->alrom);
    if (o->method != RK_METHOD_ADAPTIVE_LINEAR) return 0;
    if (cJSON_HasObjectItem(e, "koopman") || cJSON_HasObjectItem(e, "mesh_free") ||
        cJSON_HasObjectItem(e, "tolerance") || cJSON_HasObjectItem(e, "basis"))
        return rk_json_fail(c, path, "method adaptive_linear takes size (r), history, lambda, decoder and cubature; no "
                            "basis, tolerance, koopman or mesh_free");
    const char *decoder = NULL;
    if (rk_json_whole(c, e, path, "history", 1, 10000, &o->alrom.history) ||
        rk_json_number(c, e, path, "lambda", 0, &o->alrom.lambda) || rk_json_string(c, e, path, "decoder", 0, &decoder))
        return -1;
    if (!(o->alrom.lambda >= 0 && o->alrom.lambda <= 1))
        return rk_json_fail(c, path, "lambda must be in [0, 1], got %g", o->alrom.lambda);
    if (decoder && strcmp(decoder, "quadratic") && strcmp(decoder, "quadratic_pod") && strcmp(decoder, "crom"))
        return rk_json_fail(c, path, "decoder must be \"quadratic\", \"quadratic_pod\" or \"crom\", got \"%s\"", decoder);
    o->crom = decoder && !strcmp(decoder, "crom");
    o->quadratic_pod = decoder && !strcmp(decoder, "quadratic_pod");
    rk_crom_default_options(&o->crom_opt);
    char cpath[128];
    const cJSON *cr = rk_json_child(e, path, "crom", cpath, sizeof cpath);
    if (cr && !o->crom) return rk_json_fail(c, cpath, "is for decoder \"crom\"");
    if (cr) {
        static const char *const keys[] = {"encoder_width", "encoder_layers", "decoder_width", "decoder_layers",
                                           "epochs", "snapshots_per_batch", "points", "base_lr", "seed", NULL};
        rk_crom_options *co = &o->crom_opt;
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

static int parse_name(const rk_json_ctx *c, const cJSON *e, const char *path, rk_rom_entry *o)
{
    const char *name = NULL;
    if (rk_json_string(c, e, path, "name", 0, &name)) return -1;
    if (name && (!*name || strlen(name) >= sizeof o->name))
        return rk_json_fail(c, path, "name must have 1 to %zu characters", sizeof o->name - 1);
    if (name) {
        snprintf(o->name, sizeof o->name, "%s", name);
        return 0;
    }
    if (o->method == RK_METHOD_ADAPTIVE_SUBSPACE || o->method == RK_METHOD_ADAPTIVE_LINEAR) {
        snprintf(o->name, sizeof o->name, "%s-%d", o->method == RK_METHOD_ADAPTIVE_LINEAR ? "adaptive_linear" : "adaptive_subspace",
                 o->basis.size);
        return 0;
    }
    const char *type = rk_basis_type_name(o->basis.type), *cub = o->cubature ? "-cubature" : "";
    const char *mf = !o->mesh_free.enabled                             ? ""
                     : o->mesh_free.sampling == RK_SAMPLING_RANDOM ? "-meshfree-random"
                     : o->mesh_free.sampling == RK_SAMPLING_CLOUD  ? "-cloud"
                                                                   : "-meshfree";
    if (o->basis.size) snprintf(o->name, sizeof o->name, "%s-%d%s%s", type, o->basis.size, mf, cub);
    else snprintf(o->name, sizeof o->name, "%s-tol%g%s%s", type, o->basis.tolerance, mf, cub);
    return 0;
}

static int parse_entry(const rk_json_ctx *c, const cJSON *e, const char *path, double h, const char *scene_path,
                       rk_rom_entry *o)
{
    if (!cJSON_IsObject(e)) return rk_json_fail(c, path, "must be an object");
    static const char *const keys[] = {"basis", "size", "tolerance", "modes", "kernels", "integration_points",
                                       "cubature", "koopman", "name", "reference", "asset", "method", "mesh_free",
                                       "eps_g_modal", "eps_g_nodal", "eps_e", "eps_d", "subdomains", "initial_size",
                                       "downdate", "modal", "nodal", "hessian", "pcg_tol", "history", "lambda",
                                       "decoder", "crom", "training", "pin_stiffness", NULL};
    static const char *const adaptive_keys[] = {"eps_g_modal", "eps_g_nodal", "eps_e", "eps_d", "subdomains",
                                                "initial_size", "downdate", "modal", "nodal", "hessian", "pcg_tol", NULL};
    snprintf(o->path, sizeof o->path, "%s", path);
    if (rk_json_check_keys(c, e, path, keys) || parse_method(c, e, path, o)) return -1;
    if (o->method != RK_METHOD_ADAPTIVE_SUBSPACE)
        for (int k = 0; adaptive_keys[k]; k++)
            if (cJSON_HasObjectItem(e, adaptive_keys[k]))
                return rk_json_fail(c, path, "%s is a key of method adaptive_subspace", adaptive_keys[k]);
    static const char *const alrom_keys[] = {"history", "lambda", "decoder", "crom", NULL};
    if (o->method != RK_METHOD_ADAPTIVE_LINEAR)
        for (int k = 0; alrom_keys[k]; k++)
            if (cJSON_HasObjectItem(e, alrom_keys[k]))
                return rk_json_fail(c, path, "%s is a key of method adaptive_linear", alrom_keys[k]);
    if (o->method == RK_METHOD_ADAPTIVE_LINEAR && cJSON_HasObjectItem(e, "basis"))
        return rk_json_fail(c, path, "method adaptive_linear takes size (r), history, lambda and decoder; no basis");
    if (o->method != RK_METHOD_FIXED && cJSON_HasObjectItem(e, "pin_stiffness"))
        return rk_json_fail(c, path, "pin_stiffness is a key of method fixed (the fixed-basis reduced simulator's "
                            "penalty on prescribed vertices)");
    if (rk_json_number(c, e, path, "pin_stiffness", 0, &o->pin_stiffness)) return -1;
    if (cJSON_HasObjectItem(e, "pin_stiffness") && !(o->pin_stiffness > 0 && o->pin_stiffness <= 1e12))
        return rk_json_fail(c, path, "pin_stiffness must be a number in (0, 1e12] (units of (lambda + 2 mu) / "
                            "(rho L^2); default %g), got %g", RK_ROM_PIN_STIFFNESS, o->pin_stiffness);
    return parse_basis(c, e, path, o->method, &o->basis) || parse_adaptive(c, e, path, o) || parse_alrom(c, e, path, o) ||
                   parse_training(c, e, path, scene_path, o) ||
                   parse_cubature(c, e, path, o) || parse_mesh_free(c, e, path, o) || parse_koopman(c, e, path, h, o) ||
                   parse_reference(c, e, path, o) || rk_parse_asset(c, e, path, &o->asset) || parse_name(c, e, path, o)
               ? -1
               : 0;
}

int rk_parse_rom(const rk_json_ctx *c, const cJSON *rom, rk_scene *s)
{
    if (!rom) return 0;
    if (!cJSON_IsObject(rom) && !cJSON_IsArray(rom))
        return rk_json_fail(c, "rom", "must be an object or an array of objects");
    int n = cJSON_IsArray(rom) ? cJSON_GetArraySize(rom) : 1;
    if (n == 0) return 0;
    s->entries = rk_calloc((size_t)n, sizeof *s->entries, c->err);
    if (!s->entries) return -1;
    s->nentries = n;
    for (int i = 0; i < n; i++) {
        char path[32];
        snprintf(path, sizeof path, cJSON_IsArray(rom) ? "rom[%d]" : "rom", i);
        s->entries[i].index = i;
        if (parse_entry(c, cJSON_IsArray(rom) ? cJSON_GetArrayItem(rom, i) : rom, path, s->h, s->path, &s->entries[i]))
            return -1;
    }
    return 0;
}
