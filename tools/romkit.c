/* romkit: the command line. One subcommand per file; this file only dispatches. */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "util/util.h"

typedef struct {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
} command;

static const command commands[] = { /* in pipeline order */
    {"mesh", cmd_mesh, "check, convert or tetrahedralize a mesh (prints counts and quality)"},
    {"fom", cmd_fom, "full-order simulation of a scene (ground truth and training data)"},
    {"motions", cmd_motions, "training scenes: the object dropped through pachinko pegs or tumbled in a drum"},
    {"adaptive", cmd_adaptive, "a scene's adaptive_subspace entry on its own (romkit fom's outputs, the model's sizes)"},
    {"basis", cmd_basis, "build the reduced basis a scene's rom section asks for (no asset)"},
    {"cubature", cmd_cubature, "train the cubature of a scene's rom entry on a given basis (a step of plan)"},
    {"build", cmd_build, "bake the scene's reduced model into a .rombin asset for the runtime"},
    {"plan", cmd_plan, "the bake as a job graph: steps, files, a Makefile and Slurm scripts"},
    {"run", cmd_run, "step a .rombin asset with the runtime, as an application would"},
    {"rom", cmd_rom, "step a scene's reduced model in the reduced simulator, every object (splats per frame)"},
    {"compare", cmd_compare, "full-order model and every reduced method of a scene: error against time"},
    {"track", cmd_track, "dot markers followed through the frames of calibrated views (Lucas-Kanade tracks)"},
    {"dmd", cmd_dmd, "a Koopman operator (DMD) from outside snapshot data, baked into a .rombin asset"},
    {"neural-dmd", cmd_neural_dmd, "the neural DMD trained on a family of meshes and shape codes, baked at one"},
    {"control", cmd_control, "forces on named groups that make a scene's Koopman model follow a target trajectory"},
    {"inspect", cmd_inspect, "list and verify the chunks of a .rombin asset"},
    {"export", cmd_export, "a .rombin asset as glTF 2.0 (.glb): its surface, basis as morph targets, a run as animation"},
};

int is_help(const char *arg) { return strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0; }

static void usage(FILE *out)
{
    fprintf(out, "romkit: reduced-order models of deformable solids, baked offline, stepped in real time.\n\n"
                 "usage: romkit COMMAND [ARGS]   (romkit COMMAND --help for details)\n\ncommands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        fprintf(out, "  %-11s %s\n", commands[i].name, commands[i].summary);
    fprintf(out, "\nLong stages show progress on stderr when it is a terminal (--quiet: none).\n"
                 "\ntypical pipeline, from the repository root:\n"
                 "  romkit fom examples/scenes/cantilever_small.json --snapshots S.npy\n"
                 "  romkit build examples/scenes/cantilever_small.json -o cantilever.rombin\n"
                 "  romkit run cantilever.rombin --steps 50 --reference S.npy\n"
                 "  romkit inspect cantilever.rombin\n"
                 "  romkit export cantilever.rombin --gltf cantilever.glb --steps 50\n"
                 "a Koopman asset from recorded snapshots (here the full-order run's):\n"
                 "  romkit dmd --snapshots S.npy --dt 0.01 --from-rest --gravity 0,-9.81,0 --clamp -o koopman.rombin\n"
                 "  romkit run koopman.rombin --steps 50 --jump 1000\n");
}

int main(int argc, char **argv)
{
    if (argc < 2 || is_help(argv[1])) {
        usage(argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    rk_error err;
    if (rk_threads_init(&err)) { /* OpenBLAS, CHOLMOD and romkit's loops: util.h, threads */
        fprintf(stderr, "romkit: %s\n", err.msg);
        return 2;
    }
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        if (strcmp(argv[1], commands[i].name) == 0) return commands[i].run(argc - 1, argv + 1);
    fprintf(stderr, "romkit: unknown command '%s'\n\n", argv[1]);
    usage(stderr);
    return 2;
}
