/* romkit rom SCENE.json: a scene's reduced model stepped by the reduced simulator (precompute/rom),
 * every object of it, with the contact measured each step and a point cloud's Gaussian splats
 * written at every frame: what the runtime, which steps one object, cannot run. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "args.h"
#include "pipeline/pipeline.h"
#include "pipeline/method_fixed.h"
#include "commands.h"
#include "util/util.h"

static void rom_usage(FILE *out)
{
    fprintf(out,
            "usage: romkit rom SCENE.json [--entry K] [--steps N] [--splats DIR] [--object K] [--quiet]\n\n"
            "Builds the reduced model of the scene's rom section (entry K of a list, default 0) and\n"
            "steps it in the reduced simulator, all its objects together (several point clouds\n"
            "colliding, which the runtime does not run), measuring the contact after every step:\n"
            "exact crossings of the surfaces and their smallest distance.\n"
            "  --steps N     time steps (default: the scene's duration over its step)\n"
            "  --splats DIR  a point cloud's Gaussian splats at every frame as DIR/frame_NNNNN.ply\n"
            "                (3DGS PLY: centres moved, covariances F Sigma F^T, SH bands rotated)\n"
            "  --object K    the object whose splats --splats writes (default: the first point\n"
            "                cloud whose file holds splats)\n"
            "  --quiet       no progress line on stderr\n\n"
            "example:\n"
            "  romkit rom examples/scenes/donut_on_object.json --splats splats/\n");
}

/* The object whose splats to write: `object` (>= 0), else the first point cloud whose file holds
 * splat attributes. */
static int open_splats(const rk_scene *scene, const rk_scene_sim *sim, const rk_scene_rom *R, long object,
                       rk_scene_splats *sp, rk_error *err)
{
    if (object >= 0) return rk_scene_splats_open(scene, sim, R, (int)object, sp, err);
    for (int k = 0; k < scene->nobjects; k++) {
        rk_error ignored = {{0}};
        if (scene->objects[k].shape == RK_SHAPE_POINTS && !rk_scene_splats_open(scene, sim, R, k, sp, &ignored)) return 0;
    }
    return rk_fail(err, "--splats: no object of %s is a point cloud read from a splat file", scene->path);
}

int cmd_rom(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (is_help(argv[i])) {
            rom_usage(stdout);
            return 0;
        }
    const char *scene_path, *entry = "0", *steps_text = NULL, *splats_dir = NULL, *object_text = NULL;
    int quiet = 0;
    const cli_option opts[] = {{"--entry", &entry, NULL},         {"--steps", &steps_text, NULL},
                               {"--splats", &splats_dir, NULL},   {"--object", &object_text, NULL},
                               {"--quiet", NULL, &quiet},         {NULL, NULL, NULL}};
    if (cli_parse("rom", argc, argv, opts, &scene_path, "scene file")) {
        rom_usage(stderr);
        return 2;
    }
    long index, steps = -1, object = -1;
    if (cli_whole(entry, 0, 1000, &index) || (steps_text && cli_whole(steps_text, 0, 100000000, &steps)) ||
        (object_text && cli_whole(object_text, 0, 1000000, &object))) {
        fprintf(stderr, "romkit rom: --entry, --steps and --object take whole numbers\n");
        return 2;
    }
    if (object_text && !splats_dir) {
        fprintf(stderr, "romkit rom: --object names the object whose splats --splats writes: give --splats\n");
        return 2;
    }
    rk_progress_set_quiet(quiet);
    rk_error err = {{0}};
    rk_scene scene;
    rk_scene_sim sim;
    rk_scene_rom R;
    rk_rom s;
    rk_scene_splats sp;
    const rk_rom_entry *e;
    int have_scene = 0, have_sim = 0, have_rom = 0, have_sim_rom = 0, have_splats = 0, rc = 1;
    double *x = NULL;
    if (rk_scene_load(scene_path, &scene, &err)) goto done;
    have_scene = 1;
    if (rk_scene_entry(&scene, (int)index, &e, &err)) goto done;
    if (!e->method->reduced_model) {
        rk_fail(&err, "%s: %s is not a fixed-basis reduced model (romkit adaptive, compare and build run the others)",
                scene_path, e->path);
        goto done;
    }
    if (rk_scene_build(&scene, &sim, &err)) goto done;
    have_sim = 1;
    double t0 = rk_now();
    if (rk_scene_rom_build(&scene, &sim, e, NULL, 0, &R, &err)) goto done;
    have_rom = 1;
    double seconds_build = rk_now() - t0;
    if (splats_dir) {
        if (open_splats(&scene, &sim, &R, object, &sp, &err)) goto done;
        have_splats = 1;
        if (mkdir(splats_dir, 0777) && errno != EEXIST) {
            rk_fail(&err, "%s: cannot create the splats folder: %s", splats_dir, strerror(errno));
            goto done;
        }
    }
    if (rk_rom_init(&s, &R.model, NULL, NULL, &err)) goto done;
    have_sim_rom = 1;
    int ndof = 3 * sim.mesh.nv, n = steps >= 0 ? (int)steps : sim.steps, worst = 0;
    x = rk_calloc((size_t)ndof, sizeof(double), &err);
    if (!x) goto done;
    double min_d = INFINITY, seconds_steps = 0;
    char path[4200];
    for (int k = 0; k <= n; k++) {
        if (k) {
            double t = rk_now();
            if (rk_rom_step(&s, &err)) {
                rk_error_prefix(&err, "step %d", k);
                goto done;
            }
            seconds_steps += rk_now() - t;
            int inter;
            double d;
            if (R.model.has_contact) {
                if (rk_rom_contact_measure(&s, &inter, &d, &err)) goto done;
                worst = inter > worst ? inter : worst;
                min_d = fmin(min_d, d);
            }
            rk_progress("reduced simulator", k, n);
        }
        if (have_splats) {
            rk_rom_positions(R.basis.U, ndof, R.model.r, sim.mesh.X, s.q, x);
            snprintf(path, sizeof path, "%s/frame_%05d.ply", splats_dir, k);
            if (rk_scene_splats_write(&sp, &R, s.q, x, path, &err)) goto done;
        }
    }
    rk_progress_done("reduced simulator");
    printf("%s: %d objects, r = %d, built in %.3g s; %d steps, %.3g s a step, %.3g Newton iterations a step", scene_path,
           scene.nobjects, R.model.r, seconds_build, n, n ? seconds_steps / n : 0.0,
           n ? (double)s.stats.newton_iterations / n : 0.0);
    if (R.model.has_contact) printf("; contact: %d exact crossings at most, smallest distance %.3g m", worst, min_d);
    printf("\n");
    if (have_splats) printf("splats of objects[%d] (%d): %s/frame_00000.ply .. frame_%05d.ply\n", sp.object,
                            sp.splats.n, splats_dir, n);
    rc = 0;
done:
    if (rc) fprintf(stderr, "romkit rom: %s\n", err.msg);
    free(x);
    if (have_sim_rom) rk_rom_free(&s);
    if (have_splats) rk_scene_splats_free(&sp);
    if (have_rom) rk_scene_rom_free(&R);
    if (have_sim) rk_scene_sim_free(&sim);
    if (have_scene) rk_scene_free(&scene);
    return rc;
}
