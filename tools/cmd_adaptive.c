/* romkit adaptive SCENE.json: one adaptive_subspace entry of a scene run on its own, with the
 * outputs of romkit fom (positions, snapshots, frames) and the model's sizes in the report. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "args.h"
#include "commands.h"
#include "pipeline/pipeline.h"
#include "pipeline/fom_report.h"
#include "pipeline/method_adaptive_subspace.h"
#include "util/util.h"

static void adaptive_usage(FILE *out)
{
    fprintf(out,
            "usage: romkit adaptive SCENE.json [--entry K] [--positions P.npy] [--snapshots S.npy]\n"
            "                       [--frames DIR] [--fields F.npy] [--report R.json] [--quiet]\n\n"
            "Runs the scene with the adaptive subspace simulator of its rom entry K (default: the first\n"
            "entry with \"method\": \"adaptive_subspace\"), without the full-order run, and writes what is asked:\n"
            "  --positions P.npy   final positions, n x 3 float64\n"
            "  --snapshots S.npy   every frame including the start, (steps+1) x n x 3 float64\n"
            "  --frames DIR        one boundary-surface mesh per frame (frame_00000.obj, ...)\n"
            "  --fields F.npy      the enrichment per frame, (steps+1) x n x 3 float64: enriched when the\n"
            "                      step's solve ended (0/1, before downdating), the oracle's error G and\n"
            "                      progress E at its last Newton iteration (the thresholds' units: 1 is\n"
            "                      the threshold; 0 at the start, NaN on a step full order took at once)\n"
            "  --report R.json     seconds_per_step, newton_iterations, the model's sizes (adaptive.*:\n"
            "                      active columns, enriched vertices, PCG iterations, time shares), the\n"
            "                      full-space residual per step (adaptive.residual), contact\n"
            "  --quiet             no progress line on stderr\n"
            "Nothing is written when the run fails. romkit compare runs it beside full order.\n\n"
            "example:\n"
            "  romkit adaptive examples/scenes/adaptive_trampoline.json --snapshots S.npy --report a.json\n");
}

typedef struct {
    const char *scene, *entry, *positions, *snapshots, *frames, *fields, *report;
    int quiet;
} adaptive_args;

static int pick_entry(const rk_scene *s, const char *given, const rk_rom_entry **e, rk_error *err)
{
    if (given) {
        char *end;
        long k = strtol(given, &end, 10);
        if (*end || k < 0 || k > 1000000) return rk_fail(err, "--entry must be a rom entry's index, got \"%s\"", given);
        if (rk_scene_entry(s, (int)k, e, err)) return -1;
        if (!rk_adaptive_subspace_of(*e))
            return rk_fail(err, "%s: %s is not method adaptive_subspace", s->path, (*e)->path);
        return 0;
    }
    for (int k = 0; k < s->nentries; k++)
        if (rk_adaptive_subspace_of(&s->entries[k])) {
            *e = &s->entries[k];
            return 0;
        }
    return rk_fail(err, "%s: no rom entry with \"method\": \"adaptive_subspace\"", s->path);
}

int cmd_adaptive(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (is_help(argv[i])) {
            adaptive_usage(stdout);
            return 0;
        }
    adaptive_args a = {0};
    const cli_option opts[] = {{"--entry", &a.entry, NULL},     {"--positions", &a.positions, NULL},
                               {"--snapshots", &a.snapshots, NULL}, {"--frames", &a.frames, NULL}, {"--fields", &a.fields, NULL},
                               {"--report", &a.report, NULL},   {"--quiet", NULL, &a.quiet},
                               {NULL, NULL, NULL}};
    if (cli_parse("adaptive", argc, argv, opts, &a.scene, "scene file")) {
        adaptive_usage(stderr);
        return 2;
    }
    rk_progress_set_quiet(a.quiet);
    rk_error err = {{0}};
    rk_scene scene;
    rk_scene_sim sim;
    rk_adaptive ad = {0};
    rk_npy_stream snap, fld;
    int have_scene = 0, have_sim = 0, have_snap = 0, have_fld = 0, rc = 1;
    double *secs = NULL, *field = NULL;
    const rk_rom_entry *e;
    if (rk_scene_load(a.scene, &scene, &err)) goto done;
    have_scene = 1;
    if (pick_entry(&scene, a.entry, &e, &err) || rk_scene_build(&scene, &sim, &err)) goto done;
    have_sim = 1;
    if (sim.options.is_static) {
        rk_fail(&err, "%s: method adaptive_subspace simulates dynamics; the scene asks for a static solve", e->path);
        goto done;
    }
    if (rk_scene_adaptive_init(&scene, &sim, e, NULL, 0, &ad, NULL, &err)) goto done;
    int nv = sim.mesh.nv, steps = sim.steps;
    int contact = sim.options.nobstacles > 0 || sim.options.nobjects > 1 || sim.options.contact.self;
    if (!(secs = rk_calloc((size_t)steps + 1, sizeof(double), &err))) goto done;
    if (a.frames && mkdir(a.frames, 0777) != 0 && errno != EEXIST) {
        rk_fail(&err, "%s: cannot create frames folder: %s", a.frames, strerror(errno));
        goto done;
    }
    if (a.snapshots) {
        long shape[3] = {steps + 1, nv, 3};
        if (rk_npy_stream_open(&snap, a.snapshots, 3, shape, &err)) goto done;
        have_snap = 1;
        rk_npy_stream_append(&snap, ad.fom.x, 3 * (size_t)nv);
    }
    if (a.fields) {
        long shape[3] = {steps + 1, nv, 3};
        if (!(field = rk_calloc(3 * (size_t)nv, sizeof(double), &err)) ||
            rk_npy_stream_open(&fld, a.fields, 3, shape, &err))
            goto done;
        have_fld = 1;
        rk_adaptive_fields(&ad, field);
        rk_npy_stream_append(&fld, field, 3 * (size_t)nv);
    }
    rk_contact_tally tally;
    rk_contact_tally_init(&tally);
    rk_adaptive_subspace_measures res;
    memset(&res, 0, sizeof res);
    char frame[4096];
    for (int s = 0; s <= steps; s++) {
        if (s > 0) {
            double t0 = rk_now();
            if (rk_adaptive_step(&ad, &err)) goto done;
            secs[s - 1] = rk_now() - t0;
            if (ad.opt.residual) rk_adaptive_residual_add(&res, s - 1, steps, ad.stats.residual_last);
            if (have_snap) rk_npy_stream_append(&snap, ad.fom.x, 3 * (size_t)nv);
            if (have_fld) {
                rk_adaptive_fields(&ad, field);
                rk_npy_stream_append(&fld, field, 3 * (size_t)nv);
            }
            rk_progress(e->name, s, steps);
        }
        if (a.frames) {
            snprintf(frame, sizeof frame, "%s/frame_%05d.obj", a.frames, s);
            if (rk_mesh_write(frame, &sim.mesh, ad.fom.x, &err)) goto done;
        }
        if (contact) {
            int c;
            double d;
            if (rk_fom_contact_measure(&ad.fom, &c, &d, &err)) goto done;
            rk_contact_tally_add(&tally, c, d);
        }
    }
    rk_progress_done(e->name);
    if (have_snap) {
        have_snap = 0;
        if (rk_npy_stream_commit(&snap, &err)) goto done;
    }
    if (have_fld) {
        have_fld = 0;
        if (rk_npy_stream_commit(&fld, &err)) goto done;
    }
    if (a.positions) {
        long shape[2] = {nv, 3};
        if (rk_npy_write(a.positions, ad.fom.x, 2, shape, &err)) goto done;
    }
    rk_adaptive_residual_record(&res, &ad);
    rk_adaptive_residual_warn(stderr, e->name, &res, steps);
    rk_unconverged_warn(stderr, e->name, ad.fom.stats.unconverged_steps, steps);
    cJSON *report = rk_adaptive_report(&sim, &ad, secs, steps, contact ? &tally : NULL, &res);
    if (a.report && rk_json_write_file(a.report, report, &err)) {
        cJSON_Delete(report);
        goto done;
    }
    cJSON_Delete(report);
    const rk_adaptive_stats *st = &ad.stats;
    printf("%s (%s): %d vertices, %d tets; %d steps: %.4g s/step, %.1f Newton iterations a step; %.1f columns "
           "(max %d), %.1f enriched vertices (max %d) of %d subdomains; %ld steps by full order; %.1f PCG iterations a "
           "solve\n",
           a.scene, e->name, nv, sim.mesh.nt, steps, rk_median(secs, steps), (double)st->newton_iterations / steps,
           st->sum_modes / steps, st->max_modes, st->sum_nodes / steps, st->max_nodes, ad.opt.subdomains, st->steps_full,
           st->solves ? (double)st->pcg_iterations / st->solves : 0.0);
    if (res.residual)
        printf("full-space residual |d|_inf/h: mean %.3g, max %.3g m/s (its tolerance %.3g), %d steps over it\n",
               res.residual_mean, res.residual_max, res.residual_tolerance, res.residual_over);
    if (contact) printf("contact: closest %.3g m, %ld crossings over %ld frames\n", tally.min_distance, tally.intersections, tally.frames);
    rc = 0;
done:
    if (rc) fprintf(stderr, "romkit adaptive: %s\n", err.msg);
    if (have_snap) rk_npy_stream_abort(&snap);
    if (have_fld) rk_npy_stream_abort(&fld);
    free(secs);
    free(field);
    rk_adaptive_free(&ad);
    if (have_sim) rk_scene_sim_free(&sim);
    if (have_scene) rk_scene_free(&scene);
    return rc;
}
