/* A family of meshes for the neural, shape-conditioned DMD (pipeline.h, rk_family): the family
 * file parsed strictly, each member's scene built and its full-order snapshots read and checked. */
#include "pipeline/family_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* path relative to the family file's folder (dir), unless absolute. */
static void resolve(const char *dir, const char *name, char *out, size_t size)
{
    if (name[0] == '/' || !dir[0]) snprintf(out, size, "%s", name);
    else snprintf(out, size, "%s/%s", dir, name);
}

/* "gamma": g numbers, or absent / null (g = 0). *g: -1 on entry for the first member. */
static int parse_gamma(const rk_json_ctx *c, const cJSON *it, const char *path, int *g, double *gamma)
{
    char p[512];
    const cJSON *v = rk_json_child(it, path, "gamma", p, sizeof p);
    int n = !v || cJSON_IsNull(v) ? 0 : cJSON_IsArray(v) ? cJSON_GetArraySize(v) : -1;
    if (n < 0) return rk_json_fail(c, p, "must be an array of numbers (the shape code) or null");
    if (n > RK_KOOPMAN_SHAPE_MAX) return rk_json_fail(c, p, "%d values, at most %d", n, RK_KOOPMAN_SHAPE_MAX);
    if (*g >= 0 && n != *g)
        return rk_json_fail(c, p, "%d values, the first member's gamma has %d: every member needs the same length", n,
                            *g);
    *g = n;
    return n ? rk_json_vector(c, it, path, "gamma", 1, n, gamma) : 0;
}

static int parse_member(const rk_json_ctx *c, const cJSON *it, const char *path, const char *dir, int *g,
                        rk_family_member *m)
{
    static const char *const keys[] = {"scene", "snapshots", "gamma", "held_out", NULL};
    const char *scene, *snap;
    if (rk_json_check_keys(c, it, path, keys) || rk_json_string(c, it, path, "scene", 1, &scene) ||
        rk_json_string(c, it, path, "snapshots", 1, &snap) || parse_gamma(c, it, path, g, m->gamma) ||
        rk_json_bool(c, it, path, "held_out", &m->held_out))
        return -1;
    resolve(dir, scene, m->scene, sizeof m->scene);
    resolve(dir, snap, m->snapshots, sizeof m->snapshots);
    return 0;
}

/* "network" and "training" over rk_koopman_neural_default_options. */
static int parse_options(const rk_json_ctx *c, const cJSON *root, rk_koopman_neural_options *o)
{
    static const char *const net_keys[] = {"hidden", "depth", "eig_hidden", "eig_depth", NULL};
    static const char *const train_keys[] = {"pretrain_epochs", "epochs", "learning_rate", "window", "init_member",
                                             "polish", "vertices", NULL};
    char p[512];
    int seed = 0;
    if (!cJSON_GetObjectItemCaseSensitive(root, "rank")) return rk_json_fail(c, "", "rank is required (r >= 1)");
    if (rk_json_whole(c, root, "", "rank", 1, 4096, &o->rank) || rk_json_whole(c, root, "", "seed", 0, 2147483647, &seed))
        return -1;
    o->seed = (unsigned long long)seed;
    const cJSON *net = rk_json_child(root, "", "network", p, sizeof p);
    if (net && (rk_json_check_keys(c, net, p, net_keys) || rk_json_whole(c, net, p, "hidden", 1, 4096, &o->hidden) ||
                rk_json_whole(c, net, p, "depth", 1, 64, &o->depth) ||
                rk_json_whole(c, net, p, "eig_hidden", 1, 4096, &o->eig_hidden) ||
                rk_json_whole(c, net, p, "eig_depth", 1, 64, &o->eig_depth)))
        return -1;
    const cJSON *tr = rk_json_child(root, "", "training", p, sizeof p);
    if (tr && (rk_json_check_keys(c, tr, p, train_keys) ||
               rk_json_whole(c, tr, p, "pretrain_epochs", 0, 1e7, &o->pretrain_epochs) ||
               rk_json_whole(c, tr, p, "epochs", 0, 1e7, &o->epochs) ||
               rk_json_whole(c, tr, p, "polish", 0, 1e7, &o->polish) ||
               rk_json_whole(c, tr, p, "window", 1, 1000, &o->window) ||
               rk_json_whole(c, tr, p, "init_member", -1, 1e6, &o->init_mesh) ||
               rk_json_whole(c, tr, p, "vertices", 0, 1e9, &o->vertices) ||
               rk_json_number(c, tr, p, "learning_rate", 0, &o->base_lr)))
        return -1;
    if (!(o->base_lr > 0)) return rk_json_fail(c, p, "learning_rate must be positive, got %g", o->base_lr);
    return 0;
}

/* "size" and "size_per_gamma": g rows of 3. */
static int parse_size(const rk_json_ctx *c, const cJSON *sh, const char *p, rk_family *f)
{
    char q[600];
    if (rk_json_vector(c, sh, p, "size", 1, 3, f->size)) return -1;
    const cJSON *rows = rk_json_child(sh, p, "size_per_gamma", q, sizeof q);
    if (!rows || !cJSON_IsArray(rows) || cJSON_GetArraySize(rows) != f->g || f->g == 0)
        return rk_json_fail(c, q, "must be an array of %d rows [x, y, z], one per shape code value", f->g);
    for (int j = 0; j < f->g; j++) {
        const cJSON *row = cJSON_GetArrayItem(rows, j);
        int good = cJSON_IsArray(row) && cJSON_GetArraySize(row) == 3;
        for (int a = 0; good && a < 3; a++) {
            const cJSON *v = cJSON_GetArrayItem(row, a);
            good = cJSON_IsNumber(v) && isfinite(v->valuedouble);
            if (good) f->size_per_gamma[j][a] = v->valuedouble;
        }
        if (!good) return rk_json_fail(c, q, "row %d must be 3 finite numbers [x, y, z]", j);
    }
    f->has_size = 1;
    return 0;
}

/* "shape": {"scene", and "size" with "size_per_gamma", and/or "keys" (family_keys.c)}. The scene's
 * text is read now, so that every key is checked before any training. */
static int parse_shape(const rk_json_ctx *c, const cJSON *root, const char *dir, rk_family *f)
{
    static const char *const keys[] = {"scene", "size", "size_per_gamma", "keys", NULL};
    char p[512];
    const cJSON *sh = rk_json_child(root, "", "shape", p, sizeof p);
    if (!sh) return 0;
    const char *scene;
    if (rk_json_check_keys(c, sh, p, keys) || rk_json_string(c, sh, p, "scene", 1, &scene)) return -1;
    if (f->g == 0) return rk_json_fail(c, p, "needs members with a shape code (gamma)");
    resolve(dir, scene, f->shape_scene, sizeof f->shape_scene);
    int has_size = cJSON_HasObjectItem(sh, "size") || cJSON_HasObjectItem(sh, "size_per_gamma");
    if (!has_size && !cJSON_HasObjectItem(sh, "keys"))
        return rk_json_fail(c, p, "needs \"size\" with \"size_per_gamma\", or \"keys\" (how a code changes the scene)");
    if (has_size && parse_size(c, sh, p, f)) return -1;
    if (!(f->shape_text = rk_json_file_text(f->shape_scene, "shape.scene", c->err))) return -1;
    if (rk_family_parse_keys(c, sh, p, f)) return -1;
    f->has_shape = 1;
    return 0;
}

static int parse_family(const rk_json_ctx *c, const cJSON *root, const char *dir, rk_family *f)
{
    static const char *const keys[] = {"members", "rank", "network", "training", "seed", "shape", NULL};
    char p[512];
    if (rk_json_check_keys(c, root, "", keys) || parse_options(c, root, &f->options)) return -1;
    const cJSON *arr = rk_json_child(root, "", "members", p, sizeof p);
    if (!arr || !cJSON_IsArray(arr) || cJSON_GetArraySize(arr) < 1)
        return rk_json_fail(c, "members", "must be a non-empty array of {scene, snapshots, gamma}");
    f->nmembers = cJSON_GetArraySize(arr);
    f->member = rk_calloc((size_t)f->nmembers, sizeof *f->member, c->err);
    f->mesh = rk_calloc((size_t)f->nmembers, sizeof *f->mesh, c->err);
    f->train = rk_calloc((size_t)f->nmembers, sizeof *f->train, c->err);
    if (!f->member || !f->mesh || !f->train) return -1;
    f->g = -1;
    for (int i = 0; i < f->nmembers; i++) {
        snprintf(p, sizeof p, "members[%d]", i);
        if (parse_member(c, cJSON_GetArrayItem(arr, i), p, dir, &f->g, &f->member[i])) return -1;
    }
    f->options.shape_dim = f->g;
    for (int i = 0; i < f->nmembers; i++) f->ntrain += !f->member[i].held_out;
    if (f->ntrain < 1) return rk_json_fail(c, "members", "every member is held out: none left to train on");
    if (parse_shape(c, root, dir, f)) return -1;
    if (f->options.init_mesh >= f->ntrain)
        return rk_json_fail(c, "training.init_member", "%d, but there are %d members to train on", f->options.init_mesh,
                            f->ntrain);
    return 0;
}

/* The snapshots (T x nv x 3 positions, rest first) as the member's run: displacements per step. */
static int member_run(const char *file, int i, rk_family_member *m, rk_error *err)
{
    double *S;
    int ndim, nv = m->sim.mesh.nv;
    long shape[4];
    if (rk_npy_read(m->snapshots, &S, &ndim, shape, err))
        return rk_error_prefix(err, "%s: members[%d].snapshots", file, i);
    int rc = -1;
    long T = shape[0];
    if (ndim != 3 || shape[2] != 3 || shape[1] != nv || T < 3) {
        rk_fail(err, "%s: members[%d].snapshots: %s must be T x %d x 3 positions with T >= 3 (the scene %s has %d "
                "vertices), got %d dimensions (%ld x %ld x %ld)", file, i, m->snapshots, nv, m->scene, nv, ndim,
                shape[0], ndim > 1 ? shape[1] : 0, ndim > 2 ? shape[2] : 0);
        goto done;
    }
    double rest = 0, size = 1;
    for (long j = 0; j < T * 3 * nv; j++)
        if (!isfinite(S[j])) {
            rk_fail(err, "%s: members[%d].snapshots: %s: value %ld (frame %ld) is not finite", file, i, m->snapshots, j,
                    j / (3 * nv));
            goto done;
        }
    for (int j = 0; j < 3 * nv; j++) rest = fmax(rest, fabs(S[j] - m->sim.mesh.X[j])), size = fmax(size, fabs(S[j]));
    if (rest > 1e-9 * size) {
        rk_fail(err, "%s: members[%d].snapshots: %s: the first frame is %.3g m from the rest positions of %s (romkit "
                "fom --snapshots of that scene starts at rest)", file, i, m->snapshots, rest, m->scene);
        goto done;
    }
    for (long j = 3 * nv; j < T * 3 * nv; j++) S[j] -= m->sim.mesh.X[j % (3 * nv)];
    rc = rk_koopman_scene_run_frames(&m->sim, S + 3 * nv, (int)T - 1, &m->run, err);
    m->ran = !rc;
    /* a chamber's pressure, held from t = 0, is the member's load (rk_koopman_scene_pressure_accel) */
    if (!rc && (rc = rk_koopman_scene_pressure_accel(&m->sim, m->run.accel, err)))
        rk_error_prefix(err, "%s: members[%d].scene: %s", file, i, m->scene);
done:
    free(S);
    return rc;
}

static int build_members(const char *file, rk_family *f, rk_error *err)
{
    int n = 0;
    for (int i = 0; i < f->nmembers; i++) {
        rk_family_member *m = &f->member[i];
        if (rk_scene_load(m->scene, &m->sc, err)) return rk_error_prefix(err, "%s: members[%d].scene", file, i);
        if (rk_scene_build(&m->sc, &m->sim, err)) {
            rk_scene_free(&m->sc);
            return rk_error_prefix(err, "%s: members[%d].scene", file, i);
        }
        m->built = 1;
        double h = m->sim.options.h;
        if (i > 0 && h != f->options.h)
            return rk_fail(err, "%s: members[%d].scene: %s steps %g s, members[0]'s %g s: one time step for all", file,
                           i, m->scene, h, f->options.h);
        f->options.h = h;
        if (member_run(file, i, m, err)) return -1;
        f->mesh[i] = (rk_koopman_neural_mesh){m->sim.mesh.X, m->sim.mesh.nv, &m->run.t, 1, f->g ? m->gamma : NULL};
        if (!m->held_out) f->train[n++] = f->mesh[i];
    }
    return 0;
}

int rk_family_load(const char *path, rk_family *f, rk_error *err)
{
    memset(f, 0, sizeof *f);
    rk_koopman_neural_default_options(&f->options);
    char *text = rk_json_file_text(path, "family", err), dir[4096];
    if (!text) return -1;
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (slash) *slash = '\0';
    else dir[0] = '\0';
    cJSON *root = rk_json_parse_text(text, path, err);
    free(text);
    rk_json_ctx c = {path, err};
    int rc = !root || parse_family(&c, root, dir, f) || build_members(path, f, err) ? -1 : 0;
    cJSON_Delete(root);
    if (rc) rk_family_free(f);
    return rc;
}

void rk_family_free(rk_family *f)
{
    for (int i = 0; f->member && i < f->nmembers; i++) {
        rk_family_member *m = &f->member[i];
        if (m->ran) rk_koopman_run_free(&m->run);
        if (m->built) {
            rk_scene_sim_free(&m->sim);
            rk_scene_free(&m->sc);
        }
    }
    free(f->member);
    free(f->mesh);
    free(f->train);
    free(f->keys);
    free(f->shape_text);
    memset(f, 0, sizeof *f);
}

void rk_family_range(const rk_family *f, double *lo, double *hi)
{
    for (int j = 0; j < f->g; j++) {
        lo[j] = INFINITY, hi[j] = -INFINITY;
        for (int i = 0; i < f->nmembers; i++) lo[j] = fmin(lo[j], f->member[i].gamma[j]), hi[j] = fmax(hi[j], f->member[i].gamma[j]);
    }
}

/* The box form on a parsed scene: the first object's box size at gamma. */
static int box_size(const rk_family *f, const double *gamma, double *size, rk_error *err)
{
    for (int a = 0; a < 3; a++) {
        size[a] = f->size[a];
        for (int j = 0; j < f->g; j++) size[a] += gamma[j] * f->size_per_gamma[j][a];
        if (!(size[a] > 0))
            return rk_fail(err, "shape: at gamma[0] = %g the box's size %d is %g m (must be positive)", gamma[0], a,
                           size[a]);
    }
    return 0;
}

char *rk_family_shape_text(const rk_family *f, const double *gamma, rk_error *err)
{
    if (!f->has_shape) {
        rk_fail(err, "the family has no \"shape\": no mesh for a shape code");
        return NULL;
    }
    cJSON *root = rk_json_parse_text(f->shape_text, f->shape_scene, err);
    if (!root) return NULL;
    char *text = NULL;
    double size[3];
    if (!rk_family_apply_keys(f, gamma, root, err)) {
        cJSON *box = cJSON_GetObjectItem(cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(root, "objects"), 0),
                                                             "mesh"), "box");
        if (!f->has_size) text = cJSON_Print(root);
        else if (!cJSON_IsObject(box))
            rk_fail(err, "shape.scene: %s: the first object's mesh must be a box", f->shape_scene);
        else if (!box_size(f, gamma, size, err)) {
            cJSON_DeleteItemFromObject(box, "size");
            cJSON_AddItemToObject(box, "size", rk_json_array(size, 3));
            text = cJSON_Print(root);
        }
    }
    cJSON_Delete(root);
    return text;
}

int rk_family_shape_scene(const rk_family *f, const double *gamma, rk_scene *out, rk_error *err)
{
    if (!f->has_shape) return rk_fail(err, "the family has no \"shape\": no mesh for a shape code");
    int rc;
    if (f->nkeys) {
        char *text = rk_family_shape_text(f, gamma, err);
        rc = !text || rk_scene_parse(text, f->shape_scene, out, err);
        free(text);
        if (rc) return rk_error_prefix(err, "shape at gamma[0] = %g", gamma[0]);
    } else if (rk_scene_load(f->shape_scene, out, err)) {
        return rk_error_prefix(err, "shape.scene");
    }
    if (!f->has_size) return 0;
    rk_scene_object *o = &out->objects[0];
    if (out->nobjects < 1 || o->shape != RK_SHAPE_BOX) {
        rk_scene_free(out);
        return rk_fail(err, "shape.scene: %s: the first object's mesh must be a box", f->shape_scene);
    }
    if (box_size(f, gamma, o->box_size, err)) {
        rk_scene_free(out);
        return -1;
    }
    return 0;
}
