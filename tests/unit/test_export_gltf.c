/* precompute/export's .glb writer on a hand-made tetrahedron: the container's layout (header,
 * 4-byte aligned chunks, padding), the JSON's accessors against the bytes they point at (min/max
 * exactly the float32 data), points without indices, and bad input refused with nothing written. */
#include <cjson/cJSON.h>
#include <dirent.h>
#include <stdint.h>
#include <unistd.h>

#include "export/export.h"
#include "testlib.h"

static const double X[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1.1};
static const uint32_t TRIS[12] = {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2};
/* two targets: the apex up by 0.1 and a shear with -1/3 (values that round in float32: min/max must be
 * the rounded ones) */
static const double D[24] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0.1, 0, 0, 0, 0.3, 0, 0, 0.3, 0, 0, -1.0 / 3, 0.05268761143088341, 0};
static const double TIMES[3] = {0, 0.01f, 2 * (double)0.01f};
static const double W[6] = {0, 0, 0.5, -0.25, 1, 1.0 / 7};
static const double REST[2] = {0, 0};

static rk_gltf_morph tetra(void)
{
    rk_gltf_morph m = {.name = "tetra", .nv = 4, .X = X, .ntris = 4, .tris = TRIS, .r = 2, .D = D,
                       .target_prefix = 'q', .rest_weights = REST, .frames = 3, .times = TIMES, .weights = W};
    return m;
}

static uint32_t u32(const unsigned char *p) { return p[0] | p[1] << 8 | p[2] << 16 | (uint32_t)p[3] << 24; }

/* The whole file at path (malloc'd), its size in *n; NULL if it cannot be read. */
static unsigned char *slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    unsigned char *b = malloc(1 << 16);
    *n = fread(b, 1, 1 << 16, f);
    fclose(f);
    return b;
}

/* Files in dir whose names start with prefix (the target and its temporary files). */
static int files_in(const char *dir, const char *prefix)
{
    DIR *d = opendir(dir);
    int n = 0;
    for (struct dirent *e; d && (e = readdir(d));) n += strncmp(e->d_name, prefix, strlen(prefix)) == 0;
    if (d) closedir(d);
    return n;
}

static char dir[512];

/* Accessor a's float32 component k, read through its buffer view. */
static float accessor_float(const cJSON *root, const unsigned char *bin, int a, int comps, int i, int c)
{
    const cJSON *acc = cJSON_GetArrayItem(cJSON_GetObjectItem(root, "accessors"), a);
    const cJSON *view = cJSON_GetArrayItem(cJSON_GetObjectItem(root, "bufferViews"),
                                           cJSON_GetObjectItem(acc, "bufferView")->valueint);
    const cJSON *off = cJSON_GetObjectItem(acc, "byteOffset"), *stride = cJSON_GetObjectItem(view, "byteStride");
    size_t at = (size_t)cJSON_GetObjectItem(view, "byteOffset")->valuedouble + (off ? (size_t)off->valuedouble : 0) +
                (size_t)i * (stride ? (size_t)stride->valueint : 4 * (size_t)comps) + 4 * (size_t)c;
    uint32_t bits = u32(bin + at);
    float f;
    memcpy(&f, &bits, 4);
    return f;
}

TEST(writes_an_aligned_glb_whose_accessors_match_their_bytes)
{
    rk_error err;
    char path[256];
    snprintf(path, sizeof path, "%s/t.glb", dir);
    rk_gltf_morph m = tetra();
    CHECK_OK(rk_gltf_write(path, &m, &err));
    size_t n;
    unsigned char *b = slurp(path, &n);
    CHECK(b && n > 28, "no file");
    CHECK(u32(b) == 0x46546C67 && u32(b + 4) == 2 && u32(b + 8) == n, "header %x %u %u of %zu", u32(b), u32(b + 4),
          u32(b + 8), n);
    uint32_t jl = u32(b + 12), bl = u32(b + 20 + jl);
    CHECK(jl % 4 == 0 && u32(b + 16) == 0x4E4F534A && u32(b + 24 + jl) == 0x004E4942 && bl % 4 == 0 &&
              28 + jl + bl == n, "chunks: JSON %u, BIN %u bytes in %zu", jl, bl, n);
    char *json = malloc(jl + 1);
    memcpy(json, b + 20, jl);
    json[jl] = 0;
    cJSON *root = cJSON_Parse(json);
    CHECK(root, "JSON chunk does not parse: %s", json);
    const unsigned char *bin = b + 28 + jl;
    /* accessor 0: positions; 1, 2: targets; 3: indices; 4: times; 5: weights */
    const cJSON *acc = cJSON_GetObjectItem(root, "accessors");
    CHECK(cJSON_GetArraySize(acc) == 6, "%d accessors", cJSON_GetArraySize(acc));
    for (int a = 0; a < 3; a++) {
        const cJSON *mn = cJSON_GetObjectItem(cJSON_GetArrayItem(acc, a), "min");
        const cJSON *mx = cJSON_GetObjectItem(cJSON_GetArrayItem(acc, a), "max");
        CHECK(mn && mx, "accessor %d has no min/max", a);
        for (int c = 0; c < 3; c++) {
            double lo = INFINITY, hi = -INFINITY;
            for (int i = 0; i < 4; i++) {
                float f = accessor_float(root, bin, a, 3, i, c);
                CHECK(f == (float)(a ? D[12 * (a - 1) + 3 * i + c] : X[3 * i + c]), "accessor %d vertex %d", a, i);
                lo = fmin(lo, f), hi = fmax(hi, f);
            }
            CHECK(cJSON_GetArrayItem(mn, c)->valuedouble == lo && cJSON_GetArrayItem(mx, c)->valuedouble == hi,
                  "accessor %d component %d: min/max %.17g %.17g, data %.17g %.17g", a, c,
                  cJSON_GetArrayItem(mn, c)->valuedouble, cJSON_GetArrayItem(mx, c)->valuedouble, lo, hi);
        }
    }
    for (int k = 0; k < 6; k++) CHECK(accessor_float(root, bin, 5, 1, k, 0) == (float)W[k], "weight %d", k);
    for (int k = 0; k < 3; k++) CHECK(accessor_float(root, bin, 4, 1, k, 0) == (float)TIMES[k], "time %d", k);
    const cJSON *prim = cJSON_GetArrayItem(cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(root, "meshes"), 0),
                                                               "primitives"), 0);
    CHECK(cJSON_GetObjectItem(prim, "mode")->valueint == 4 && cJSON_GetObjectItem(prim, "indices")->valueint == 3,
          "triangles through accessor 3");
    cJSON_Delete(root);
    free(json);
    free(b);
    unlink(path);
}

TEST(a_point_cloud_is_points_without_indices_and_no_frames_no_animation)
{
    rk_error err;
    char path[256];
    snprintf(path, sizeof path, "%s/p.glb", dir);
    rk_gltf_morph m = tetra();
    m.ntris = 0;
    m.frames = 1;
    CHECK_OK(rk_gltf_write(path, &m, &err));
    size_t n;
    unsigned char *b = slurp(path, &n);
    CHECK(b, "no file");
    uint32_t jl = u32(b + 12);
    char *json = calloc(jl + 1, 1);
    memcpy(json, b + 20, jl);
    cJSON *root = cJSON_Parse(json);
    const cJSON *prim = cJSON_GetArrayItem(cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(root, "meshes"), 0),
                                                               "primitives"), 0);
    CHECK(root && cJSON_GetObjectItem(prim, "mode")->valueint == 0 && !cJSON_GetObjectItem(prim, "indices") &&
              !cJSON_GetObjectItem(root, "animations") && u32(b + 20 + jl) == 4 * 12 * 3,
          "points, no indices, no animation, only positions and targets in BIN: %s", json);
    cJSON_Delete(root);
    free(json);
    free(b);
    unlink(path);
}

TEST(bad_input_is_refused_and_writes_nothing)
{
    rk_error err;
    char path[256];
    snprintf(path, sizeof path, "%s/bad.glb", dir);
    double w[6], times[3] = {0, 0.01, 0.01}, nan_x[12];
    uint32_t tris[12];
    memcpy(w, W, sizeof w);
    w[3] = NAN;
    memcpy(nan_x, X, sizeof nan_x);
    nan_x[4] = 1e39; /* finite in double, infinite in float32 */
    memcpy(tris, TRIS, sizeof tris);
    tris[7] = 4;
    rk_gltf_morph m = tetra();
    m.weights = w;
    CHECK(rk_gltf_write(path, &m, &err) != 0 && strstr(err.msg, "morph weights"), "NaN weight: %s", err.msg);
    m = tetra();
    m.times = times;
    CHECK(rk_gltf_write(path, &m, &err) != 0 && strstr(err.msg, "keyframe 2"), "repeated time: %s", err.msg);
    m = tetra();
    m.X = nan_x;
    CHECK(rk_gltf_write(path, &m, &err) != 0 && strstr(err.msg, "rest positions"), "overflow: %s", err.msg);
    m = tetra();
    m.tris = tris;
    CHECK(rk_gltf_write(path, &m, &err) != 0 && strstr(err.msg, "triangle 2 uses vertex 4"), "index: %s", err.msg);
    CHECK(files_in(dir, "bad.glb") == 0, "a refused export left %d files in %s", files_in(dir, "bad.glb"), dir);
}

int main(void)
{
    snprintf(dir, sizeof dir, "%s/rk_test_export_XXXXXX", tl_tmpdir());
    if (!mkdtemp(dir)) return 1;
    RUN(writes_an_aligned_glb_whose_accessors_match_their_bytes);
    RUN(a_point_cloud_is_points_without_indices_and_no_frames_no_animation);
    RUN(bad_input_is_refused_and_writes_nothing);
    rmdir(dir); /* fails, leaving the folder to look at, when a test left a file */
    return test_finish();
}
