/* A morph-target mesh and its weight animation as one .glb: the JSON chunk (cJSON) and one BIN
 * chunk holding, in order, the base positions, the targets' deltas, the indices, the keyframe
 * times and the weights. Every block is a multiple of 4 bytes, so every accessor is aligned. */
#include <cjson/cJSON.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "export/export.h"

enum {
    GLB_MAGIC = 0x46546C67,      /* "glTF" */
    GLB_JSON = 0x4E4F534A,       /* "JSON" */
    GLB_BIN = 0x004E4942,        /* "BIN\0" */
    GL_FLOAT = 5126,
    GL_UNSIGNED_INT = 5125,
    GL_ARRAY_BUFFER = 34962,
    GL_ELEMENT_ARRAY_BUFFER = 34963,
    MODE_POINTS = 0,
    MODE_TRIANGLES = 4
};

static void put_u32(unsigned char *p, uint32_t v)
{
    for (int k = 0; k < 4; k++) p[k] = (unsigned char)(v >> (8 * k)); /* little-endian on any host */
}

static void put_f32(unsigned char *p, float v)
{
    uint32_t bits;
    memcpy(&bits, &v, 4);
    put_u32(p, bits);
}

/* v rounded to float32 as the file stores it; -1 when it is not finite there. */
static int to_f32(double v, float *out)
{
    *out = (float)v;
    return isfinite(*out) ? 0 : -1;
}

/* Writes n float32 values at p; min/max (length comps) of comps-vectors for the accessor. */
static int put_floats(unsigned char *p, const double *v, size_t n, int comps, double *mn, double *mx, const char *what,
                      rk_error *err)
{
    for (int c = 0; c < comps; c++) mn[c] = INFINITY, mx[c] = -INFINITY;
    for (size_t k = 0; k < n; k++) {
        float f;
        if (to_f32(v[k], &f)) return rk_fail(err, "%s: value %zu (%g) is not a finite float32", what, k, v[k]);
        put_f32(p + 4 * k, f);
        int c = (int)(k % (size_t)comps);
        if (f < mn[c]) mn[c] = f;
        if (f > mx[c]) mx[c] = f;
    }
    return 0;
}

/* Numbers printed with 17 digits, so a reader parses back exactly the float32 value in the buffer
 * (cJSON's own printing stops at 15 digits when those compare equal within an epsilon, and an
 * accessor's min/max must equal its data exactly). */
static cJSON *number_array(const double *v, int n)
{
    cJSON *a = cJSON_CreateArray();
    for (int k = 0; a && k < n; k++) {
        char text[32];
        snprintf(text, sizeof text, "%.17g", v[k]);
        cJSON_AddItemToArray(a, cJSON_CreateRaw(text));
    }
    return a;
}

static void add_buffer_view(cJSON *views, size_t offset, size_t length, int stride, int target)
{
    cJSON *v = cJSON_CreateObject();
    cJSON_AddNumberToObject(v, "buffer", 0);
    cJSON_AddNumberToObject(v, "byteOffset", (double)offset);
    cJSON_AddNumberToObject(v, "byteLength", (double)length);
    if (stride) cJSON_AddNumberToObject(v, "byteStride", stride);
    if (target) cJSON_AddNumberToObject(v, "target", target);
    cJSON_AddItemToArray(views, v);
}

/* An accessor; mn/mx (comps values each) or NULL. */
static void add_accessor(cJSON *accessors, int view, size_t offset, int type, size_t count, int comps, const double *mn,
                         const double *mx)
{
    cJSON *a = cJSON_CreateObject();
    cJSON_AddNumberToObject(a, "bufferView", view);
    if (offset) cJSON_AddNumberToObject(a, "byteOffset", (double)offset);
    cJSON_AddNumberToObject(a, "componentType", type);
    cJSON_AddNumberToObject(a, "count", (double)count);
    cJSON_AddStringToObject(a, "type", comps == 3 ? "VEC3" : "SCALAR");
    if (mn) {
        cJSON_AddItemToObject(a, "min", number_array(mn, comps));
        cJSON_AddItemToObject(a, "max", number_array(mx, comps));
    }
    cJSON_AddItemToArray(accessors, a);
}

/* Fills bin (already sized) and the JSON's buffer views and accessors, and the mesh and animation. */
static int build(const rk_gltf_morph *m, unsigned char *bin, size_t bin_bytes, cJSON *root, rk_error *err)
{
    size_t nv = (size_t)m->nv, r = (size_t)m->r, at = 0;
    int animated = m->frames >= 2;
    double mn[3], mx[3];
    cJSON *views = cJSON_AddArrayToObject(root, "bufferViews");
    cJSON *accessors = cJSON_AddArrayToObject(root, "accessors");
    cJSON *mesh = cJSON_CreateObject(), *prim = cJSON_CreateObject();
    cJSON_AddStringToObject(mesh, "name", m->name);
    cJSON_AddItemToArray(cJSON_AddArrayToObject(mesh, "primitives"), prim);
    cJSON_AddItemToArray(cJSON_AddArrayToObject(root, "meshes"), mesh);

    /* base positions (view 0, accessor 0) */
    if (put_floats(bin + at, m->X, 3 * nv, 3, mn, mx, "rest positions", err)) return -1;
    add_buffer_view(views, at, 12 * nv, 12, GL_ARRAY_BUFFER);
    add_accessor(accessors, 0, 0, GL_FLOAT, nv, 3, mn, mx);
    cJSON_AddNumberToObject(cJSON_AddObjectToObject(prim, "attributes"), "POSITION", 0);
    at += 12 * nv;

    /* the targets: one view (several accessors share it, so it states its stride), accessors 1..r */
    cJSON *targets = cJSON_AddArrayToObject(prim, "targets");
    /* three.js and Blender name the targets from extras.targetNames */
    cJSON *names = cJSON_AddArrayToObject(cJSON_AddObjectToObject(mesh, "extras"), "targetNames");
    add_buffer_view(views, at, 12 * nv * r, 12, GL_ARRAY_BUFFER);
    for (size_t j = 0; j < r; j++) {
        char what[48], name[32];
        snprintf(what, sizeof what, "morph target %zu", j);
        if (put_floats(bin + at + 12 * nv * j, m->D + 3 * nv * j, 3 * nv, 3, mn, mx, what, err)) return -1;
        add_accessor(accessors, 1, 12 * nv * j, GL_FLOAT, nv, 3, mn, mx);
        cJSON *t = cJSON_CreateObject();
        cJSON_AddNumberToObject(t, "POSITION", (double)(1 + j));
        cJSON_AddItemToArray(targets, t);
        snprintf(name, sizeof name, "%c%zu", m->target_prefix, j);
        cJSON_AddItemToArray(names, cJSON_CreateString(name));
    }
    at += 12 * nv * r;
    float w;
    double *rest = rk_calloc(r, sizeof(double), err); /* as float32, like the animation's weights */
    if (!rest) return -1;
    for (size_t j = 0; j < r; j++) {
        if (to_f32(m->rest_weights[j], &w)) {
            free(rest);
            return rk_fail(err, "rest weight %zu (%g) is not finite", j, m->rest_weights[j]);
        }
        rest[j] = w;
    }
    cJSON_AddItemToObject(mesh, "weights", number_array(rest, m->r));
    free(rest);

    int next_view = 2, next_accessor = (int)(1 + r);
    if (m->ntris > 0) {
        for (size_t k = 0; k < 3 * (size_t)m->ntris; k++) {
            if (m->tris[k] >= nv) return rk_fail(err, "triangle %zu uses vertex %u of %zu", k / 3, m->tris[k], nv);
            put_u32(bin + at + 4 * k, m->tris[k]);
        }
        add_buffer_view(views, at, 12 * (size_t)m->ntris, 0, GL_ELEMENT_ARRAY_BUFFER);
        add_accessor(accessors, next_view++, 0, GL_UNSIGNED_INT, 3 * (size_t)m->ntris, 1, NULL, NULL);
        cJSON_AddNumberToObject(prim, "indices", next_accessor++);
        at += 12 * (size_t)m->ntris;
    }
    cJSON_AddNumberToObject(prim, "mode", m->ntris > 0 ? MODE_TRIANGLES : MODE_POINTS);

    if (animated) {
        size_t T = (size_t)m->frames;
        float prev = -INFINITY;
        for (size_t k = 0; k < T; k++) {
            if (to_f32(m->times[k], &w) || !(w > prev))
                return rk_fail(err, "keyframe %zu: time %g does not follow %g in float32", k, m->times[k], (double)prev);
            prev = w;
        }
        if (put_floats(bin + at, m->times, T, 1, mn, mx, "keyframe times", err)) return -1;
        add_buffer_view(views, at, 4 * T, 0, 0);
        add_accessor(accessors, next_view++, 0, GL_FLOAT, T, 1, mn, mx); /* an input states its range */
        at += 4 * T;
        if (put_floats(bin + at, m->weights, T * r, 1, mn, mx, "morph weights", err)) return -1;
        add_buffer_view(views, at, 4 * T * r, 0, 0);
        add_accessor(accessors, next_view++, 0, GL_FLOAT, T * r, 1, NULL, NULL);
        at += 4 * T * r;

        cJSON *anim = cJSON_CreateObject(), *sampler = cJSON_CreateObject(), *channel = cJSON_CreateObject();
        cJSON_AddStringToObject(anim, "name", "run");
        cJSON_AddNumberToObject(sampler, "input", next_accessor);
        cJSON_AddNumberToObject(sampler, "output", next_accessor + 1);
        cJSON_AddStringToObject(sampler, "interpolation", "LINEAR");
        cJSON_AddItemToArray(cJSON_AddArrayToObject(anim, "samplers"), sampler);
        cJSON_AddNumberToObject(channel, "sampler", 0);
        cJSON *target = cJSON_AddObjectToObject(channel, "target");
        cJSON_AddNumberToObject(target, "node", 0);
        cJSON_AddStringToObject(target, "path", "weights");
        cJSON_AddItemToArray(cJSON_AddArrayToObject(anim, "channels"), channel);
        cJSON_AddItemToArray(cJSON_AddArrayToObject(root, "animations"), anim);
    }
    if (at != bin_bytes) return rk_fail(err, "internal: %zu of %zu buffer bytes laid out", at, bin_bytes);
    cJSON *buffer = cJSON_CreateObject();
    cJSON_AddNumberToObject(buffer, "byteLength", (double)bin_bytes);
    cJSON_AddItemToArray(cJSON_AddArrayToObject(root, "buffers"), buffer);
    return 0;
}

/* The 12-byte header and both chunks through f (padding: spaces after the JSON, zeros after BIN). */
static int write_glb(FILE *fp, const char *json, size_t json_bytes, const unsigned char *bin, size_t bin_bytes)
{
    size_t jpad = (4 - json_bytes % 4) % 4, bpad = (4 - bin_bytes % 4) % 4;
    size_t total = 12 + 8 + json_bytes + jpad + 8 + bin_bytes + bpad;
    unsigned char head[12], chunk[8];
    put_u32(head, GLB_MAGIC);
    put_u32(head + 4, 2);
    put_u32(head + 8, (uint32_t)total);
    fwrite(head, 1, 12, fp);
    put_u32(chunk, (uint32_t)(json_bytes + jpad));
    put_u32(chunk + 4, GLB_JSON);
    fwrite(chunk, 1, 8, fp);
    fwrite(json, 1, json_bytes, fp);
    fwrite("   ", 1, jpad, fp);
    put_u32(chunk, (uint32_t)(bin_bytes + bpad));
    put_u32(chunk + 4, GLB_BIN);
    fwrite(chunk, 1, 8, fp);
    fwrite(bin, 1, bin_bytes, fp);
    fwrite("\0\0\0", 1, bpad, fp);
    return ferror(fp) ? -1 : 0;
}

int rk_gltf_write(const char *path, const rk_gltf_morph *m, rk_error *err)
{
    if (!m || m->nv < 1 || m->r < 1 || m->ntris < 0 || !m->X || !m->D || !m->rest_weights ||
        (m->ntris > 0 && !m->tris) || (m->frames >= 2 && (!m->times || !m->weights)))
        return rk_fail(err, "%s: nothing to export (no shown vertex, no morph target or a missing array)", path);
    size_t nv = (size_t)m->nv, r = (size_t)m->r, T = m->frames >= 2 ? (size_t)m->frames : 0;
    /* the sizes in doubles first: a .glb states its length in 32 bits */
    double need = 12.0 * nv * (1.0 + r) + 12.0 * m->ntris + 4.0 * T * (1.0 + r);
    if (need > 4.0e9) return rk_fail(err, "%s: %.3g bytes of data, more than a .glb can hold (4 GiB)", path, need);
    size_t bin_bytes = (size_t)need;
    unsigned char *bin = calloc(bin_bytes + 1, 1);
    cJSON *root = cJSON_CreateObject();
    char *json = NULL;
    int rc = -1;
    if (!bin || !root) {
        rk_fail(err, "%s: out of memory for %zu bytes", path, bin_bytes);
        goto done;
    }
    cJSON *asset = cJSON_AddObjectToObject(root, "asset");
    cJSON_AddStringToObject(asset, "version", "2.0");
    cJSON_AddStringToObject(asset, "generator", "romkit export");
    cJSON_AddNumberToObject(root, "scene", 0);
    cJSON *scene = cJSON_CreateObject(), *node = cJSON_CreateObject();
    cJSON_AddItemToObject(scene, "nodes", number_array((const double[]){0}, 1));
    cJSON_AddItemToArray(cJSON_AddArrayToObject(root, "scenes"), scene);
    cJSON_AddStringToObject(node, "name", m->name);
    cJSON_AddNumberToObject(node, "mesh", 0);
    cJSON_AddItemToArray(cJSON_AddArrayToObject(root, "nodes"), node);
    if (build(m, bin, bin_bytes, root, err)) goto done;
    json = cJSON_PrintUnformatted(root);
    if (!json) {
        rk_fail(err, "%s: out of memory for the JSON chunk", path);
        goto done;
    }
    rk_atomic_file f;
    if (rk_atomic_open(&f, path, err)) goto done;
    if (write_glb(f.fp, json, strlen(json), bin, bin_bytes)) {
        rk_atomic_abort(&f);
        rk_fail(err, "%s: write failed", path);
        goto done;
    }
    rc = rk_atomic_commit(&f, err);
done:
    free(bin);
    free(json);
    cJSON_Delete(root);
    return rc;
}
