/* romkit build SCENE.json -o OUT.rombin: the whole pipeline the scene's (first) rom entry asks
 * for, baked into an asset the runtime opens in place (precompute/asset, formats/ROMBIN.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "asset_open.h"
#include "commands.h"
#include "formats/rombin_read.h"
#include "formats/rombin_write.h"
#include "pipeline/pipeline.h"
#include "stage_inputs.h"
#include "util/util.h"

/* Opens the written asset with this romkit's runtime, as romkit run would, and warns when the
 * runtime finds its model inconsistent (ROMRT_E_MODEL): a basis whose columns are nearly dependent
 * bakes a reduced mass that a float32 Cholesky cannot factor (a thin bar's clamped skinning weights
 * times affine handles), which the double precompute does not see. Other refusals (an r above this
 * build's bound, a Koopman-only asset) are an app's runtime's business, not warned of. */
static void warn_if_runtime_refuses(const char *path)
{
    tool_asset a;
    romrt_error rerr;
    rk_error err = {{0}};
    if (tool_asset_open(&a, path, 0, &rerr, &err) && rerr.status == ROMRT_E_MODEL) {
        rombin_file file;
        rombin_error fe;
        /* a float64 asset whose mass does not factor has columns dependent in double as well */
        int f64 = a.data && !rombin_open(&file, a.data, a.bytes, NULL, &fe) && file.real_type == ROMBIN_REAL_F64;
        const char *hint = !strstr(err.msg, "'MASS'") ? ""
                           : f64 ? " (the basis's columns are dependent even in double: fewer weights, rom.size)"
                                 : " (the basis's columns are nearly dependent at this precision: bake with "
                                   "--precision float64, or fewer weights)";
        fprintf(stderr, "romkit build: warning: %s does not open in this romkit's %s runtime: %s%s\n", path,
                sizeof(romrt_real) == 4 ? "float32" : "float64", err.msg, hint);
    }
    tool_asset_close(&a);
}

static void build_usage(FILE *f)
{
    fprintf(f, "usage: romkit build SCENE.json -o OUT.rombin [--report R.json] [--precision float32|float64]\n"
               "                    [--compress] [--entry K] [--training S.npy] [--quiet]\n"
               "                    [--training-run S.npy ...] [--basis U.npy] [--cubature C.json]\n"
               "                    [--trajectory-run S.npy ...]\n"
               "  builds the reduced model of one rom entry of the scene (basis, cubature) and bakes it\n"
               "  into OUT.rombin with only what the runtime needs: the reduced operators, the cubature\n"
               "  elements with the basis rows of the vertices they touch, and the rows of the shown\n"
               "  vertices (rom.asset.show, default the surface) and of the named groups (rom.asset.groups).\n"
               "  With rom.koopman the asset holds a Koopman operator instead, learned by DMD from the\n"
               "  scene's own full-order runs (rom.koopman.trajectories vary gravity, initial velocity and\n"
               "  loads; rom.koopman.project fits on the basis's coordinates; rank, energy, clamp).\n"
               "  --precision   real type of the asset's arrays (default rom.asset.precision, else float32)\n"
               "  --compress    deflate the chunks (smaller to ship; romkit run inflates, the runtime\n"
               "                itself opens stored chunks only)\n"
               "  --report      sizes, eigenvalues, cubature, the asset's chunks and bytes, timings\n"
               "  --entry K     bake entry K of the scene's rom list instead of the first (0)\n"
               "  --training    the scene's full-order frames from romkit fom --snapshots, used instead\n"
               "                of running the scene again (cubature, POD and tolerances train on them)\n"
               "  --training-run  one per item of the entry's training list, in order: that item's frames\n"
               "                (romkit fom ITEM --snapshots), read instead of running the item here\n"
               "  --trajectory-run  one per rom.koopman trajectory, in order: its frames (romkit fom\n"
               "                --entry K --trajectory I --snapshots), read instead of running it here\n"
               "  --basis       the basis from romkit basis --basis (modes, modal_derivatives, pod)\n"
               "  --cubature    the cubature from romkit cubature -o (element ids and weights)\n"
               "                (the three are the steps of romkit plan: the asset is byte-identical)\n"
               "  --quiet       no progress lines on stderr\n"
               "  Nothing is written when the build fails.\n\n"
               "example:\n"
               "  romkit build examples/scenes/cantilever_small.json -o cantilever.rombin --report build.json\n");
}

int cmd_build(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (is_help(argv[i])) {
            build_usage(stdout);
            return 0;
        }
    const char *scene_path, *out = NULL, *report_out = NULL, *precision = NULL, *entry_text = NULL;
    int quiet = 0, compress = 0;
    tool_stage st = {0};
    const cli_option opts[] = {{"-o", &out, NULL},           {"--report", &report_out, NULL},
                               {"--precision", &precision, NULL}, {"--compress", NULL, &compress},
                               {"--entry", &entry_text, NULL}, {"--training", &st.training, NULL},
                               {"--basis", &st.basis, NULL},   {"--cubature", &st.cubature, NULL},
                               {"--quiet", NULL, &quiet},     {NULL, NULL, NULL}};
    if (tool_stage_args("build", &argc, argv, &st) || cli_parse("build", argc, argv, opts, &scene_path, "scene file")) {
        build_usage(stderr);
        return 2;
    }
    if (!out) {
        fprintf(stderr, "romkit build: -o OUT.rombin is required\n");
        build_usage(stderr);
        return 2;
    }
    rk_bake_request req = {.compress = compress};
    if (cli_precision("build", precision, &req.has_real_type, &req.real_type)) return 2;
    rk_progress_set_quiet(quiet);
    rk_error err = {{0}};
    rk_scene scene;
    rk_baked baked = {0};
    const rk_rom_entry *e;
    int have_scene = 0, rc = 1;
    long entry = 0;
    if (rk_scene_load(scene_path, &scene, &err)) goto done;
    have_scene = 1;
    if (entry_text && (scene.nentries == 0 || cli_whole(entry_text, 0, scene.nentries - 1, &entry))) {
        rk_fail(&err, "--entry must be a rom entry of %s, 0..%d, got '%s'", scene_path, scene.nentries - 1, entry_text);
        goto done;
    }
    if (rk_scene_entry(&scene, (int)entry, &e, &err)) goto done;
    if (tool_stage_load(&st, &scene, e, &req, &err)) goto done;
    if (rk_scene_bake(&scene, e, &req, &baked, &err)) {
        if (st.training) rk_error_prefix(&err, "--training %s", st.training);
        goto done;
    }
    if (rombin_save(out, baked.data, baked.bytes, &err) ||
        (report_out && rk_json_write_file(report_out, baked.report, &err)))
        goto done;
    printf("%s: %s\n", out, baked.summary);
    warn_if_runtime_refuses(out);
    rc = 0;
done:
    if (rc) fprintf(stderr, "romkit build: %s\n", err.msg);
    tool_stage_free(&st);
    rk_baked_free(&baked);
    if (have_scene) rk_scene_free(&scene);
    return rc;
}
