/* The files between a split bake's steps (romkit plan; method_fixed.h): the basis as romkit basis
 * writes it (n x 3 x r float64 .npy, exact) and the cubature as JSON (element ids and weights).
 * The weights are printed here with %.17g, which reads back to the same double: cJSON 1.7.15 prints
 * 15 digits whenever they read back within DBL_EPSILON relative (compare_double), up to an ulp off,
 * and an ulp in a weight changed a float64 asset's bytes. strtod (cJSON's parse) rounds correctly. */
#include "pipeline/method_fixed.h"
#include "pipeline/parse_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int rk_scene_basis_read(const char *path, rk_basis_type type, rk_basis *b, rk_error *err)
{
    double *T = NULL;
    int ndim;
    long shape[4];
    memset(b, 0, sizeof *b);
    if (rk_npy_read(path, &T, &ndim, shape, err)) return -1;
    if (ndim != 3 || shape[1] != 3 || shape[0] < 1 || shape[2] < 1 || shape[0] > (1L << 28) || shape[2] > 100000) {
        free(T);
        return rk_fail(err, "%s: a basis is n x 3 x r (romkit basis --basis), got a %d-dimensional array", path, ndim);
    }
    int n = (int)shape[0], r = (int)shape[2];
    b->U = rk_calloc((size_t)3 * n * r, sizeof(double), err);
    if (!b->U) {
        free(T);
        return -1;
    }
    for (size_t i = 0; i < 3 * (size_t)n; i++)
        for (int j = 0; j < r; j++) {
            double v = T[i * r + j];
            if (!isfinite(v)) {
                free(T);
                rk_basis_free(b);
                return rk_fail(err, "%s: vertex %zu, column %d is not finite", path, i / 3, j);
            }
            b->U[(size_t)j * 3 * n + i] = v;
        }
    free(T);
    b->type = type;
    b->n = n;
    b->r = r;
    return 0;
}

/* A finite double as JSON text that reads back to it bit for bit (null otherwise). */
static cJSON *exact(double v)
{
    char text[40];
    if (!isfinite(v)) return cJSON_CreateNull();
    snprintf(text, sizeof text, "%.17g", v);
    return cJSON_CreateRaw(text);
}

int rk_scene_cubature_write(const char *path, const rk_scene_rom *R, rk_error *err)
{
    const rk_cubature_set *s = &R->cubature_set;
    if (s->count < 1) return rk_fail(err, "%s: no cubature to write (the entry integrates exactly)", path);
    cJSON *j = cJSON_CreateObject();
    cJSON *ids = cJSON_AddArrayToObject(j, "elements");
    for (int i = 0; i < s->count; i++) cJSON_AddItemToArray(ids, cJSON_CreateNumber(s->index[i]));
    cJSON *w = cJSON_AddArrayToObject(j, "weights");
    for (int i = 0; i < s->count; i++) cJSON_AddItemToArray(w, exact(s->weight[i]));
    cJSON_AddItemToObject(j, "relative_error", exact(s->relative_error));
    cJSON_AddBoolToObject(j, "reached", s->reached);
    cJSON_AddNumberToObject(j, "greedy_count", s->greedy_count);
    cJSON_AddNumberToObject(j, "poses", R->cubature_poses);
    int rc = rk_json_write_file(path, j, err);
    cJSON_Delete(j);
    return rc;
}

static int number(const cJSON *j, const char *key, const char *path, double *out, rk_error *err)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(j, key);
    if (!cJSON_IsNumber(v)) return rk_fail(err, "%s: %s must be a number (romkit cubature's file)", path, key);
    *out = v->valuedouble;
    return 0;
}

int rk_scene_cubature_read(const char *path, rk_cubature_set *s, int *poses, rk_error *err)
{
    memset(s, 0, sizeof *s);
    char *text = rk_json_file_text(path, "cubature", err);
    if (!text) return -1;
    cJSON *j = rk_json_parse_text(text, path, err);
    free(text);
    if (!j) return -1;
    const cJSON *ids = cJSON_GetObjectItemCaseSensitive(j, "elements"), *w = cJSON_GetObjectItemCaseSensitive(j, "weights");
    double e = 0, greedy = 0, np = 0;
    int rc = 0, n = cJSON_GetArraySize(ids);
    if (!cJSON_IsArray(ids) || !cJSON_IsArray(w) || n < 1 || cJSON_GetArraySize(w) != n)
        rc = rk_fail(err, "%s: elements and weights must be arrays of the same length, at least 1", path);
    if (cJSON_IsNull(cJSON_GetObjectItemCaseSensitive(j, "relative_error"))) e = NAN; /* (not measured) */
    else rc = rc || number(j, "relative_error", path, &e, err);
    rc = rc || number(j, "greedy_count", path, &greedy, err) ||
         number(j, "poses", path, &np, err);
    if (!rc) {
        s->index = rk_calloc(n, sizeof(int), err);
        s->weight = rk_calloc(n, sizeof(double), err);
        rc = !s->index || !s->weight;
    }
    for (int i = 0; !rc && i < n; i++) {
        const cJSON *a = cJSON_GetArrayItem(ids, i), *b = cJSON_GetArrayItem(w, i);
        if (!cJSON_IsNumber(a) || !cJSON_IsNumber(b) || a->valuedouble != (int)a->valuedouble)
            rc = rk_fail(err, "%s: elements[%d] must be a whole number and weights[%d] a number", path, i, i);
        else {
            s->index[i] = (int)a->valuedouble;
            s->weight[i] = b->valuedouble;
        }
    }
    if (!rc) {
        s->count = n;
        s->relative_error = e;
        s->reached = cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(j, "reached"));
        s->greedy_count = (int)greedy;
        *poses = (int)np;
    }
    cJSON_Delete(j);
    if (rc) rk_cubature_set_free(s);
    return rc ? -1 : 0;
}
