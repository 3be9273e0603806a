/* Strict JSON getters for the scene parser (parse_impl.h). */
#include "pipeline/parse_impl.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int rk_json_fail(const rk_json_ctx *c, const char *path, const char *fmt, ...)
{
    char what[700];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    return rk_fail(c->err, "%s: %s: %s", c->file, path[0] ? path : "(top level)", what);
}

int rk_json_check_keys(const rk_json_ctx *c, const cJSON *obj, const char *path,
                       const char *const *allowed)
{
    if (!cJSON_IsObject(obj)) return rk_json_fail(c, path, "must be an object");
    for (const cJSON *it = obj->child; it; it = it->next) {
        int known = 0;
        for (const char *const *a = allowed; *a; a++)
            if (strcmp(it->string, *a) == 0) known = 1;
        if (!known) {
            char list[400] = "";
            for (const char *const *a = allowed; *a; a++) {
                if (strlen(list) + strlen(*a) + 3 >= sizeof list) break;
                strcat(list, list[0] ? ", " : "");
                strcat(list, *a);
            }
            return rk_json_fail(c, path, "unknown key '%s' (expected one of: %s)", it->string, list);
        }
    }
    return 0;
}

const cJSON *rk_json_child(const cJSON *obj, const char *path, const char *key,
                           char *child_path, size_t child_path_size)
{
    snprintf(child_path, child_path_size, "%s%s%s", path, path[0] ? "." : "", key);
    return cJSON_GetObjectItemCaseSensitive(obj, key);
}

int rk_json_number(const rk_json_ctx *c, const cJSON *obj, const char *path, const char *key,
                   int required, double *out)
{
    char p[512];
    const cJSON *v = rk_json_child(obj, path, key, p, sizeof p);
    if (!v) return required ? rk_json_fail(c, p, "missing (a number is required)") : 0;
    if (!cJSON_IsNumber(v)) return rk_json_fail(c, p, "must be a number");
    if (!isfinite(v->valuedouble)) return rk_json_fail(c, p, "must be finite");
    *out = v->valuedouble;
    return 0;
}

int rk_json_whole(const rk_json_ctx *c, const cJSON *obj, const char *path, const char *key, double lo,
                  double hi, int *out)
{
    double v = *out;
    if (rk_json_number(c, obj, path, key, 0, &v)) return -1;
    if (v != floor(v) || v < lo || v > hi)
        return rk_json_fail(c, path, "%s must be a whole number from %g to %g, got %g", key, lo, hi, v);
    *out = (int)v;
    return 0;
}

int rk_json_vector(const rk_json_ctx *c, const cJSON *obj, const char *path, const char *key,
                   int required, int n, double *out)
{
    char p[512];
    const cJSON *v = rk_json_child(obj, path, key, p, sizeof p);
    if (!v) return required ? rk_json_fail(c, p, "missing (an array of %d numbers is required)", n) : 0;
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != n)
        return rk_json_fail(c, p, "must be an array of %d numbers", n);
    int i = 0;
    for (const cJSON *it = v->child; it; it = it->next, i++) {
        if (!cJSON_IsNumber(it) || !isfinite(it->valuedouble))
            return rk_json_fail(c, p, "entry %d must be a finite number", i);
        out[i] = it->valuedouble;
    }
    return 0;
}

int rk_json_bool(const rk_json_ctx *c, const cJSON *obj, const char *path, const char *key, int *out)
{
    char p[512];
    const cJSON *v = rk_json_child(obj, path, key, p, sizeof p);
    if (!v) return 0;
    if (!cJSON_IsBool(v)) return rk_json_fail(c, p, "must be true or false");
    *out = cJSON_IsTrue(v);
    return 0;
}

int rk_json_string(const rk_json_ctx *c, const cJSON *obj, const char *path, const char *key,
                   int required, const char **out)
{
    char p[512];
    const cJSON *v = rk_json_child(obj, path, key, p, sizeof p);
    if (!v) return required ? rk_json_fail(c, p, "missing (a string is required)") : 0;
    if (!cJSON_IsString(v) || !v->valuestring) return rk_json_fail(c, p, "must be a string");
    *out = v->valuestring;
    return 0;
}

char *rk_json_file_text(const char *path, const char *what, rk_error *err)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) {
        rk_fail(err, "%s: cannot open %s: %s", path, what, strerror(errno));
        return NULL;
    }
    fseek(fp, 0, SEEK_END);
    long size = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    if (size < 0 || size > (64L << 20)) {
        fclose(fp);
        rk_fail(err, "%s: %s file too large (over 64 MiB)", path, what);
        return NULL;
    }
    char *text = malloc((size_t)size + 1);
    if (!text) {
        fclose(fp);
        rk_fail(err, "%s: out of memory", path);
        return NULL;
    }
    size_t got = fread(text, 1, (size_t)size, fp);
    fclose(fp);
    text[got] = '\0';
    return text;
}

cJSON *rk_json_parse_text(const char *text, const char *path, rk_error *err)
{
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithOpts(text, &end, 1);
    if (!root) {
        /* cJSON gives where it stopped: turn that into a line and column. */
        long line = 1, col = 1;
        for (const char *q = text; end && q < end; q++) {
            if (*q == '\n') { line++; col = 1; }
            else col++;
        }
        rk_fail(err, "%s:%ld:%ld: invalid JSON", path, line, col);
    }
    return root;
}
