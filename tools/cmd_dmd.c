/* romkit dmd --snapshots S.npy [--snapshots S2.npy ...] --dt H -o OUT.rombin: a Koopman operator
 * from trajectories recorded anywhere (another simulator, tracked markers), baked into an asset.
 * With --markers, the recording is k tracked vertices of a scene's mesh, lifted to every vertex
 * through the scene's linear modes (Sec. 7.5) and fitted on the modal coordinates. The work is
 * precompute/pipeline/dmd.h's; this file parses the options, calls it and writes the files. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "commands.h"
#include "formats/rombin_write.h"
#include "pipeline/dmd.h"
#include "mesh/mesh.h"
#include "video/video.h"
#include "util/util.h"

#define MAX_FILES RK_DMD_MAX_RECORDINGS

static void dmd_usage(FILE *f)
{
    fprintf(f,
            "usage: romkit dmd --snapshots S.npy [--snapshots S2.npy ...] --dt H -o OUT.rombin\n"
            "                  [--rank R | --energy E] [--clamp | --no-refit] [--pod P] [--gravity GX,GY,GZ]\n"
            "                  [--accel AX,AY,AZ ...] [--from-rest] [--rest R.npy] [--mesh M] [--vertex-mass KG]\n"
            "                  [--precision float32|float64] [--compress] [--report R.json] [--quiet]\n"
            "       romkit dmd --markers M.npy --marker-vertices V.txt --scene SCENE.json --modes B --dt H\n"
            "                  -o OUT.rombin [--marker-ridge RHO] [the fit, --gravity, --from-rest and output options]\n"
            "       romkit dmd --tracks TRACKS.json [--cameras CAMS.json] --scene SCENE.json [--modes B] [--dt H]\n"
            "                  -o OUT.rombin [--match-tol D] [--marker-ridge RHO] [the same options as --markers]\n"
            "  fits a Koopman operator by DMD on states [u_t; u_t - u_{t-1}] from every file jointly (each\n"
            "  one trajectory at time step H) and bakes it into OUT.rombin for the runtime.\n"
            "  S.npy: T x n x 3 positions (u = x - rest), or T x d observables used as they are.\n"
            "  --rank, --energy  the DMD rank, or the singular-value energy kept (default 0.999999)\n"
            "  --clamp           scale every |lambda| > 1 down to 1 (stable long rollouts)\n"
            "  --no-refit        keep the fit's eigenvalues as fitted: by default, a fit of data whose energy\n"
            "                    does not grow that leaves the unit circle is refitted under |lambda| <= 1\n"
            "                    (the modes held; the summary says how many moved and what it cost)\n"
            "  --pod P           fit on the P leading POD coordinates of the data first\n"
            "  --gravity         the constant acceleration acting during every recording and when the\n"
            "                    asset is stepped (m/s^2; default none)\n"
            "  --accel           the acceleration during one recording, in --snapshots order (overrides\n"
            "                    --gravity for it): forces then act as impulses (Eq. 19)\n"
            "  --from-rest       every recording starts at rest (its first frame is also the one before):\n"
            "                    the first step, from rest, becomes a training pair too\n"
            "  --rest            n x 3 rest positions (default: the first frame of the first file)\n"
            "  --mesh            a mesh over the same n vertices: its surface is what the asset shows\n"
            "  --vertex-mass     each vertex's mass (kg, default 1) for forces an app applies\n"
            "  --precision       real type of the asset's arrays: float32 (default) or float64\n"
            "  --compress        deflate the asset's chunks\n"
            "  --report R.json   rank, eigenvalues, the asset's bytes, timings\n"
            "  --quiet           no progress on stderr\n"
            "  The asset starts at the first recording's first frame, at rest.\n"
            "  Learning from markers (Sec. 7.5), instead of --snapshots:\n"
            "  --markers M.npy   T x k x 3 positions of k tracked vertices of the scene's mesh, one frame\n"
            "                    per H seconds (displacements are taken from those vertices' rest positions);\n"
            "                    or T x n x 3, every vertex of the scene (romkit fom --snapshots): the listed\n"
            "                    vertices are taken from it, the others never read\n"
            "  --marker-vertices V.txt  the k vertex indices (0-based), one per line, in M.npy's order\n"
            "  --scene           the scene whose mesh, material and fixed vertices give the linear modes\n"
            "  --modes B         each frame's markers are fitted by the first B modes (least squares, 3k >= B);\n"
            "                    DMD then runs on the B modal coordinates and the modes lift it to every vertex\n"
            "                    (the scene's masses and surface go into the asset)\n"
            "  --marker-ridge RHO  each frame's fit minimises |markers - modes q|^2 + lambda^2 sum_j (w_j q_j)^2,\n"
            "                    w_j = omega_j / omega_1 (the penalty is the elastic energy), lambda = RHO times\n"
            "                    the largest singular value of the weighted modes at the markers: less\n"
            "                    amplified tracking noise, at a bias towards rest (default 0: none; 0.03 cut\n"
            "                    the lift's error under 0.5 mm noise from 36%% to 3.1%% with 4 markers on 12 modes)\n"
            "  Learning from video (romkit track's output), instead of --markers and --marker-vertices:\n"
            "  --tracks T.json   the 2D dot tracks of each view, one frame per H seconds, frame 0 at rest (--dt:\n"
            "                    default the cameras' \"dt\"; --modes: default 12)\n"
            "  --cameras C.json  each view's calibration, in the tracks' view order (default: the cameras the\n"
            "                    tracks carry from romkit track --cameras): {\"views\": [{\"name\", \"frames\",\n"
            "                    \"K\": 3 x 3, \"R\": 3 x 3 (world -> camera, a rotation), \"t\": [3], \"size\": [w, h]}]};\n"
            "                    x_cam = R X + t, pixel = K x_cam / z, pixel (0, 0) the top-left pixel's centre\n"
            "  --match-tol D     frame 0's dots are ray-cast onto the scene's rest surface; dots of different\n"
            "                    views whose hits lie within D (default 1%% of the rest shape's diagonal) are one\n"
            "                    marker, at the hit's surface point (its modes' rows: its triangle's, by its\n"
            "                    barycentric weights). Each frame's position is the midpoint of the views' rays;\n"
            "                    a dot seen by one view only, or a marker tracked by fewer than two views at some\n"
            "                    frame, is dropped (one ray has no depth). --report adds markers.video: the\n"
            "                    counts and the reprojection error in pixels\n\n"
            "example (snapshots of a full-order run, then the operator, then 1000 steps at once):\n"
            "  romkit fom examples/scenes/cantilever_small.json --snapshots S.npy\n"
            "  romkit dmd --snapshots S.npy --dt 0.01 --from-rest --gravity 0,-9.81,0 --clamp -o koopman.rombin\n"
            "  romkit run koopman.rombin --steps 50 --jump 1000\n"
            "example (6 vertices of the same run as tracked markers, 12 modes, against the run):\n"
            "  printf '48\\n54\\n62\\n146\\n178\\n188\\n' >V.txt\n"
            "  romkit dmd --markers S.npy --marker-vertices V.txt --scene examples/scenes/cantilever_small.json\n"
            "             --modes 12 --dt 0.01 --from-rest --gravity 0,-9.81,0 -o markers.rombin\n"
            "  romkit run markers.rombin --steps 50 --reference S.npy\n");
}

typedef struct {
    const char *snapshots[MAX_FILES], *accel[MAX_FILES];
    int nsnap, naccel;
    const char *dt, *rank, *energy, *pod, *gravity, *rest, *mesh, *mass, *out, *report, *precision;
    const char *markers, *marker_vertices, *scene, *modes, *marker_ridge, *tracks, *cameras, *match_tol;
    int clamp, no_refit, compress, quiet, from_rest;
} dmd_args;

/* --markers takes the recording, rest, masses and surface from the scene: all four of its options,
 * none of those that would give them otherwise. */
static int markers_args(const dmd_args *a)
{
    if (a->tracks || a->cameras || a->match_tol) {
        if (!a->tracks || !a->scene || !a->out || a->markers || a->marker_vertices) {
            fprintf(stderr, "romkit dmd: learning from video needs --tracks, --scene and -o (and --cameras unless romkit "
                    "track was given them; not --markers or --marker-vertices)\n");
            return -1;
        }
    } else if (!a->markers || !a->marker_vertices || !a->scene || !a->modes || !a->dt || !a->out) {
        fprintf(stderr, "romkit dmd: learning from markers needs --markers, --marker-vertices, --scene, --modes, --dt "
                "and -o\n");
        return -1;
    }
    const char *clash = a->nsnap ? "--snapshots" : a->pod ? "--pod" : a->rest ? "--rest" : a->mesh ? "--mesh"
                      : a->mass ? "--vertex-mass" : a->naccel ? "--accel" : NULL;
    if (clash) {
        fprintf(stderr, "romkit dmd: %s does not go with %s (the scene gives the recording's rest, masses and "
                "surface; --gravity sets the acceleration)\n", clash, a->tracks ? "--tracks" : "--markers");
        return -1;
    }
    return 0;
}

static int parse_args(int argc, char **argv, dmd_args *a)
{
    struct {
        const char *name;
        const char **value;
    } values[] = {{"--dt", &a->dt},       {"--rank", &a->rank}, {"--energy", &a->energy},       {"--pod", &a->pod},
                  {"--gravity", &a->gravity}, {"--rest", &a->rest}, {"--mesh", &a->mesh}, {"--vertex-mass", &a->mass},
                  {"-o", &a->out},        {"--report", &a->report}, {"--precision", &a->precision},
                  {"--markers", &a->markers}, {"--marker-vertices", &a->marker_vertices}, {"--scene", &a->scene},
                  {"--modes", &a->modes}, {"--marker-ridge", &a->marker_ridge}, {"--tracks", &a->tracks},
                  {"--cameras", &a->cameras}, {"--match-tol", &a->match_tol}};
    memset(a, 0, sizeof *a);
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        int *flag = !strcmp(arg, "--clamp") ? &a->clamp : !strcmp(arg, "--no-refit") ? &a->no_refit
                  : !strcmp(arg, "--compress") ? &a->compress
                  : !strcmp(arg, "--quiet") ? &a->quiet : !strcmp(arg, "--from-rest") ? &a->from_rest : NULL;
        if (flag) {
            *flag = 1;
            continue;
        }
        if (i + 1 >= argc) {
            fprintf(stderr, "romkit dmd: %s needs a value (or is unknown)\n", arg);
            return -1;
        }
        if (!strcmp(arg, "--snapshots") || !strcmp(arg, "--accel")) {
            int *n = arg[2] == 's' ? &a->nsnap : &a->naccel;
            if (*n == MAX_FILES) {
                fprintf(stderr, "romkit dmd: at most %d %s\n", MAX_FILES, arg);
                return -1;
            }
            (arg[2] == 's' ? a->snapshots : a->accel)[(*n)++] = argv[++i];
            continue;
        }
        size_t k = 0;
        while (k < sizeof values / sizeof values[0] && strcmp(values[k].name, arg)) k++;
        if (k == sizeof values / sizeof values[0]) {
            fprintf(stderr, "romkit dmd: unknown option %s\n", arg);
            return -1;
        }
        *values[k].value = argv[++i];
    }
    if (a->markers || a->marker_vertices || a->scene || a->modes || a->marker_ridge || a->tracks || a->cameras ||
        a->match_tol)
        return markers_args(a);
    if (!a->nsnap || !a->dt || !a->out) {
        fprintf(stderr, "romkit dmd: --snapshots, --dt and -o are required\n");
        return -1;
    }
    if (a->naccel > 1 && a->naccel != a->nsnap) {
        fprintf(stderr, "romkit dmd: give one --accel for all recordings or one per --snapshots (%d for %d)\n",
                a->naccel, a->nsnap);
        return -1;
    }
    return 0;
}

/* A number (finite, in [lo, hi]), a whole one, or three comma-separated ones. */
static int number(const char *what, const char *text, double lo, double hi, double *out, rk_error *err)
{
    if (cli_real(text, lo, hi, out)) return rk_fail(err, "%s must be a number in [%g, %g], got '%s'", what, lo, hi, text);
    return 0;
}

static int whole(const char *what, const char *text, long lo, long hi, int *out, rk_error *err)
{
    long v;
    if (cli_whole(text, lo, hi, &v)) return rk_fail(err, "%s must be a whole number in [%ld, %ld], got '%s'", what, lo, hi, text);
    *out = (int)v;
    return 0;
}

static int vector3(const char *what, const char *text, double v[3], rk_error *err)
{
    if (sscanf(text, "%lf,%lf,%lf", &v[0], &v[1], &v[2]) != 3 || !isfinite(v[0] + v[1] + v[2]))
        return rk_fail(err, "%s must be three comma-separated numbers, got '%s'", what, text);
    return 0;
}

/* --tracks without --modes: the modes each frame's markers are fitted by (12 fitted the filmed
 * cantilever of cli_track.sh to 1.2% with 14 markers). */
#define RK_DMD_TRACKS_MODES 12

/* --tracks without --dt: the seconds between frames the cameras give ("dt", carried by romkit track
 * into the tracks, or in --cameras). */
static int tracks_dt(const dmd_args *a, double *h, rk_error *err)
{
    rk_tracks tr;
    rk_cameras cams;
    double dt = 0;
    if (a->cameras) {
        if (rk_cameras_load(a->cameras, &cams, err)) return rk_error_prefix(err, "--cameras");
        dt = cams.dt;
    } else {
        if (rk_tracks_load(a->tracks, &tr, err)) return rk_error_prefix(err, "--tracks");
        dt = tr.calibrated ? tr.cams.dt : 0;
        rk_tracks_free(&tr);
    }
    if (!(dt > 0))
        return rk_fail(err, "--dt is needed: the cameras (%s) give no \"dt\", the seconds between frames",
                       a->cameras ? a->cameras : a->tracks);
    *h = dt;
    return 0;
}

/* --markers: the scene's modes, the markers lifted (dmd.h), as the one recording. */
static int markers_recording(const dmd_args *a, rk_dmd_markers *mk, rk_dmd_recordings *r, rk_error *err)
{
    int b = 0;
    double ridge = 0, tol = 0;
    if (!a->modes && a->tracks) b = RK_DMD_TRACKS_MODES;
    else if (whole("--modes", a->modes, 1, 4096, &b, err))
        return -1;
    if ((a->marker_ridge && number("--marker-ridge", a->marker_ridge, 0, 1e6, &ridge, err)) ||
        (a->match_tol && number("--match-tol", a->match_tol, 1e-12, 1e12, &tol, err)))
        return -1;
    if (a->tracks ? rk_dmd_markers_video(a->scene, a->tracks, a->cameras, b, ridge, tol, mk, err)
                  : rk_dmd_markers_load(a->scene, a->markers, a->marker_vertices, b, ridge, mk, err))
        return -1;
    return rk_dmd_recordings_markers(mk, a->from_rest, r, err);
}

/* --snapshots (with --rest, --vertex-mass) as the recordings. */
static int snapshot_recordings(const dmd_args *a, rk_dmd_recordings *r, rk_error *err)
{
    double m = 1;
    memset(r, 0, sizeof *r);
    if (a->mass && number("--vertex-mass", a->mass, 1e-30, 1e30, &m, err)) return -1;
    return rk_dmd_recordings_load(a->snapshots, a->nsnap, a->from_rest, a->rest, m, r, err);
}

/* --gravity and --accel into each recording's constant acceleration. */
static int recordings_accel(const dmd_args *a, rk_dmd_recordings *r, double gravity[3], rk_error *err)
{
    double accel[MAX_FILES][3];
    if (a->gravity && vector3("--gravity", a->gravity, gravity, err)) return -1;
    for (int f = 0; f < a->naccel; f++)
        if (vector3("--accel", a->accel[f], accel[f], err)) return -1;
    return rk_dmd_recordings_accel(r, a->gravity ? gravity : NULL, (const double(*)[3])accel, a->naccel, err);
}

int cmd_dmd(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (is_help(argv[i])) {
            dmd_usage(stdout);
            return 0;
        }
    dmd_args a;
    if (parse_args(argc, argv, &a)) {
        dmd_usage(stderr);
        return 2;
    }
    rk_progress_set_quiet(a.quiet);
    double t0 = rk_now(), gravity[3] = {0, 0, 0};
    rk_error err = {{0}};
    rk_dmd_recordings rec;
    rk_dmd_markers mk;
    rk_koopman k;
    rk_mesh mesh;
    rk_asset_options ao;
    rk_koopman_options o;
    int have_mesh = 0, rc = 1, pod = 0;
    memset(&k, 0, sizeof k);
    memset(&mk, 0, sizeof mk);
    memset(&rec, 0, sizeof rec);
    rk_asset_default_options(&ao);
    rk_koopman_default_options(&o);
    int has_real_type, real_type;
    if (cli_precision("dmd", a.precision, &has_real_type, &real_type)) return 2;
    if (has_real_type) ao.real_type = real_type;
    ao.compress = a.compress;
    if ((a.tracks && !a.dt ? tracks_dt(&a, &o.h, &err) : number("--dt", a.dt, 1e-12, 1e6, &o.h, &err)) ||
        (a.rank && whole("--rank", a.rank, 1, 4096, &o.rank, &err)) ||
        (a.energy && number("--energy", a.energy, 1e-12, 1, &o.energy, &err)) ||
        (a.pod && whole("--pod", a.pod, 1, 100000, &pod, &err)))
        goto done;
    o.clamp = a.clamp;
    int sparse = a.markers || a.tracks; /* markers lifted through the scene's modes */
    o.stabilize = a.no_refit ? -1 : 0;
    if (sparse ? markers_recording(&a, &mk, &rec, &err) : snapshot_recordings(&a, &rec, &err)) goto done_rec;
    if (recordings_accel(&a, &rec, gravity, &err)) goto done_rec;
    double fit_t = rk_now();
    if (sparse ? rk_koopman_fit_projected(rec.traj, 1, 3 * rec.nv, mk.Pin, mk.Phi, mk.b, &o, &k, &err)
        : pod ? rk_koopman_fit_pod(rec.traj, rec.ntraj, 3 * rec.nv, pod, &o, &k, &err)
              : rk_koopman_fit(rec.traj, rec.ntraj, 3 * rec.nv, &o, &k, &err))
        goto done_rec;
    fit_t = rk_now() - fit_t;
    int *tris = NULL, ntris = 0;
    if (a.mesh) {
        rk_mesh_report mr;
        if (rk_mesh_load(a.mesh, RK_MESH_KEEP_FLAT, &mesh, &mr, &err)) goto done_rec; /* its vertices as recorded */
        have_mesh = 1;
        if (mesh.nv != rec.nv) {
            rk_fail(&err, "%s has %d vertices, the recordings %d", a.mesh, mesh.nv, rec.nv);
            goto done_rec;
        }
        if (rk_mesh_boundary(&mesh, &tris, &ntris, &err)) goto done_rec;
    }
    rk_baked baked;
    if (!rk_dmd_bake(&k, &rec, sparse ? &mk : NULL, tris, ntris, have_mesh ? mesh.nt : 0, a.gravity ? gravity : NULL,
                     &ao, a.tracks ? "romkit dmd --tracks" : a.markers ? "romkit dmd --markers" : "romkit dmd", fit_t,
                     &baked, &err)) {
        cJSON_AddNumberToObject(cJSON_GetObjectItem(baked.report, "seconds"), "total", rk_now() - t0);
        if (!rombin_save(a.out, baked.data, baked.bytes, &err) &&
            (!a.report || !rk_json_write_file(a.report, baked.report, &err))) {
            printf("%s: ", a.out);
            if (a.tracks) {
                const rk_video_markers *v = &mk.video;
                printf("dots in frame 0");
                for (int i = 0; i < v->nviews; i++) printf("%s %d", i ? "," : "", v->dots[i]);
                printf(" (per view): %d on the rest surface, %d markers matched across views, %d dots seen by one view "
                       "only, %d markers lost, %d triangulated (reprojection error rms %.3g px, max %.3g px); ", v->hit,
                       v->matched, v->single_view, v->lost, v->triangulated, v->reproj_rms, v->reproj_max);
            }
            if (sparse)
                printf("%d markers on %d modes (they miss the markers by at most %.3g of the largest marker "
                       "displacement), ", mk.k, mk.b, mk.marker_misfit);
            printf("%s\n", baked.summary);
            rc = 0;
        }
        rk_baked_free(&baked);
    }
    free(tris);
done_rec:
    rk_dmd_recordings_free(&rec);
    rk_dmd_markers_free(&mk);
done:
    if (have_mesh) rk_mesh_free(&mesh);
    rk_koopman_free(&k);
    if (rc) fprintf(stderr, "romkit dmd: %s\n", err.msg);
    return rc;
}
