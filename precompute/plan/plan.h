/* precompute/plan: a scene entry's bake as a job graph (romkit plan). Each step is one plain romkit
 * command that reads and writes files in one folder, with its inputs, its output and the steps it
 * waits for; the graph is written as plan.json, as a Makefile (make -j runs it; a rerun redoes only
 * what is missing or older than its inputs) and, for Slurm, as sbatch scripts and a submit.sh (the
 * training runs as one job array, the rest chained with --dependency=afterok).
 *
 *   training runs  romkit fom ITEM --snapshots train-K.npy: the scene's own run, or each scene of
 *                  the entry's training list (snapshot files in the list are inputs, not steps);
 *                  only where the basis or the cubature trains on frames; and a Koopman entry's
 *                  trajectories, romkit fom --entry K --trajectory I --snapshots trajectory-I.npy
 *   basis          romkit basis --basis basis.npy (modes, modal_derivatives, pod bases)
 *   cubature       romkit cubature --basis basis.npy -o cubature.json (entries with rom.cubature)
 *   bake           romkit build --basis basis.npy --cubature cubature.json -o asset.rombin
 *
 * The asset is byte-identical to romkit build's at the same ROMKIT_THREADS (the plan fixes it for
 * every step): every file between the steps is exact (float64 .npy, 17-digit JSON), and each step
 * computes what romkit build computes from the same numbers. Entries that cannot be split yet are
 * one romkit build step after their training runs: koopman (the fit and the bake: no operator file
 * yet; its trajectories are steps), adaptive_linear (the decoder and the bake: no decoder file yet;
 * its training list's runs are steps), adaptive_subspace (its own trainings, run inside), and
 * skinning, rkpm_skinning and mesh-free bases (more than U: weights, kernels, points). */
#ifndef RK_PLAN_H
#define RK_PLAN_H

#include "pipeline/method_koopman.h"
#include "pipeline/pipeline.h"

/* training runs, Koopman trajectories, basis, cubature, bake */
#define RK_PLAN_MAX_RUNS (RK_MAX_TRAINING + RK_KOOPMAN_MAX_TRAJECTORIES)
#define RK_PLAN_MAX_STEPS (RK_PLAN_MAX_RUNS + 4)
#define RK_PLAN_MAX_ARGS (2 * RK_PLAN_MAX_RUNS + 16)
#define RK_PLAN_MAX_INPUTS (RK_PLAN_MAX_RUNS + 16)

typedef enum { RK_STEP_TRAIN = 0, RK_STEP_BASIS = 1, RK_STEP_CUBATURE = 2, RK_STEP_BAKE = 3 } rk_step_kind;

typedef struct {
    char id[32];              /* "train-0", "basis", "cubature", "bake" */
    rk_step_kind kind;
    int nargs;
    char args[RK_PLAN_MAX_ARGS][1024]; /* the romkit command's arguments after "romkit" */
    char output[64];          /* the file it writes, in the plan's folder */
    int ninputs;
    char inputs[RK_PLAN_MAX_INPUTS][1024]; /* files it reads: absolute (the scene, its meshes), or
                                            * other steps' outputs */
    int nafter;
    int after[RK_PLAN_MAX_STEPS]; /* the steps it waits for (indices) */
    int too_many;             /* more inputs than RK_PLAN_MAX_INPUTS (an error) */
} rk_plan_step;

typedef struct {
    char scene[1024];         /* absolute */
    int entry;
    char entry_name[96], method[32];
    int split;                /* basis and cubature are steps of their own */
    char whole_reason[256];   /* why not, when not */
    int threads;              /* ROMKIT_THREADS of every step */
    int ntrain;               /* the first ntrain steps are the training runs (the job array) */
    int nsteps;
    rk_plan_step steps[RK_PLAN_MAX_STEPS];
} rk_plan;

/* The plan of entry e of the loaded scene (scene_abs: its absolute path, which the steps name).
 * p is large: allocate it. Fails naming a file the steps could not name (a space or a character
 * make or sh would read). */
int rk_plan_make(const rk_scene *scene, const rk_rom_entry *e, const char *scene_abs, int threads, rk_plan *p,
                 rk_error *err);

/* Writes dir/plan.json and dir/Makefile, and with slurm dir/slurm/{train,basis,cubature,bake}.sbatch
 * and dir/submit.sh; dir (absolute) must exist. romkit: the binary the steps run (absolute; the
 * Makefile's ROMKIT and the scripts' $ROMKIT override it). */
int rk_plan_write(const rk_plan *p, const char *dir, const char *romkit, int slurm, rk_error *err);

#endif
