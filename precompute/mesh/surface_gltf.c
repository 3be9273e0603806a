/* glTF 2.0 surfaces: .gltf (JSON, its buffers in files beside it or in data: URIs) and .glb (the
 * binary container: a JSON chunk and a BIN chunk). The triangles of every mesh primitive that the
 * default scene's nodes reach, each node's transform applied (a mirroring one flips the winding),
 * the corners welded where exactly equal (glTF splits vertices at UV and normal seams). Strips and
 * fans become triangles; points and lines are skipped and counted in a warning. Sparse accessors,
 * positions that are not float, and required extensions (Draco, meshopt) are refused, naming the
 * accessor or the extension: every read is checked against its buffer view and its buffer. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "mesh/mesh_impl.h"
#include "mesh/text_reader_impl.h"

enum { GLTF_U8 = 5121, GLTF_U16 = 5123, GLTF_U32 = 5125, GLTF_F32 = 5126 };
enum { GLB_MAGIC = 0x46546C67u, GLB_JSON = 0x4E4F534Au, GLB_BIN = 0x004E4942u };
#define MAX_BUFFERS 256
#define MAX_DEPTH 1000 /* nodes nested deeper than this: refused rather than recursed into */

typedef struct {
    const char *path;
    rk_error *err;
    cJSON *root;
    const cJSON *accessors, *views, *meshes, *nodes;
    const unsigned char *bin;      /* a .glb's BIN chunk, or NULL */
    size_t bin_bytes;
    int nbuffers;
    unsigned char *buffer[MAX_BUFFERS]; /* each buffer's bytes (owned) */
    size_t buffer_bytes[MAX_BUFFERS];
    double *corners;               /* 9 a triangle */
    size_t ntris, cap;
    int skipped;                   /* primitives that are points or lines */
} gltf;

static uint32_t le32(const unsigned char *p) { return p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24; }

/* A whole number under obj[key] in [0, hi]; def when absent (def < 0: required). */
static int whole(gltf *g, const cJSON *obj, const char *key, double hi, long def, const char *where, long *out)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!v) {
        if (def < 0) return rk_fail(g->err, "%s: %s: '%s' is missing", g->path, where, key);
        *out = def;
        return 0;
    }
    if (!cJSON_IsNumber(v) || v->valuedouble != floor(v->valuedouble) || v->valuedouble < 0 || v->valuedouble > hi)
        return rk_fail(g->err, "%s: %s: '%s' must be a whole number in [0, %.0f]", g->path, where, key, hi);
    *out = (long)v->valuedouble;
    return 0;
}

static int base64_value(int c)
{
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    return c == '+' ? 62 : c == '/' ? 63 : -1;
}

/* A data: URI's base64 payload into *out (malloc'd). */
static int decode_base64(gltf *g, const char *s, const char *where, unsigned char **out, size_t *bytes)
{
    size_t n = strlen(s), k = 0;
    unsigned char *o = rk_calloc(n / 4 * 3 + 3, 1, g->err);
    if (!o) return -1;
    uint32_t acc = 0;
    int bits = 0;
    for (size_t i = 0; i < n && s[i] != '='; i++) {
        int v = base64_value((unsigned char)s[i]);
        if (v < 0) {
            free(o);
            return rk_fail(g->err, "%s: %s: the data URI holds '%c', which is not base64", g->path, where, s[i]);
        }
        acc = acc << 6 | (uint32_t)v;
        bits += 6;
        if (bits >= 8) o[k++] = (unsigned char)(acc >> (bits -= 8));
    }
    *out = o;
    *bytes = k;
    return 0;
}

/* buffers[i]: the GLB's BIN chunk (no uri), a data: URI, or a file beside the .gltf. */
static int load_buffer(gltf *g, int i, const cJSON *b)
{
    char where[40];
    snprintf(where, sizeof where, "buffers[%d]", i);
    long length;
    if (whole(g, b, "byteLength", 1e15, -1, where, &length)) return -1;
    const cJSON *uri = cJSON_GetObjectItemCaseSensitive(b, "uri");
    size_t have = 0;
    if (!uri) {
        if (i != 0 || !g->bin) return rk_fail(g->err, "%s: %s has no uri and there is no GLB BIN chunk for it", g->path, where);
        if (!(g->buffer[i] = rk_calloc(g->bin_bytes + 1, 1, g->err))) return -1;
        memcpy(g->buffer[i], g->bin, g->bin_bytes);
        have = g->bin_bytes;
    } else if (!cJSON_IsString(uri)) {
        return rk_fail(g->err, "%s: %s: 'uri' must be a string", g->path, where);
    } else if (strncmp(uri->valuestring, "data:", 5) == 0) {
        const char *comma = strstr(uri->valuestring, ";base64,");
        if (!comma) return rk_fail(g->err, "%s: %s: a data URI must be base64 (';base64,')", g->path, where);
        if (decode_base64(g, comma + 8, where, &g->buffer[i], &have)) return -1;
    } else {
        char file[4096];
        const char *slash = strrchr(g->path, '/');
        int dir = slash ? (int)(slash - g->path + 1) : 0;
        if (strstr(uri->valuestring, "%") || snprintf(file, sizeof file, "%.*s%s", dir, g->path, uri->valuestring) >= (int)sizeof file)
            return rk_fail(g->err, "%s: %s: uri '%s' is not a plain relative file name", g->path, where, uri->valuestring);
        rk_reader r;
        if (rk_reader_open(&r, file, 0, g->err)) return rk_error_prefix(g->err, "%s: %s", g->path, where);
        g->buffer[i] = (unsigned char *)r.buf; /* taken over: freed with the others */
        have = r.len;
    }
    if (have < (size_t)length)
        return rk_fail(g->err, "%s: %s holds %zu bytes, its byteLength says %ld (truncated)", g->path, where, have, length);
    g->buffer_bytes[i] = (size_t)length; /* the buffer is its byteLength (a GLB chunk may pad past it) */
    return 0;
}

/* One accessor, checked: its element type, component types allowed, and that every element it
 * names lies inside its buffer view and the view inside its buffer. *base, *stride, *count and
 * *component describe where element i is (base + i stride). */
typedef struct {
    const unsigned char *base;
    size_t stride, count;
    int component;
    char name[96];                 /* "accessors[3] (POSITION of meshes[0].primitives[1])" */
} gltf_view;

static size_t component_bytes(int c) { return c == GLTF_U8 ? 1 : c == GLTF_U16 ? 2 : 4; }

static int accessor(gltf *g, long a, const char *role, const char *type, int ncomp, const int *allowed, gltf_view *v)
{
    snprintf(v->name, sizeof v->name, "accessors[%ld] (%s)", a, role);
    const cJSON *acc = cJSON_GetArrayItem(g->accessors, (int)a);
    if (!acc || a >= cJSON_GetArraySize(g->accessors))
        return rk_fail(g->err, "%s: %s: there is no such accessor (the file has %d)", g->path, v->name,
                       cJSON_GetArraySize(g->accessors));
    if (cJSON_GetObjectItemCaseSensitive(acc, "sparse"))
        return rk_fail(g->err, "%s: %s is sparse, which romkit does not read", g->path, v->name);
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(acc, "type");
    if (!cJSON_IsString(t) || strcmp(t->valuestring, type) != 0)
        return rk_fail(g->err, "%s: %s: type must be %s", g->path, v->name, type);
    long comp, count, offset, view;
    if (whole(g, acc, "componentType", 1e5, -1, v->name, &comp) || whole(g, acc, "count", 1e9, -1, v->name, &count) ||
        whole(g, acc, "byteOffset", 1e15, 0, v->name, &offset))
        return -1;
    int ok = 0;
    for (int k = 0; allowed[k]; k++) ok |= comp == allowed[k];
    if (!ok) return rk_fail(g->err, "%s: %s: componentType %ld is not one romkit reads here", g->path, v->name, comp);
    if (!cJSON_GetObjectItemCaseSensitive(acc, "bufferView"))
        return rk_fail(g->err, "%s: %s has no bufferView (all zeros), nothing to read", g->path, v->name);
    if (whole(g, acc, "bufferView", 1e9, -1, v->name, &view)) return -1;
    const cJSON *bv = cJSON_GetArrayItem(g->views, (int)view);
    if (!bv || view >= cJSON_GetArraySize(g->views))
        return rk_fail(g->err, "%s: %s: bufferView %ld does not exist", g->path, v->name, view);
    long buffer, voff, vlen, stride;
    if (whole(g, bv, "buffer", MAX_BUFFERS - 1, -1, v->name, &buffer) || whole(g, bv, "byteOffset", 1e15, 0, v->name, &voff) ||
        whole(g, bv, "byteLength", 1e15, -1, v->name, &vlen) || whole(g, bv, "byteStride", 252, 0, v->name, &stride))
        return -1;
    if (buffer >= g->nbuffers) return rk_fail(g->err, "%s: %s: buffer %ld does not exist", g->path, v->name, buffer);
    if ((size_t)voff + (size_t)vlen > g->buffer_bytes[buffer])
        return rk_fail(g->err, "%s: %s: bufferView %ld runs past the end of buffer %ld (%zu bytes)", g->path, v->name, view,
                       buffer, g->buffer_bytes[buffer]);
    size_t elem = component_bytes((int)comp) * (size_t)ncomp;
    v->stride = stride ? (size_t)stride : elem;
    if (v->stride < elem) return rk_fail(g->err, "%s: %s: byteStride %ld is below an element's %zu bytes", g->path, v->name, stride, elem);
    if (count > 0 && (size_t)offset + v->stride * (size_t)(count - 1) + elem > (size_t)vlen)
        return rk_fail(g->err, "%s: %s: %ld elements from byte %ld run past its bufferView's %ld bytes", g->path, v->name,
                       count, offset, vlen);
    v->base = g->buffer[buffer] + voff + offset;
    v->count = (size_t)count;
    v->component = (int)comp;
    return 0;
}

static uint32_t index_at(const gltf_view *v, size_t i)
{
    const unsigned char *p = v->base + i * v->stride;
    return v->component == GLTF_U8 ? p[0] : v->component == GLTF_U16 ? (uint32_t)(p[0] | p[1] << 8) : le32(p);
}

static int add_triangle(gltf *g, const gltf_view *pos, const double M[16], int flip, uint32_t a, uint32_t b, uint32_t c)
{
    if (a == b || b == c || a == c) return 0; /* a strip's stitching triangles, or a degenerate one */
    if (g->ntris >= RK_MESH_MAX_COUNT / 3) return rk_fail(g->err, "%s: too many triangles", g->path);
    if (rk_grow(&g->corners, &g->cap, 9 * (g->ntris + 1), sizeof(double), g->err)) return -1;
    uint32_t id[3] = {a, flip ? c : b, flip ? b : c};
    double *out = g->corners + 9 * g->ntris;
    for (int k = 0; k < 3; k++) {
        float f[3];
        for (int j = 0; j < 3; j++) {
            uint32_t bits = le32(pos->base + id[k] * pos->stride + 4 * (size_t)j);
            memcpy(&f[j], &bits, 4);
        }
        for (int i = 0; i < 3; i++) {
            out[3 * k + i] = M[i] * f[0] + M[4 + i] * f[1] + M[8 + i] * f[2] + M[12 + i];
            if (!isfinite(out[3 * k + i]))
                return rk_fail(g->err, "%s: %s: vertex %u is not finite (after its node's transform)", g->path, pos->name, id[k]);
        }
    }
    g->ntris++;
    return 0;
}

/* Primitive p of mesh m, under the world transform M. */
static int read_primitive(gltf *g, long m, int p, const cJSON *prim, const double M[16], int flip)
{
    char where[64];
    snprintf(where, sizeof where, "meshes[%ld].primitives[%d]", m, p);
    long mode, ipos, iind;
    if (whole(g, prim, "mode", 6, 4, where, &mode)) return -1;
    if (mode < 4) {
        g->skipped++;
        return 0;
    }
    const cJSON *attrs = cJSON_GetObjectItemCaseSensitive(prim, "attributes");
    if (!cJSON_IsObject(attrs)) return rk_fail(g->err, "%s: %s: 'attributes' must be an object", g->path, where);
    if (whole(g, attrs, "POSITION", 1e9, -1, where, &ipos)) return -1;
    static const int floats[] = {GLTF_F32, 0}, indices[] = {GLTF_U8, GLTF_U16, GLTF_U32, 0};
    char role[80];
    gltf_view pos, ind = {0};
    snprintf(role, sizeof role, "POSITION of %s", where);
    if (accessor(g, ipos, role, "VEC3", 3, floats, &pos)) return -1;
    int indexed = cJSON_GetObjectItemCaseSensitive(prim, "indices") != NULL;
    snprintf(role, sizeof role, "indices of %s", where);
    if (indexed && (whole(g, prim, "indices", 1e9, -1, where, &iind) || accessor(g, iind, role, "SCALAR", 1, indices, &ind)))
        return -1;
    size_t n = indexed ? ind.count : pos.count;
    for (size_t i = 0; indexed && i < n; i++)
        if (index_at(&ind, i) >= pos.count)
            return rk_fail(g->err, "%s: %s: element %zu is %u, but its POSITION holds %zu vertices", g->path, ind.name, i,
                           index_at(&ind, i), pos.count);
#define AT(i) (indexed ? index_at(&ind, (i)) : (uint32_t)(i))
    int rc = 0;
    if (mode == 4)
        for (size_t t = 0; rc == 0 && t + 2 < n; t += 3) rc = add_triangle(g, &pos, M, flip, AT(t), AT(t + 1), AT(t + 2));
    else if (mode == 5) /* strip: every other triangle turns the other way */
        for (size_t t = 0; rc == 0 && t + 2 < n; t++)
            rc = t % 2 ? add_triangle(g, &pos, M, flip, AT(t + 1), AT(t), AT(t + 2))
                       : add_triangle(g, &pos, M, flip, AT(t), AT(t + 1), AT(t + 2));
    else /* fan */
        for (size_t t = 1; rc == 0 && t + 1 < n; t++) rc = add_triangle(g, &pos, M, flip, AT(0), AT(t), AT(t + 1));
#undef AT
    if (rc == 0 && mode == 4 && n % 3)
        rk_warn("%s: %s: %zu indices, not a whole number of triangles: the last %zu dropped", g->path, where, n, n % 3);
    return rc;
}

static void mat_mul(const double A[16], const double B[16], double C[16])
{
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            double s = 0;
            for (int k = 0; k < 4; k++) s += A[4 * k + r] * B[4 * c + k];
            C[4 * c + r] = s;
        }
}

/* The numbers of obj[key] (an array of n), or leaves out alone when absent. */
static int numbers(gltf *g, const cJSON *obj, const char *key, int n, const char *where, double *out)
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!a) return 0;
    if (!cJSON_IsArray(a) || cJSON_GetArraySize(a) != n)
        return rk_fail(g->err, "%s: %s: '%s' must be an array of %d numbers", g->path, where, key, n);
    for (int i = 0; i < n; i++) {
        const cJSON *v = cJSON_GetArrayItem(a, i);
        if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble))
            return rk_fail(g->err, "%s: %s: '%s'[%d] is not a finite number", g->path, where, key, i);
        out[i] = v->valuedouble;
    }
    return 0;
}

/* Node k's local transform: its matrix (column-major), or translation * rotation * scale. */
static int local_transform(gltf *g, const cJSON *node, const char *where, double L[16])
{
    static const double I[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    memcpy(L, I, sizeof I);
    if (cJSON_GetObjectItemCaseSensitive(node, "matrix")) return numbers(g, node, "matrix", 16, where, L);
    double t[3] = {0, 0, 0}, q[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1};
    if (numbers(g, node, "translation", 3, where, t) || numbers(g, node, "rotation", 4, where, q) ||
        numbers(g, node, "scale", 3, where, s))
        return -1;
    double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(n > 0)) return rk_fail(g->err, "%s: %s: the rotation quaternion is zero", g->path, where);
    double x = q[0] / n, y = q[1] / n, z = q[2] / n, w = q[3] / n;
    double R[9] = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w),  /* column 0 */
                   2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w),  /* column 1 */
                   2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y)}; /* column 2 */
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++) L[4 * c + r] = R[3 * c + r] * s[c];
    for (int r = 0; r < 3; r++) L[12 + r] = t[r];
    return 0;
}

static int read_mesh(gltf *g, long m, const double M[16])
{
    const cJSON *mesh = cJSON_GetArrayItem(g->meshes, (int)m);
    if (!mesh || m >= cJSON_GetArraySize(g->meshes)) return rk_fail(g->err, "%s: meshes[%ld] does not exist", g->path, m);
    const cJSON *prims = cJSON_GetObjectItemCaseSensitive(mesh, "primitives");
    double det = M[0] * (M[5] * M[10] - M[9] * M[6]) - M[4] * (M[1] * M[10] - M[9] * M[2]) + M[8] * (M[1] * M[6] - M[5] * M[2]);
    for (int p = 0; p < cJSON_GetArraySize(prims); p++)
        if (read_primitive(g, m, p, cJSON_GetArrayItem(prims, p), M, det < 0)) return -1;
    return 0;
}

/* Node k and its children under the parent transform P; depth bounds a cycle. */
static int read_node(gltf *g, long k, const double P[16], int depth)
{
    char where[40];
    snprintf(where, sizeof where, "nodes[%ld]", k);
    const cJSON *node = cJSON_GetArrayItem(g->nodes, (int)k);
    if (!node || k >= cJSON_GetArraySize(g->nodes)) return rk_fail(g->err, "%s: %s does not exist", g->path, where);
    if (depth > cJSON_GetArraySize(g->nodes) || depth > MAX_DEPTH)
        return rk_fail(g->err, "%s: the node hierarchy has a cycle through %s (or is nested over %d deep)", g->path, where,
                       MAX_DEPTH);
    double L[16], W[16];
    long m;
    if (local_transform(g, node, where, L)) return -1;
    mat_mul(P, L, W);
    if (cJSON_GetObjectItemCaseSensitive(node, "mesh") && (whole(g, node, "mesh", 1e9, -1, where, &m) || read_mesh(g, m, W)))
        return -1;
    const cJSON *c, *kids = cJSON_GetObjectItemCaseSensitive(node, "children");
    cJSON_ArrayForEach(c, kids) /* node indices: check_trees read them first */
        if (read_node(g, (long)c->valuedouble, W, depth + 1)) return -1;
    return 0;
}

/* The default scene's root nodes under I; without scenes, every node without a parent; without
 * nodes, every mesh untransformed. */
static int read_roots(gltf *g, const char *child, const double I[16])
{
    const cJSON *scenes = cJSON_GetObjectItemCaseSensitive(g->root, "scenes");
    if (cJSON_GetArraySize(scenes) > 0) {
        long s;
        if (whole(g, g->root, "scene", cJSON_GetArraySize(scenes) - 1, 0, "the file", &s)) return -1;
        const cJSON *roots = cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(scenes, (int)s), "nodes");
        for (int i = 0; i < cJSON_GetArraySize(roots); i++) {
            const cJSON *r = cJSON_GetArrayItem(roots, i);
            if (!cJSON_IsNumber(r) || r->valuedouble < 0) return rk_fail(g->err, "%s: scenes[%ld]: a root is not a node index", g->path, s);
            if (read_node(g, (long)r->valuedouble, I, 0)) return -1;
        }
        return 0;
    }
    int nn = cJSON_GetArraySize(g->nodes);
    if (nn == 0) {
        for (int m = 0; m < cJSON_GetArraySize(g->meshes); m++)
            if (read_mesh(g, m, I)) return -1;
        return 0;
    }
    for (int k = 0; k < nn; k++)
        if (!child[k] && read_node(g, k, I, 0)) return -1;
    return 0;
}

/* glTF's nodes form trees: a child that is no node, or a node with two parents (which would be
 * walked once per path, exponentially often in a crafted file), is refused. child[k]: k has a parent. */
static int check_trees(gltf *g, char *child)
{
    int nn = cJSON_GetArraySize(g->nodes);
    for (int k = 0; k < nn; k++) {
        const cJSON *kids = cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(g->nodes, k), "children");
        for (int i = 0; i < cJSON_GetArraySize(kids); i++) {
            const cJSON *c = cJSON_GetArrayItem(kids, i);
            if (!cJSON_IsNumber(c) || c->valuedouble < 0 || c->valuedouble >= nn || c->valuedouble != floor(c->valuedouble))
                return rk_fail(g->err, "%s: nodes[%d]: children[%d] is not a node index", g->path, k, i);
            if (child[(int)c->valuedouble]++)
                return rk_fail(g->err, "%s: nodes[%d] has two parents (glTF's nodes form trees)", g->path, (int)c->valuedouble);
        }
    }
    return 0;
}

/* The default scene (read_roots), its node trees checked first. */
static int read_scene(gltf *g)
{
    static const double I[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    int nn = cJSON_GetArraySize(g->nodes);
    char *child = rk_calloc((size_t)nn + 1, 1, g->err);
    if (!child) return -1;
    int rc = check_trees(g, child);
    if (rc == 0) rc = read_roots(g, child, I);
    free(child);
    return rc;
}

/* The JSON text of a .gltf, or of a .glb's first chunk (its BIN chunk into g). */
static int container(gltf *g, rk_reader *r, const char **json, size_t *json_bytes)
{
    const unsigned char *b = (const unsigned char *)r->buf;
    if (r->len < 12 || le32(b) != GLB_MAGIC) { /* a .gltf: the whole file is JSON */
        *json = r->buf;
        *json_bytes = r->len;
        return 0;
    }
    if (le32(b + 4) != 2) return rk_fail(g->err, "%s: GLB version %u (romkit reads 2)", g->path, le32(b + 4));
    if (le32(b + 8) > r->len) return rk_fail(g->err, "%s: the GLB header says %u bytes, the file has %zu (truncated)", g->path, le32(b + 8), r->len);
    size_t at = 12, end = le32(b + 8);
    for (int chunk = 0; at + 8 <= end; chunk++) {
        size_t len = le32(b + at), type = le32(b + at + 4);
        if (len > end - at - 8) return rk_fail(g->err, "%s: GLB chunk %d runs past the end of the file (truncated)", g->path, chunk);
        if (chunk == 0 && type != GLB_JSON) return rk_fail(g->err, "%s: the GLB's first chunk is not JSON", g->path);
        if (chunk == 0) *json = (const char *)b + at + 8, *json_bytes = len;
        if (chunk == 1 && type == GLB_BIN) g->bin = b + at + 8, g->bin_bytes = len;
        at += 8 + len;
    }
    if (!*json) return rk_fail(g->err, "%s: the GLB has no JSON chunk", g->path);
    return 0;
}

int rk_read_gltf(const char *path, rk_surface *s, rk_error *err)
{
    gltf g = {.path = path, .err = err};
    rk_reader r;
    *s = (rk_surface){0};
    if (rk_reader_open(&r, path, 0, err)) return -1;
    const char *json = NULL;
    size_t json_bytes = 0;
    int rc = container(&g, &r, &json, &json_bytes);
    if (rc == 0 && !(g.root = cJSON_ParseWithLength(json, json_bytes)))
        rc = rk_fail(err, "%s: not valid JSON near byte %ld", path, (long)(cJSON_GetErrorPtr() ? cJSON_GetErrorPtr() - json : 0));
    if (rc == 0) {
        const cJSON *req = cJSON_GetObjectItemCaseSensitive(g.root, "extensionsRequired");
        if (cJSON_GetArraySize(req) > 0 && cJSON_IsString(cJSON_GetArrayItem(req, 0)))
            rc = rk_fail(err, "%s: the file requires extension %s, which romkit does not read", path,
                         cJSON_GetArrayItem(req, 0)->valuestring);
    }
    if (rc == 0) {
        g.accessors = cJSON_GetObjectItemCaseSensitive(g.root, "accessors");
        g.views = cJSON_GetObjectItemCaseSensitive(g.root, "bufferViews");
        g.meshes = cJSON_GetObjectItemCaseSensitive(g.root, "meshes");
        g.nodes = cJSON_GetObjectItemCaseSensitive(g.root, "nodes");
        const cJSON *buffers = cJSON_GetObjectItemCaseSensitive(g.root, "buffers");
        if (cJSON_GetArraySize(buffers) > MAX_BUFFERS) rc = rk_fail(err, "%s: more than %d buffers", path, MAX_BUFFERS);
        for (int i = 0; rc == 0 && i < cJSON_GetArraySize(buffers); i++, g.nbuffers++)
            rc = load_buffer(&g, i, cJSON_GetArrayItem(buffers, i));
    }
    if (rc == 0) rc = read_scene(&g);
    if (rc == 0 && g.ntris == 0) rc = rk_fail(err, "%s: no triangles in the default scene", path);
    if (rc == 0 && g.skipped)
        rk_warn("%s: %d primitives of points or lines skipped (a surface is its triangles)", path, g.skipped);
    if (rc == 0) rc = rk_surface_weld(g.corners, (int)g.ntris, s, err);
    for (int i = 0; i < g.nbuffers; i++) free(g.buffer[i]);
    free(g.corners);
    cJSON_Delete(g.root);
    rk_reader_close(&r);
    return rc ? -1 : 0;
}
