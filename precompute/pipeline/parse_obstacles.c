/* The scene's "obstacles" and "contact" (DESIGN.md, "Scene file"):
 *   {"plane": {"point", "normal"}}, {"sphere": {"center", "radius"}},
 *   {"capsule": {"a", "b", "radius"}}, {"box": {"min", "max"}},
 *   {"mesh": {"file", "scale", "translate"}}, each with an optional "translate": {"velocity"} or
 *   "twist": {"axis", "degrees_per_second", "center"};
 *   "contact": {"dhat": m, "friction": mu, "eps_v": m/s, "friction_iterations": n, "self": bool,
 *               "kappa": J}. */
#include "pipeline/parse_impl.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define PATH_LEN 512

static int positive(const rk_json_ctx *c, const char *path, const char *what, double v)
{
    return v > 0 ? 0 : rk_json_fail(c, path, "%s must be positive, got %g", what, v);
}

static int parse_shape(const rk_json_ctx *c, const cJSON *it, const char *path, const char *scene_dir,
                       rk_scene_obstacle *o)
{
    static const char *const kinds[] = {"plane", "sphere", "capsule", "box", "mesh"};
    const cJSON *shape = NULL;
    int kind = -1;
    for (int k = 0; k < 5; k++)
        if (cJSON_HasObjectItem(it, kinds[k])) {
            if (shape) return rk_json_fail(c, path, "names two shapes ('%s' and '%s'): one per obstacle", kinds[kind], kinds[k]);
            shape = cJSON_GetObjectItemCaseSensitive(it, kinds[k]);
            kind = k;
        }
    if (!shape) return rk_json_fail(c, path, "needs one of 'plane', 'sphere', 'capsule', 'box' or 'mesh'");
    char p[PATH_LEN];
    snprintf(p, sizeof p, "%s.%s", path, kinds[kind]);
    if (!cJSON_IsObject(shape)) return rk_json_fail(c, p, "must be an object");
    rk_obstacle *s = &o->shape;
    switch (kind) {
    case 0: {
        static const char *const keys[] = {"point", "normal", NULL};
        s->kind = RK_OBSTACLE_PLANE;
        if (rk_json_check_keys(c, shape, p, keys) || rk_json_vector(c, shape, p, "point", 1, 3, s->point) ||
            rk_json_vector(c, shape, p, "normal", 1, 3, s->normal))
            return -1;
        double len = sqrt(s->normal[0] * s->normal[0] + s->normal[1] * s->normal[1] + s->normal[2] * s->normal[2]);
        if (!(len > 0)) return rk_json_fail(c, p, "normal must not be zero");
        for (int k = 0; k < 3; k++) s->normal[k] /= len;
        return 0;
    }
    case 1: {
        static const char *const keys[] = {"center", "radius", NULL};
        s->kind = RK_OBSTACLE_SPHERE;
        return rk_json_check_keys(c, shape, p, keys) || rk_json_vector(c, shape, p, "center", 1, 3, s->center) ||
                       rk_json_number(c, shape, p, "radius", 1, &s->radius) || positive(c, p, "radius", s->radius)
                   ? -1 : 0;
    }
    case 2: {
        static const char *const keys[] = {"a", "b", "radius", NULL};
        s->kind = RK_OBSTACLE_CAPSULE;
        return rk_json_check_keys(c, shape, p, keys) || rk_json_vector(c, shape, p, "a", 1, 3, s->center) ||
                       rk_json_vector(c, shape, p, "b", 1, 3, s->end) ||
                       rk_json_number(c, shape, p, "radius", 1, &s->radius) || positive(c, p, "radius", s->radius)
                   ? -1 : 0;
    }
    case 3: {
        static const char *const keys[] = {"min", "max", NULL};
        s->kind = RK_OBSTACLE_BOX;
        if (rk_json_check_keys(c, shape, p, keys) || rk_json_vector(c, shape, p, "min", 1, 3, s->min) ||
            rk_json_vector(c, shape, p, "max", 1, 3, s->max))
            return -1;
        for (int k = 0; k < 3; k++)
            if (!(s->min[k] < s->max[k]))
                return rk_json_fail(c, p, "min must be below max on every axis (axis %d: %g, %g)", k, s->min[k], s->max[k]);
        return 0;
    }
    default: {
        static const char *const keys[] = {"file", "scale", "translate", NULL};
        const char *file;
        s->kind = RK_OBSTACLE_MESH;
        o->scale = 1;
        if (rk_json_check_keys(c, shape, p, keys) || rk_json_string(c, shape, p, "file", 1, &file) ||
            rk_json_number(c, shape, p, "scale", 0, &o->scale) || rk_json_vector(c, shape, p, "translate", 0, 3, o->translate))
            return -1;
        if (!(o->scale > 0)) return rk_json_fail(c, p, "scale must be positive, got %g", o->scale);
        if (file[0] == '/' || !scene_dir[0]) snprintf(o->file, sizeof o->file, "%s", file);
        else snprintf(o->file, sizeof o->file, "%s/%s", scene_dir, file);
        return 0;
    }
    }
}

int rk_parse_obstacle(const rk_json_ctx *c, const cJSON *it, const char *path, int i, void *user)
{
    const char *scene_dir = ((const char **)user)[0];
    rk_scene *s = ((rk_scene **)user)[1];
    rk_scene_obstacle *o = &s->obstacles[i];
    memset(o, 0, sizeof *o);
    static const char *const keys[] = {"plane", "sphere", "capsule", "box", "mesh", "translate", "twist", NULL};
    if (!cJSON_IsObject(it)) return rk_json_fail(c, path, "must be an object");
    if (rk_json_check_keys(c, it, path, keys) || parse_shape(c, it, path, scene_dir, o)) return -1;
    rk_scene_motion mo = {0};
    if (rk_parse_motion(c, it, path, &mo)) return -1;
    rk_obstacle *sh = &o->shape;
    sh->motion = mo.kind;
    memcpy(sh->axis, mo.axis, sizeof sh->axis);
    memcpy(sh->velocity, mo.velocity, sizeof sh->velocity);
    sh->rate = mo.rate;
    if (mo.kind != RK_MOTION_FIXED && sh->kind == RK_OBSTACLE_PLANE)
        return rk_json_fail(c, path, "a plane cannot move (a moving box does what a moving plane would)");
    if (mo.kind == RK_MOTION_TWIST) {
        if (!mo.has_center) return rk_json_fail(c, path, "twist: an obstacle's twist needs its center");
        memcpy(sh->motion_center, mo.center, sizeof sh->motion_center);
    }
    return 0;
}

int rk_parse_contact(const rk_json_ctx *c, const cJSON *root, rk_scene *s)
{
    char p[PATH_LEN];
    rk_contact_default_options(&s->contact);
    const cJSON *k = rk_json_child(root, "", "contact", p, sizeof p);
    if (!k) return 0;
    if (!cJSON_IsObject(k)) return rk_json_fail(c, p, "must be an object");
    static const char *const keys[] = {"dhat", "friction", "eps_v", "friction_iterations", "self", "kappa", NULL};
    rk_contact_options *o = &s->contact;
    if (rk_json_check_keys(c, k, p, keys) || rk_json_number(c, k, p, "dhat", 0, &o->dhat) ||
        rk_json_number(c, k, p, "friction", 0, &o->friction) || rk_json_bool(c, k, p, "self", &o->self) ||
        rk_json_number(c, k, p, "eps_v", 0, &o->eps_v) ||
        rk_json_whole(c, k, p, "friction_iterations", 1, 100, &o->friction_iterations) ||
        rk_json_number(c, k, p, "kappa", 0, &o->kappa))
        return -1;
    if (!(o->eps_v > 0)) return rk_json_fail(c, p, "eps_v must be positive (m/s), got %g", o->eps_v);
    if (!(o->dhat >= 0)) return rk_json_fail(c, p, "dhat must be positive (m), got %g", o->dhat);
    if (cJSON_HasObjectItem(k, "dhat") && !(o->dhat > 0)) return rk_json_fail(c, p, "dhat must be positive (m), got %g", o->dhat);
    if (!(o->friction >= 0)) return rk_json_fail(c, p, "friction must not be negative, got %g", o->friction);
    if (!(o->kappa >= 0)) return rk_json_fail(c, p, "kappa must not be negative, got %g", o->kappa);
    return 0;
}
