/* The scene's "rom" section (an object, or a list of them) into rk_rom_entry: the method (its own
 * keys go to its module's parse, method.h), the basis keys, the cubature, the asset keys
 * (parse_asset.c), the name and a published reference number. Each key lands in the option struct
 * of the stage that uses it. */
#include "pipeline/parse_impl.h"

#include "pipeline/method.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static int parse_basis(const rk_json_ctx *c, const cJSON *e, const char *path, const rk_method *m, rk_basis_options *o)
{
    const char *name = NULL;
    /* an adaptive subspace's candidates are skinning eigenmodes unless the entry says otherwise (Sec. 4) */
    if (rk_json_string(c, e, path, "basis", m->basis_required, &name)) return -1;
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
    const char *clamp = NULL;
    if (rk_json_string(c, e, path, "clamp", 0, &clamp)) return -1;
    if (clamp && strcmp(clamp, "dirichlet") && strcmp(clamp, "penalty") && strcmp(clamp, "lifted"))
        return rk_json_fail(c, path, "clamp must be \"dirichlet\" (skinning weights vanish on the fixed region), "
                            "\"penalty\" (free weights, the fixed vertices held by pin_stiffness) or \"lifted\" "
                            "(as dirichlet, and the moving group held exactly by a lifting handle), got \"%s\"", clamp);
    o->clamp_penalty = clamp && !strcmp(clamp, "penalty");
    o->clamp_lifted = clamp && !strcmp(clamp, "lifted");
    if (o->clamp_lifted && o->type != RK_BASIS_RKPM_SKINNING)
        return rk_json_fail(c, path, "clamp \"lifted\" is for basis rkpm_skinning only (not yet for %s)",
                            rk_basis_type_name(o->type));
    if (o->clamp_lifted && tol > 0)
        return rk_json_fail(c, path, "clamp \"lifted\" takes size, not tolerance (a tolerance would cut "
                            "the lifting handle off)");
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
    static const char *const keys[] = {"tolerance", "max_points", "poses", "sample", "prune", "vertex_cost", NULL};
    if (rk_json_check_keys(c, cub, cpath, keys)) return -1;
    double tol = o->cub.tolerance;
    if (rk_json_number(c, cub, cpath, "tolerance", 0, &tol) ||
        rk_json_whole(c, cub, cpath, "max_points", 0, 1e7, &o->cub.max_points) ||
        rk_json_whole(c, cub, cpath, "poses", 1, 10000, &o->cub.poses) ||
        rk_json_whole(c, cub, cpath, "sample", 0, 1e7, &o->cub.sample) ||
        rk_json_bool(c, cub, cpath, "prune", &o->cub.prune) ||
        rk_json_number(c, cub, cpath, "vertex_cost", 0, &o->cub.vertex_cost))
        return -1;
    if (!(o->cub.vertex_cost >= 0 && o->cub.vertex_cost <= 1e6))
        return rk_json_fail(c, cpath, "vertex_cost must be in [0, 1e6], got %g", o->cub.vertex_cost);
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
    if (o->method->training_needs_pod && o->basis.type != RK_BASIS_POD)
        return rk_json_fail(c, tpath, "is for what trains on full-order runs: basis pod or method adaptive_linear");
    return 0;
}

/* rom[i].method: a method by name (methods.c), "fixed" when absent; an entry of method fixed with a
 * key that implies a method (a koopman section) is that method. */
static int parse_method(const rk_json_ctx *c, const cJSON *e, const char *path, rk_rom_entry *o)
{
    const char *name = NULL;
    if (rk_json_string(c, e, path, "method", 0, &name)) return -1;
    const rk_method *m = rk_method_find(name ? name : "fixed");
    if (!m) {
        char list[512] = "";
        size_t len = 0;
        int n = 0, named = 0;
        for (int i = 0; i < rk_method_count(); i++) named += rk_method_at(i)->implied_by == NULL;
        for (int i = 0; i < rk_method_count(); i++) {
            const rk_method *k = rk_method_at(i);
            if (k->implied_by) continue;
            n++;
            len += (size_t)snprintf(list + len, sizeof list - len, "%s\"%s\"", n == 1 ? "" : n == named ? " or " : ", ",
                                    k->name);
            if (len >= sizeof list) break;
        }
        return rk_json_fail(c, path, "method must be %s, got \"%s\"", list, name);
    }
    if (m == rk_method_find("fixed"))
        for (int i = 0; i < rk_method_count(); i++)
            if (rk_method_at(i)->implied_by && cJSON_HasObjectItem(e, rk_method_at(i)->implied_by)) m = rk_method_at(i);
    o->method = m;
    memset(o->own, 0, sizeof o->own);
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
    if (o->method->default_name) o->method->default_name(o, o->name, sizeof o->name);
    else snprintf(o->name, sizeof o->name, "%s-%d", o->method->name, o->basis.size);
    return 0;
}

/* rom.volume ("projected" or "pointwise") and rom.pressure ("weights", the default, "constant" or
 * "weights_affine"; given alone, it implies "projected"): cubature.h. Without either, a skinning
 * basis (skinning, rkpm_skinning) gets the projected volume on its weights (issue 37), which does
 * not lock: the FreeForm beam at nu = 0.45 sags 96-101% of the converged solid from m = 9 to 32,
 * the pointwise volume 77-93% (m = 6: 113% against 45%; docs/results/volume_sag.md and
 * docs/methods.md say why no pressure space does better there). At lambda = 0 it is the pointwise
 * energy bit for bit, so one default serves every nu. The column bases (modes, modal_derivatives,
 * pod) keep the pointwise volume: their pressure space would be the constant alone, which leaves
 * the deviatoric part only (the beam sags 148%); so does clamp "lifted", whose lifting handle the
 * pressure weights cannot take yet (pipeline/volume.c). romkit compare says when its linear-tet
 * reference locks (compare.c, reference_locking). Called after parse_basis (the basis type). */
static int parse_volume(const rk_json_ctx *c, const cJSON *e, const char *path, rk_rom_entry *o)
{
    static const char *const volumes[] = {"projected", "pointwise", NULL}, *const spaces[] = {"weights", "constant", "weights_affine", NULL};
    const char *v = NULL, *p = NULL;
    int skinning = o->basis.type == RK_BASIS_SKINNING || o->basis.type == RK_BASIS_RKPM_SKINNING;
    o->volume = o->method->reduced_model && skinning && !o->basis.clamp_lifted ? RK_VOLUME_PROJECTED : RK_VOLUME_POINTWISE;
    o->pressure = RK_PRESSURE_WEIGHTS;
    if (rk_json_string(c, e, path, "volume", 0, &v) || rk_json_string(c, e, path, "pressure", 0, &p)) return -1;
    if ((v || p) && !o->method->reduced_model)
        return rk_json_fail(c, path, "%s is a key of method fixed (the fixed-basis reduced simulator's elastic energy)",
                            v ? "volume" : "pressure");
    if (v) {
        int k = 0;
        while (volumes[k] && strcmp(volumes[k], v)) k++;
        if (!volumes[k]) return rk_json_fail(c, path, "volume must be \"projected\" or \"pointwise\", got \"%s\"", v);
        o->volume = k;
    }
    if (p) {
        int k = 0;
        while (spaces[k] && strcmp(spaces[k], p)) k++;
        if (!spaces[k])
            return rk_json_fail(c, path, "pressure must be \"weights\", \"constant\" or \"weights_affine\", got \"%s\"", p);
        if (v && o->volume != RK_VOLUME_PROJECTED) return rk_json_fail(c, path, "pressure needs volume \"projected\"");
        o->volume = RK_VOLUME_PROJECTED; /* a pressure space given asks for the projection */
        o->pressure = k;
    }
    return 0;
}

static int parse_entry(const rk_json_ctx *c, const cJSON *e, const char *path, double h, const char *scene_path,
                       rk_rom_entry *o)
{
    if (!cJSON_IsObject(e)) return rk_json_fail(c, path, "must be an object");
    /* the keys every entry may have, then each method's own */
    static const char *const common[] = {"basis", "size", "tolerance", "modes", "kernels", "integration_points",
                                         "cubature", "koopman", "name", "reference", "asset", "method", "mesh_free",
                                         "training", "pin_stiffness", "clamp", "volume", "pressure", NULL};
    const char *keys[160];
    int n = 0;
    for (int k = 0; common[k]; k++) keys[n++] = common[k];
    for (int i = 0; i < rk_method_count(); i++)
        for (const char *const *k = rk_method_at(i)->keys; k && *k && n < 159; k++) keys[n++] = *k;
    keys[n] = NULL;
    snprintf(o->path, sizeof o->path, "%s", path);
    if (rk_json_check_keys(c, e, path, keys) || parse_method(c, e, path, o)) return -1;
    for (int i = 0; i < rk_method_count(); i++) {
        const rk_method *m = rk_method_at(i);
        for (const char *const *k = m->keys; m != o->method && k && *k; k++)
            if (cJSON_HasObjectItem(e, *k)) return rk_json_fail(c, path, "%s is a key of method %s", *k, m->name);
    }
    if (o->method->check && o->method->check(c, e, path)) return -1;
    if (!o->method->reduced_model && cJSON_HasObjectItem(e, "pin_stiffness"))
        return rk_json_fail(c, path, "pin_stiffness is a key of method fixed (the fixed-basis reduced simulator's "
                            "penalty on prescribed vertices)");
    if (rk_json_number(c, e, path, "pin_stiffness", 0, &o->pin_stiffness)) return -1;
    if (cJSON_HasObjectItem(e, "pin_stiffness") && !(o->pin_stiffness > 0 && o->pin_stiffness <= 1e12))
        return rk_json_fail(c, path, "pin_stiffness must be a number in (0, 1e12] (units of (lambda + 2 mu) / "
                            "(rho L^2); default %g), got %g", RK_ROM_PIN_STIFFNESS, o->pin_stiffness);
    if (parse_basis(c, e, path, o->method, &o->basis) || parse_volume(c, e, path, o)) return -1;
    return (o->method->parse && o->method->parse(c, e, path, h, o)) || parse_training(c, e, path, scene_path, o) ||
                   parse_cubature(c, e, path, o) || parse_mesh_free(c, e, path, o) ||
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
