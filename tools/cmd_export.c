/* romkit export ASSET.rombin --gltf OUT.glb [--steps N]: the asset's shown vertices as a glTF 2.0
 * morph-target mesh (precompute/export), and a run of N steps by the runtime, from the asset's start
 * under its own scene, as the morph weights' animation. The runtime opens (validates) and steps the
 * asset, and says what is shown, its triangles and the reduced coordinates at every frame; the
 * rows those coordinates multiply come from the container. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "asset_open.h"
#include "commands.h"
#include "export/export.h"
#include "formats/rombin_write.h"
#include "runtime/romrt.h"
#include "util/util.h"

static void export_usage(FILE *f)
{
    fprintf(f, "usage: romkit export ASSET.rombin --gltf OUT.glb [--steps N] [--koopman] [--quiet]\n"
               "  writes the asset's shown vertices as a glTF 2.0 binary mesh at rest (the surface's triangles,\n"
               "  or POINTS for a point cloud; no normals: viewers derive them from the moving positions),\n"
               "  its basis as morph targets (one per reduced coordinate: the shown vertices' rows as POSITION\n"
               "  deltas) and a run as the weights' animation (LINEAR keyframes): N runtime steps from the\n"
               "  asset's start (rest; a Koopman asset's initial state) under its own scene (gravity, pins,\n"
               "  planes as baked), frame 0 the start, keyframe k at k h. At every frame the rest positions\n"
               "  plus the weighted targets are the runtime's positions to float32 rounding (romkit run's).\n"
               "  --gltf      the .glb to write (atomically: nothing is left on failure)\n"
               "  --steps     frames after the start (default 100; 0: no animation, the mesh at the start)\n"
               "  --koopman   export the asset's Koopman operator (targets: its output rows, weights: its\n"
               "              eigen-coordinates y) where the asset also holds a reduced model\n"
               "  --quiet     no progress line\n"
               "  A skinning basis is exported as morph targets too (12 per handle), not as a glTF skin: glTF\n"
               "  joints move only by translation, rotation and scale, a handle's affine map also shears, and\n"
               "  skin weights must be non-negative and sum to one, which skinning eigenmodes' are not.\n\n"
               "example (after romkit build examples/scenes/cantilever_small.json -o cantilever.rombin):\n"
               "  romkit export cantilever.rombin --gltf cantilever.glb --steps 50\n");
}

/* The name of the mesh: the asset file's name without its folder and extension. */
static void base_name(const char *path, char *out, size_t n)
{
    const char *slash = strrchr(path, '/');
    snprintf(out, n, "%s", slash ? slash + 1 : path);
    char *dot = strrchr(out, '.');
    if (dot && dot != out) *dot = 0;
}

/* Steps the model `steps` times from its start; times (steps + 1) and weights ((steps + 1) x r). */
static int run_frames(romrt_model *m, long steps, int quiet, double *times, double *weights, romrt_real *q,
                      rk_error *err)
{
    size_t r = romrt_reduced_size(m);
    double h = (double)romrt_time_step(m);
    romrt_error rerr;
    for (long k = 0; k <= steps; k++) {
        if (k > 0 && romrt_step(m, &rerr) != ROMRT_OK)
            return rk_fail(err, "step %ld: %s: %s", k, romrt_status_string(rerr.status), rerr.message);
        if (romrt_reduced_coordinates(m, q, r, &rerr) != ROMRT_OK)
            return rk_fail(err, "step %ld: %s", k, rerr.message);
        times[k] = (double)k * h;
        for (size_t j = 0; j < r; j++) weights[(size_t)k * r + j] = (double)q[j];
        if (!quiet && k > 0) rk_progress("export run", k, steps);
    }
    if (!quiet && steps > 0) rk_progress_done("export run");
    return 0;
}

int cmd_export(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (is_help(argv[i])) {
            export_usage(stdout);
            return 0;
        }
    const char *path, *out = NULL, *steps_text = NULL;
    int koopman = 0, quiet = 0;
    const cli_option opts[] = {{"--gltf", &out, NULL}, {"--steps", &steps_text, NULL}, {"--koopman", NULL, &koopman},
                               {"--quiet", NULL, &quiet}, {NULL, NULL, NULL}};
    long steps = 100;
    if (cli_parse("export", argc, argv, opts, &path, "asset file")) {
        export_usage(stderr);
        return 2;
    }
    if (!out) {
        fprintf(stderr, "romkit export: --gltf OUT.glb is required\n");
        export_usage(stderr);
        return 2;
    }
    if (steps_text && cli_whole(steps_text, 0, 1000000, &steps)) {
        fprintf(stderr, "romkit export: --steps must be a whole number in 0..1000000, got '%s'\n", steps_text);
        return 2;
    }
    rk_error err = {{0}};
    romrt_error rerr;
    tool_asset asset = {0};
    double *X = NULL, *D = NULL, *times = NULL, *weights = NULL;
    romrt_real *q = NULL;
    uint32_t *tris = NULL;
    int32_t *itris = NULL;
    int rc = 1;
    if (tool_asset_open(&asset, path, koopman, &rerr, &err)) goto fail;
    romrt_model *m = asset.m;
    int n = (int)romrt_shown_count(m), r = (int)romrt_reduced_size(m), nt = (int)romrt_triangle_count(m);
    int is_koopman = romrt_model_kind(m) == ROMRT_KIND_KOOPMAN;
    if (n < 1) {
        rk_fail(&err, "%s shows no vertices (baked with \"show\": \"none\"): there is nothing to draw", path);
        goto fail;
    }
    X = calloc((size_t)3 * n, sizeof(double));
    D = calloc((size_t)3 * n * r, sizeof(double));
    times = calloc((size_t)steps + 1, sizeof(double));
    weights = calloc(((size_t)steps + 1) * r, sizeof(double));
    q = calloc((size_t)r, sizeof(romrt_real));
    itris = calloc((size_t)3 * nt + 1, sizeof(int32_t));
    tris = calloc((size_t)3 * nt + 1, sizeof(uint32_t));
    if (!X || !D || !times || !weights || !q || !itris || !tris) {
        rk_fail(&err, "out of memory for %d shown vertices, r = %d and %ld steps", n, r, steps);
        goto fail;
    }
    if (romrt_triangles(m, itris, (size_t)3 * nt, &rerr)) {
        rk_fail(&err, "%s: %s", path, rerr.message);
        goto fail;
    }
    for (int k = 0; k < 3 * nt; k++) tris[k] = (uint32_t)itris[k];
    if (rk_export_rows(asset.data, asset.bytes, is_koopman, n, r, X, D, &err) ||
        run_frames(m, steps, quiet, times, weights, q, &err)) {
        rk_error_prefix(&err, "%s", path);
        goto fail;
    }
    char name[256];
    base_name(path, name, sizeof name);
    rk_gltf_morph g = {.name = name, .nv = n, .X = X, .ntris = nt, .tris = tris, .r = r, .D = D,
                       .target_prefix = is_koopman ? 'y' : 'q', .rest_weights = weights, .frames = (int)steps + 1,
                       .times = times, .weights = weights};
    if (rk_gltf_write(out, &g, &err)) goto fail;
    printf("%s: %d shown vertices, %d triangles%s, %d morph targets (%s), %ld frames of %g s\n", out, n, nt,
           nt ? "" : " (drawn as points)", r, is_koopman ? "Koopman output rows" : "basis columns", steps + 1,
           (double)romrt_time_step(m));
    rc = 0;
    goto done;
fail:
    fprintf(stderr, "romkit export: %s\n", err.msg);
done:
    tool_asset_close(&asset);
    free(X);
    free(D);
    free(times);
    free(weights);
    free(q);
    free(itris);
    free(tris);
    return rc;
}
