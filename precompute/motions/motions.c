/* romkit motions: a template scene's object measured in the frame gravity sets, then `count`
 * scenes written around it, each with its own draw (motions.h). */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "motions/motions_impl.h"
#include "pipeline/parse_impl.h"
#include "pipeline/pipeline.h"

#define DEFAULT_FRICTION 0.3 /* a drum carries the object up by friction; the scene's own wins */

const char *rk_motions_kind_name(rk_motions_kind k) { return k == RK_MOTIONS_DRYER ? "dryer" : "pachinko"; }

static void normalize(double v[3])
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; k++) v[k] /= n;
}

/* The frame of the object's n vertices X under gravity g (nonzero). */
static void measure(const double *X, int n, const double g[3], rk_motions_frame *F)
{
    memset(F, 0, sizeof *F);
    F->g = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    int least = 0;
    for (int k = 0; k < 3; k++) {
        F->u[k] = -g[k] / F->g;
        if (fabs(F->u[k]) < fabs(F->u[least])) least = k;
    }
    for (int k = 0; k < 3; k++) F->a[k] = (k == least) - F->u[least] * F->u[k];
    normalize(F->a);
    F->b[0] = F->a[1] * F->u[2] - F->a[2] * F->u[1];
    F->b[1] = F->a[2] * F->u[0] - F->a[0] * F->u[2];
    F->b[2] = F->a[0] * F->u[1] - F->a[1] * F->u[0];
    for (int k = 0; k < 3; k++) F->a[k] += 0.0, F->b[k] += 0.0; /* no -0 written */
    const double *dir[3] = {F->a, F->u, F->b};
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < n; i++)
        for (int d = 0; d < 3; d++) {
            const double *x = X + 3 * (size_t)i;
            double p = x[0] * dir[d][0] + x[1] * dir[d][1] + x[2] * dir[d][2];
            if (p < lo[d]) lo[d] = p;
            if (p > hi[d]) hi[d] = p;
        }
    for (int d = 0; d < 3; d++) {
        F->ext[d] = hi[d] - lo[d];
        if (F->ext[d] > F->L) F->L = F->ext[d];
        F->D += F->ext[d] * F->ext[d];
        for (int k = 0; k < 3; k++) F->c[k] += 0.5 * (lo[d] + hi[d]) * dir[d][k];
    }
    F->D = sqrt(F->D);
}

/* The template checked and its object measured (built as every command builds it). */
static int read_template(const char *text, const char *path, rk_scene *sc, rk_motions_frame *F, rk_error *err)
{
    if (rk_scene_parse(text, path, sc, err)) return -1;
    int rc = -1;
    rk_scene_sim sim;
    if (sc->nobjects != 1) {
        rk_fail(err, "%s: romkit motions drops one object; the scene has %d", path, sc->nobjects);
        goto done;
    }
    if (sc->objects[0].nmotions) {
        rk_fail(err, "%s: objects[0] has fixed or moving vertices; a dropped object must be free", path);
        goto done;
    }
    if (!(fabs(sc->gravity[0]) + fabs(sc->gravity[1]) + fabs(sc->gravity[2]) > 0)) {
        rk_fail(err, "%s: gravity is zero; the motions are drops and tumbles under gravity", path);
        goto done;
    }
    if (rk_scene_build(sc, &sim, err)) goto done;
    measure(sim.mesh.X, sim.mesh.nv, sc->gravity, F);
    rk_scene_sim_free(&sim);
    if (!(F->L > 0)) {
        rk_fail(err, "%s: objects[0] has no extent", path);
        goto done;
    }
    rc = 0;
done:
    if (rc) rk_scene_free(sc);
    return rc;
}

/* Sets obj[key] to a new item (replacing one there). */
static void put(cJSON *obj, const char *key, cJSON *item)
{
    if (cJSON_HasObjectItem(obj, key)) cJSON_ReplaceItemInObjectCaseSensitive(obj, key, item);
    else cJSON_AddItemToObject(obj, key, item);
}

/* The template's JSON made a training scene's base: the object's mesh file absolute, its place and
 * velocity left to each draw, no rom, reference or obstacles, friction given. */
static cJSON *base_scene(const char *text, const char *path, const rk_scene *sc, const rk_motions_options *o,
                         int *replaced, rk_error *err)
{
    cJSON *root = rk_json_parse_text(text, path, err);
    if (!root) return NULL;
    cJSON *mesh = cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(root, "objects"), 0),
                                                   "mesh");
    const char *keys[] = {"file", "points"};
    for (int i = 0; i < 2; i++)
        if (cJSON_HasObjectItem(mesh, keys[i])) {
            char abs[PATH_MAX];
            if (!realpath(sc->objects[0].file, abs)) {
                cJSON_Delete(root);
                return rk_fail(err, "%s: objects[0].mesh.%s %s: %s", path, keys[i], sc->objects[0].file, strerror(errno)),
                       NULL;
            }
            put(mesh, keys[i], cJSON_CreateString(abs));
        }
    cJSON *obstacles = cJSON_GetObjectItemCaseSensitive(root, "obstacles");
    *replaced = cJSON_GetArraySize(obstacles);
    cJSON_DeleteItemFromObjectCaseSensitive(root, "obstacles");
    cJSON_DeleteItemFromObjectCaseSensitive(root, "rom");
    cJSON_DeleteItemFromObjectCaseSensitive(root, "reference");
    cJSON *contact = cJSON_GetObjectItemCaseSensitive(root, "contact");
    if (!contact) contact = cJSON_AddObjectToObject(root, "contact");
    if (!cJSON_HasObjectItem(contact, "friction")) cJSON_AddNumberToObject(contact, "friction", DEFAULT_FRICTION);
    if (o->duration > 0) {
        cJSON *time = cJSON_GetObjectItemCaseSensitive(root, "time");
        if (!time) time = cJSON_AddObjectToObject(root, "time");
        put(time, "duration", cJSON_CreateNumber(o->duration));
    }
    return root;
}

/* One scene's draw: on the board a place along it (within half a peg spacing of the middle, so
 * it meets the first row's middle peg or falls beside it) and a velocity in the board's plane,
 * downward or level; in the drum a velocity in any direction and the drum's rate and sense. */
static void draw(uint64_t *state, const rk_motions_frame *F, const rk_motions_options *o, rk_motions_draw *d)
{
    double speed = (o->speed > 0 ? o->speed : RK_MOTIONS_SPEED) * rk_uniform(state);
    memset(d, 0, sizeof *d);
    if (o->kind == RK_MOTIONS_PACHINKO) {
        d->offset = (rk_uniform(state) - 0.5) * rk_motions_peg_spacing(F);
        double th = M_PI * (1 + rk_uniform(state)); /* sin <= 0: not upward */
        for (int k = 0; k < 3; k++) d->velocity[k] = speed * (cos(th) * F->a[k] + sin(th) * F->u[k]);
    } else {
        double z = 2 * rk_uniform(state) - 1, ph = 2 * M_PI * rk_uniform(state), r = sqrt(1 - z * z);
        double dir[3] = {r * cos(ph), r * sin(ph), z};
        for (int k = 0; k < 3; k++) d->velocity[k] = speed * dir[k];
        double rate = (0.3 + 0.4 * rk_uniform(state)) * sqrt(F->g / rk_motions_drum_radius(F));
        d->spin = (rk_uniform(state) < 0.5 ? -1 : 1) * rate * 180 / M_PI;
    }
}

/* Removes the files written so far (and the folder if made here). */
static void undo(char (*written)[PATH_MAX], int n, const char *dir, int made_dir)
{
    for (int i = 0; i < n; i++) unlink(written[i]);
    if (made_dir) rmdir(dir);
}

int rk_motions_write(const char *template_path, const rk_motions_options *o, const char *dir, rk_motions_report *rep,
                     rk_error *err)
{
    if (o->count < 1 || o->count > RK_MOTIONS_MAX)
        return rk_fail(err, "count must be from 1 to %d, got %d", RK_MOTIONS_MAX, o->count);
    if (!(o->duration >= 0) || !(o->speed >= 0) || !isfinite(o->duration) || !isfinite(o->speed))
        return rk_fail(err, "duration and speed must be finite and not negative (0: the defaults)");
    memset(rep, 0, sizeof *rep);
    rk_scene sc;
    rk_motions_frame F;
    char *text = rk_json_file_text(template_path, "scene", err);
    if (!text) return -1;
    if (read_template(text, template_path, &sc, &F, err)) {
        free(text);
        return -1;
    }
    cJSON *base = base_scene(text, template_path, &sc, o, &rep->replaced, err);
    free(text);
    rk_scene_free(&sc);
    if (!base) return -1;
    rep->extent = F.L;

    /* every scene made and parsed as a scene before anything is written */
    cJSON **scenes = calloc((size_t)o->count, sizeof *scenes);
    char (*written)[PATH_MAX] = calloc((size_t)o->count + 1, sizeof *written);
    rk_surface drum = {0};
    int rc = -1, nwritten = 0, made_dir = 0;
    if (!scenes || !written) {
        rk_fail(err, "out of memory for %d scenes", o->count);
        goto done;
    }
    if (o->kind == RK_MOTIONS_DRYER && rk_motions_drum_surface(&F, &drum, rep, err)) goto done;
    cJSON *board = o->kind == RK_MOTIONS_PACHINKO ? rk_motions_board(&F, rep) : NULL;
    uint64_t state = o->seed;
    for (int k = 0; k < o->count; k++) {
        rk_motions_draw *d = &rep->draw[k];
        draw(&state, &F, o, d);
        cJSON *s = scenes[k] = cJSON_Duplicate(base, 1);
        cJSON *obj = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(s, "objects"), 0);
        cJSON *mesh = cJSON_GetObjectItemCaseSensitive(obj, "mesh");
        double t[3] = {0, 0, 0};
        cJSON *tr = cJSON_GetObjectItemCaseSensitive(mesh, "translate");
        for (int i = 0; i < 3 && tr; i++) t[i] = cJSON_GetArrayItem(tr, i)->valuedouble;
        for (int i = 0; i < 3; i++) t[i] += d->offset * F.a[i];
        put(mesh, "translate", cJSON_CreateDoubleArray(t, 3));
        put(obj, "velocity", cJSON_CreateDoubleArray(d->velocity, 3));
        cJSON_AddItemToObject(s, "obstacles", board ? cJSON_Duplicate(board, 1) : rk_motions_drum(&F, "drum.obj", d->spin));
        rep->obstacles = cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(s, "obstacles"));
        char *out = cJSON_Print(s);
        char path[PATH_MAX];
        snprintf(path, sizeof path, "%s/%s_%d.json", dir, rk_motions_kind_name(o->kind), k);
        rk_scene check;
        int bad = 1;
        if (!out) rk_fail(err, "out of memory formatting %s", path);
        else if (rk_scene_parse(out, path, &check, err)) rk_error_prefix(err, "the scene written would not read (a bug)");
        else bad = 0, rk_scene_free(&check);
        free(out);
        if (bad) {
            cJSON_Delete(board);
            goto done;
        }
    }
    cJSON_Delete(board);

    if (mkdir(dir, 0777) == 0) made_dir = 1;
    else if (errno != EEXIST) {
        rk_fail(err, "%s: cannot make the folder: %s", dir, strerror(errno));
        goto done;
    }
    if (o->kind == RK_MOTIONS_DRYER) {
        snprintf(written[nwritten], PATH_MAX, "%s/drum.obj", dir);
        if (rk_surface_write(written[nwritten], &drum, err)) goto done;
        nwritten++;
    }
    for (int k = 0; k < o->count; k++) {
        snprintf(written[nwritten], PATH_MAX, "%s/%s_%d.json", dir, rk_motions_kind_name(o->kind), k);
        if (rk_json_write_file(written[nwritten], scenes[k], err)) goto done;
        nwritten++;
    }
    rc = 0;
done:
    if (rc) undo(written, nwritten, dir, made_dir);
    for (int k = 0; scenes && k < o->count; k++) cJSON_Delete(scenes[k]);
    free(scenes);
    free(written);
    rk_surface_free(&drum);
    cJSON_Delete(base);
    return rc;
}
