/* A rom entry's "asset" keys into rk_asset_options (asset.h):
 *   {"precision": "float32" | "float64", "compress": bool, "show": "surface" | "all" | "none",
 *    "colliders": true (the collision vertices and surface) | "vertices" (the vertices alone) | false,
 *    "groups": [{"name": "tip", "box": [[..], [..]]}, ...], "contact_pairs": n (the runtime's obstacle
 *    pair capacity; 0, the default: sized at bake)} */
#include "pipeline/parse_impl.h"

#include <stdio.h>
#include <string.h>

static int parse_groups(const rk_json_ctx *c, const cJSON *a, const char *path, rk_asset_options *o)
{
    char gpath[128];
    const cJSON *list = rk_json_child(a, path, "groups", gpath, sizeof gpath);
    if (!list) return 0;
    if (!cJSON_IsArray(list)) return rk_json_fail(c, gpath, "must be an array of {\"name\", \"box\"}");
    int n = cJSON_GetArraySize(list);
    if (n > RK_ASSET_MAX_GROUPS) return rk_json_fail(c, gpath, "at most %d groups, got %d", RK_ASSET_MAX_GROUPS, n);
    static const char *const keys[] = {"name", "box", NULL};
    for (int i = 0; i < n; i++) {
        char p[160];
        const cJSON *g = cJSON_GetArrayItem(list, i);
        snprintf(p, sizeof p, "%s[%d]", gpath, i);
        if (!cJSON_IsObject(g)) return rk_json_fail(c, p, "must be an object {\"name\", \"box\"}");
        const char *name;
        if (rk_json_check_keys(c, g, p, keys) || rk_json_string(c, g, p, "name", 1, &name) ||
            rk_json_box(c, g, p, &o->groups[i].box))
            return -1;
        if (!*name || strlen(name) >= ROMBIN_GROUP_NAME_BYTES)
            return rk_json_fail(c, p, "name must have 1 to %d characters", ROMBIN_GROUP_NAME_BYTES - 1);
        for (int j = 0; j < i; j++)
            if (strcmp(o->groups[j].name, name) == 0) return rk_json_fail(c, p, "name \"%s\" is used twice", name);
        snprintf(o->groups[i].name, sizeof o->groups[i].name, "%s", name);
    }
    o->ngroups = n;
    return 0;
}

static int parse_colliders(const rk_json_ctx *c, const cJSON *a, const char *path, rk_asset_options *o)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(a, "colliders");
    if (!v) return 0;
    if (cJSON_IsBool(v)) o->colliders = cJSON_IsTrue(v) ? RK_COLLIDERS_SURFACE : RK_COLLIDERS_NONE;
    else if (cJSON_IsString(v) && strcmp(v->valuestring, "vertices") == 0) o->colliders = RK_COLLIDERS_VERTICES;
    else return rk_json_fail(c, path, "colliders must be true, false or \"vertices\"");
    return 0;
}

int rk_parse_asset(const rk_json_ctx *c, const cJSON *e, const char *path, rk_asset_options *o)
{
    char apath[96];
    rk_asset_default_options(o);
    const cJSON *a = rk_json_child(e, path, "asset", apath, sizeof apath);
    if (!a) return 0;
    if (!cJSON_IsObject(a)) return rk_json_fail(c, apath, "must be an object");
    static const char *const keys[] = {"precision", "compress", "show", "colliders", "groups", "contact_pairs", NULL};
    const char *precision = NULL, *show = NULL;
    if (rk_json_check_keys(c, a, apath, keys) || rk_json_string(c, a, apath, "precision", 0, &precision) ||
        rk_json_string(c, a, apath, "show", 0, &show) || rk_json_bool(c, a, apath, "compress", &o->compress) ||
        parse_colliders(c, a, apath, o) ||
        rk_json_whole(c, a, apath, "contact_pairs", 0, 1 << 28, &o->contact_pairs) ||
        parse_groups(c, a, apath, o))
        return -1;
    if (precision) {
        if (strcmp(precision, "float32") == 0) o->real_type = ROMBIN_REAL_F32;
        else if (strcmp(precision, "float64") == 0) o->real_type = ROMBIN_REAL_F64;
        else return rk_json_fail(c, apath, "precision must be \"float32\" or \"float64\", got \"%s\"", precision);
    }
    if (show) {
        if (strcmp(show, "surface") == 0) o->show = RK_SHOW_SURFACE;
        else if (strcmp(show, "all") == 0) o->show = RK_SHOW_ALL;
        else if (strcmp(show, "none") == 0) o->show = RK_SHOW_NONE;
        else return rk_json_fail(c, apath, "show must be \"surface\", \"all\" or \"none\", got \"%s\"", show);
    }
    return 0;
}
