/* romkit fom SCENE.json: full-order simulation (or a static solve) of a scene. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "args.h"
#include "commands.h"
#include "fom/fom.h"
#include "pipeline/fom_report.h"
#include "pipeline/method_koopman.h"
#include "util/util.h"

static void fom_usage(FILE *out)
{
    fprintf(out,
            "usage: romkit fom SCENE.json [--positions P.npy] [--snapshots S.npy] [--frames DIR]\n"
            "                  [--frame-format obj|ply|vtk|mesh] [--stress T.npy] [--report R.json] [--quiet]\n"
            "                  [--entry K --trajectory I]\n\n"
            "Runs the full-order simulation the scene describes (or its static equilibrium when\n"
            "time.static is true) and writes what is asked:\n"
            "  --positions P.npy   final positions, n x 3 float64\n"
            "  --snapshots S.npy   every frame including the rest state, (steps+1) x n x 3 float64\n"
            "  --frames DIR        one boundary-surface mesh per frame (frame_00000.obj, ...)\n"
            "  --frame-format F    the format of those files: obj (default), ply, vtk or mesh\n"
            "  --stress T.npy      every frame's largest principal Cauchy stress (Pa) at each vertex,\n"
            "                      (steps+1) x n float64 (the tets' stresses averaged by volume)\n"
            "  --report R.json     counts, timings (seconds_per_step; seconds.* and shares.* of the\n"
            "                      parts: factorization, assembly, solve, line search, contact ...;\n"
            "                      newton.*: the median iteration against its factorization), final state\n"
            "  --quiet             no progress line on stderr\n"
            "  --trajectory I      run trajectory I of rom entry K's koopman section instead (its\n"
            "                      gravity, load scale, initial velocity; 0 for an entry listing none):\n"
            "                      what romkit build --trajectory-run reads (a step of romkit plan)\n"
            "  --entry K           the rom entry (default 0) whose trajectory --trajectory runs\n"
            "A point cloud (mesh.points) runs on its full-order body, the tets filling its contact\n"
            "surface with the cloud's mass; positions, snapshots and stresses are at the scene's vertices\n"
            "as romkit rom numbers them (its points, then its contact surface's), frames show the body.\n"
            "Nothing is written when the run fails. ROMKIT_THREADS=N: threads (default: the CPUs).\n\n"
            "example:\n"
            "  romkit fom examples/scenes/cantilever_small.json --snapshots S.npy --report fom.json\n");
}

typedef struct {
    const char *scene, *positions, *snapshots, *frames, *report, *stress;
    const char *frame_format;
    const char *entry, *trajectory;
    int quiet;
} fom_args;

static int parse_args(int argc, char **argv, fom_args *a)
{
    memset(a, 0, sizeof *a);
    a->frame_format = "obj";
    const cli_option opts[] = {{"--positions", &a->positions, NULL}, {"--snapshots", &a->snapshots, NULL},
                               {"--frames", &a->frames, NULL},       {"--frame-format", &a->frame_format, NULL},
                               {"--report", &a->report, NULL},       {"--quiet", NULL, &a->quiet},
                               {"--stress", &a->stress, NULL},       {"--entry", &a->entry, NULL},
                               {"--trajectory", &a->trajectory, NULL}, {NULL, NULL, NULL}};
    if (cli_parse("fom", argc, argv, opts, &a->scene, "scene file")) return -1;
    if (a->entry && !a->trajectory) {
        fprintf(stderr, "romkit fom: --entry names whose --trajectory to run; give --trajectory I too\n");
        return -1;
    }
    const char *formats[] = {"obj", "ply", "vtk", "mesh"};
    for (int k = 0; k < 4; k++)
        if (strcmp(a->frame_format, formats[k]) == 0) return 0;
    fprintf(stderr, "romkit fom: --frame-format must be obj, ply, vtk or mesh\n");
    return -1;
}

static int write_frame(const fom_args *a, const rk_mesh *m, const double *x, int frame, rk_error *err)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/frame_%05d.%s", a->frames, frame, a->frame_format);
    return rk_mesh_write(path, m, x, err);
}

/* What the command writes frame by frame, beside the measurement (fom_report.h). */
typedef struct {
    const fom_args *a;
    const rk_scene_sim *sim;
    rk_npy_stream snap, stress;
    int have_snap, have_stress;
    double *sigma;            /* nv: the frame's largest principal stresses */
    double *shown;            /* 3 layout.nv: a frame at the scene's vertices (point clouds' points) */
    double *sigma_shown;      /* layout.nv */
} fom_output;

/* A frame's positions as written: the run's, or taken back to the scene's vertices (layout). */
static const double *shown(const fom_output *o, const double *x)
{
    if (!o->sim->layout.nv) return x;
    rk_scene_layout_apply(&o->sim->layout, x, o->shown);
    return o->shown;
}

/* The scene's vertex count, as the snapshots and positions hold them. */
static int shown_nv(const rk_scene_sim *sim) { return sim->layout.nv ? sim->layout.nv : sim->mesh.nv; }

static int on_frame(void *ctx, int step, rk_fom *fom, double seconds, rk_error *err)
{
    fom_output *o = ctx;
    if (o->have_snap) rk_npy_stream_append(&o->snap, shown(o, fom->x), 3 * (size_t)shown_nv(o->sim));
    if (o->have_stress) {
        if (rk_fem_principal_stress(&o->sim->fem, fom->x, o->sigma, err)) return -1;
        const double *sigma = o->sigma;
        if (o->sim->layout.nv) { /* a point's stress: its tet's vertices' at its barycentric coordinates */
            const rk_scene_layout *L = &o->sim->layout;
            for (int j = 0; j < L->nv; j++) {
                o->sigma_shown[j] = 0;
                for (int a = 0; a < 4; a++) o->sigma_shown[j] += L->weight[4 * j + a] * o->sigma[L->vertex[4 * j + a]];
            }
            sigma = o->sigma_shown;
        }
        rk_npy_stream_append(&o->stress, sigma, (size_t)shown_nv(o->sim));
    }
    return o->a->frames ? write_frame(o->a, &o->sim->mesh, fom->x, step, err) : 0;
}

/* --entry K --trajectory I: the built scene changed to run as that Koopman trajectory runs. */
static int vary(const rk_scene *scene, rk_scene_sim *sim, const fom_args *a, rk_error *err)
{
    long k = 0, i;
    const rk_rom_entry *e;
    if (a->entry && (scene->nentries == 0 || cli_whole(a->entry, 0, scene->nentries - 1, &k)))
        return rk_fail(err, "--entry must be a rom entry of %s, 0..%d, got '%s'", a->scene, scene->nentries - 1, a->entry);
    if (rk_scene_entry(scene, (int)k, &e, err)) return -1;
    const rk_koopman_entry *ko = rk_koopman_of(e);
    if (!ko) return rk_fail(err, "--trajectory: %s (%s) has no koopman section", e->path, e->name);
    int n = ko->ntraj ? ko->ntraj : 1;
    if (cli_whole(a->trajectory, 0, n - 1, &i))
        return rk_fail(err, "--trajectory must be one of %s's %d trajectories, 0..%d, got '%s'", e->path, n, n - 1,
                       a->trajectory);
    return rk_koopman_scene_vary(sim, ko->ntraj ? &ko->traj[i] : NULL, err);
}

int cmd_fom(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (is_help(argv[i])) {
            fom_usage(stdout);
            return 0;
        }
    fom_args a;
    if (parse_args(argc, argv, &a)) {
        fom_usage(stderr);
        return 2;
    }
    rk_progress_set_quiet(a.quiet);
    double t0 = rk_now();
    rk_error err = {{0}};
    rk_scene scene;
    rk_scene_sim sim;
    fom_output out = {.a = &a};
    rk_fom_measure m = {0};
    int have_scene = 0, have_sim = 0, have_m = 0, rc = 1;
    if (rk_scene_load(a.scene, &scene, &err)) goto done;
    have_scene = 1;
    if (rk_scene_build_full_order(&scene, &sim, &err)) goto done;
    have_sim = 1;
    if (a.trajectory && vary(&scene, &sim, &a, &err)) goto done;
    int nv = shown_nv(&sim), steps = sim.options.is_static ? 1 : sim.steps;
    out.sim = &sim;
    if (sim.layout.nv && (!(out.shown = rk_calloc(3 * (size_t)nv, sizeof(double), &err)) ||
                          !(out.sigma_shown = rk_calloc((size_t)nv, sizeof(double), &err))))
        goto done;
    if (a.frames && mkdir(a.frames, 0777) != 0 && errno != EEXIST) {
        rk_fail(&err, "%s: cannot create frames folder: %s", a.frames, strerror(errno));
        goto done;
    }
    if (a.snapshots) {
        long shape[3] = {steps + 1, nv, 3};
        if (rk_npy_stream_open(&out.snap, a.snapshots, 3, shape, &err)) goto done;
        out.have_snap = 1;
    }
    if (a.stress) {
        long shape[2] = {steps + 1, nv};
        if (!(out.sigma = rk_calloc((size_t)sim.mesh.nv, sizeof(double), &err)) ||
            rk_npy_stream_open(&out.stress, a.stress, 2, shape, &err))
            goto done;
        out.have_stress = 1;
    }
    if (rk_scene_fom_measure(&sim, on_frame, &out, &m, &err)) goto done;
    have_m = 1;
    if (out.have_snap) {
        out.have_snap = 0;
        if (rk_npy_stream_commit(&out.snap, &err)) goto done;
    }
    if (out.have_stress) {
        out.have_stress = 0;
        if (rk_npy_stream_commit(&out.stress, &err)) goto done;
    }
    if (a.positions) {
        long shape[2] = {nv, 3};
        if (rk_npy_write(a.positions, shown(&out, m.x), 2, shape, &err)) goto done;
    }
    rk_unconverged_warn(stderr, "full order", m.stats.unconverged_steps, m.steps);
    cJSON *report = rk_fom_report(&sim, &m, rk_now() - t0);
    if (a.report && rk_json_write_file(a.report, report, &err)) {
        cJSON_Delete(report);
        goto done;
    }
    printf("%s: %d vertices, %d tets; %d %s of %g s: %.4g s/step (factorization %.0f%%), "
           "%.2f Newton iterations/step\n",
           a.scene, sim.mesh.nv, sim.mesh.nt, m.steps, sim.options.is_static ? "static solve" : "steps", sim.options.h,
           cJSON_GetObjectItem(report, "seconds_per_step")->valuedouble,
           100 * cJSON_GetObjectItem(report, "factorization_share")->valuedouble,
           (double)m.stats.newton_iterations / m.steps);
    printf("Newton iteration: %.3g s (median), %.2f x its factorization (%.3g s), %d threads\n", m.iteration.median,
           m.factorization.median > 0 ? m.iteration.median / m.factorization.median : 0.0, m.factorization.median,
           rk_threads());
    printf("final: %d inverted elements, max displacement %.4g m, kinetic energy %.4g J\n", m.inverted,
           m.max_displacement, m.kinetic_energy);
    if (sim.body_points)
        printf("point clouds: %d points embedded in their full-order bodies (%d outside, %d surface vertices' inset "
               "cut back; %d contact surface vertices outside); snapshots and positions are at the scene's %d vertices\n",
               sim.body_points, sim.body_outside, sim.body_backed_off, sim.body_surface_outside, nv);
    if (m.contact)
        printf("contact: closest %.3g m, %ld crossings over %ld frames, %.1f pairs per evaluation (at most %ld); "
               "broad phase %.3g s, CCD %.3g s\n", m.tally.min_distance, m.tally.intersections, m.tally.frames,
               m.contact_stats.gathers ? (double)m.contact_stats.pairs / m.contact_stats.gathers : 0.0,
               m.contact_stats.max_pairs, m.contact_stats.seconds_broad, m.contact_stats.seconds_ccd);
    cJSON_Delete(report);
    rc = 0;
done:
    if (rc) fprintf(stderr, "romkit fom: %s\n", err.msg);
    if (out.have_snap) rk_npy_stream_abort(&out.snap);
    if (out.have_stress) rk_npy_stream_abort(&out.stress);
    free(out.sigma);
    free(out.shown);
    free(out.sigma_shown);
    if (have_m) rk_fom_measure_free(&m);
    if (have_sim) rk_scene_sim_free(&sim);
    if (have_scene) rk_scene_free(&scene);
    return rc;
}
