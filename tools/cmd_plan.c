/* romkit plan SCENE.json -o DIR: a rom entry's bake as a job graph in DIR (precompute/plan): plan.json,
 * a Makefile, and with --slurm the sbatch scripts and submit.sh; --run runs the steps here, in order. */
#include <errno.h>
#include <limits.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "args.h"
#include "commands.h"
#include "plan/plan.h"
#include "util/util.h"

extern char **environ;

static void plan_usage(FILE *f)
{
    fprintf(f, "usage: romkit plan SCENE.json -o DIR [--entry K] [--slurm] [--run] [--threads N]\n"
               "  writes the bake of rom entry K (default 0) as a job graph into DIR (made if missing):\n"
               "  each training run (romkit fom --snapshots), the basis (romkit basis), the cubature\n"
               "  (romkit cubature) and the bake (romkit build --basis --cubature) as a step of its own,\n"
               "  a plain romkit command reading and writing files in DIR, listed with its inputs, output\n"
               "  and dependencies in DIR/plan.json, and DIR/Makefile: make -C DIR -j2 runs it, and a\n"
               "  rerun after a failure redoes only what is missing or out of date. DIR/asset.rombin is\n"
               "  byte-identical to romkit build's at the same ROMKIT_THREADS. A Koopman entry's\n"
               "  trajectories are steps (romkit fom --trajectory). Entries that cannot be split yet\n"
               "  (koopman's fit, adaptive_linear's decoder, adaptive_subspace; skinning, rkpm_skinning,\n"
               "  mesh-free bases) are one romkit build step after their training runs; plan.json\n"
               "  says why.\n"
               "  --slurm       also DIR/slurm/*.sbatch and DIR/submit.sh: the training runs as one job\n"
               "                array, the other steps chained with --dependency=afterok (sbatch --parsable)\n"
               "  --run         run the steps here, in order, each only when its output is missing or\n"
               "                older than its inputs\n"
               "  --threads N   ROMKIT_THREADS of every step (default: this machine's, as romkit build)\n"
               "  Nothing is written when the plan fails.\n\n"
               "example:\n"
               "  romkit plan examples/scenes/cantilever_small.json -o bake --slurm && make -C bake -j2\n");
}

/* Whether step s must run: its output missing or older than an input. */
static int stale(const char *dir, const rk_plan_step *s)
{
    char path[PATH_MAX + 64];
    struct stat out, in;
    snprintf(path, sizeof path, "%s/%s", dir, s->output);
    if (stat(path, &out) != 0) return 1;
    for (int i = 0; i < s->ninputs; i++) {
        const char *f = s->inputs[i];
        if (f[0] != '/') snprintf(path, sizeof path, "%s/%s", dir, f);
        else snprintf(path, sizeof path, "%s", f);
        if (stat(path, &in) != 0 || in.st_mtime > out.st_mtime) return 1;
    }
    return 0;
}

/* The steps in order (the plan lists each after what it needs), in DIR, as separate processes of
 * this romkit with ROMKIT_THREADS set: the same commands the Makefile runs. */
static int run_plan(const rk_plan *p, const char *dir, const char *romkit, rk_error *err)
{
    char threads[16];
    snprintf(threads, sizeof threads, "%d", p->threads);
    if (setenv("ROMKIT_THREADS", threads, 1) != 0 || chdir(dir) != 0)
        return rk_fail(err, "%s: cannot run the plan there: %s", dir, strerror(errno));
    for (int k = 0; k < p->nsteps; k++) {
        const rk_plan_step *s = &p->steps[k];
        if (!stale(".", s)) {
            printf("%s: %s is up to date\n", s->id, s->output);
            continue;
        }
        char *argv[RK_PLAN_MAX_ARGS + 2];
        argv[0] = (char *)romkit;
        for (int i = 0; i < s->nargs; i++) argv[i + 1] = (char *)s->args[i];
        argv[s->nargs + 1] = NULL;
        printf("%s: romkit", s->id);
        for (int i = 0; i < s->nargs; i++) printf(" %s", s->args[i]);
        printf("\n");
        fflush(stdout);
        pid_t pid;
        int status;
        if (posix_spawn(&pid, romkit, NULL, NULL, argv, environ) != 0 || waitpid(pid, &status, 0) != pid)
            return rk_fail(err, "step %s: cannot start %s", s->id, romkit);
        if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
            return rk_fail(err, "step %s failed (%s not written; rerun to retry from there)", s->id, s->output);
    }
    return 0;
}

int cmd_plan(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (is_help(argv[i])) {
            plan_usage(stdout);
            return 0;
        }
    const char *scene_path, *dir = NULL, *entry_text = "0", *threads_text = NULL;
    int slurm = 0, run = 0;
    const cli_option opts[] = {{"-o", &dir, NULL},          {"--entry", &entry_text, NULL},
                               {"--slurm", NULL, &slurm},   {"--run", NULL, &run},
                               {"--threads", &threads_text, NULL}, {NULL, NULL, NULL}};
    if (cli_parse("plan", argc, argv, opts, &scene_path, "scene file")) {
        plan_usage(stderr);
        return 2;
    }
    if (!dir) {
        fprintf(stderr, "romkit plan: -o DIR is required\n");
        plan_usage(stderr);
        return 2;
    }
    long threads = 0;
    if (threads_text && cli_whole(threads_text, 1, RK_THREADS_MAX, &threads)) {
        fprintf(stderr, "romkit plan: --threads must be a whole number from 1 to %d, got '%s'\n", RK_THREADS_MAX,
                threads_text);
        return 2;
    }
    rk_error err = {{0}};
    rk_scene scene;
    rk_plan *p = NULL;
    const rk_rom_entry *e;
    int have_scene = 0, made_dir = 0, rc = 1;
    long entry = 0;
    char scene_abs[PATH_MAX], dir_abs[PATH_MAX], romkit[PATH_MAX];
    /* loaded by its absolute path, so every file it names (meshes, training scenes) is absolute
     * too: the steps run in DIR */
    if (!realpath(scene_path, scene_abs)) {
        rk_fail(&err, "%s: cannot read the scene: %s", scene_path, strerror(errno));
        goto done;
    }
    if (rk_scene_load(scene_abs, &scene, &err)) goto done;
    have_scene = 1;
    if (scene.nentries == 0 || cli_whole(entry_text, 0, scene.nentries - 1, &entry)) {
        rk_fail(&err, "--entry must be a rom entry of %s, 0..%d, got '%s'", scene_path, scene.nentries - 1, entry_text);
        goto done;
    }
    if (rk_scene_entry(&scene, (int)entry, &e, &err)) goto done;
    ssize_t len = readlink("/proc/self/exe", romkit, sizeof romkit - 1);
    if (len <= 0) {
        rk_fail(&err, "cannot tell where this romkit is (/proc/self/exe): %s", strerror(errno));
        goto done;
    }
    romkit[len] = '\0';
    p = calloc(1, sizeof *p);
    if (!p) {
        rk_fail(&err, "out of memory for the plan");
        goto done;
    }
    if (rk_plan_make(&scene, e, scene_abs, threads ? (int)threads : rk_threads(), p, &err)) goto done;
    if (mkdir(dir, 0755) == 0) made_dir = 1;
    else if (errno != EEXIST) {
        rk_fail(&err, "-o %s: cannot create the plan's folder: %s", dir, strerror(errno));
        goto done;
    }
    if (!realpath(dir, dir_abs)) {
        rk_fail(&err, "-o %s: %s", dir, strerror(errno));
        goto done;
    }
    if (rk_plan_write(p, dir_abs, romkit, slurm, &err)) {
        rk_error_prefix(&err, "-o %s", dir);
        goto done;
    }
    made_dir = 0; /* written: kept whatever --run does */
    printf("%s: %d steps for %s (%s)%s%s; run with make -C %s -j2%s\n", dir, p->nsteps, e->name, e->path,
           p->split ? "" : ", baked in one step: ", p->split ? "" : p->whole_reason, dir,
           slurm ? ", or on Slurm with sh submit.sh there" : "");
    for (int k = 0; k < p->nsteps; k++) printf("  %-9s -> %s\n", p->steps[k].id, p->steps[k].output);
    if (run && run_plan(p, dir_abs, romkit, &err)) goto done;
    rc = 0;
done:
    if (rc) fprintf(stderr, "romkit plan: %s\n", err.msg);
    if (made_dir) rmdir(dir);
    free(p);
    if (have_scene) rk_scene_free(&scene);
    return rc;
}
