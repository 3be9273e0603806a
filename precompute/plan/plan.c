/* A scene entry's bake as steps (plan.h): which runs it trains on, whether its basis and cubature
 * can be steps of their own, and each step's command, files and dependencies. */
#include "plan/plan.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "pipeline/method_adaptive_linear.h"
#include "pipeline/method_fixed.h"
#include "pipeline/method_koopman.h"

/* A file the Makefile and the scripts name as it is: no space, quote or character make or sh reads. */
static int nameable(const char *path, rk_error *err)
{
    for (const char *c = path; *c; c++)
        if (strchr(" \t\n\"'\\$#:;%*?`&|<>()[]{}=", *c))
            return rk_fail(err, "%s: the plan's Makefile and scripts cannot name a file with '%c' in its path; move or "
                           "rename it", path, *c);
    if (strlen(path) >= 1024) return rk_fail(err, "%s: path too long for a plan (1023 characters at most)", path);
    return 0;
}

static void input(rk_plan_step *s, const char *file);

/* Every step reads plan.json: a plan made again differently (another entry, other threads) in the
 * same folder makes every output out of date, rather than leaving the last plan's files looking
 * done (rk_plan_write leaves an unchanged plan.json alone). */
static rk_plan_step *add_step(rk_plan *p, rk_step_kind kind, const char *id, const char *output)
{
    rk_plan_step *s = &p->steps[p->nsteps++];
    memset(s, 0, sizeof *s);
    s->kind = kind;
    snprintf(s->id, sizeof s->id, "%s", id);
    snprintf(s->output, sizeof s->output, "%s", output);
    input(s, "plan.json");
    return s;
}

static void arg(rk_plan_step *s, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(s->args[s->nargs++], sizeof s->args[0], fmt, ap);
    va_end(ap);
}

static void input(rk_plan_step *s, const char *file)
{
    for (int i = 0; i < s->ninputs; i++)
        if (!strcmp(s->inputs[i], file)) return;
    if (s->ninputs == RK_PLAN_MAX_INPUTS) {
        s->too_many = 1; /* (rk_plan_make fails on it) */
        return;
    }
    size_t n = strlen(file) < sizeof s->inputs[0] ? strlen(file) : sizeof s->inputs[0] - 1;
    memmove(s->inputs[s->ninputs], file, n); /* (file may be another step's output in the same plan) */
    s->inputs[s->ninputs++][n] = '\0';
}

/* s waits for step k and reads its output. */
static void after(rk_plan *p, rk_plan_step *s, int k)
{
    s->after[s->nafter++] = k;
    input(s, p->steps[k].output);
}

/* The training files a step passes on: --training for the scene's own run, --training-run per
 * item of the list (a step's output, or the list's own snapshot file). */
static void training_args(rk_plan *p, const rk_rom_entry *e, rk_plan_step *s)
{
    if (!e->ntraining) {
        arg(s, "--training");
        arg(s, "%s", p->steps[0].output);
        after(p, s, 0);
        return;
    }
    for (int k = 0, t = 0; k < e->ntraining; k++) {
        arg(s, "--training-run");
        if (e->training[k].snapshots) {
            arg(s, "%s", e->training[k].file);
            input(s, e->training[k].file);
        } else {
            arg(s, "%s", p->steps[t].output);
            after(p, s, t++);
        }
    }
}

/* What a step reading the scene reads with it: the objects' mesh and point files and the
 * obstacles' meshes, so that make redoes the steps when one changes. */
static int scene_files(const rk_scene *scene, rk_plan_step *s, rk_error *err)
{
    for (int k = 0; k < scene->nobjects; k++)
        if (scene->objects[k].shape != RK_SHAPE_BOX) {
            if (nameable(scene->objects[k].file, err)) return rk_error_prefix(err, "objects[%d].mesh", k);
            input(s, scene->objects[k].file);
        }
    for (int k = 0; k < scene->nobstacles; k++)
        if (scene->obstacles[k].file[0]) {
            if (nameable(scene->obstacles[k].file, err)) return rk_error_prefix(err, "obstacles[%d]", k);
            input(s, scene->obstacles[k].file);
        }
    return 0;
}

/* A full-order run as a step, "NAME-K" writing NAME-K.npy: romkit fom of scene file (the plan's
 * scene or a training item's), or trajectory `trajectory` of entry e (e NULL: none). */
static rk_plan_step *fom_step(rk_plan *p, const char *name, int k, const char *file, const rk_rom_entry *e,
                              int trajectory)
{
    char id[32], out[64];
    snprintf(id, sizeof id, "%s-%d", name, k);
    snprintf(out, sizeof out, "%s-%d.npy", name, k);
    rk_plan_step *s = add_step(p, RK_STEP_TRAIN, id, out);
    arg(s, "fom");
    arg(s, "%s", file);
    if (e) {
        arg(s, "--entry");
        arg(s, "%d", e->index);
        arg(s, "--trajectory");
        arg(s, "%d", trajectory);
    }
    arg(s, "--snapshots");
    arg(s, "%s", s->output);
    arg(s, "--quiet");
    input(s, file);
    return s;
}

/* Why entry e is baked in one step, or "" when its basis and cubature can be steps. */
static void whole_reason(const rk_scene *scene, const rk_rom_entry *e, char *why, size_t size)
{
    rk_basis_type t = e->basis.type;
    why[0] = '\0';
    if (rk_koopman_of(e))
        snprintf(why, size, "a koopman entry: its trajectories are steps of their own, the fit and the bake one romkit "
                 "build (no operator file yet)");
    else if (rk_adaptive_linear_of(e))
        snprintf(why, size, "method adaptive_linear: its training list's runs are steps, its decoder, cubature and "
                 "model one romkit build (no decoder file yet)");
    else if (e->method != &rk_method_fixed)
        snprintf(why, size, "method %s: its trainings and models are built and baked in one romkit build (not "
                 "split yet)", e->method->name);
    else if (t != RK_BASIS_MODES && t != RK_BASIS_MODAL_DERIVATIVES && t != RK_BASIS_POD)
        snprintf(why, size, "a %s basis is more than U (weights, kernels): no basis file for it yet",
                 rk_basis_type_name(t));
    else if (rk_scene_mesh_free(scene, e))
        snprintf(why, size, "a mesh-free entry: its integration points are made with the basis (no file for them yet)");
}

int rk_plan_make(const rk_scene *scene, const rk_rom_entry *e, const char *scene_abs, int threads, rk_plan *p,
                 rk_error *err)
{
    memset(p, 0, sizeof *p);
    if (nameable(scene_abs, err)) return -1;
    for (int k = 0; k < e->ntraining; k++)
        if (nameable(e->training[k].file, err)) return rk_error_prefix(err, "%s.training[%d]", e->path, k);
    snprintf(p->scene, sizeof p->scene, "%s", scene_abs);
    p->entry = e->index;
    snprintf(p->entry_name, sizeof p->entry_name, "%s", e->name);
    snprintf(p->method, sizeof p->method, "%s", e->method->name);
    p->threads = threads;
    whole_reason(scene, e, p->whole_reason, sizeof p->whole_reason);
    p->split = p->whole_reason[0] == '\0';
    /* the training runs, where something trains on frames (rk_scene_entry_frames: the basis or the
     * cubature of a reduced model; a point cloud has no full order). Other methods train inside
     * their own build. */
    const rk_koopman_entry *ko = rk_koopman_of(e);
    const rk_adaptive_linear_entry *al = rk_adaptive_linear_of(e);
    int frames = rk_scene_clouds(scene) == 0 &&
                 (ko   ? e->cubature || (ko->project && rk_basis_needs_frames(&e->basis))
                  : al ? e->ntraining && (e->cubature || al->quadratic_pod || al->crom) /* (its list only) */
                       : e->method == &rk_method_fixed && (e->cubature || rk_basis_needs_frames(&e->basis)));
    if (frames && !e->ntraining && scene_files(scene, fom_step(p, "train", 0, scene_abs, NULL, -1), err)) return -1;
    for (int k = 0; frames && k < e->ntraining; k++) /* (an item's own meshes are not listed) */
        if (!e->training[k].snapshots) fom_step(p, "train", p->nsteps, e->training[k].file, NULL, -1);
    /* a Koopman entry's trajectories: the scene run as each varies it (one: as written) */
    int first_traj = p->nsteps, ntraj = ko ? (ko->ntraj ? ko->ntraj : 1) : 0;
    for (int i = 0; i < ntraj; i++)
        if (scene_files(scene, fom_step(p, "trajectory", i, scene_abs, e, i), err)) return -1;
    p->ntrain = p->nsteps;
    int basis = -1, cubature = -1;
    if (p->split) {
        rk_plan_step *s = add_step(p, RK_STEP_BASIS, "basis", "basis.npy");
        basis = p->nsteps - 1;
        arg(s, "basis");
        arg(s, "%s", scene_abs);
        arg(s, "--entry");
        arg(s, "%d", e->index);
        input(s, scene_abs);
        if (scene_files(scene, s, err)) return -1;
        if (frames && rk_basis_needs_frames(&e->basis)) training_args(p, e, s);
        arg(s, "--basis");
        arg(s, "%s", s->output);
        arg(s, "--quiet");
    }
    if (p->split && e->cubature) {
        rk_plan_step *s = add_step(p, RK_STEP_CUBATURE, "cubature", "cubature.json");
        cubature = p->nsteps - 1;
        arg(s, "cubature");
        arg(s, "%s", scene_abs);
        arg(s, "--entry");
        arg(s, "%d", e->index);
        input(s, scene_abs);
        if (scene_files(scene, s, err)) return -1;
        arg(s, "--basis");
        arg(s, "%s", p->steps[basis].output);
        after(p, s, basis);
        if (frames) training_args(p, e, s);
        arg(s, "-o");
        arg(s, "%s", s->output);
        arg(s, "--quiet");
    }
    rk_plan_step *s = add_step(p, RK_STEP_BAKE, "bake", "asset.rombin");
    arg(s, "build");
    arg(s, "%s", scene_abs);
    arg(s, "--entry");
    arg(s, "%d", e->index);
    input(s, scene_abs);
    if (scene_files(scene, s, err)) return -1;
    if (p->split) {
        arg(s, "--basis");
        arg(s, "%s", p->steps[basis].output);
        after(p, s, basis);
        if (cubature >= 0) {
            arg(s, "--cubature");
            arg(s, "%s", p->steps[cubature].output);
            after(p, s, cubature);
        }
    } else if (frames) {
        training_args(p, e, s);
    }
    for (int i = 0; i < ntraj; i++) {
        arg(s, "--trajectory-run");
        arg(s, "%s", p->steps[first_traj + i].output);
        after(p, s, first_traj + i);
    }
    arg(s, "-o");
    arg(s, "%s", s->output);
    arg(s, "--quiet");
    for (int k = 0; k < p->nsteps; k++)
        if (p->steps[k].too_many)
            return rk_fail(err, "step %s reads more than %d files: too many for a plan", p->steps[k].id, RK_PLAN_MAX_INPUTS);
    return 0;
}
