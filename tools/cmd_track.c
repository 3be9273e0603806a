/* romkit track: dot markers filmed from one or more views followed through the frames
 * (koopman-dmd-log-linear paper, Sec. 7.5): the dots of each view's first frame (precompute/video
 * dots.c), then pyramidal Lucas-Kanade from each frame to the next with a forward-backward check
 * (lk.c); the 2D tracks of every view into one JSON file for romkit dmd --tracks. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "commands.h"
#include "video/video.h"

static void track_usage(FILE *f)
{
    fprintf(f,
            "usage: romkit track --cameras CAMS.json -o TRACKS.json [--frames T] [options]\n"
            "       romkit track --view PATTERN [--view PATTERN ...] -o TRACKS.json [--frames T]\n"
            "                    [--start N] [--bright] [--threshold L] [--min-area A] [--max-area A]\n"
            "                    [--levels L] [--window HW] [--fb PX] [--quiet]\n"
            "  finds dot markers in each view's first frame and follows them through T frames with pyramidal\n"
            "  Lucas-Kanade optical flow; a track whose forward-backward round trip misses by more than --fb\n"
            "  pixels, or whose window leaves the image or turns flat, is lost from that frame on.\n"
            "  --cameras CAMS.json  the calibrated views, each with its frames (\"frames\": \"cam0/%%04d.png\"; the\n"
            "                    file romkit dmd --cameras reads; a view without \"size\" takes its frames'; \"dt\", the\n"
            "                    seconds between frames, is romkit dmd's --dt): the tracks file carries the\n"
            "                    cameras along, so romkit dmd --tracks needs no --cameras\n"
            "  --view PATTERN    instead, one uncalibrated view's frames, a printf pattern of the frame number:\n"
            "                    'cam0/%%04d.png' (PNG: gray, RGB, with or without alpha, 8 or 16 bit; or binary\n"
            "                    PGM, P5)\n"
            "  --frames T        frames per view (T >= 2), numbered --start (default 0) to --start + T - 1\n"
            "                    (default: the first view's frames from --start up to the first one missing)\n"
            "  --bright          bright dots on a dark surface (default: dark dots on a light one)\n"
            "  --threshold L     dot pixels are darker than luminance L in [0, 1] (default 0.3; --bright:\n"
            "                    brighter than 1 - L)\n"
            "  --min-area A, --max-area A  a dot's pixels (default 4 and 2000); components touching the\n"
            "                    border are not dots either\n"
            "  --levels L        pyramid levels (default 3), --window HW the half window (default 7: 15 x 15)\n"
            "  --fb PX           forward-backward threshold in pixels (default 0.5)\n"
            "  -o TRACKS.json    per view: the frames' pattern, size, the dot counts, and per dot the pixel\n"
            "                    positions up to the frame it is lost at ('lost', -1: never)\n"
            "example (two calibrated views of a filmed object, then the model, see romkit dmd --help):\n"
            "  romkit track --cameras cams.json -o tracks.json\n"
            "  romkit dmd --tracks tracks.json --scene beam.json --modes 12 --dt 0.01\n"
            "             --from-rest --gravity 0,-9.81,0 -o video.rombin\n");
}

typedef struct {
    const char *view[RK_VIDEO_MAX_VIEWS], *frames, *start, *out, *threshold, *min_area, *max_area, *levels, *window, *fb,
        *cameras;
    int nviews, bright, quiet;
} track_args;

static int parse_args(int argc, char **argv, track_args *a)
{
    struct {
        const char *name;
        const char **value;
    } values[] = {{"--frames", &a->frames},     {"--start", &a->start},       {"-o", &a->out},
                  {"--threshold", &a->threshold}, {"--min-area", &a->min_area}, {"--max-area", &a->max_area},
                  {"--levels", &a->levels},     {"--window", &a->window},     {"--fb", &a->fb},
                  {"--cameras", &a->cameras}};
    memset(a, 0, sizeof *a);
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--bright") || !strcmp(argv[i], "--quiet")) {
            *(argv[i][2] == 'b' ? &a->bright : &a->quiet) = 1;
            continue;
        }
        if (i + 1 >= argc) {
            fprintf(stderr, "romkit track: %s needs a value (or is unknown)\n", argv[i]);
            return -1;
        }
        if (!strcmp(argv[i], "--view")) {
            if (a->nviews == RK_VIDEO_MAX_VIEWS) {
                fprintf(stderr, "romkit track: at most %d --view\n", RK_VIDEO_MAX_VIEWS);
                return -1;
            }
            a->view[a->nviews++] = argv[++i];
            continue;
        }
        size_t k = 0;
        while (k < sizeof values / sizeof values[0] && strcmp(values[k].name, argv[i])) k++;
        if (k == sizeof values / sizeof values[0]) {
            fprintf(stderr, "romkit track: unknown option %s\n", argv[i]);
            return -1;
        }
        *values[k].value = argv[++i];
    }
    if (!(a->nviews || a->cameras) || !a->out) {
        fprintf(stderr, "romkit track: --cameras (or --view) and -o are required\n");
        return -1;
    }
    if (a->nviews && a->cameras) {
        fprintf(stderr, "romkit track: --view does not go with --cameras (the cameras file names each view's frames)\n");
        return -1;
    }
    return 0;
}

/* A pattern with exactly one integer conversion (%d, %04d, ...; %% for a percent sign). */
static int check_pattern(const char *p, rk_error *err)
{
    int conv = 0;
    for (const char *s = p; *s; s++) {
        if (*s != '%') continue;
        if (s[1] == '%') {
            s++;
            continue;
        }
        s++;
        while (*s >= '0' && *s <= '9') s++;
        if (*s != 'd') return rk_fail(err, "--view '%s': only %%d conversions (with a width: %%04d) are allowed", p);
        conv++;
    }
    return conv == 1 ? 0 : rk_fail(err, "--view '%s': expected one %%d for the frame number, found %d", p, conv);
}

static int load_frame(const char *pattern, int view, int frame, int number, rk_image *im, const rk_image *first,
                      rk_error *err)
{
    char path[4096];
    snprintf(path, sizeof path, pattern, number);
    if (rk_image_load(path, im, err)) return rk_error_prefix(err, "view %d, frame %d", view, frame);
    if (first && (im->w != first->w || im->h != first->h)) {
        rk_fail(err, "view %d, frame %d: %s is %d x %d pixels, the view's first frame %d x %d", view, frame, path, im->w,
                im->h, first->w, first->h);
        rk_image_free(im);
        return -1;
    }
    return 0;
}

/* One view: the dots of its first frame, then frame to frame. */
static int track_view(const char *pattern, int view, int T, int start, const rk_dot_options *dopt,
                      const rk_lk_options *lo, rk_view_tracks *v, rk_error *err)
{
    rk_image first, im;
    rk_pyramid P, Q;
    rk_dot *dots = NULL;
    snprintf(v->source, sizeof v->source, "%s", pattern);
    if (check_pattern(pattern, err) || load_frame(pattern, view, 0, start, &first, NULL, err)) return -1;
    v->w = first.w, v->h = first.h;
    if (rk_dots_find(&first, dopt, &dots, &v->n, &v->dots, err)) {
        rk_image_free(&first);
        char path[4096];
        snprintf(path, sizeof path, pattern, start);
        return rk_error_prefix(err, "view %d, frame 0 (%s)", view, path);
    }
    int rc = -1;
    v->xy = rk_calloc((size_t)2 * T * v->n, sizeof(double), err);
    v->lost = rk_calloc((size_t)v->n, sizeof(int), err);
    if (!v->xy || !v->lost || rk_pyramid_build(&first, lo->levels, &P, err)) goto done_first;
    for (int i = 0; i < v->n; i++) {
        v->xy[(size_t)2 * T * i] = dots[i].x, v->xy[(size_t)2 * T * i + 1] = dots[i].y;
        v->lost[i] = -1;
    }
    for (int t = 1; t < T; t++) {
        if (load_frame(pattern, view, t, start + t, &im, &first, err)) goto done_p;
        int fail = rk_pyramid_build(&im, lo->levels, &Q, err);
        rk_image_free(&im);
        if (fail) goto done_p;
        for (int i = 0; i < v->n; i++) {
            if (v->lost[i] >= 0) continue;
            double *a = v->xy + (size_t)2 * (T * i + t - 1), fb;
            if (rk_lk_track_fb(&P, &Q, lo, a[0], a[1], a + 2, a + 3, &fb) != RK_LK_OK) v->lost[i] = t;
            else if (fb > v->fb_max) v->fb_max = fb;
        }
        rk_pyramid_free(&P);
        P = Q;
        rk_progress("track", t, (long)T - 1);
    }
    rc = 0;
done_p:
    rk_pyramid_free(&P);
done_first:
    rk_image_free(&first);
    free(dots);
    return rc;
}

static int options(const track_args *a, int *T, int *start, rk_dot_options *d, rk_lk_options *l, rk_error *err)
{
    long v;
    double x;
    rk_dot_default_options(d);
    rk_lk_default_options(l);
    d->dark = !a->bright;
    *T = 0; /* counted from the files when not given */
    if (a->frames && cli_whole(a->frames, 2, 1000000, &v))
        return rk_fail(err, "--frames must be a whole number >= 2, got '%s'", a->frames);
    if (a->frames) *T = (int)v;
    *start = 0;
    if (a->start) {
        if (cli_whole(a->start, 0, 1000000000, &v)) return rk_fail(err, "--start must be a whole number >= 0, got '%s'", a->start);
        *start = (int)v;
    }
#define WHOLE(opt, lo, hi, dst)                                                                                     \
    if (opt) {                                                                                                      \
        if (cli_whole(opt, lo, hi, &v)) return rk_fail(err, "%s must be a whole number in [%d, %d], got '%s'", #dst, \
                                                       lo, hi, opt);                                                \
        dst = (int)v;                                                                                               \
    }
    WHOLE(a->min_area, 1, 1 << 24, d->min_area)
    WHOLE(a->max_area, 1, 1 << 24, d->max_area)
    WHOLE(a->levels, 1, RK_LK_MAX_LEVELS, l->levels)
    WHOLE(a->window, 1, 20, l->half_window)
#undef WHOLE
    if (a->threshold) {
        if (cli_real(a->threshold, 0, 1, &x)) return rk_fail(err, "--threshold must be a luminance in [0, 1], got '%s'", a->threshold);
        d->threshold = x;
    }
    if (a->fb) {
        if (cli_real(a->fb, 1e-6, 1e6, &x)) return rk_fail(err, "--fb must be a positive number of pixels, got '%s'", a->fb);
        l->fb_threshold = x;
    }
    if (d->min_area > d->max_area) return rk_fail(err, "--min-area %d is above --max-area %d", d->min_area, d->max_area);
    return 0;
}

/* The frames of pattern from start up to the first missing file: how many (at least 2). */
static int count_frames(const char *pattern, int start, int *T, rk_error *err)
{
    if (check_pattern(pattern, err)) return -1;
    char path[1024];
    int t = 0;
    for (; t < 1000000; t++) {
        snprintf(path, sizeof path, pattern, start + t);
        FILE *f = fopen(path, "rb");
        if (!f) break;
        fclose(f);
    }
    if (t < 2) {
        snprintf(path, sizeof path, pattern, start + t);
        return rk_fail(err, "'%s': %d frame%s from %d on (%s is missing): tracking needs at least 2", pattern, t,
                       t == 1 ? "" : "s", start, path);
    }
    *T = t;
    return 0;
}

/* --cameras: the views and their frames from the cameras file, carried into the tracks. */
static int calibrated_views(const char *path, track_args *a, rk_tracks *tr, rk_error *err)
{
    if (rk_cameras_load(path, &tr->cams, err)) return rk_error_prefix(err, "--cameras");
    for (int v = 0; v < tr->cams.n; v++) {
        if (!tr->cams.cam[v].frames[0])
            return rk_fail(err, "--cameras %s: views[%d] has no \"frames\" (its frames' printf pattern)", path, v);
        a->view[v] = tr->cams.cam[v].frames;
    }
    a->nviews = tr->cams.n;
    tr->calibrated = 1;
    return 0;
}

int cmd_track(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (is_help(argv[i])) {
            track_usage(stdout);
            return 0;
        }
    track_args a;
    if (parse_args(argc, argv, &a)) {
        track_usage(stderr);
        return 2;
    }
    rk_progress_set_quiet(a.quiet);
    rk_error err = {{0}};
    rk_tracks tr;
    rk_dot_options dopt;
    rk_lk_options lo;
    int start = 0, rc = 1;
    memset(&tr, 0, sizeof tr);
    if (options(&a, &tr.T, &start, &dopt, &lo, &err)) {
        fprintf(stderr, "romkit track: %s\n", err.msg);
        return 2;
    }
    if (a.cameras && calibrated_views(a.cameras, &a, &tr, &err)) goto done;
    tr.nviews = a.nviews;
    if (!tr.T && count_frames(a.view[0], start, &tr.T, &err)) goto done;
    for (int v = 0; v < a.nviews; v++)
        if (track_view(a.view[v], v, tr.T, start, &dopt, &lo, &tr.v[v], &err)) goto done;
    for (int v = 0; tr.calibrated && v < a.nviews; v++) {
        if (!tr.cams.cam[v].w) { /* no "size" in the cameras file: the frames' */
            tr.cams.cam[v].w = tr.v[v].w;
            tr.cams.cam[v].h = tr.v[v].h;
        }
        if (tr.v[v].w != tr.cams.cam[v].w || tr.v[v].h != tr.cams.cam[v].h) {
            rk_fail(&err, "view %d (%s): the frames are %d x %d pixels, the camera is calibrated for %d x %d (%s)", v,
                    a.view[v], tr.v[v].w, tr.v[v].h, tr.cams.cam[v].w, tr.cams.cam[v].h, a.cameras);
            goto done;
        }
    }
    rk_progress_done("track");
    if (rk_tracks_save(a.out, &tr, &err)) goto done;
    for (int v = 0; v < tr.nviews; v++) {
        int lost = 0;
        for (int i = 0; i < tr.v[v].n; i++) lost += tr.v[v].lost[i] >= 0;
        printf("%s: view %d (%s, %d x %d): %d dots found (%d components, %d too small, %d too large, %d on the border), "
               "%d lost over %d frames, largest forward-backward miss kept %.3g px\n", a.out, v, tr.v[v].source,
               tr.v[v].w, tr.v[v].h, tr.v[v].n, tr.v[v].dots.components, tr.v[v].dots.too_small, tr.v[v].dots.too_large,
               tr.v[v].dots.on_border, lost, tr.T, tr.v[v].fb_max);
    }
    rc = 0;
done:
    rk_tracks_free(&tr);
    if (rc) fprintf(stderr, "romkit track: %s\n", err.msg);
    return rc;
}
