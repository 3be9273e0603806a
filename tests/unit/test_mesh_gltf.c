/* glTF 2.0 surfaces (precompute/mesh/surface_gltf.c): the decimated knight as two primitives (one
 * indexed, one a loose triangle list whose corners must be welded) under a node hierarchy (a
 * matrix, translation-rotation-scale, a mirror), as a .gltf with a .bin beside it, with a data: URI,
 * and as a .glb, reads to the same surface as its twin transformed here; broken files are refused
 * naming the accessor, the buffer or the extension. */
#include "testlib.h"
#include "test_mesh_formats.h"

#include <math.h>

#define GLTF_MAX 4096

typedef struct {
    unsigned char *bin;
    size_t bytes;
    int split;           /* triangles [0, split) indexed (u16), the rest a loose list */
    size_t pos_a, pos_b, idx_a; /* byte offsets of the three arrays */
    int nv, nb;          /* positions of primitive A, corners of primitive B */
} knight_bin;

static void put_float(unsigned char *p, double v)
{
    float f = (float)v;
    memcpy(p, &f, 4); /* little-endian host, as the format (the project's platforms) */
}

static int build_bin(const rk_surface *s, knight_bin *k)
{
    k->split = s->nf / 2;
    k->nv = s->nv;
    k->nb = 3 * (s->nf - k->split);
    k->pos_a = 0;
    k->pos_b = 12 * (size_t)k->nv;
    k->idx_a = k->pos_b + 12 * (size_t)k->nb;
    k->bytes = k->idx_a + 2 * 3 * (size_t)k->split;
    k->bytes = (k->bytes + 3) / 4 * 4;
    k->bin = calloc(k->bytes, 1);
    if (!k->bin) return -1;
    for (int v = 0; v < s->nv; v++)
        for (int d = 0; d < 3; d++) put_float(k->bin + k->pos_a + 12 * (size_t)v + 4 * d, s->X[3 * v + d]);
    for (int c = 0; c < k->nb; c++)
        for (int d = 0; d < 3; d++) put_float(k->bin + k->pos_b + 12 * (size_t)c + 4 * d, s->X[3 * s->tris[3 * k->split + c] + d]);
    for (int i = 0; i < 3 * k->split; i++) {
        uint16_t x = (uint16_t)s->tris[i];
        memcpy(k->bin + k->idx_a + 2 * (size_t)i, &x, 2);
    }
    return 0;
}

/* The node hierarchy: node 0 (a matrix: scale 2, shift) holds node 1 (rotation 90 degrees about z,
 * translation, scale 0.5) holding the mesh; node 2, a mirror in x, holds the mesh again shifted
 * 5 m away (two copies: the mirrored one must stay outward). */
static const double root_matrix[16] = {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 1, 2, 3, 1};

/* JSON for the knight: `uri` is the buffer's "uri" member text (empty: none, the GLB's BIN);
 * extra: text spliced in at the top (an extension, a damage). pos_type: POSITION's componentType. */
static void gltf_json(char *out, size_t cap, const knight_bin *k, const char *uri, const char *extra, int pos_accessor,
                      int pos_type, long byte_length)
{
    snprintf(out, cap,
             "{\"asset\": {\"version\": \"2.0\"}, %s"
             " \"scene\": 0, \"scenes\": [{\"nodes\": [0, 2]}],"
             " \"nodes\": [{\"matrix\": [2,0,0,0, 0,2,0,0, 0,0,2,0, 1,2,3,1], \"children\": [1]},"
             "  {\"mesh\": 0, \"translation\": [0.5, 0, -1], \"rotation\": [0, 0, 0.70710678118654752, 0.70710678118654752],"
             "   \"scale\": [0.5, 0.5, 0.5]},"
             "  {\"mesh\": 0, \"scale\": [-1, 1, 1], \"translation\": [5, 0, 0]}],"
             " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": %d}, \"indices\": 2},"
             "  {\"attributes\": {\"POSITION\": 1}, \"mode\": 4}, {\"attributes\": {\"POSITION\": 1}, \"mode\": 0}]}],"
             " \"accessors\": [{\"bufferView\": 0, \"componentType\": %d, \"count\": %d, \"type\": \"VEC3\"},"
             "  {\"bufferView\": 1, \"componentType\": 5126, \"count\": %d, \"type\": \"VEC3\"},"
             "  {\"bufferView\": 2, \"componentType\": 5123, \"count\": %d, \"type\": \"SCALAR\"}],"
             " \"bufferViews\": [{\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu},"
             "  {\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu},"
             "  {\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu}],"
             " \"buffers\": [{%s\"byteLength\": %ld}]}",
             extra, pos_accessor, pos_type, k->nv, k->nb, 3 * k->split, k->pos_a, 12 * (size_t)k->nv, k->pos_b,
             12 * (size_t)k->nb, k->idx_a, 2 * 3 * (size_t)k->split, uri, byte_length);
}

/* The twin: the knight's surface under both node paths, in double from the float-rounded positions,
 * the mirrored copy's triangles turned over. */
static void twin(const rk_surface *s, rk_surface *t)
{
    t->nv = 2 * s->nv;
    t->nf = 2 * s->nf;
    t->X = calloc(3 * (size_t)t->nv, sizeof(double));
    t->tris = calloc(3 * (size_t)t->nf, sizeof(int));
    for (int v = 0; v < s->nv; v++) {
        double p[3] = {(float)s->X[3 * v], (float)s->X[3 * v + 1], (float)s->X[3 * v + 2]};
        /* node 1: scale 0.5, rotate 90 about z (x -> y, y -> -x), translate */
        double q[3] = {-0.5 * p[1] + 0.5, 0.5 * p[0], 0.5 * p[2] - 1};
        for (int d = 0; d < 3; d++) t->X[3 * v + d] = root_matrix[5 * d] * q[d] + root_matrix[12 + d];
        double m[3] = {-p[0] + 5, p[1], p[2]};
        memcpy(t->X + 3 * (size_t)(s->nv + v), m, sizeof m);
    }
    for (int f = 0; f < s->nf; f++) {
        for (int k = 0; k < 3; k++) t->tris[3 * f + k] = s->tris[3 * f + k];
        t->tris[3 * (s->nf + f)] = s->nv + s->tris[3 * f];
        t->tris[3 * (s->nf + f) + 1] = s->nv + s->tris[3 * f + 2];
        t->tris[3 * (s->nf + f) + 2] = s->nv + s->tris[3 * f + 1];
    }
}

/* a and b the same surface up to vertex order and each triangle's starting corner: every vertex of
 * a within tol of one of b, and the triangles the same under that map. */
static int same_up_to_order(const rk_surface *a, const rk_surface *b, double tol, char *why, size_t cap)
{
    if (a->nv != b->nv || a->nf != b->nf) {
        snprintf(why, cap, "counts %d vertices / %d triangles against %d / %d", a->nv, a->nf, b->nv, b->nf);
        return 0;
    }
    int *map = calloc((size_t)a->nv, sizeof(int)), ok = 1;
    for (int i = 0; i < a->nv && ok; i++) {
        int best = -1;
        double bd = INFINITY;
        for (int j = 0; j < b->nv; j++) {
            double d = 0;
            for (int k = 0; k < 3; k++) d = fmax(d, fabs(a->X[3 * i + k] - b->X[3 * j + k]));
            if (d < bd) bd = d, best = j;
        }
        map[i] = best;
        if (bd > tol) snprintf(why, cap, "vertex %d is %.3g from the twin's nearest", i, bd), ok = 0;
    }
    char *used = calloc((size_t)b->nf, 1);
    for (int f = 0; f < a->nf && ok; f++) {
        int t[3] = {map[a->tris[3 * f]], map[a->tris[3 * f + 1]], map[a->tris[3 * f + 2]]}, found = 0;
        for (int g = 0; g < b->nf && !found; g++) {
            if (used[g]) continue;
            const int *u = b->tris + 3 * g;
            for (int r = 0; r < 3 && !found; r++)
                if (u[r] == t[0] && u[(r + 1) % 3] == t[1] && u[(r + 2) % 3] == t[2]) found = 1, used[g] = 1;
        }
        if (!found) snprintf(why, cap, "triangle %d has no twin of the same orientation", f), ok = 0;
    }
    free(used);
    free(map);
    return ok;
}

static void base64(const unsigned char *in, size_t n, char *out)
{
    static const char a[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t o = 0;
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)in[i] << 16 | (i + 1 < n ? (uint32_t)in[i + 1] << 8 : 0) | (i + 2 < n ? in[i + 2] : 0);
        out[o++] = a[v >> 18 & 63], out[o++] = a[v >> 12 & 63];
        out[o++] = i + 1 < n ? a[v >> 6 & 63] : '=';
        out[o++] = i + 2 < n ? a[v & 63] : '=';
    }
    out[o] = 0;
}

static int write_glb(const char *path, const char *json, const knight_bin *k)
{
    size_t jl = (strlen(json) + 3) / 4 * 4, total = 12 + 8 + jl + 8 + k->bytes;
    unsigned char *b = calloc(total, 1);
    uint32_t h[3] = {0x46546C67u, 2, (uint32_t)total}, jc[2] = {(uint32_t)jl, 0x4E4F534Au}, bc[2] = {(uint32_t)k->bytes, 0x004E4942u};
    memcpy(b, h, 12);
    memcpy(b + 12, jc, 8);
    memset(b + 20, ' ', jl);
    memcpy(b + 20, json, strlen(json));
    memcpy(b + 20 + jl, bc, 8);
    memcpy(b + 28 + jl, k->bin, k->bytes);
    int rc = write_all(path, b, (long)total);
    free(b);
    return rc;
}

static rk_surface knight, expected;
static knight_bin kb;
static char dir[512];

static int setup(rk_error *err)
{
    if (rk_surface_load(test_data("meshes/decimated-knight.off"), &knight, err) || build_bin(&knight, &kb)) return -1;
    twin(&knight, &expected);
    tl_scratch(dir, sizeof dir, "gltf_knight");
    char bin[600];
    snprintf(bin, sizeof bin, "%s.bin", dir);
    return write_all(bin, kb.bin, (long)kb.bytes);
}

/* Writes the .gltf (buffer beside it) with the given damage and reads it. */
static int read_variant(const char *extra, int pos_accessor, int pos_type, long byte_length, rk_surface *s, rk_error *err)
{
    static char json[GLTF_MAX * 2];
    char path[600], uri[700];
    const char *slash = strrchr(dir, '/');
    snprintf(uri, sizeof uri, "\"uri\": \"%s.bin\", ", slash ? slash + 1 : dir);
    gltf_json(json, sizeof json, &kb, uri, extra, pos_accessor, pos_type, byte_length);
    snprintf(path, sizeof path, "%s.gltf", dir);
    if (write_all(path, json, (long)strlen(json))) return rk_fail(err, "cannot write %s", path);
    return rk_surface_load(path, s, err);
}

TEST(gltf_bin_data_uri_and_glb_read_as_their_obj_twin)
{
    rk_error err = {{0}};
    CHECK_OK(setup(&err));
    char why[256], path[600];
    rk_surface s;
    CHECK_OK(read_variant("", 0, 5126, (long)kb.bytes, &s, &err));
    CHECK(same_up_to_order(&s, &expected, 1e-12, why, sizeof why), ".gltf + .bin: %s", why);
    CHECK(rk_surface_check(&s, "knight.gltf", &err) == 0, "the read surface is not closed and outward: %s", err.msg);
    rk_surface_free(&s);

    size_t n64 = (kb.bytes + 2) / 3 * 4;
    char *uri = calloc(n64 + 100, 1), *json = calloc(n64 + 2 * GLTF_MAX, 1);
    strcpy(uri, "\"uri\": \"data:application/octet-stream;base64,");
    base64(kb.bin, kb.bytes, uri + strlen(uri));
    strcat(uri, "\", ");
    gltf_json(json, n64 + 2 * GLTF_MAX, &kb, uri, "", 0, 5126, (long)kb.bytes);
    snprintf(path, sizeof path, "%s_data.gltf", dir);
    CHECK(write_all(path, json, (long)strlen(json)) == 0, "write");
    CHECK_OK(rk_surface_load(path, &s, &err));
    CHECK(same_up_to_order(&s, &expected, 1e-12, why, sizeof why), "data URI: %s", why);
    rk_surface_free(&s);

    gltf_json(json, n64 + 2 * GLTF_MAX, &kb, "", "", 0, 5126, (long)kb.bytes);
    snprintf(path, sizeof path, "%s.glb", dir);
    CHECK(write_glb(path, json, &kb) == 0, "write");
    CHECK_OK(rk_surface_load(path, &s, &err));
    CHECK(same_up_to_order(&s, &expected, 1e-12, why, sizeof why), ".glb: %s", why);
    rk_surface_free(&s);
    free(uri);
    free(json);
}

/* Each damage is refused with a message naming what and where. */
static void expect_refused(const char *label, const char *extra, int pos_accessor, int pos_type, long byte_length,
                           const char *message)
{
    rk_error err = {{0}};
    rk_surface s;
    int rc = read_variant(extra, pos_accessor, pos_type, byte_length, &s, &err);
    if (rc == 0) rk_surface_free(&s);
    printf("# %s: %s\n", label, err.msg);
    CHECK(rc != 0 && strstr(err.msg, message), "%s: expected '%s', got '%s'", label, message, rc ? err.msg : "success");
}

TEST(broken_gltf_is_refused_naming_the_accessor)
{
    expect_refused("bad accessor", "", 9, 5126, (long)kb.bytes,
                   "accessors[9] (POSITION of meshes[0].primitives[0]): there is no such accessor");
    expect_refused("truncated buffer", "", 0, 5126, (long)kb.bytes + 64, "(truncated)");
    expect_refused("wrong component type", "", 0, 5123, (long)kb.bytes,
                   "accessors[0] (POSITION of meshes[0].primitives[0]): componentType 5123 is not one romkit reads here");
    expect_refused("compressed", "\"extensionsRequired\": [\"KHR_draco_mesh_compression\"],", 0, 5126, (long)kb.bytes,
                   "requires extension KHR_draco_mesh_compression");
    expect_refused("a view past its buffer", "", 0, 5126, 12, "runs past the end of buffer 0");
}

int main(void)
{
    RUN(gltf_bin_data_uri_and_glb_read_as_their_obj_twin);
    RUN(broken_gltf_is_refused_naming_the_accessor);
    static const char *const made[] = {".gltf", ".bin", "_data.gltf", ".glb"};
    for (int i = 0; i < 4; i++) {
        char path[600];
        snprintf(path, sizeof path, "%s%s", dir, made[i]);
        remove(path);
    }
    rk_surface_free(&knight);
    rk_surface_free(&expected);
    free(kb.bin);
    return test_finish();
}
