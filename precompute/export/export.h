/* precompute/export: a .rombin asset's shown vertices as a glTF 2.0 binary (.glb) for engines and
 * DCC tools, a run of the asset as its animation.
 *
 * Every asset the runtime steps draws x = X + B q over its shown vertices (B: the basis rows of a
 * reduced model, dense or skinning; a Koopman operator's output rows with q its eigen-coordinates
 * y). glTF's morph targets are exactly that: a base mesh plus Σ_j w_j D_j, with D_j column j of the
 * shown rows and the weights w = q, animated per frame with LINEAR interpolation. So one form
 * serves every kind of asset, and the animation reproduces the runtime's positions at its frames
 * to float precision (tests/integration/cli_export.sh reads the file back).
 *
 * A skinning basis goes the same way, one target per handle coordinate (12 per handle), not as a
 * glTF skin: a glTF joint moves only by translation, rotation and scale, and a skinning handle's
 * affine map also shears and scales unevenly; and skin weights must be non-negative and sum to one,
 * which skinning eigenmodes' weights are not. A skin would not reproduce the runtime. */
#ifndef RK_EXPORT_H
#define RK_EXPORT_H

#include <stddef.h>
#include <stdint.h>

#include "util/util.h"

/* A morph-target mesh and its weight animation. Reals are double here and float32 in the file. */
typedef struct {
    const char *name;            /* the mesh's and its node's name */
    int nv;                      /* vertices (>= 1) */
    const double *X;             /* 3 nv base positions */
    int ntris;                   /* triangles over them; 0: drawn as points (a point cloud) */
    const uint32_t *tris;        /* 3 ntris vertex indices, counter-clockwise seen from outside */
    int r;                       /* morph targets (>= 1) */
    const double *D;             /* 3 nv x r, column-major: target j's POSITION deltas at column j */
    char target_prefix;          /* targets are named <prefix>0, <prefix>1, ... (q: reduced, y: Koopman) */
    const double *rest_weights;  /* r: the mesh's weights when no animation plays */
    int frames;                  /* keyframes; fewer than 2: no animation */
    const double *times;         /* frames (s), strictly increasing */
    const double *weights;       /* frames x r, frame-major: the weights at each keyframe */
} rk_gltf_morph;

/* Writes m to path as a .glb (glTF 2.0 binary: little-endian, 4-byte aligned chunks, accessor
 * min/max, one buffer), atomically: on any failure nothing is left at path. Refuses non-finite
 * values, times that do not increase, indices out of range, and a file beyond the 4 GiB a .glb
 * can address. */
int rk_gltf_write(const char *path, const rk_gltf_morph *m, rk_error *err);

/* The first `shown` stored vertices of an asset (a stored, not deflated .rombin in memory):
 * their rest positions X (3 shown) and their rows as r columns D (3 shown x r, column-major), from
 * VERT and ROWS, from VERT and WGHT with SKIN (a skinning basis: w_j(v) X̄_c at column 12 j + 4 a + c,
 * as rk_skinning_to_U), or, with koopman set, from VERT and KOUT. r and shown are what the runtime
 * opened; a chunk that disagrees with them is an error naming it. */
int rk_export_rows(const void *asset, size_t bytes, int koopman, int shown, int r, double *X, double *D, rk_error *err);

#endif
