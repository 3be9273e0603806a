/* precompute/pipeline: a Koopman operator from recordings made anywhere (romkit dmd): the
 * recordings read and made displacement trajectories (rk_dmd_recordings), tracked markers lifted
 * to a whole mesh through a scene's linear modes (rk_dmd_markers, koopman-dmd-log-linear paper
 * Sec. 7.5), the fit on the leading POD coordinates (rk_koopman_fit_pod) and the bake with its
 * report (rk_dmd_bake). The command parses its options, calls these and writes the files. */
#ifndef RK_PIPELINE_DMD_H
#define RK_PIPELINE_DMD_H

#include "pipeline/method_koopman.h"
#include "video/video.h"

/* The most recordings one fit takes. */
#define RK_DMD_MAX_RECORDINGS 64

typedef struct {
    int nv, T, b, k;       /* mesh vertices, frames, modes, markers */
    double *X;             /* 3 nv rest positions (the scene's) */
    double *vertex_mass;   /* nv (the scene's lumped masses) */
    double *u;             /* 3 nv x T: the dense displacements Phi q_t */
    double *Phi;           /* 3 nv x b, column-major: the modes */
    double *Pin;           /* b x 3 nv, column-major: (Phi^T M Phi)^-1 Phi^T M, so Pin Phi = I */
    int *tris, ntris, ntets;
    double ridge;          /* rk_koopman_marker_coords' */
    double *weight;        /* b: omega_j / omega_1 (the ridge's weights: its penalty the elastic energy) */
    double marker_misfit;  /* max over frames of |S Phi q_t - m_t| / max_t |m_t|: what b modes miss */
    int from_video;        /* the markers came from tracks (rk_dmd_markers_video): video holds the lift */
    rk_video_markers video;
} rk_dmd_markers;

/* The scene's first b linear modes (rk_scene_basis, type modes), the markers (T x k x 3 positions
 * of the k vertices listed in vertices_path, one index per line) as displacements from those
 * vertices' rest positions, their modal coordinates by least squares (rk_koopman_marker_coords,
 * with its ridge), and the dense frames. Every input is checked first; errors name the file and
 * the row (and the romkit dmd option that gave it). */
int rk_dmd_markers_load(const char *scene_path, const char *markers_path, const char *vertices_path, int b,
                        double ridge, rk_dmd_markers *out, rk_error *err);
/* The same from filmed dots (romkit dmd --tracks): the 2D tracks of tracks_path (rk_tracks_load)
 * of the views calibrated in cameras_path (NULL: the cameras the tracks carry) lifted onto the scene's rest surface (rk_video_lift,
 * matching tolerance tol; <= 0: 1% of the rest shape's bounding-box diagonal), each marker a
 * surface point whose modes' rows are its triangle's mixed by its barycentric weights; the fit
 * and the dense frames as rk_dmd_markers_load's (one implementation). */
int rk_dmd_markers_video(const char *scene_path, const char *tracks_path, const char *cameras_path, int b, double ridge,
                         double tol, rk_dmd_markers *out, rk_error *err);
void rk_dmd_markers_free(rk_dmd_markers *m);

/* The recordings as displacement trajectories of n = 3 nv values (T x d data padded to a
 * multiple of 3), with the rest positions, the vertex masses and each recording's constant
 * acceleration (NULL: none). */
typedef struct {
    int ntraj, nv, d, positions; /* d values per recorded frame; positions: T x n x 3 files */
    double *X, *vertex_mass;
    double *data[RK_DMD_MAX_RECORDINGS], *accel[RK_DMD_MAX_RECORDINGS];
    rk_koopman_trajectory traj[RK_DMD_MAX_RECORDINGS];
} rk_dmd_recordings;

/* nfiles .npy recordings (T x n x 3 positions, or T x d observables; T >= 3, one layout for all),
 * frame 0 repeated first when from_rest (a body released from rest). Then rest: the rest
 * positions from rest_file (d values), else the first recording's first frame (positions) or
 * zero; every frame made a displacement from it; each vertex's mass vertex_mass. */
int rk_dmd_recordings_load(const char *const *files, int nfiles, int from_rest, const char *rest_file,
                           double vertex_mass, rk_dmd_recordings *r, rk_error *err);
/* The markers' dense frames as the one recording (frame 0 repeated first when from_rest); the
 * rest positions and masses are taken over from m. */
int rk_dmd_recordings_markers(rk_dmd_markers *m, int from_rest, rk_dmd_recordings *r, rk_error *err);
/* Recording f's constant acceleration: accel[f] (naccel == ntraj), accel[0] (naccel == 1), else
 * gravity (NULL: none). Positions only. */
int rk_dmd_recordings_accel(rk_dmd_recordings *r, const double *gravity, const double (*accel)[3], int naccel,
                            rk_error *err);
void rk_dmd_recordings_free(rk_dmd_recordings *r);

/* The operator fitted on the P leading (unweighted) POD directions of every displacement frame of
 * the ntraj trajectories (n values each), lifted back by them. */
int rk_koopman_fit_pod(const rk_koopman_trajectory *traj, int ntraj, int n, int P, const rk_koopman_options *o,
                       rk_koopman *k, rk_error *err);

/* Operator k over the recordings baked (rk_bake_koopman): the boundary tris (source_tets tets;
 * NULL: none, or the markers' scene's when m), gravity (NULL: none) as the asset's acceleration,
 * the start at the first recording's first frame, and the report's vertices, trajectories,
 * markers.* (with m) and seconds.fit. source names the producer in the asset's INFO chunk. */
int rk_dmd_bake(const rk_koopman *k, const rk_dmd_recordings *r, const rk_dmd_markers *m, const int *tris, int ntris,
                int source_tets, const double *gravity, const rk_asset_options *ao, const char *source,
                double seconds_fit, rk_baked *out, rk_error *err);

#endif
