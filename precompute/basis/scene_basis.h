/* precompute/basis, scene side: the `rom` section's basis keys, and a basis built for a scene
 * (constraints from its fixed and moving boxes, materials from its objects and regions, full-
 * order snapshots from its own simulation when POD or a tolerance needs them). */
#ifndef RK_SCENE_BASIS_H
#define RK_SCENE_BASIS_H

#include <cjson/cJSON.h>

#include "basis/basis.h"
#include "scene/scene.h"

typedef struct {
    rk_basis_type type;
    int size;               /* columns (modes, modal_derivatives, pod) or weights m (skinning); 0: by tolerance */
    double tolerance;       /* relative M-norm projection error of the scene's full-order frames; 0: by size */
    int modes;              /* modal_derivatives: linear modes to differentiate (0: automatic) */
    int kernels;            /* rkpm_skinning: kernel centres (default 1000, Sec. 7.1) */
    int integration_points; /* rkpm_skinning: grid points inside a mesh, or the cloud's cap (default 40000) */
} rk_basis_options;

/* Reads rom (an object, or the index-th entry of an array). Keys: basis (required), size,
 * tolerance (at least one), modes, kernels, integration_points; the keys of later stages
 * (cubature, koopman, name) are allowed and left alone. Messages name the file and JSON path. */
int rk_basis_options_parse(const cJSON *rom, int index, const char *file, rk_basis_options *o,
                           rk_error *err);

typedef struct {
    int vertices, tets;        /* what the basis is evaluated on (tets 0 for a point cloud) */
    double *X;                 /* 3 vertices rest positions (owned) */
    int fom_frames;            /* full-order frames run for training (0 if none) */
    double projection_error;   /* over those frames (NAN if none) */
    double projection_error_below; /* with one size less (one weight less for skinning); NAN if none:
                                    * with a tolerance, why the size is not smaller */
    double seconds_fom, seconds_basis;
    rk_rkpm_timing rkpm;       /* rkpm_skinning only */
    int kernels, integration_points;
} rk_scene_basis_info;

/* Builds the basis the options ask for on the scene's objects (one mesh, or one point cloud
 * for rkpm_skinning). Modes and modal derivatives are computed with the fixed vertices held (moving
 * ones are free: the reduced model pins them to their targets). With a tolerance, the scene's full-order run gives the frames, and the
 * smallest basis (up to size, or a default maximum) whose projection error meets it is kept;
 * failing to reach it is an error that says how close it came. */
int rk_scene_basis_build(const rk_scene *scene, const rk_basis_options *o, rk_basis *b,
                         rk_scene_basis_info *info, rk_error *err);
/* The same with the scene's full-order displacement frames already run (3 nv x T, column-major,
 * as the scene's own simulation gives them), so a caller that runs it anyway runs it once. */
int rk_scene_basis_build_frames(const rk_scene *scene, const rk_basis_options *o, const double *frames, int T,
                                rk_basis *b, rk_scene_basis_info *info, rk_error *err);
void rk_scene_basis_info_free(rk_scene_basis_info *info);
/* Whether building this basis needs the scene's full-order frames (POD, or a size by tolerance). */
int rk_basis_needs_frames(const rk_basis_options *o);
/* The scene's own full-order run as displacement frames (*D: 3 nv x *T, column-major, malloc'd). */
int rk_scene_training_frames(const rk_scene_sim *sim, double **D, int *T, rk_error *err);

#endif
