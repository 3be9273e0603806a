/* romkit run OUT.rombin --steps N: steps an asset through the runtime (runtime/romrt.h), exactly
 * as an application would: ask for the arena size, open in place, step, read positions. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "args.h"
#include "asset_open.h"
#include "commands.h"
#include "run_contact.h"
#include "run_splats.h"
#include "run_stress.h"
#include "formats/rombin_read.h"
#include "formats/rombin_write.h"
#include "runtime/romrt.h"
#include "util/util.h"
#include "pipeline/pipeline.h"

static size_t max_reduced_size(void)
{
    romrt_limits limits;
    limits.size = sizeof limits;
    return romrt_get_limits(&limits, NULL) == ROMRT_OK ? limits.max_reduced_size : 0;
}

static void run_usage(FILE *f)
{
    fprintf(f, "usage: romkit run ASSET.rombin --steps N [--positions P.npy] [--snapshots S.npy]\n"
               "                  [--report R.json] [--jump N] [--dt H] [--damping MU]\n"
               "                  [--reference S.npy] [--frames DIR] [--splats DIR] [--koopman] [--newton K]\n"
               "                  [--hessian-reuse K] [--scene SCENE.json] [--stress T.npy] [--quiet]\n"
               "  opens the asset with the runtime (float32 build, r up to %d) and steps it N times\n"
               "  --positions   final positions of the shown vertices (n x 3 float64)\n"
               "  --snapshots   every frame's shown positions (N x n x 3 float64)\n"
               "  --report      seconds_per_step (median), seconds_positions (drawing every shown vertex),\n"
               "                Newton work (iterations, factorizations; hessian_reuse: the mode in force),\n"
               "                the most contact pairs of a step, arena and asset bytes\n"
               "  --jump        after the steps, advance a Koopman asset N steps at once (seconds_jump:\n"
               "                the median of 21 timed jumps from the same state)\n"
               "  --koopman     step the asset's Koopman operator (an asset may hold one beside its reduced\n"
               "                model; --jump, --dt and --damping imply it)\n"
               "  --dt          a Koopman asset's time step (s), rescaled from the training one (Eq. 21)\n"
               "  --damping     a Koopman asset's eigenvalues times (1 - MU) (Sec. 7.2)\n"
               "  --frames DIR  the shown surface at every frame as DIR/frame_NNNNN.obj (frame 0: the start)\n"
               "  --splats DIR  a Gaussian-splat asset's splats at every frame as DIR/frame_NNNNN.ply (3DGS PLY:\n"
               "                centres moved, covariances F Sigma F^T, view-dependent colour turned with F's\n"
               "                rotation; frame 0: the start)\n"
               "  --reference   T x n x 3 positions of the whole source mesh (romkit fom --snapshots: frame\n"
               "                0 at t = 0): the report's reference.{normalized_mse, relative_error} over\n"
               "                the shown vertices and the first min(N, T - 1) steps\n"
               "  --newton K    a reduced model's fixed-cost mode: exactly K full Newton steps per time step,\n"
               "                no line search or convergence test (romrt_set_newton_iterations; 0, the\n"
               "                default: Newton to the asset's tolerance)\n"
               "  --hessian-reuse K  a reduced model's Newton matrix kept for up to K steps (modified Newton:\n"
               "                only the gradient per iteration; romrt_set_hessian_reuse; 0 or 1: a fresh\n"
               "                matrix every iteration; the default: kept 10 steps in the converged mode,\n"
               "                fresh with --newton, and where the asset has obstacles other than planes,\n"
               "                several objects or self-contact, fresh while a contact term acts)\n"
               "  --scene       the scene the asset was built from: the report's contact.{min_distance,\n"
               "                intersections, intersecting_frames, frames}, measured on the start and every\n"
               "                step as romkit fom measures its frames (the exact segment-triangle test; the\n"
               "                scene's collision surface, obstacles and objects; the asset must show the surface),\n"
               "                when the scene has contact; with --reference, a caged object's full-order frames\n"
               "                (mesh.cage: the cage's vertices) carried to the surface the asset shows\n"
               "  --stress T.npy  every frame's largest principal Cauchy stress (Pa) at each shown vertex,\n"
               "                (N+1) x n float64 (frame 0: the start), as romkit fom --stress with --scene's\n"
               "                materials: a point cloud's from the runtime's deformation gradients (GRAD), a\n"
               "                mesh's from its tets (bake it with rom.asset.show \"all\")\n"
               "  --quiet       no progress line on stderr\n"
               "  a deflate-compressed asset is inflated in memory first, as an app shipping one would.\n\n"
               "example (after romkit build examples/scenes/cantilever_small.json -o cantilever.rombin\n"
               "         and romkit fom examples/scenes/cantilever_small.json --snapshots S.npy):\n"
               "  romkit run cantilever.rombin --steps 50 --reference S.npy --report run.json\n",
           (int)max_reduced_size());
}

static int parse_count(const char *what, const char *text, long *out)
{
    if (cli_whole(text, 0, 100000000, out) == 0) return 0;
    fprintf(stderr, "romkit run: %s must be a whole number in 0..1e8, got '%s'\n", what, text ? text : "(none)");
    return -1;
}

/* --dt and --damping: a number (what range makes sense, the runtime says when it is set). */
static int parse_real(const char *what, const char *text, romrt_real *out)
{
    double v;
    if (cli_real(text, -1e30, 1e30, &v) == 0) return *out = (romrt_real)v, 0;
    fprintf(stderr, "romkit run: %s must be a number, got '%s'\n", what, text);
    return -1;
}

/* --reference: the source mesh's frames, the asset's shown vertices among them (VMAP), and the
 * errors of util/util.h over the shown vertices, their rest shape being the reference's frame 0. */
typedef struct {
    double *frames;     /* T x nv x 3 */
    long T, nv;
    uint32_t *source;   /* shown vertex -> source vertex */
    int shown;
    const run_scene *S; /* --scene, carrying a cage's frames to its embedded surface, or NULL */
    double *rest, *at;  /* the shown vertices in frame 0 and in the frame being compared (3 shown) */
    rk_run_error error;
} reference;

/* The shown vertices' positions in reference frame k. */
static void reference_gather(const reference *ref, long k, double *out)
{
    const double *F = ref->frames + (size_t)k * ref->nv * 3;
    for (int i = 0; i < ref->shown; i++)
        if (ref->S) run_scene_shown_at(ref->S, F, i, out + 3 * i);
        else
            for (int a = 0; a < 3; a++) out[3 * i + a] = F[3 * (size_t)ref->source[i] + a];
}

static int reference_open(reference *ref, const char *path, const unsigned char *asset, size_t bytes, int shown,
                          const run_scene *S, rk_error *err)
{
    int ndim;
    long shape[4];
    rombin_file f;
    rombin_error e;
    rombin_chunk c;
    if (rk_npy_read(path, &ref->frames, &ndim, shape, err)) return -1;
    if (ndim != 3 || shape[2] != 3 || shape[0] < 2)
        return rk_fail(err, "%s: --reference must be T x n x 3 positions with T >= 2", path);
    ref->T = shape[0];
    ref->nv = shape[1];
    if (rombin_open(&f, asset, bytes, NULL, &e) || !rombin_find(&f, ROMBIN_VMAP, &c) || c.raw < 4 * (uint64_t)shown)
        return rk_fail(err, "--reference: the asset has no VMAP chunk saying which source vertex each one is");
    ref->shown = shown;
    ref->source = calloc((size_t)shown + 1, sizeof(uint32_t));
    ref->rest = calloc((size_t)3 * shown + 1, sizeof(double));
    ref->at = calloc((size_t)3 * shown + 1, sizeof(double));
    if (!ref->source || !ref->rest || !ref->at) return rk_fail(err, "out of memory");
    memcpy(ref->source, c.data, 4 * (size_t)shown);
    rombin_chunk head;
    uint32_t source_nv = rombin_find(&f, ROMBIN_HEAD, &head) ? ((const uint32_t *)head.data)[ROMBIN_HEAD_SOURCE_VERTICES] : 0;
    /* a surface embedded in a cage (mesh.cage): the full-order frames are the cage's, carried to it
     * by its barycentric coordinates in the cage's tets, which --scene knows */
    if (S && S->sim.embedded.nv > 0 && ref->nv == S->sim.mesh.nv) ref->S = S;
    for (int i = 0; i < shown && !ref->S; i++)
        if (ref->source[i] >= ref->nv)
            return rk_fail(err, "%s has %ld vertices; the asset's vertex %d comes from source vertex %u%s", path, ref->nv,
                           i, ref->source[i],
                           source_nv && ref->source[i] >= source_nv
                               ? " (a surface embedded in a simulation cage, mesh.cage: the full-order frames are the "
                                 "cage's; give --scene SCENE.json to carry them to the surface)"
                               : "");
    reference_gather(ref, 0, ref->rest);
    rk_run_error_init(&ref->error, ref->rest, shown);
    return 0;
}

/* Step k's shown positions xyz against reference frame k. */
static void reference_add(reference *ref, long k, const double *xyz)
{
    if (!ref->frames || k >= ref->T) return;
    reference_gather(ref, k, ref->at);
    rk_run_error_add(&ref->error, xyz, ref->at);
}

static void reference_free(reference *ref)
{
    free(ref->frames);
    free(ref->source);
    free(ref->rest);
    free(ref->at);
}

/* What drawing costs: the median of 21 romrt_positions calls for every shown vertex. */
static double timed_positions(const romrt_model *m, romrt_real *xyz, size_t n)
{
    enum { REPEATS = 21 };
    double t[REPEATS];
    for (int k = 0; k < REPEATS; k++) {
        double t0 = rk_now();
        if (romrt_positions(m, xyz, 3 * n, 3, NULL)) return NAN;
        t[k] = rk_now() - t0;
    }
    return rk_median(t, REPEATS);
}

/* --frames DIR: the shown vertices and the asset's surface triangles as DIR/frame_NNNNN.obj. */
static int write_obj(const char *dir, long frame, const romrt_model *m, const romrt_real *xyz, const int32_t *tris,
                     rk_error *err)
{
    char path[4096];
    rk_atomic_file f;
    snprintf(path, sizeof path, "%s/frame_%05ld.obj", dir, frame);
    if (rk_atomic_open(&f, path, err)) return -1;
    for (size_t i = 0; i < romrt_shown_count(m); i++)
        fprintf(f.fp, "v %.9g %.9g %.9g\n", (double)xyz[3 * i], (double)xyz[3 * i + 1], (double)xyz[3 * i + 2]);
    for (size_t t = 0; t < romrt_triangle_count(m); t++)
        fprintf(f.fp, "f %ld %ld %ld\n", (long)tris[3 * t] + 1, (long)tris[3 * t + 1] + 1, (long)tris[3 * t + 2] + 1);
    return rk_atomic_commit(&f, err);
}

/* Jumps `n` steps from the current state 21 times (restoring it between), keeps the last:
 * *seconds is the median of the timings. */
static romrt_status timed_jump(romrt_model *m, unsigned long n, double *seconds, romrt_error *err)
{
    enum { REPEATS = 21 };
    double t[REPEATS];
    size_t count = romrt_state_size(m);
    romrt_real *state = calloc(count, sizeof(romrt_real));
    romrt_status st = state ? romrt_get_state(m, state, count, err) : ROMRT_E_ARGUMENT;
    for (int k = 0; k < REPEATS && st == ROMRT_OK; k++) {
        if (k && (st = romrt_set_state(m, state, count, err))) break;
        double t0 = rk_now();
        st = romrt_jump(m, n, err);
        t[k] = rk_now() - t0;
    }
    *seconds = st == ROMRT_OK ? rk_median(t, REPEATS) : NAN;
    free(state);
    return st;
}

int cmd_run(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (is_help(argv[i])) {
            run_usage(stdout);
            return 0;
        }
    const char *path, *steps_text = NULL, *pos_out = NULL, *snap_out = NULL, *report_out = NULL, *jump_text = NULL;
    const char *dt_text = NULL, *damping_text = NULL, *ref_path = NULL, *frames_dir = NULL, *newton_text = NULL;
    const char *splats_dir = NULL, *reuse_text = NULL, *scene_path = NULL, *stress_out = NULL;
    int quiet = 0, koopman = 0;
    const cli_option opts[] = {{"--steps", &steps_text, NULL},   {"--positions", &pos_out, NULL},
                               {"--snapshots", &snap_out, NULL}, {"--report", &report_out, NULL},
                               {"--jump", &jump_text, NULL},     {"--dt", &dt_text, NULL},
                               {"--damping", &damping_text, NULL}, {"--reference", &ref_path, NULL},
                               {"--frames", &frames_dir, NULL},   {"--koopman", NULL, &koopman},
                               {"--newton", &newton_text, NULL}, {"--quiet", NULL, &quiet},
                               {"--splats", &splats_dir, NULL}, {"--hessian-reuse", &reuse_text, NULL},
                               {"--scene", &scene_path, NULL},  {"--stress", &stress_out, NULL},
                               {NULL, NULL, NULL}};
    long steps, jump = 0, fixed_newton = 0, reuse = 0;
    romrt_real dt = 0, damping = 0;
    if (cli_parse("run", argc, argv, opts, &path, "asset file") || parse_count("--steps", steps_text, &steps) ||
        (jump_text && parse_count("--jump", jump_text, &jump)) || (dt_text && parse_real("--dt", dt_text, &dt)) ||
        (damping_text && parse_real("--damping", damping_text, &damping)) ||
        (newton_text && parse_count("--newton", newton_text, &fixed_newton)) ||
        (reuse_text && parse_count("--hessian-reuse", reuse_text, &reuse))) {
        run_usage(stderr);
        return 2;
    }
    rk_error err = {{0}};
    romrt_error rerr;
    tool_asset asset = {0};
    double *frame = NULL, *seconds = NULL;
    int32_t *tris = NULL;
    reference ref;
    memset(&ref, 0, sizeof ref);
    romrt_real *xyz = NULL;
    rk_npy_stream snap;
    int snapping = 0, rc = 1;
    run_splats splats;
    memset(&splats, 0, sizeof splats);
    run_scene scene;
    memset(&scene, 0, sizeof scene);
    run_contact contact;
    memset(&contact, 0, sizeof contact);
    run_stress stress;
    memset(&stress, 0, sizeof stress);
    int measure_contact = 0;
    double t0 = rk_now();
    long newton = 0, unconverged = 0, factorizations = 0, most_pairs = 0, hessian_reuse = 0;
    /* an asset may hold a reduced model and a Koopman operator: the Koopman options pick the latter */
    koopman |= jump_text || dt_text || damping_text;
    if (tool_asset_open(&asset, path, koopman, &rerr, &err)) {
        if (koopman && rerr.status == ROMRT_E_UNSUPPORTED)
            rk_fail(&err, "%s: this asset has no Koopman operator (no KHED chunk)",
                    jump_text ? "--jump" : dt_text ? "--dt" : damping_text ? "--damping" : "--koopman");
        goto fail;
    }
    romrt_model *m = asset.m;
    const unsigned char *data = asset.data;
    size_t size = asset.bytes;
    if (dt_text && romrt_set_time_step(m, dt, &rerr) != ROMRT_OK) goto runtime_fail;
    if (damping_text && romrt_set_damping(m, damping, &rerr) != ROMRT_OK)
        goto runtime_fail;
    if (newton_text && romrt_set_newton_iterations(m, (size_t)fixed_newton, &rerr) != ROMRT_OK)
        goto runtime_fail;
    if (reuse_text && romrt_set_hessian_reuse(m, (size_t)reuse, &rerr) != ROMRT_OK)
        goto runtime_fail;
    size_t n = romrt_shown_count(m);
    xyz = calloc(3 * n + 1, sizeof(romrt_real));
    frame = calloc(3 * n + 1, sizeof(double));
    seconds = calloc((size_t)steps + 1, sizeof(double));
    if (!xyz || !frame || !seconds) {
        rk_fail(&err, "out of memory for %zu shown vertices", n);
        goto fail;
    }
    if (frames_dir) {
        tris = calloc(3 * romrt_triangle_count(m) + 1, sizeof(int32_t));
        if (!tris || (mkdir(frames_dir, 0777) != 0 && errno != EEXIST)) {
            rk_fail(&err, "%s: cannot create the frames folder: %s", frames_dir, tris ? strerror(errno) : "out of memory");
            goto fail;
        }
        if (romrt_triangles(m, tris, 3 * romrt_triangle_count(m), &rerr) ||
            romrt_positions(m, xyz, 3 * n, 3, &rerr))
            goto runtime_fail;
        if (write_obj(frames_dir, 0, m, xyz, tris, &err)) goto fail;
    }
    if (splats_dir) {
        if (run_splats_open(&splats, splats_dir, data, size, m, &err)) goto fail;
        if (romrt_positions(m, xyz, 3 * n, 3, &rerr)) goto runtime_fail;
        if (run_splats_frame(&splats, m, 0, xyz, &err)) goto fail;
    }
    if (stress_out && !scene_path) {
        rk_fail(&err, "--stress needs --scene SCENE.json, the scene the asset was built from: its materials");
        goto fail;
    }
    if (scene_path) {
        if (run_scene_open(&scene, scene_path, data, size, m, &err)) goto fail;
        /* --scene measures contact; with --stress or --reference it may have none */
        measure_contact = (!stress_out && !ref_path) || run_contact_wanted(&scene);
    }
    if (ref_path && reference_open(&ref, ref_path, data, size, (int)n, scene_path ? &scene : NULL, &err)) goto fail;
    if (measure_contact) {
        if (run_contact_open(&contact, &scene, &err)) goto fail;
        if (romrt_positions(m, xyz, 3 * n, 3, &rerr)) goto runtime_fail;
        if (run_contact_frame(&contact, m, romrt_time(m), xyz, &err)) goto fail;
    }
    if (stress_out) {
        if (run_stress_open(&stress, stress_out, steps + 1, &scene, m, &err)) goto fail;
        if (romrt_positions(m, xyz, 3 * n, 3, &rerr)) goto runtime_fail;
        if (run_stress_frame(&stress, m, 0, xyz, &err)) goto fail;
    }
    if (snap_out) {
        long shape[3] = {steps, (long)n, 3};
        if (rk_npy_stream_open(&snap, snap_out, 3, shape, &err)) goto fail;
        snapping = 1;
    }
    for (long k = 0; k < steps; k++) {
        double s0 = rk_now();
        if (romrt_step(m, &rerr) != ROMRT_OK) goto runtime_fail;
        seconds[k] = rk_now() - s0;
        romrt_step_info info;
        info.size = sizeof info; /* romrt.h: out-structs carry their size */
        if (romrt_last_step(m, &info, &rerr)) goto runtime_fail;
        newton += (long)info.newton_iterations;
        factorizations += (long)info.factorizations;
        if ((long)info.contact_pairs > most_pairs) most_pairs = (long)info.contact_pairs;
        hessian_reuse = (long)info.hessian_reuse;
        unconverged += !info.converged;
        if (snapping || ref.frames || frames_dir || splats_dir || measure_contact || stress_out) {
            if (romrt_positions(m, xyz, 3 * n, 3, &rerr)) goto runtime_fail;
            for (size_t i = 0; i < 3 * n; i++) frame[i] = xyz[i];
            if (snapping) rk_npy_stream_append(&snap, frame, 3 * n);
            reference_add(&ref, k + 1, frame);
            if (frames_dir && write_obj(frames_dir, k + 1, m, xyz, tris, &err)) goto fail;
            if (splats_dir && run_splats_frame(&splats, m, k + 1, xyz, &err)) goto fail;
            if (measure_contact && run_contact_frame(&contact, m, romrt_time(m), xyz, &err)) goto fail;
            if (stress_out && run_stress_frame(&stress, m, k + 1, xyz, &err)) goto fail;
        }
        if (!quiet) rk_progress("run", k + 1, steps);
    }
    if (!quiet) rk_progress_done("run");
    double seconds_jump = NAN, seconds_positions = report_out ? timed_positions(m, xyz, n) : NAN;
    if (jump_text && timed_jump(m, (unsigned long)jump, &seconds_jump, &rerr) != ROMRT_OK) goto runtime_fail;
    if (romrt_positions(m, xyz, 3 * n, 3, &rerr)) goto runtime_fail;
    for (size_t i = 0; i < 3 * n; i++) frame[i] = xyz[i];
    if (snapping) {
        snapping = 0;
        if (rk_npy_stream_commit(&snap, &err)) goto fail;
    }
    if (run_stress_commit(&stress, &err)) goto fail;
    long pshape[2] = {(long)n, 3};
    if (pos_out && rk_npy_write(pos_out, frame, 2, pshape, &err)) goto fail;
    double median = steps ? rk_median(seconds, (int)steps) : 0;
    if (report_out) {
        cJSON *r = cJSON_CreateObject();
        cJSON_AddNumberToObject(r, "vertices", (double)n);
        cJSON_AddNumberToObject(r, "r", (double)romrt_reduced_size(m));
        cJSON_AddNumberToObject(r, "steps", (double)steps);
        cJSON_AddNumberToObject(r, "time", romrt_time(m));
        cJSON_AddNumberToObject(r, "seconds_per_step", median);
        cJSON_AddNumberToObject(r, "seconds_positions", seconds_positions);
        if (jump_text) {
            cJSON_AddNumberToObject(r, "jump", (double)jump);
            cJSON_AddNumberToObject(r, "seconds_jump", seconds_jump);
        }
        cJSON_AddStringToObject(r, "kind", romrt_model_kind(m) == ROMRT_KIND_KOOPMAN ? "koopman" : "reduced");
        cJSON_AddNumberToObject(r, "newton_iterations", (double)newton);
        cJSON_AddNumberToObject(r, "unconverged_steps", (double)unconverged);
        cJSON_AddNumberToObject(r, "fixed_newton_iterations", (double)fixed_newton); /* 0: converged mode */
        /* the mode in force (romrt_step_info): the asset's default unless --hessian-reuse set one */
        cJSON_AddNumberToObject(r, "hessian_reuse", (double)hessian_reuse);
        cJSON_AddNumberToObject(r, "factorizations", (double)factorizations);
        cJSON_AddNumberToObject(r, "contact_pairs_max", (double)most_pairs);
        cJSON_AddNumberToObject(r, "arena_bytes", (double)asset.arena_bytes);
        cJSON_AddStringToObject(r, "precision", sizeof(romrt_real) == 4 ? "float32" : "float64");
        if (ref.frames) {
            cJSON *rj = cJSON_AddObjectToObject(r, "reference");
            cJSON_AddNumberToObject(rj, "frames", (double)ref.error.frames);
            cJSON_AddNumberToObject(rj, "normalized_mse", rk_normalized_mse(&ref.error));
            cJSON_AddNumberToObject(rj, "relative_error", rk_relative_error(&ref.error));
        }
        if (measure_contact) rk_contact_tally_report(cJSON_AddObjectToObject(r, "contact"), &contact.tally);
        cJSON *a = cJSON_AddObjectToObject(r, "asset");
        cJSON_AddNumberToObject(a, "bytes", (double)asset.file_bytes);
        cJSON *s = cJSON_AddObjectToObject(r, "seconds");
        cJSON_AddNumberToObject(s, "total", rk_now() - t0);
        int bad = rk_json_write_file(report_out, r, &err);
        cJSON_Delete(r);
        if (bad) goto fail;
    }
    printf("%s: %ld steps of %g s, r = %zu, %zu shown vertices, %.3g us/step (median), %ld Newton iterations, "
           "arena %zu bytes\n", path, steps, (double)romrt_time_step(m), romrt_reduced_size(m), n, median * 1e6, newton,
           asset.arena_bytes);
    if (ref.error.frames)
        printf("  against %s over %ld frames: relative error %.3g, normalized MSE %.3g\n", ref_path, ref.error.frames,
               rk_relative_error(&ref.error), rk_normalized_mse(&ref.error));
    if (measure_contact)
        printf("  contact with %s: closest %.3g m, %ld crossings in %ld of %ld frames\n", scene_path,
               contact.tally.min_distance, contact.tally.intersections, contact.tally.intersecting_frames,
               contact.tally.frames);
    if (jump_text) printf("  then a jump of %ld steps in %.3g us, to t = %g s\n", jump, seconds_jump * 1e6, (double)romrt_time(m));
    rc = 0;
    goto done;
runtime_fail:
    rk_fail(&err, "%s: %s: %s", path, romrt_status_string(rerr.status), rerr.message);
fail:
    fprintf(stderr, "romkit run: %s\n", err.msg);
done:
    if (snapping) rk_npy_stream_abort(&snap);
    tool_asset_close(&asset);
    run_splats_close(&splats);
    run_contact_close(&contact);
    run_stress_close(&stress);
    run_scene_close(&scene);
    free(xyz);
    free(frame);
    free(seconds);
    reference_free(&ref);
    free(tris);
    return rc;
}
