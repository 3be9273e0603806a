/* Private to precompute/pipeline: strict JSON access for the scene parser (json.c) and the
 * parsers of the scene's parts. Every getter checks the type and, on failure, writes
 * "<file>: <json.path>: <what is wrong>" into err. */
#ifndef RK_PIPELINE_PARSE_IMPL_H
#define RK_PIPELINE_PARSE_IMPL_H

#include <cjson/cJSON.h>

#include "pipeline/pipeline.h"
#include "util/util.h"

typedef struct rk_json_ctx {
    const char *file;  /* scene file, for messages */
    rk_error *err;
} rk_json_ctx;

/* The whole of a JSON file (at most 64 MiB; what names it in messages: "scene"), malloc'd, or NULL
 * with err set. */
char *rk_json_file_text(const char *path, const char *what, rk_error *err);
/* The parsed text, or NULL with "<path>:<line>:<column>: invalid JSON" in err. */
cJSON *rk_json_parse_text(const char *text, const char *path, rk_error *err);

/* Fails with "<file>: <path>: <message>". Returns -1. */
int rk_json_fail(const rk_json_ctx *c, const char *path, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* `obj` must be a JSON object whose keys are all in the NULL-terminated `allowed` list. */
int rk_json_check_keys(const rk_json_ctx *c, const cJSON *obj, const char *path,
                       const char *const *allowed);

/* Child `key` of `obj`, its JSON path written into child_path. NULL when absent. */
const cJSON *rk_json_child(const cJSON *obj, const char *path, const char *key,
                           char *child_path, size_t child_path_size);

/* A finite number. When absent: fails if required, otherwise leaves *out unchanged. */
int rk_json_number(const rk_json_ctx *c, const cJSON *obj, const char *path, const char *key,
                   int required, double *out);
/* A whole number in [lo, hi] (the message names the parent path and the key). When absent,
 * leaves *out unchanged. */
int rk_json_whole(const rk_json_ctx *c, const cJSON *obj, const char *path, const char *key, double lo,
                  double hi, int *out);
/* An array of exactly n finite numbers. */
int rk_json_vector(const rk_json_ctx *c, const cJSON *obj, const char *path, const char *key,
                   int required, int n, double *out);
int rk_json_bool(const rk_json_ctx *c, const cJSON *obj, const char *path, const char *key,
                 int *out);
/* A string; *out points into the JSON tree. */
int rk_json_string(const rk_json_ctx *c, const cJSON *obj, const char *path, const char *key,
                   int required, const char **out);

/* "box": [[xmin, ymin, zmin], [xmax, ymax, zmax]] under obj (required). */
int rk_json_box(const rk_json_ctx *c, const cJSON *obj, const char *path, rk_box *b);

/* "twist": {"axis", "degrees_per_second", "center"} and/or "translate": {"velocity"} under it
 * (neither: fixed; both: a screw, the twist carried along at the velocity), into mo (its box left
 * alone). */
int rk_parse_motion(const rk_json_ctx *c, const cJSON *it, const char *path, rk_scene_motion *mo);
/* Obstacle i of the "obstacles" list (parse_obstacles.c; user: {scene folder, rk_scene objects},
 * as each_item hands it over). */
int rk_parse_obstacle(const rk_json_ctx *c, const cJSON *it, const char *path, int i, void *user);
/* The "contact" section into s->contact. */
int rk_parse_contact(const rk_json_ctx *c, const cJSON *root, rk_scene *s);

/* The rom section (an object or a list of them; NULL: none) into s->entries (parse_rom.c). */
int rk_parse_rom(const rk_json_ctx *c, const cJSON *rom, rk_scene *s);
/* Entry e's "asset" keys (parse_asset.c); absent keys keep the defaults. */
int rk_parse_asset(const rk_json_ctx *c, const cJSON *e, const char *path, rk_asset_options *o);

#endif
