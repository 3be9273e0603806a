/* romkit fom SCENE.json: full-order simulation (or a static solve) of a scene. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "args.h"
#include "commands.h"
#include "contact_report.h"
#include "fom/fom.h"
#include "pipeline/pipeline.h"
#include "util/util.h"

int rk_fem_inverted(const rk_fem *f, const double *x, double *min_J);

static void fom_usage(FILE *out)
{
    fprintf(out,
            "usage: romkit fom SCENE.json [--positions P.npy] [--snapshots S.npy] [--frames DIR]\n"
            "                  [--frame-format obj|ply|vtk|mesh] [--report R.json] [--quiet]\n\n"
            "Runs the full-order simulation the scene describes (or its static equilibrium when\n"
            "time.static is true) and writes what is asked:\n"
            "  --positions P.npy   final positions, n x 3 float64\n"
            "  --snapshots S.npy   every frame including the rest state, (steps+1) x n x 3 float64\n"
            "  --frames DIR        one boundary-surface mesh per frame (frame_00000.obj, ...)\n"
            "  --frame-format F    the format of those files: obj (default), ply, vtk or mesh\n"
            "  --report R.json     counts, timings (seconds_per_step; seconds.* and shares.* of the\n"
            "                      parts: factorization, assembly, solve, line search, contact ...;\n"
            "                      newton.*: the median iteration against its factorization), final state\n"
            "  --quiet             no progress line on stderr\n"
            "Nothing is written when the run fails. ROMKIT_THREADS=N: threads (default: the CPUs).\n\n"
            "example:\n"
            "  romkit fom examples/scenes/cantilever_small.json --snapshots S.npy --report fom.json\n");
}

typedef struct {
    const char *scene, *positions, *snapshots, *frames, *report;
    const char *frame_format;
    int quiet;
} fom_args;

static int parse_args(int argc, char **argv, fom_args *a)
{
    memset(a, 0, sizeof *a);
    a->frame_format = "obj";
    const cli_option opts[] = {{"--positions", &a->positions, NULL}, {"--snapshots", &a->snapshots, NULL},
                               {"--frames", &a->frames, NULL},       {"--frame-format", &a->frame_format, NULL},
                               {"--report", &a->report, NULL},       {"--quiet", NULL, &a->quiet},
                               {NULL, NULL, NULL}};
    if (cli_parse("fom", argc, argv, opts, &a->scene, "scene file")) return -1;
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

/* The median of a timing over the Newton iterations, with its spread. */
typedef struct {
    double median, min, max;
} iter_stat;

static iter_stat stat_of(const double *v, long n)
{
    iter_stat st = {0, 0, 0};
    double *t = n > 0 ? malloc(sizeof(double) * (size_t)n) : NULL;
    if (!t) return st;
    memcpy(t, v, sizeof(double) * (size_t)n);
    st.median = rk_median(t, (int)n); /* sorts t */
    st.min = t[0];
    st.max = t[n - 1];
    free(t);
    return st;
}

/* What a run leaves behind, gathered frame by frame (rk_scene_fom_run). */
typedef struct {
    const fom_args *a;
    const rk_scene_sim *sim;
    rk_npy_stream snap;
    int have_snap, steps;
    double *x;             /* the last frame's positions */
    cJSON *final;          /* the final state's report keys */
    int contact, max_inverted;  /* contact measured; the most inverted elements of a frame */
    rk_contact_tally tally; /* exact crossings and the closest the surfaces came, over the frames */
    rk_contact_stats stats; /* the contact stage's counters at the end */
    iter_stat iter, factor; /* per Newton iteration: its seconds and its factorization's */
} fom_output;

static int on_frame(void *ctx, int step, rk_fom *fom, double seconds, rk_error *err)
{
    fom_output *o = ctx;
    const rk_scene_sim *sim = o->sim;
    int nv = sim->mesh.nv;
    if (o->have_snap) rk_npy_stream_append(&o->snap, fom->x, 3 * (size_t)nv);
    if (o->a->frames && write_frame(o->a, &sim->mesh, fom->x, step, err)) return -1;
    memcpy(o->x, fom->x, sizeof(double) * 3 * (size_t)nv);
    double min_J, max_disp = 0, closest;
    int inverted = rk_fem_inverted(&sim->fem, fom->x, &min_J), crossings;
    if (inverted > o->max_inverted) o->max_inverted = inverted;
    if (o->contact) {
        if (rk_fom_contact_measure(fom, &crossings, &closest, err)) return -1;
        rk_contact_tally_add(&o->tally, crossings, closest);
    }
    if (step < o->steps) return 0;
    const double *it, *fa;
    long n = rk_fom_iterations(fom, &it, &fa);
    o->iter = stat_of(it, n);
    o->factor = stat_of(fa, n);
    for (int v = 0; v < nv; v++) {
        double d2 = 0;
        for (int i = 0; i < 3; i++) d2 += pow(fom->x[3 * v + i] - sim->mesh.X[3 * v + i], 2);
        max_disp = fmax(max_disp, sqrt(d2));
    }
    cJSON *fin = o->final = cJSON_CreateObject();
    cJSON_AddNumberToObject(fin, "time", fom->t);
    cJSON_AddNumberToObject(fin, "inverted_elements", inverted);
    cJSON_AddNumberToObject(fin, "min_det_F", min_J);
    cJSON_AddNumberToObject(fin, "max_displacement", max_disp);
    cJSON_AddNumberToObject(fin, "kinetic_energy", rk_fom_kinetic_energy(fom));
    cJSON_AddNumberToObject(fin, "elastic_energy", rk_fem_energy(&sim->fem, fom->x));
    if (o->contact && rk_fom_contact_stats(fom)) o->stats = *rk_fom_contact_stats(fom);
    return 0;
}

/* The report's "contact" object: what the run came to and what contact cost. */
static void add_contact(cJSON *r, const fom_output *o, const rk_contact_stats *cs)
{
    cJSON *c = cJSON_AddObjectToObject(r, "contact");
    contact_tally_report(c, &o->tally);
    cJSON_AddNumberToObject(c, "mean_pairs", cs->gathers ? (double)cs->pairs / cs->gathers : 0);
    cJSON_AddNumberToObject(c, "max_pairs", (double)cs->max_pairs);
    cJSON_AddNumberToObject(c, "ccd_calls", (double)cs->ccd_calls);
    cJSON *sec = cJSON_AddObjectToObject(c, "seconds");
    cJSON_AddNumberToObject(sec, "broad_phase", cs->seconds_broad);
    cJSON_AddNumberToObject(sec, "ccd", cs->seconds_ccd);
    cJSON_AddNumberToObject(sec, "barrier", cs->seconds_potential);
}

/* seconds.X and shares.X (of seconds.simulate) */
static void add_part(cJSON *sec, cJSON *shares, const char *name, double seconds, double simulate)
{
    cJSON_AddNumberToObject(sec, name, seconds);
    cJSON_AddNumberToObject(shares, name, simulate > 0 ? seconds / simulate : 0);
}

static cJSON *make_report(const rk_scene_sim *sim, const rk_fom_stats *st, const fom_output *o, int steps,
                          cJSON *final, double seconds_total)
{
    cJSON *r = cJSON_CreateObject();
    cJSON_AddNumberToObject(r, "vertices", sim->mesh.nv);
    cJSON_AddNumberToObject(r, "tets", sim->mesh.nt);
    cJSON_AddNumberToObject(r, "steps", steps);
    cJSON_AddNumberToObject(r, "h", sim->options.h);
    cJSON_AddStringToObject(r, "integrator", sim->options.is_static ? "static"
                                             : sim->options.integrator == RK_BDF2 ? "bdf2"
                                                                                   : "backward_euler");
    cJSON_AddNumberToObject(r, "seconds_per_step", steps > 0 ? st->seconds_total / steps : st->seconds_total);
    cJSON_AddNumberToObject(r, "newton_iterations", (double)st->newton_iterations);
    cJSON_AddNumberToObject(r, "unconverged_steps", (double)st->unconverged_steps);
    /* Where the simulation's time went: disjoint parts of seconds.simulate, each with its share
     * (shares.*): CHOLMOD's analyses in steps (contact changing the pattern), numeric
     * factorizations and solves; the Newton iterations' potential with gradient and Newton matrix
     * (assembly; the elastic Hessians with their PSD projection are seconds.hessian, a part of
     * it), the line search's potential values, the contact stage; other: the rest (predictor,
     * prescribed motion, checks). seconds.analysis_init: the analysis before the first step. */
    double sim_s = st->seconds_total;
    double other = sim_s - st->seconds_analyze - st->seconds_factor - st->seconds_solve - st->seconds_assemble -
                   st->seconds_line_search - st->seconds_contact;
    cJSON *sec = cJSON_AddObjectToObject(r, "seconds");
    cJSON *shares = cJSON_CreateObject();
    cJSON_AddNumberToObject(sec, "total", seconds_total);
    cJSON_AddNumberToObject(sec, "simulate", sim_s);
    cJSON_AddNumberToObject(sec, "analysis_init", st->seconds_analyze_init);
    add_part(sec, shares, "analysis", st->seconds_analyze, sim_s);
    add_part(sec, shares, "factorization", st->seconds_factor, sim_s);
    add_part(sec, shares, "solve", st->seconds_solve, sim_s);
    add_part(sec, shares, "assembly", st->seconds_assemble, sim_s);
    add_part(sec, shares, "hessian", st->seconds_hessian, sim_s);
    add_part(sec, shares, "line_search", st->seconds_line_search, sim_s);
    add_part(sec, shares, "contact", st->seconds_contact, sim_s);
    add_part(sec, shares, "other", other > 0 ? other : 0, sim_s);
    cJSON_AddItemToObject(r, "shares", shares);
    cJSON_AddNumberToObject(r, "factorization_share", sim_s > 0 ? st->seconds_factor / sim_s : 0);
    /* Per Newton iteration (median over the run's iterations, with the fastest and slowest):
     * its seconds (potential, factorization, solve, line search) against its numeric
     * factorization's alone. */
    cJSON *nw = cJSON_AddObjectToObject(r, "newton");
    cJSON_AddNumberToObject(nw, "iterations", (double)st->newton_iterations);
    cJSON_AddNumberToObject(nw, "line_search_halvings", (double)st->line_search_halvings);
    cJSON_AddNumberToObject(nw, "analyses", (double)st->analyses);
    cJSON_AddNumberToObject(nw, "projected_hessians", (double)st->projected_hessians);
    cJSON_AddNumberToObject(nw, "seconds_per_iteration", o->iter.median);
    cJSON_AddNumberToObject(nw, "seconds_per_iteration_min", o->iter.min);
    cJSON_AddNumberToObject(nw, "seconds_per_iteration_max", o->iter.max);
    cJSON_AddNumberToObject(nw, "factorization_seconds", o->factor.median);
    cJSON_AddNumberToObject(nw, "factorization_seconds_min", o->factor.min);
    cJSON_AddNumberToObject(nw, "factorization_seconds_max", o->factor.max);
    cJSON_AddNumberToObject(nw, "iteration_per_factorization", o->factor.median > 0 ? o->iter.median / o->factor.median : 0);
    cJSON_AddNumberToObject(r, "threads", rk_threads());
    cJSON *mesh = cJSON_AddObjectToObject(r, "mesh");
    cJSON_AddNumberToObject(mesh, "components", sim->mesh_report.components);
    cJSON_AddNumberToObject(mesh, "reoriented", sim->mesh_report.reoriented);
    cJSON_AddNumberToObject(mesh, "min_quality", sim->mesh_report.min_quality);
    /* Slivers simulated (kept: thicker than rounding) and flat tets dropped, with the vertices only
     * they used (each named in a warning on stderr when the scene was built). */
    cJSON_AddNumberToObject(mesh, "slivers", sim->mesh_report.slivers);
    cJSON_AddNumberToObject(mesh, "flat_dropped", sim->mesh_report.flat_dropped);
    cJSON_AddNumberToObject(mesh, "flat_inside", sim->mesh_report.ghosts); /* kept as ghosts (mesh.h) */
    cJSON_AddNumberToObject(mesh, "orphans_removed", sim->mesh_report.orphans_removed);
    cJSON_AddItemToObject(r, "final", final);
    return r;
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
    rk_contact_tally_init(&out.tally);
    int have_scene = 0, have_sim = 0, rc = 1;
    if (rk_scene_load(a.scene, &scene, &err)) goto done;
    have_scene = 1;
    if (rk_scene_build(&scene, &sim, &err)) goto done;
    have_sim = 1;
    int nv = sim.mesh.nv;
    out.sim = &sim;
    out.contact = sim.options.nobstacles > 0 || sim.options.nobjects > 1 || sim.options.contact.self;
    out.steps = sim.options.is_static ? 1 : sim.steps;
    if (!(out.x = rk_calloc(3 * (size_t)nv, sizeof(double), &err))) goto done;
    if (a.frames && mkdir(a.frames, 0777) != 0 && errno != EEXIST) {
        rk_fail(&err, "%s: cannot create frames folder: %s", a.frames, strerror(errno));
        goto done;
    }
    if (a.snapshots) {
        long shape[3] = {out.steps + 1, nv, 3};
        if (rk_npy_stream_open(&out.snap, a.snapshots, 3, shape, &err)) goto done;
        out.have_snap = 1;
    }
    rk_fom_stats stats;
    if (rk_scene_fom_run(&sim, NULL, "full-order run", on_frame, &out, &stats, &err)) goto done;
    if (out.have_snap) {
        out.have_snap = 0;
        if (rk_npy_stream_commit(&out.snap, &err)) goto done;
    }
    if (a.positions) {
        long shape[2] = {nv, 3};
        if (rk_npy_write(a.positions, out.x, 2, shape, &err)) goto done;
    }
    cJSON *report = make_report(&sim, &stats, &out, out.steps, out.final, rk_now() - t0);
    out.final = NULL;
    cJSON_AddNumberToObject(report, "max_inverted_elements", out.max_inverted);
    if (out.contact) add_contact(report, &out, &out.stats);
    if (a.report && rk_json_write_file(a.report, report, &err)) {
        cJSON_Delete(report);
        goto done;
    }
    const cJSON *fin = cJSON_GetObjectItem(report, "final");
    printf("%s: %d vertices, %d tets; %d %s of %g s: %.4g s/step (factorization %.0f%%), "
           "%.2f Newton iterations/step\n",
           a.scene, nv, sim.mesh.nt, out.steps, sim.options.is_static ? "static solve" : "steps", sim.options.h,
           cJSON_GetObjectItem(report, "seconds_per_step")->valuedouble,
           100 * cJSON_GetObjectItem(report, "factorization_share")->valuedouble,
           (double)stats.newton_iterations / out.steps);
    printf("Newton iteration: %.3g s (median), %.2f x its factorization (%.3g s), %d threads\n", out.iter.median,
           out.factor.median > 0 ? out.iter.median / out.factor.median : 0.0, out.factor.median, rk_threads());
    printf("final: %d inverted elements, max displacement %.4g m, kinetic energy %.4g J\n",
           cJSON_GetObjectItem(fin, "inverted_elements")->valueint,
           cJSON_GetObjectItem(fin, "max_displacement")->valuedouble,
           cJSON_GetObjectItem(fin, "kinetic_energy")->valuedouble);
    if (out.contact)
        printf("contact: closest %.3g m, %ld crossings over %ld frames, %.1f pairs per evaluation (at most %ld); "
               "broad phase %.3g s, CCD %.3g s\n", out.tally.min_distance, out.tally.intersections, out.tally.frames,
               out.stats.gathers ? (double)out.stats.pairs / out.stats.gathers : 0.0, out.stats.max_pairs,
               out.stats.seconds_broad, out.stats.seconds_ccd);
    cJSON_Delete(report);
    rc = 0;
done:
    if (rc) fprintf(stderr, "romkit fom: %s\n", err.msg);
    if (out.have_snap) rk_npy_stream_abort(&out.snap);
    cJSON_Delete(out.final);
    free(out.x);
    if (have_sim) rk_scene_sim_free(&sim);
    if (have_scene) rk_scene_free(&scene);
    return rc;
}
