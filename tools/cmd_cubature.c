/* romkit cubature SCENE.json -o C.json: the cubature step of a split bake (romkit plan): entry K's
 * reduced model on a basis from romkit basis --basis, its cubature trained on the training files as
 * romkit build trains it, written as element ids and weights for romkit build --cubature. */
#include <stdio.h>
#include <stdlib.h>

#include "args.h"
#include "commands.h"
#include "pipeline/method_fixed.h"
#include "stage_inputs.h"
#include "util/util.h"

static void cubature_usage(FILE *f)
{
    fprintf(f, "usage: romkit cubature SCENE.json -o C.json [--entry K] [--basis U.npy]\n"
               "                       [--training S.npy | --training-run S.npy ...] [--quiet]\n"
               "  trains the cubature of rom entry K (default 0; it must have rom.cubature) as romkit build\n"
               "  does and writes its elements and weights (JSON: elements, weights, relative_error,\n"
               "  reached, greedy_count, poses) for romkit build --cubature; a step of romkit plan.\n"
               "  --basis         the basis from romkit basis --basis (else built here)\n"
               "  --training      the scene's own full-order run (romkit fom --snapshots), not run here\n"
               "  --training-run  one per item of the entry's training list, in order\n"
               "  Nothing is written when it fails.\n\n"
               "example:\n"
               "  romkit basis examples/scenes/cantilever_small.json --basis U.npy\n"
               "  romkit fom examples/scenes/cantilever_small.json --snapshots S.npy\n"
               "  romkit cubature examples/scenes/cantilever_small.json --basis U.npy --training S.npy -o C.json\n");
}

int cmd_cubature(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (is_help(argv[i])) {
            cubature_usage(stdout);
            return 0;
        }
    const char *scene_path, *out = NULL, *entry_text = "0";
    int quiet = 0;
    tool_stage st = {0};
    const cli_option opts[] = {{"-o", &out, NULL},           {"--entry", &entry_text, NULL},
                               {"--basis", &st.basis, NULL}, {"--training", &st.training, NULL},
                               {"--quiet", NULL, &quiet},    {NULL, NULL, NULL}};
    if (tool_stage_args("cubature", &argc, argv, &st) || cli_parse("cubature", argc, argv, opts, &scene_path, "scene file")) {
        cubature_usage(stderr);
        return 2;
    }
    if (!out) {
        fprintf(stderr, "romkit cubature: -o C.json is required\n");
        cubature_usage(stderr);
        return 2;
    }
    rk_progress_set_quiet(quiet);
    rk_error err = {{0}};
    rk_scene scene;
    rk_scene_sim sim;
    rk_scene_rom R;
    const rk_rom_entry *e;
    rk_bake_request req = {0};
    double *frames = NULL;
    const char *trained_on;
    int have_scene = 0, have_sim = 0, have_rom = 0, rc = 1, T = 0;
    long entry = 0;
    if (rk_scene_load(scene_path, &scene, &err)) goto done;
    have_scene = 1;
    if (scene.nentries == 0 || cli_whole(entry_text, 0, scene.nentries - 1, &entry)) {
        rk_fail(&err, "--entry must be a rom entry of %s, 0..%d, got '%s'", scene_path, scene.nentries - 1, entry_text);
        goto done;
    }
    if (rk_scene_entry(&scene, (int)entry, &e, &err)) goto done;
    if (!e->cubature) {
        rk_fail(&err, "%s (%s) has no rom.cubature: it integrates exactly, there is no cubature to train", e->path, e->name);
        goto done;
    }
    if (tool_stage_load(&st, &scene, e, &req, &err)) goto done;
    if (rk_scene_build(&scene, &sim, &err)) goto done;
    have_sim = 1;
    if (rk_scene_entry_frames(&scene, &sim, e, &req, &frames, &T, &trained_on, &err)) goto done;
    rk_scene_rom_given g = {req.basis, NULL, 0};
    if (rk_scene_rom_build_given(&scene, &sim, e, frames, T, &g, &R, &err)) goto done;
    have_rom = 1;
    if (rk_scene_cubature_write(out, &R, &err)) goto done;
    printf("%s: %d of %d elements, trained on %s: %s\n", out, R.cubature_set.count, sim.mesh.nt, trained_on,
           R.cubature_reason);
    rc = 0;
done:
    if (rc) fprintf(stderr, "romkit cubature: %s\n", err.msg);
    free(frames);
    tool_stage_free(&st);
    if (have_rom) rk_scene_rom_free(&R);
    if (have_sim) rk_scene_sim_free(&sim);
    if (have_scene) rk_scene_free(&scene);
    return rc;
}
