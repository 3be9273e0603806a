/* romkit dmd --markers (koopman-dmd-log-linear paper, Sec. 7.5, learning from video): tracked
 * markers lifted to a whole mesh through the scene's linear modes, for cmd_dmd.c to fit and bake. */
#ifndef ROMKIT_DMD_MARKERS_H
#define ROMKIT_DMD_MARKERS_H

#include "util/util.h"

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
} dmd_markers;

/* The scene's first b linear modes (rk_scene_basis, type modes), the markers (T x k x 3 positions
 * of the k vertices listed in vertices_path, one index per line) as displacements from those
 * vertices' rest positions, their modal coordinates by least squares (rk_koopman_marker_coords,
 * with its ridge),
 * and the dense frames. Every input is checked first; errors name the file and the row. */
int dmd_markers_load(const char *scene_path, const char *markers_path, const char *vertices_path, int b,
                     double ridge, dmd_markers *out, rk_error *err);
void dmd_markers_free(dmd_markers *m);

#endif
