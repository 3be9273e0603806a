/* precompute/video: dot markers filmed from calibrated views, followed through the frames and
 * lifted onto a scene's rest surface (koopman-dmd-log-linear paper, Sec. 7.5: dots on real
 * objects, pyramidal Lucas-Kanade optical flow, DMD trained on the sparse tracks).
 *
 *   images    PNG (libpng: gray, gray+alpha, RGB, RGBA, 8 or 16 bit) or binary PGM (P5) read as
 *             float luminance in [0, 1]; gray PNG written (the test renderer's frames)
 *   dots      dark or bright blobs of the first frame: threshold, 4-connected components with
 *             size limits, intensity-weighted centroids
 *   lk        Bouguet's pyramidal Lucas-Kanade (image pyramid, per-level iterative LK over a
 *             window, bilinear sampling) with a forward-backward check
 *   tracks    the 2D tracks of every view as JSON (romkit track's output)
 *   cameras   calibrated pinhole views as JSON: x_cam = R X + t (R world -> camera, a rotation),
 *             pixel = K x_cam / z (z = x_cam's third component, in front when > 0); pixel (0, 0)
 *             is the centre of the top-left pixel, x to the right, y down
 *   lift      frame-0 dots ray-cast onto the rest surface and paired across views, each marker's
 *             material point (triangle + barycentric), its position per frame by the views' ray
 *             midpoint, and the reprojection error */
#ifndef RK_VIDEO_H
#define RK_VIDEO_H

#include "util/util.h"

#define RK_VIDEO_MAX_VIEWS 8
#define RK_LK_MAX_LEVELS 8

/* ==== images (image.c) ==== */

typedef struct {
    int w, h;
    float *px; /* w h luminances, row by row, in [0, 1] */
} rk_image;

int rk_image_alloc(rk_image *im, int w, int h, rk_error *err);
void rk_image_free(rk_image *im);
/* A .png (by its signature) or a P5 .pgm; RGB as 0.2126 R + 0.7152 G + 0.0722 B, alpha ignored.
 * Errors name the path and what is wrong with it. */
int rk_image_load(const char *path, rk_image *im, rk_error *err);
/* 8-bit gray PNG, written atomically (a temporary file, then rename). */
int rk_image_save_png(const char *path, const rk_image *im, rk_error *err);
/* Bilinear sample at (x, y) (pixel centres at whole numbers), coordinates clamped to the image. */
double rk_image_sample(const rk_image *im, double x, double y);

/* ==== dots (dots.c) ==== */

typedef struct {
    int dark;            /* 1: dark dots on a light surface; 0: bright on dark */
    double threshold;    /* dark dots: pixels below this luminance (default 0.3); bright: above 1 - it */
    int min_area, max_area; /* pixels of one dot's component */
} rk_dot_options;
void rk_dot_default_options(rk_dot_options *o);

typedef struct {
    double x, y; /* intensity-weighted centroid, pixels */
    int area;
} rk_dot;

typedef struct {
    int components, too_small, too_large, on_border, kept;
    double threshold; /* the one used */
} rk_dot_counts;

/* The dots of im (*dots malloc'ed, *n of them, in row order of their first pixel). Fails (naming
 * the counts) when none is kept. */
int rk_dots_find(const rk_image *im, const rk_dot_options *o, rk_dot **dots, int *n, rk_dot_counts *c, rk_error *err);

/* ==== pyramidal Lucas-Kanade (lk.c) ==== */

typedef struct {
    int levels;          /* pyramid levels (1: none) */
    int half_window;     /* 1..20: the window is (2 hw + 1)^2 pixels at every level */
    int iterations;      /* at most, per level */
    double epsilon;      /* stop a level when its update is below this (pixels) */
    double min_eigen;    /* smallest eigenvalue of the window's gradient matrix / window pixels */
    double fb_threshold; /* a forward-backward round trip missing by more loses the track (pixels) */
} rk_lk_options;
void rk_lk_default_options(rk_lk_options *o);

typedef struct {
    int levels;
    rk_image img[RK_LK_MAX_LEVELS], gx[RK_LK_MAX_LEVELS], gy[RK_LK_MAX_LEVELS];
} rk_pyramid;
/* Level 0 is im (copied); each level above is the one below smoothed by [1 2 1]/4 both ways and
 * halved ((w + 1) / 2), as in Bouguet's note; gx, gy the central-difference gradients. */
int rk_pyramid_build(const rk_image *im, int levels, rk_pyramid *p, rk_error *err);
void rk_pyramid_free(rk_pyramid *p);

enum { RK_LK_OK = 0, RK_LK_OUTSIDE, RK_LK_FLAT, RK_LK_LOST_FB };
/* The point (x, y) of I followed into J: (*ox, *oy). Returns RK_LK_OK, RK_LK_OUTSIDE (the window
 * left the image) or RK_LK_FLAT (the window's gradient matrix is near singular at some level). */
int rk_lk_track(const rk_pyramid *I, const rk_pyramid *J, const rk_lk_options *o, double x, double y, double *ox,
                double *oy);
/* The same, then tracked back from J into I: RK_LK_LOST_FB when the round trip misses (x, y) by
 * more than o->fb_threshold; *fb gets the miss (NAN when a pass failed). */
int rk_lk_track_fb(const rk_pyramid *I, const rk_pyramid *J, const rk_lk_options *o, double x, double y, double *ox,
                   double *oy, double *fb);

/* ==== cameras (cameras.c) ==== */

typedef struct {
    char name[64];
    char frames[512];        /* the view's frames, a printf pattern of the frame number ("" if not given) */
    double K[9], R[9], t[3]; /* row-major */
    int w, h;
} rk_camera;

typedef struct {
    int n;
    rk_camera cam[RK_VIDEO_MAX_VIEWS];
    double dt;               /* seconds between frames ("dt", optional: 0 when not given) */
} rk_cameras;

/* {"views": [{"name": "cam0", "frames": "cam0/%04d.png", "K": [[fx, s, cx], [0, fy, cy], [0, 0, 1]],
 * "R": [[...], [...], [...]], "t": [tx, ty, tz], "size": [w, h]}, ...], "dt": h} ("name", "frames",
 * "size" and "dt" optional: a view without "size" takes its frames' (w = h = 0 until then). R must be a rotation (R^T R = I and det R = +1 to
 * 1e-6), K upper triangular with positive fx, fy and K[2][2] = 1. */
int rk_cameras_load(const char *path, rk_cameras *c, rk_error *err);
/* The pixel of world point X; returns its depth z (<= 0: behind the camera). */
double rk_camera_project(const rk_camera *c, const double X[3], double px[2]);
/* The ray through a pixel: origin (the camera centre -R^T t) and unit direction, world frame. */
void rk_camera_ray(const rk_camera *c, const double px[2], double origin[3], double dir[3]);

/* ==== tracks (tracks.c) ==== */

typedef struct {
    char source[512];     /* the frames' pattern */
    int w, h, n;          /* image size, tracks */
    double *xy;           /* n x T x 2 pixel positions (valid before lost) */
    int *lost;            /* n: the first frame a track is lost at, or -1 */
    rk_dot_counts dots;   /* frame 0's detection */
    double fb_max;        /* the largest forward-backward miss of a step kept (pixels) */
} rk_view_tracks;

typedef struct {
    int T, nviews;
    rk_view_tracks v[RK_VIDEO_MAX_VIEWS];
    int calibrated;       /* cams holds the views' cameras (romkit track --cameras) */
    rk_cameras cams;
} rk_tracks;

void rk_tracks_free(rk_tracks *t);
/* JSON: {"frames": T, "views": [{"source", "size": [w, h], "dots": {...}, "tracks": [{"lost": f|-1,
 * "xy": [x0, y0, x1, y1, ...]}]}], "cameras": {"views": [...]}} (xy up to the frame before lost;
 * "cameras", as rk_cameras_load reads them, when calibrated). */
int rk_tracks_save(const char *path, const rk_tracks *t, rk_error *err);
int rk_tracks_load(const char *path, rk_tracks *t, rk_error *err);

/* ==== lift (lift.c) ==== */

typedef struct {
    int k, T, nviews;     /* markers, frames, views */
    int *tri;             /* 3 k: the vertices of each marker's surface triangle */
    double *bary;         /* 3 k: its barycentric weights there */
    double *disp;         /* 3 k x T: displacements from frame 0, frame by frame */
    int dots[RK_VIDEO_MAX_VIEWS]; /* frame-0 dots per view */
    int hit, matched, single_view, lost, triangulated; /* dots that hit the surface; markers */
    double reproj_rms, reproj_max; /* pixels, over every frame and view of the kept markers */
    double match_max;     /* the largest frame-0 spread of a marker's surface hits (length) */
} rk_video_markers;

/* Tracks of tr->nviews views (view i seen by camera i, sizes checked) lifted onto the rest surface
 * (X: 3 nv positions, tris: ntris boundary triangles facing out): frame 0's dots ray-cast onto it,
 * dots of different views whose hits lie within tol of each other made one marker (a dot whose
 * hit no other view's comes near is dropped: single_view), each marker's material point the hit
 * nearest its triangulated frame-0 position; then every frame's position by the midpoint of the
 * views' rays (least squares over the views), displacements from frame 0. A marker that fewer
 * than two views still track at some frame is dropped (lost). Fails when none is left. */
int rk_video_lift(const rk_tracks *tr, const rk_cameras *c, const double *X, int nv, const int *tris, int ntris,
                  double tol, rk_video_markers *out, rk_error *err);
void rk_video_markers_free(rk_video_markers *m);

#endif
