/* "shape.keys" of a family file (family.h): numbers of the shape's scene, named by their JSON
 * path, that move with the shape code, so that a family varies more than a box's size (a
 * pneumatic finger's chamber length, wall thickness, offset: Sec. 7.4's chamber family). */
#include "pipeline/family_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The node that key ("objects[0].mesh.voids[0].box[1][0]": names joined by '.', each followed by
 * any number of [index]) names in root, or NULL with why (what is wrong, and where) written. */
static cJSON *find_key(cJSON *root, const char *key, char *why, size_t size)
{
    cJSON *node = root;
    const char *s = key;
    int at = 0; /* characters of key walked, for the messages */
    while (*s) {
        if (*s == '[') {
            char *end;
            long i = strtol(s + 1, &end, 10);
            if (end == s + 1 || *end != ']' || i < 0) {
                snprintf(why, size, "a bad index after '%.*s' (need [N], N >= 0)", at, key);
                return NULL;
            }
            if (!cJSON_IsArray(node)) {
                snprintf(why, size, "'%.*s' is not an array", at, key);
                return NULL;
            }
            if (i >= cJSON_GetArraySize(node)) {
                snprintf(why, size, "index %ld is out of range: '%.*s' has %d items", i, at, key, cJSON_GetArraySize(node));
                return NULL;
            }
            node = cJSON_GetArrayItem(node, (int)i);
            s = end + 1;
        } else {
            if (s != key) {
                if (*s != '.') {
                    snprintf(why, size, "expected '.' or '[' after '%.*s'", at, key);
                    return NULL;
                }
                s++;
            }
            size_t n = strcspn(s, ".[");
            char name[128];
            if (n == 0 || n >= sizeof name) {
                snprintf(why, size, "an empty or overlong name after '%.*s'", at, key);
                return NULL;
            }
            memcpy(name, s, n);
            name[n] = '\0';
            if (!cJSON_IsObject(node)) {
                snprintf(why, size, "'%.*s' is not an object (no key \"%s\" in it)", at, key, name);
                return NULL;
            }
            cJSON *child = cJSON_GetObjectItemCaseSensitive(node, name);
            if (!child) {
                snprintf(why, size, "unknown key: no \"%s\" in '%.*s'", name, at, at ? key : "the scene");
                return NULL;
            }
            node = child;
            s += n;
        }
        at = (int)(s - key);
    }
    return node;
}

int rk_family_parse_keys(const rk_json_ctx *c, const cJSON *sh, const char *p, rk_family *f)
{
    static const char *const keys[] = {"key", "per_gamma", "range", "step", NULL};
    char q[600], r[700], why[512];
    const cJSON *arr = rk_json_child(sh, p, "keys", q, sizeof q);
    if (!arr) return 0;
    if (!cJSON_IsArray(arr) || cJSON_GetArraySize(arr) < 1)
        return rk_json_fail(c, q, "must be a non-empty array of {\"key\", \"per_gamma\", \"range\"}");
    cJSON *root = rk_json_parse_text(f->shape_text, f->shape_scene, c->err);
    if (!root) return -1;
    f->nkeys = cJSON_GetArraySize(arr);
    f->keys = rk_calloc((size_t)f->nkeys, sizeof *f->keys, c->err);
    double lo[RK_KOOPMAN_SHAPE_MAX], hi[RK_KOOPMAN_SHAPE_MAX];
    rk_family_range(f, lo, hi);
    int rc = f->keys ? 0 : -1;
    for (int k = 0; !rc && k < f->nkeys; k++) {
        rk_family_key *fk = &f->keys[k];
        const cJSON *it = cJSON_GetArrayItem(arr, k);
        const char *key;
        double range[2] = {-INFINITY, INFINITY};
        snprintf(r, sizeof r, "%s[%d]", q, k);
        if (rk_json_check_keys(c, it, r, keys) || rk_json_string(c, it, r, "key", 1, &key) ||
            rk_json_vector(c, it, r, "per_gamma", 1, f->g, fk->per_gamma) || rk_json_vector(c, it, r, "range", 0, 2, range) ||
            rk_json_number(c, it, r, "step", 0, &fk->step)) {
            rc = -1;
            break;
        }
        if (fk->step < 0) {
            rc = rk_json_fail(c, r, "step %g must be positive (or 0: none)", fk->step);
            break;
        }
        snprintf(fk->key, sizeof fk->key, "%s", key);
        cJSON *node = find_key(root, key, why, sizeof why);
        if (!node) {
            rc = rk_json_fail(c, r, "key '%s' in %s: %s", key, f->shape_scene, why);
        } else if (!cJSON_IsNumber(node)) {
            rc = rk_json_fail(c, r, "key '%s' in %s is not a number: only numbers move with the code", key, f->shape_scene);
        } else {
            /* the value is affine in gamma: its extremes over the members' box are at its corners */
            double vlo = fk->base = node->valuedouble, vhi = vlo;
            for (int j = 0; j < f->g; j++)
                vlo += fmin(fk->per_gamma[j] * lo[j], fk->per_gamma[j] * hi[j]),
                vhi += fmax(fk->per_gamma[j] * lo[j], fk->per_gamma[j] * hi[j]);
            if (vlo < range[0] || vhi > range[1])
                rc = rk_json_fail(c, r, "key '%s' goes from %g to %g over the members' codes, outside its range [%g, %g]",
                                  key, vlo, vhi, range[0], range[1]);
        }
    }
    cJSON_Delete(root);
    return rc;
}

int rk_family_apply_keys(const rk_family *f, const double *gamma, cJSON *root, rk_error *err)
{
    char why[512];
    for (int k = 0; k < f->nkeys; k++) {
        const rk_family_key *fk = &f->keys[k];
        cJSON *node = find_key(root, fk->key, why, sizeof why);
        if (!node || !cJSON_IsNumber(node)) /* checked when the file was read: the text is the same */
            return rk_fail(err, "shape.keys[%d]: key '%s': %s", k, fk->key, node ? "not a number" : why);
        double d = 0;
        for (int j = 0; j < f->g; j++) d += gamma[j] * fk->per_gamma[j];
        /* whole steps: a carved void's wall moves from between one row of tet centroids to between
         * the next (carve.c takes a tet by its centroid), never through a row, which would leave
         * jagged walls and a chamber surface that is not one closed sheet */
        if (fk->step > 0) d = fk->step * floor(d / fk->step + 0.5);
        cJSON_SetNumberValue(node, fk->base + d);
    }
    return 0;
}
