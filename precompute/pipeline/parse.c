/* Scene file -> rk_scene (objects, obstacles, time, damping, Newton; the rom section in
 * parse_rom.c). Strict: unknown keys, wrong types and nonsense values are errors naming the JSON
 * path; nothing is guessed. */
#include "pipeline/parse_impl.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


#define PATH_LEN 512

static int parse_material(const rk_json_ctx *c, const cJSON *obj, const char *path, int required,
                          rk_material *m)
{
    static const char *const keys[] = {"model", "young", "poisson", "density", NULL};
    if (rk_json_check_keys(c, obj, path, keys)) return -1;
    const char *model = NULL;
    if (rk_json_string(c, obj, path, "model", required, &model)) return -1;
    if (model) {
        static const char *const names[] = {"linear", "corotated", "stvk", "neohookean"};
        static const rk_material_model ids[] = {RK_MAT_LINEAR, RK_MAT_COROTATED, RK_MAT_STVK,
                                                RK_MAT_NEOHOOKEAN};
        int found = -1;
        for (int i = 0; i < 4; i++)
            if (strcmp(model, names[i]) == 0) found = i;
        if (found < 0) {
            char p[PATH_LEN];
            snprintf(p, sizeof p, "%s.model", path);
            return rk_json_fail(c, p, "unknown material model '%s' (expected linear, corotated, stvk, neohookean)",
                                model);
        }
        m->model = ids[found];
    }
    if (rk_json_number(c, obj, path, "young", required, &m->young)) return -1;
    if (rk_json_number(c, obj, path, "poisson", required, &m->poisson)) return -1;
    if (rk_json_number(c, obj, path, "density", required, &m->density)) return -1;
    char p[PATH_LEN];
    if (!(m->young > 0)) {
        snprintf(p, sizeof p, "%s.young", path);
        return rk_json_fail(c, p, "Young's modulus must be positive (Pa), got %g", m->young);
    }
    if (!(m->poisson > -1.0 && m->poisson < 0.5)) {
        snprintf(p, sizeof p, "%s.poisson", path);
        return rk_json_fail(c, p, "Poisson's ratio must be in (-1, 0.5), got %g", m->poisson);
    }
    if (!(m->density > 0)) {
        snprintf(p, sizeof p, "%s.density", path);
        return rk_json_fail(c, p, "density must be positive (kg/m^3), got %g", m->density);
    }
    return 0;
}

/* "box": [[xmin, ymin, zmin], [xmax, ymax, zmax]] */
int rk_json_box(const rk_json_ctx *c, const cJSON *obj, const char *path, rk_box *b)
{
    char p[PATH_LEN];
    const cJSON *v = rk_json_child(obj, path, "box", p, sizeof p);
    if (!v) return rk_json_fail(c, p, "missing (a selection box [[min x, y, z], [max x, y, z]] is required)");
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 2)
        return rk_json_fail(c, p, "must be [[min x, y, z], [max x, y, z]]");
    double *corner[2] = {b->min, b->max};
    for (int k = 0; k < 2; k++) {
        const cJSON *row = cJSON_GetArrayItem(v, k);
        if (!cJSON_IsArray(row) || cJSON_GetArraySize(row) != 3)
            return rk_json_fail(c, p, "corner %d must be an array of 3 numbers", k);
        for (int i = 0; i < 3; i++) {
            const cJSON *x = cJSON_GetArrayItem(row, i);
            if (!cJSON_IsNumber(x) || !isfinite(x->valuedouble))
                return rk_json_fail(c, p, "corner %d entry %d must be a finite number", k, i);
            corner[k][i] = x->valuedouble;
        }
    }
    for (int i = 0; i < 3; i++)
        if (b->min[i] > b->max[i])
            return rk_json_fail(c, p, "min exceeds max on axis %d (%g > %g)", i, b->min[i], b->max[i]);
    return 0;
}

/* Iterates an optional array member; calls fn(ctx, item, item_path, index, user) on each entry. */
typedef int (*item_fn)(const rk_json_ctx *c, const cJSON *item, const char *path, int i, void *user);
static int each_item(const rk_json_ctx *c, const cJSON *obj, const char *path, const char *key,
                     int *count, item_fn fn, void *user)
{
    char p[PATH_LEN];
    const cJSON *arr = rk_json_child(obj, path, key, p, sizeof p);
    if (!arr) return 0;
    if (!cJSON_IsArray(arr)) return rk_json_fail(c, p, "must be an array");
    int i = 0;
    for (const cJSON *it = arr->child; it; it = it->next, i++) {
        char ip[PATH_LEN];
        snprintf(ip, sizeof ip, "%s[%d]", p, i);
        if (fn(c, it, ip, i, user)) return -1;
    }
    *count = i;
    return 0;
}

/* "cage": {"max_tets": N}: the surface file is simulated on a cage of at most N tets around it
 * (precompute/cage) and shown embedded in it. */
static int parse_cage(const rk_json_ctx *c, const cJSON *obj, const char *path, rk_scene_object *o)
{
    char p[PATH_LEN];
    const cJSON *cage = rk_json_child(obj, path, "cage", p, sizeof p);
    if (!cage) return 0;
    static const char *const keys[] = {"max_tets", NULL};
    if (!cJSON_IsObject(cage)) return rk_json_fail(c, p, "must be an object such as {\"max_tets\": 20000}");
    if (rk_json_check_keys(c, cage, p, keys)) return -1;
    if (!cJSON_GetObjectItemCaseSensitive(cage, "max_tets")) return rk_json_fail(c, p, "needs max_tets");
    if (rk_json_whole(c, cage, p, "max_tets", RK_CAGE_MIN_TETS, 1 << 24, &o->cage_tets)) return -1;
    int surface = o->shape == RK_SHAPE_FILE && rk_path_is_surface(o->file);
    if (!surface)
        return rk_json_fail(c, p, "a cage goes around a closed surface file (.obj .off .stl .ply .gltf .glb), not %s",
                            o->shape == RK_SHAPE_FILE ? o->file : o->shape == RK_SHAPE_BOX ? "a box" : "a point cloud");
    if (o->max_volume > 0) return rk_json_fail(c, p, "max_volume does not go with a cage (it picks its own tets)");
    return 0;
}

/* "voids": [{"box": [[x0, y0, z0], [x1, y1, z1]]}, ...]: cavities cut out of a tet mesh (a
 * pneumatic chamber's, rk_mesh_carve). */
static int parse_voids(const rk_json_ctx *c, const cJSON *obj, const char *path, rk_scene_object *o)
{
    char p[PATH_LEN], q[PATH_LEN];
    const cJSON *voids = rk_json_child(obj, path, "voids", p, sizeof p);
    if (!voids) return 0;
    if (!cJSON_IsArray(voids)) return rk_json_fail(c, p, "must be a list of {\"box\": [[x0, y0, z0], [x1, y1, z1]]}");
    if (o->shape == RK_SHAPE_POINTS || o->cage_tets)
        return rk_json_fail(c, p, "voids are cut from a tet mesh (a file or a box), not from %s",
                            o->cage_tets ? "a cage" : "a point cloud");
    int n = cJSON_GetArraySize(voids);
    if (!(o->voids = rk_calloc((size_t)n + 1, sizeof *o->voids, c->err))) return -1;
    for (int i = 0; i < n; i++) {
        const cJSON *it = cJSON_GetArrayItem(voids, i);
        static const char *const keys[] = {"box", NULL};
        snprintf(q, sizeof q, "%s[%d]", p, i);
        if (!cJSON_IsObject(it)) return rk_json_fail(c, q, "must be {\"box\": [[x0, y0, z0], [x1, y1, z1]]}");
        if (rk_json_check_keys(c, it, q, keys) || rk_json_box(c, it, q, &o->voids[i])) return -1;
        o->nvoids++;
    }
    return 0;
}

static int parse_mesh(const rk_json_ctx *c, const cJSON *obj, const char *path, const char *scene_dir,
                      rk_scene_object *o)
{
    static const char *const keys[] = {"file", "box", "points", "scale", "translate", "quality",
                                       "max_volume", "refine", "proxy_voxel", "proxy", "cage", "voids", NULL};
    if (rk_json_check_keys(c, obj, path, keys)) return -1;
    const char *file = NULL, *points = NULL;
    if (rk_json_string(c, obj, path, "file", 0, &file)) return -1;
    if (rk_json_string(c, obj, path, "points", 0, &points)) return -1;
    char p[PATH_LEN];
    const cJSON *box = rk_json_child(obj, path, "box", p, sizeof p);
    if ((file != NULL) + (points != NULL) + (box != NULL) != 1)
        return rk_json_fail(c, path, "needs exactly one of 'file', 'box' or 'points'");
    if (box) {
        static const char *const box_keys[] = {"size", "cells", NULL};
        if (rk_json_check_keys(c, box, p, box_keys)) return -1;
        double cells[3];
        if (rk_json_vector(c, box, p, "size", 1, 3, o->box_size)) return -1;
        if (rk_json_vector(c, box, p, "cells", 1, 3, cells)) return -1;
        for (int i = 0; i < 3; i++) {
            if (!(o->box_size[i] > 0)) return rk_json_fail(c, p, "size entries must be positive");
            if (cells[i] < 1 || cells[i] > 1000 || cells[i] != floor(cells[i]))
                return rk_json_fail(c, p, "cells entries must be whole numbers from 1 to 1000");
            o->box_cells[i] = (int)cells[i];
        }
        o->shape = RK_SHAPE_BOX;
    } else {
        const char *name = file ? file : points;
        o->shape = file ? RK_SHAPE_FILE : RK_SHAPE_POINTS;
        if (name[0] == '/' || !scene_dir[0]) snprintf(o->file, sizeof o->file, "%s", name);
        else snprintf(o->file, sizeof o->file, "%s/%s", scene_dir, name);
    }
    o->scale = 1.0;
    if (rk_json_number(c, obj, path, "scale", 0, &o->scale)) return -1;
    if (!(o->scale > 0)) return rk_json_fail(c, path, "scale must be positive, got %g", o->scale);
    if (rk_json_vector(c, obj, path, "translate", 0, 3, o->translate)) return -1;
    if (rk_json_number(c, obj, path, "quality", 0, &o->quality)) return -1;
    if (rk_json_number(c, obj, path, "max_volume", 0, &o->max_volume)) return -1;
    if (o->quality != 0 && !(o->quality >= 1.0))
        return rk_json_fail(c, path, "quality (radius-edge ratio bound) must be at least 1, got %g", o->quality);
    if (o->max_volume < 0) return rk_json_fail(c, path, "max_volume must not be negative");
    /* Levels of 1:8 refinement; the tet count it reaches is checked when the mesh is built
     * (RK_MESH_REFINE_MAX_TETS), once the file's count is known. */
    if (rk_json_whole(c, obj, path, "refine", 0, RK_MESH_REFINE_MAX_LEVELS, &o->refine)) return -1;
    if (o->refine && o->shape == RK_SHAPE_POINTS)
        return rk_json_fail(c, path, "refine applies to tet meshes (file or box), not to a point cloud");
    if (parse_cage(c, obj, path, o)) return -1;
    if (parse_voids(c, obj, path, o)) return -1;
    if (rk_json_number(c, obj, path, "proxy_voxel", 0, &o->proxy_voxel)) return -1;
    if (o->proxy_voxel != 0 && (o->shape != RK_SHAPE_POINTS || !(o->proxy_voxel > 0)))
        return rk_json_fail(c, path, "proxy_voxel (m) is a point cloud's contact-proxy voxel edge: positive, and "
                            "only with points");
    const char *proxy = NULL;
    if (rk_json_string(c, obj, path, "proxy", 0, &proxy)) return -1;
    if (proxy && (o->shape != RK_SHAPE_POINTS || (strcmp(proxy, "march") != 0 && strcmp(proxy, "voxels") != 0)))
        return rk_json_fail(c, path, "proxy is a point cloud's contact surface, \"march\" (the default) or \"voxels\", "
                            "and only with points; got \"%s\"", proxy);
    o->proxy_voxels = proxy && strcmp(proxy, "voxels") == 0;
    return 0;
}

static int parse_region(const rk_json_ctx *c, const cJSON *it, const char *path, int i, void *user)
{
    rk_scene_object *o = user;
    static const char *const keys[] = {"box", "tag", "ball", "material", NULL};
    if (rk_json_check_keys(c, it, path, keys)) return -1;
    rk_scene_region *r = &o->regions[i];
    r->by_tag = cJSON_HasObjectItem(it, "tag");
    r->by_ball = cJSON_HasObjectItem(it, "ball");
    if (r->by_tag + r->by_ball + cJSON_HasObjectItem(it, "box") > 1)
        return rk_json_fail(c, path, "gives more than one of box, tag and ball: a region selects its tets by one of them");
    char p[PATH_LEN];
    if (r->by_ball) { /* "ball": {"center": [x, y, z], "radius": r} */
        static const char *const ball_keys[] = {"center", "radius", NULL};
        const cJSON *b = rk_json_child(it, path, "ball", p, sizeof p);
        if (!cJSON_IsObject(b)) return rk_json_fail(c, p, "must be {\"center\": [x, y, z], \"radius\": r}");
        if (rk_json_check_keys(c, b, p, ball_keys) || rk_json_vector(c, b, p, "center", 1, 3, r->center) ||
            rk_json_number(c, b, p, "radius", 1, &r->radius))
            return -1;
        if (!(r->radius > 0) || !isfinite(r->radius)) return rk_json_fail(c, p, "radius must be positive, got %g", r->radius);
    } else if (r->by_tag ? rk_json_whole(c, it, path, "tag", -2147483647.0, 2147483647.0, &r->tag)
                         : rk_json_box(c, it, path, &r->box))
        return -1;
    const cJSON *m = rk_json_child(it, path, "material", p, sizeof p);
    if (!m) return rk_json_fail(c, p, "missing");
    r->material = o->material; /* inherit what the region leaves out */
    return parse_material(c, m, p, 0, &r->material);
}

static int parse_fixed(const rk_json_ctx *c, const cJSON *it, const char *path, int i, void *user)
{
    rk_scene_object *o = user;
    static const char *const keys[] = {"box", NULL};
    if (rk_json_check_keys(c, it, path, keys)) return -1;
    rk_scene_motion *mo = &o->motions[o->nmotions++];
    mo->kind = RK_MOTION_FIXED;
    return rk_json_box(c, it, path, &mo->box);
}

static int parse_moving(const rk_json_ctx *c, const cJSON *it, const char *path, int i, void *user)
{
    rk_scene_object *o = user;
    static const char *const keys[] = {"box", "twist", "translate", NULL};
    if (rk_json_check_keys(c, it, path, keys)) return -1;
    rk_scene_motion *mo = &o->motions[o->nmotions++];
    if (rk_json_box(c, it, path, &mo->box)) return -1;
    if (!cJSON_HasObjectItem(it, "twist") && !cJSON_HasObjectItem(it, "translate"))
        return rk_json_fail(c, path, "needs 'twist', 'translate' or both (a screw)");
    return rk_parse_motion(c, it, path, mo);
}

int rk_parse_motion(const rk_json_ctx *c, const cJSON *it, const char *path, rk_scene_motion *mo)
{
    char tp[PATH_LEN], sp[PATH_LEN];
    const cJSON *twist = rk_json_child(it, path, "twist", tp, sizeof tp);
    const cJSON *shift = rk_json_child(it, path, "translate", sp, sizeof sp);
    mo->kind = RK_MOTION_FIXED;
    if (shift) {
        static const char *const skeys[] = {"velocity", NULL};
        if (rk_json_check_keys(c, shift, sp, skeys)) return -1;
        if (rk_json_vector(c, shift, sp, "velocity", 1, 3, mo->velocity)) return -1;
        mo->kind = RK_MOTION_TRANSLATE;
    }
    if (twist) { /* with translate too: a screw, the twist's center carried along */
        static const char *const tkeys[] = {"axis", "degrees_per_second", "center", NULL};
        if (rk_json_check_keys(c, twist, tp, tkeys)) return -1;
        double dps = 0;
        if (rk_json_vector(c, twist, tp, "axis", 1, 3, mo->axis)) return -1;
        if (rk_json_number(c, twist, tp, "degrees_per_second", 1, &dps)) return -1;
        double len = sqrt(mo->axis[0] * mo->axis[0] + mo->axis[1] * mo->axis[1] + mo->axis[2] * mo->axis[2]);
        if (!(len > 0)) return rk_json_fail(c, tp, "axis must not be zero");
        for (int k = 0; k < 3; k++) mo->axis[k] /= len;
        mo->has_center = cJSON_GetObjectItemCaseSensitive(twist, "center") != NULL;
        if (rk_json_vector(c, twist, tp, "center", 0, 3, mo->center)) return -1;
        mo->rate = dps * M_PI / 180.0;
        mo->kind = RK_MOTION_TWIST;
    }
    return 0;
}

static int parse_load(const rk_json_ctx *c, const cJSON *it, const char *path, int i, void *user)
{
    rk_scene_object *o = user;
    static const char *const keys[] = {"box", "force", NULL};
    if (rk_json_check_keys(c, it, path, keys)) return -1;
    if (rk_json_box(c, it, path, &o->loads[i].box)) return -1;
    return rk_json_vector(c, it, path, "force", 1, 3, o->loads[i].force);
}

/* {"name": "c0", "box": [[..], [..]], "pressure": P}: a pneumatic chamber (rk_scene_chamber). */
static int parse_chamber(const rk_json_ctx *c, const cJSON *it, const char *path, int i, void *user)
{
    rk_scene_object *o = user;
    static const char *const keys[] = {"name", "box", "pressure", NULL};
    if (rk_json_check_keys(c, it, path, keys)) return -1;
    if (o->shape == RK_SHAPE_POINTS || o->cage_tets)
        return rk_json_fail(c, path, "a chamber is a void's walls in a tet mesh, not in %s",
                            o->cage_tets ? "a cage" : "a point cloud");
    rk_scene_chamber *ch = &o->chambers[i];
    const char *name = NULL;
    if (rk_json_string(c, it, path, "name", 1, &name)) return -1;
    if (!name[0] || strlen(name) >= RK_CHAMBER_NAME || strpbrk(name, ",:"))
        return rk_json_fail(c, path, "name '%s' must be 1 to %d characters without ',' or ':'", name,
                            RK_CHAMBER_NAME - 1);
    snprintf(ch->name, sizeof ch->name, "%s", name);
    if (rk_json_box(c, it, path, &ch->box)) return -1;
    char p[PATH_LEN];
    const cJSON *sched = rk_json_child(it, path, "pressure", p, sizeof p);
    if (cJSON_IsArray(sched)) { /* [[t, P], ...]: times increasing */
        int n = cJSON_GetArraySize(sched);
        if (n < 1) return rk_json_fail(c, p, "a pressure schedule needs at least one [t, P] pair");
        if (!(ch->keys = rk_calloc(2 * (size_t)n, sizeof(double), c->err))) return -1;
        for (int k = 0; k < n; k++) {
            const cJSON *kv = cJSON_GetArrayItem(sched, k);
            if (!cJSON_IsArray(kv) || cJSON_GetArraySize(kv) != 2 || !cJSON_IsNumber(cJSON_GetArrayItem(kv, 0)) ||
                !cJSON_IsNumber(cJSON_GetArrayItem(kv, 1)))
                return rk_json_fail(c, p, "entry %d must be [t, P] (seconds, pascals)", k);
            ch->keys[2 * k] = cJSON_GetArrayItem(kv, 0)->valuedouble;
            ch->keys[2 * k + 1] = cJSON_GetArrayItem(kv, 1)->valuedouble;
            if (!isfinite(ch->keys[2 * k]) || !isfinite(ch->keys[2 * k + 1]))
                return rk_json_fail(c, p, "entry %d is not finite", k);
            if (k > 0 && !(ch->keys[2 * k] > ch->keys[2 * k - 2]))
                return rk_json_fail(c, p, "entry %d's time %g s does not come after %g s", k, ch->keys[2 * k],
                                    ch->keys[2 * k - 2]);
            ch->nkeys++;
        }
        return 0;
    }
    if (sched && !cJSON_IsNumber(sched))
        return rk_json_fail(c, p, "must be a pressure in Pa or a schedule [[t, P], ...]");
    if (rk_json_number(c, it, path, "pressure", 0, &ch->pressure)) return -1;
    if (!isfinite(ch->pressure)) return rk_json_fail(c, path, "pressure %g (Pa) is not finite", ch->pressure);
    return 0;
}

static int array_size(const cJSON *obj, const char *key)
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(obj, key);
    return cJSON_IsArray(a) ? cJSON_GetArraySize(a) : 0;
}

static int parse_object(const rk_json_ctx *c, const cJSON *it, const char *path, int i, void *user)
{
    const char *scene_dir = ((const char **)user)[0];
    rk_scene_object *o = &((rk_scene_object *)((void **)user)[1])[i];
    static const char *const keys[] = {"mesh", "material", "regions", "fixed", "moving", "loads",
                                       "chambers", "velocity", NULL};
    if (rk_json_check_keys(c, it, path, keys)) return -1;
    char p[PATH_LEN];
    const cJSON *mesh = rk_json_child(it, path, "mesh", p, sizeof p);
    if (!mesh) return rk_json_fail(c, p, "missing");
    if (parse_mesh(c, mesh, p, scene_dir, o)) return -1;
    const cJSON *mat = rk_json_child(it, path, "material", p, sizeof p);
    if (!mat) return rk_json_fail(c, p, "missing");
    if (parse_material(c, mat, p, 1, &o->material)) return -1;
    o->regions = rk_calloc((size_t)array_size(it, "regions"), sizeof *o->regions, c->err);
    o->motions = rk_calloc((size_t)(array_size(it, "fixed") + array_size(it, "moving")),
                           sizeof *o->motions, c->err);
    o->loads = rk_calloc((size_t)array_size(it, "loads"), sizeof *o->loads, c->err);
    o->chambers = rk_calloc((size_t)array_size(it, "chambers") + 1, sizeof *o->chambers, c->err);
    if (!o->regions || !o->motions || !o->loads || !o->chambers) return -1;
    int nfixed = 0, nmoving = 0;
    if (each_item(c, it, path, "regions", &o->nregions, parse_region, o)) return -1;
    if (each_item(c, it, path, "fixed", &nfixed, parse_fixed, o)) return -1;
    if (each_item(c, it, path, "moving", &nmoving, parse_moving, o)) return -1;
    if (each_item(c, it, path, "loads", &o->nloads, parse_load, o)) return -1;
    if (each_item(c, it, path, "chambers", &o->nchambers, parse_chamber, o)) return -1;
    return rk_json_vector(c, it, path, "velocity", 0, 3, o->velocity);
}

static int parse_time(const rk_json_ctx *c, const cJSON *t, const char *path, rk_scene *s)
{
    static const char *const keys[] = {"step", "duration", "integrator", "static", NULL};
    if (rk_json_check_keys(c, t, path, keys)) return -1;
    if (rk_json_number(c, t, path, "step", 0, &s->h)) return -1;
    if (rk_json_number(c, t, path, "duration", 0, &s->duration)) return -1;
    if (rk_json_bool(c, t, path, "static", &s->is_static)) return -1;
    const char *integ = NULL;
    if (rk_json_string(c, t, path, "integrator", 0, &integ)) return -1;
    char p[PATH_LEN];
    if (integ) {
        if (strcmp(integ, "backward_euler") == 0) s->integrator = RK_BACKWARD_EULER;
        else if (strcmp(integ, "bdf2") == 0) s->integrator = RK_BDF2;
        else {
            snprintf(p, sizeof p, "%s.integrator", path);
            return rk_json_fail(c, p, "unknown integrator '%s' (expected backward_euler or bdf2)", integ);
        }
    }
    if (!(s->h > 0)) {
        snprintf(p, sizeof p, "%s.step", path);
        return rk_json_fail(c, p, "time step must be positive (s), got %g", s->h);
    }
    if (s->duration < 0) {
        snprintf(p, sizeof p, "%s.duration", path);
        return rk_json_fail(c, p, "duration must not be negative (s), got %g", s->duration);
    }
    if (s->duration / s->h > 1e8) {
        snprintf(p, sizeof p, "%s.duration", path);
        return rk_json_fail(c, p, "duration / step asks for more than 1e8 steps");
    }
    return 0;
}

/* Tets of a box object after `levels` refinements (6 per cell, 8 children each). */
static double box_tets(const rk_scene_object *o, double levels)
{
    return 6.0 * o->box_cells[0] * o->box_cells[1] * o->box_cells[2] * pow(8.0, levels);
}

/* A tet count for a message: exact while it is one, else its magnitude. */
static void count_text(char *buf, size_t size, double n)
{
    if (n < 1e15) snprintf(buf, size, "%.0f", n);
    else if (n <= 1e300) snprintf(buf, size, "%.3g", n);
    else snprintf(buf, size, "over 1e300");
}

/* "reference": {"refine": k, "order": o}: romkit compare's full-order reference on every object's
 * mesh refined k more times (after its own mesh.refine; default 0), on linear (o = 1, the default) or
 * quadratic tets (o = 2: rk_p2_fom_run, which converges where P1 locks). The levels in all must stay
 * within what rk_mesh_refine makes; a box's tet count is known here, so the message says what k
 * would make (a mesh file's is known when it is loaded, and rk_mesh_refine's message says it then). */
static int parse_reference(const rk_json_ctx *c, const cJSON *ref, const char *path, rk_scene *s)
{
    static const char *const keys[] = {"refine", "order", NULL};
    if (!cJSON_IsObject(ref)) return rk_json_fail(c, path, "must be an object such as {\"refine\": 1}");
    if (rk_json_check_keys(c, ref, path, keys)) return -1;
    char p[PATH_LEN];
    double order = 1;
    if (rk_json_number(c, ref, path, "order", 0, &order)) return -1;
    snprintf(p, sizeof p, "%s.order", path);
    if (order != 1 && order != 2)
        return rk_json_fail(c, p, "must be 1 (linear tets) or 2 (quadratic tets), got %g", order);
    if (!cJSON_GetObjectItemCaseSensitive(ref, "refine") && order == 1)
        return rk_json_fail(c, path, "names neither \"refine\" nor \"order\": 2, so it is the scene's own run");
    s->reference_order = (int)order;
    snprintf(p, sizeof p, "%s.refine", path);
    double k = 0;
    if (rk_json_number(c, ref, path, "refine", 0, &k)) return -1;
    if (k < 0 || k != floor(k))
        return rk_json_fail(c, p, "must be a whole number of 1:8 refinement levels (0: the scene's own mesh, 1, 2, "
                            "...), got %g", k);
    for (int i = 0; i < s->nobjects && k > 0; i++) {
        const rk_scene_object *o = &s->objects[i];
        if (o->shape == RK_SHAPE_POINTS)
            return rk_json_fail(c, p, "objects[%d] is a point cloud: only tet meshes (mesh.file or mesh.box) refine", i);
        double levels = o->refine + k;
        char n[64];
        if (o->shape == RK_SHAPE_BOX) {
            double tets = box_tets(o, levels);
            count_text(n, sizeof n, tets);
            if (levels > RK_MESH_REFINE_MAX_LEVELS || tets > RK_MESH_REFINE_MAX_TETS)
                return rk_json_fail(c, p, "%g level%s would turn objects[%d]'s %d x %d x %d box (%.0f tets after its "
                                    "mesh.refine %d) into %s tets; a reference may have at most %d tets and %d levels "
                                    "in all", k, k == 1 ? "" : "s", i, o->box_cells[0], o->box_cells[1], o->box_cells[2],
                                    box_tets(o, o->refine), o->refine, n, RK_MESH_REFINE_MAX_TETS,
                                    RK_MESH_REFINE_MAX_LEVELS);
        } else if (levels > RK_MESH_REFINE_MAX_LEVELS) {
            count_text(n, sizeof n, pow(8.0, levels));
            return rk_json_fail(c, p, "%g level%s on top of objects[%d]'s mesh.refine %d would make %s times its "
                                "file's tets; a reference may have at most %d tets and %d levels in all", k,
                                k == 1 ? "" : "s", i, o->refine, n,
                                RK_MESH_REFINE_MAX_TETS, RK_MESH_REFINE_MAX_LEVELS);
        }
    }
    s->reference_refine = (int)k;
    return 0;
}

static int parse_root(const rk_json_ctx *c, const cJSON *root, const char *scene_dir, rk_scene *s)
{
    static const char *const keys[] = {"objects", "gravity", "obstacles", "contact", "time", "rom", "damping",
                                       "newton", "lumped_mass", "reference", NULL};
    if (rk_json_check_keys(c, root, "", keys)) return -1;
    char p[PATH_LEN];
    const cJSON *objects = rk_json_child(root, "", "objects", p, sizeof p);
    if (!cJSON_IsArray(objects) || cJSON_GetArraySize(objects) < 1)
        return rk_json_fail(c, "objects", "must be a non-empty array of objects");
    s->objects = rk_calloc((size_t)cJSON_GetArraySize(objects), sizeof *s->objects, c->err);
    s->obstacles = rk_calloc((size_t)array_size(root, "obstacles") + 1, sizeof *s->obstacles, c->err);
    if (!s->objects || !s->obstacles) return -1;
    /* Count first so rk_scene_free releases whatever a failed parse allocated. */
    s->nobjects = cJSON_GetArraySize(objects);
    const void *user[2] = {scene_dir, s->objects};
    if (each_item(c, root, "", "objects", &s->nobjects, parse_object, (void *)user)) return -1;
    for (int k = 0; k < s->nobjects; k++) /* chamber names are control inputs: one chamber each */
        for (int j = 0; j < s->objects[k].nchambers; j++)
            for (int k2 = 0; k2 <= k; k2++)
                for (int j2 = 0; j2 < (k2 == k ? j : s->objects[k2].nchambers); j2++)
                    if (!strcmp(s->objects[k].chambers[j].name, s->objects[k2].chambers[j2].name)) {
                        char cp[PATH_LEN];
                        snprintf(cp, sizeof cp, "objects[%d].chambers[%d].name", k, j);
                        return rk_json_fail(c, cp, "'%s' is already objects[%d].chambers[%d]'s name",
                                            s->objects[k].chambers[j].name, k2, j2);
                    }
    if (rk_json_vector(c, root, "", "gravity", 0, 3, s->gravity)) return -1;
    const void *obstacle_user[2] = {scene_dir, s};
    if (each_item(c, root, "", "obstacles", &s->nobstacles, rk_parse_obstacle, (void *)obstacle_user) ||
        rk_parse_contact(c, root, s))
        return -1;
    s->h = 0.01;
    s->duration = 1.0;
    const cJSON *t = rk_json_child(root, "", "time", p, sizeof p);
    if (t && parse_time(c, t, p, s)) return -1;
    const cJSON *damping = rk_json_child(root, "", "damping", p, sizeof p);
    if (damping) {
        static const char *const dkeys[] = {"mass", "stiffness", NULL};
        if (rk_json_check_keys(c, damping, p, dkeys)) return -1;
        if (rk_json_number(c, damping, p, "mass", 0, &s->damping_mass)) return -1;
        if (rk_json_number(c, damping, p, "stiffness", 0, &s->damping_stiffness)) return -1;
        if (s->damping_mass < 0 || s->damping_stiffness < 0)
            return rk_json_fail(c, p, "Rayleigh coefficients must not be negative");
    }
    const cJSON *newton = rk_json_child(root, "", "newton", p, sizeof p);
    if (newton) {
        static const char *const nkeys[] = {"tolerance", "max_iterations", NULL};
        if (rk_json_check_keys(c, newton, p, nkeys)) return -1;
        double iters = 0;
        if (rk_json_number(c, newton, p, "tolerance", 0, &s->newton_tol)) return -1;
        if (rk_json_number(c, newton, p, "max_iterations", 0, &iters)) return -1;
        if (s->newton_tol < 0 || iters < 0 || iters > 10000 || iters != floor(iters))
            return rk_json_fail(c, p, "tolerance must be >= 0 and max_iterations a whole number up to 10000");
        s->newton_max_iter = (int)iters;
    }
    if (rk_json_bool(c, root, "", "lumped_mass", &s->lumped_mass)) return -1;
    const cJSON *reference = rk_json_child(root, "", "reference", p, sizeof p);
    if (reference && parse_reference(c, reference, p, s)) return -1;
    return rk_parse_rom(c, cJSON_GetObjectItemCaseSensitive(root, "rom"), s);
}

int rk_scene_parse(const char *text, const char *path, rk_scene *s, rk_error *err)
{
    memset(s, 0, sizeof *s);
    snprintf(s->path, sizeof s->path, "%s", path);
    char dir[4096];
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (slash) *slash = '\0';
    else dir[0] = '\0';
    rk_json_ctx c = {path, err};
    cJSON *root = rk_json_parse_text(text, path, err);
    if (!root) return -1;
    int rc = parse_root(&c, root, dir, s);
    cJSON_Delete(root);
    if (rc) rk_scene_free(s);
    return rc;
}

int rk_scene_load(const char *path, rk_scene *s, rk_error *err)
{
    memset(s, 0, sizeof *s);
    char *text = rk_json_file_text(path, "scene", err);
    if (!text) return -1;
    int rc = rk_scene_parse(text, path, s, err);
    free(text);
    return rc;
}

void rk_scene_free(rk_scene *s)
{
    for (int i = 0; i < s->nobjects; i++) {
        free(s->objects[i].regions);
        free(s->objects[i].motions);
        free(s->objects[i].loads);
        free(s->objects[i].voids);
        for (int j = 0; s->objects[i].chambers && j < s->objects[i].nchambers; j++) free(s->objects[i].chambers[j].keys);
        free(s->objects[i].chambers);
    }
    free(s->objects);
    free(s->obstacles);
    free(s->entries);
    memset(s, 0, sizeof *s);
}

int rk_scene_entry(const rk_scene *s, int k, const rk_rom_entry **out, rk_error *err)
{
    if (s->nentries == 0)
        return rk_fail(err, "%s: the scene has no rom section: nothing to build (it names the basis, cubature or "
                       "Koopman operator)", s->path);
    if (k < 0 || k >= s->nentries)
        return rk_fail(err, "%s: no rom entry %d (the scene has %d: 0..%d)", s->path, k, s->nentries, s->nentries - 1);
    *out = &s->entries[k];
    return 0;
}
