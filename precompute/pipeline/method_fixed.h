/* precompute/pipeline: method "fixed", a reduced model on a fixed basis (PCA/POD, skinning, linear
 * modes and modal derivatives, RKPM skinning): the scene's parts that build it (basis.c,
 * mesh_free.c, rom.c, splats.c) and its table entry (method_fixed.c). The Koopman method builds
 * one too when its entry has a cubature. */
#ifndef RK_PIPELINE_METHOD_FIXED_H
#define RK_PIPELINE_METHOD_FIXED_H

#include "pipeline/method.h"
#include "rom/rom.h"

extern const rk_method rk_method_fixed;

/* ---- an entry's basis (basis.c) ---- */

typedef struct {
    int vertices, tets;        /* what the basis is evaluated on (tets 0 for a point cloud) */
    double *X;                 /* 3 vertices rest positions (owned) */
    int fom_frames;            /* full-order frames it trained on (0 if none) */
    double projection_error;   /* over those frames (NAN if none) */
    double projection_error_below; /* with one size less (one weight less for skinning); NAN if none:
                                    * with a tolerance, why the size is not smaller */
    double seconds_fom, seconds_basis;
    rk_rkpm_timing rkpm;       /* rkpm_skinning only */
    int kernels, integration_points;
} rk_scene_basis_info;

/* Builds the basis o asks for on the scene's objects (one mesh, or one point cloud for
 * rkpm_skinning: then sim is NULL). Modes and modal derivatives are computed with the fixed
 * vertices held (moving ones are free: the reduced model pins them to their targets). frames
 * (3 nv x T, may be NULL): the scene's full-order displacements when already run; a basis that
 * needs them (rk_basis_needs_frames) runs the scene otherwise. With a tolerance the smallest basis
 * (up to size, or a default maximum) whose projection error meets it is kept; failing to reach it
 * is an error that says how close it came. */
/* nv flags (calloc'd): the vertices the scene holds fixed (moving ones are free), which linear
 * modes and modal derivatives are computed with. NULL on failure. */
unsigned char *rk_scene_fixed_vertices(const rk_scene_sim *sim, rk_error *err);
/* The index of the scene's one moving prescribed group (rom.clamp "lifted"), and its vertices as
 * flags; both fail (-1, NULL), saying why, when the scene has none or several. */
int rk_scene_moving_group(const rk_scene_sim *sim, rk_error *err);
unsigned char *rk_scene_moving_vertices(const rk_scene_sim *sim, rk_error *err);
int rk_scene_basis(const rk_scene *scene, const rk_scene_sim *sim, const rk_basis_options *o, const double *frames,
                   int T, rk_basis *b, rk_scene_basis_info *info, rk_error *err);
void rk_scene_basis_info_free(rk_scene_basis_info *info);

/* ---- a mesh-free entry's integration points (mesh_free.c) ---- */

/* Whether entry o integrates at points: rom.mesh_free, or a point-cloud object. */
int rk_scene_mesh_free(const rk_scene *scene, const rk_rom_entry *o);

/* Samples o's points in the scene's object (point cloud: its own points), weights them by volume,
 * gives each its object's material there, and the weights W_j and gradients of basis b (which
 * must be rkpm_skinning) at it. */
int rk_scene_mesh_free_points(const rk_scene *scene, const rk_scene_sim *sim, const rk_mesh_free_options *o,
                              const rk_basis *b, rk_skin_points *P, rk_error *err);
/* Basis b's (rkpm_skinning) weights and gradients at n points X of object k, in P (n, H = b->m, X,
 * W, dW; nothing else): the object's own handles' columns, the other objects' 0. */
int rk_scene_object_weights(const rk_basis *b, int k, const double *X, int n, rk_skin_points *P, rk_error *err);


/* ---- an entry's reduced model (rom.c) ---- */

typedef struct {
    rk_basis basis;
    rk_scene_basis_info basis_info;
    rk_rom_model model;
    rk_skin_points points;         /* mesh-free: the integration points (n = 0 otherwise) */
    double *cloud_grad;            /* a point cloud: the weights' gradients at its points (3 n x H), or NULL */
    const char *splat_file;        /* a point cloud's source PLY (the scene's; for the asset's SPLY) */
    double *embedded_W;            /* an rkpm_skinning basis in a scene with a cage: its weights evaluated
                                    * at each shown surface vertex itself (nv x H, column-major), or NULL
                                    * (then the asset interpolates them in the vertex's tet) */
    int cubature_points;           /* 0 for exact integration */
    rk_cubature_set cubature_set;  /* the trained (or given) elements and weights, what romkit cubature
                                    * writes (count 0 for exact integration) */
    double cubature_error;         /* relative force error on the training poses (NAN: exact) */
    int cubature_reached, cubature_poses;
    double seconds_basis, seconds_cubature;
    char basis_reason[256];        /* which option bound the basis size, with the numbers */
    char cubature_reason[256];     /* which option bound the cubature size */
    char volume_warning[256];      /* the pointwise volume on a skinning basis of a nearly incompressible
                                    * material (volume.c says why), or empty */
} rk_scene_rom;

/* Builds entry e's reduced model for the built scene sim. frames: the scene's full-order
 * displacements (3 nv x T, column-major) when they have been run, else NULL (then bases that need
 * them run their own, and the cubature trains on random poses only). */
int rk_scene_rom_build(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e, const double *frames,
                       int T, rk_scene_rom *out, rk_error *err);
/* What a split bake (romkit plan) gives the reduced model instead of building it: the basis from a
 * basis step's file (only bases that are U alone: modes, modal_derivatives, pod), the cubature from
 * a cubature step's (rk_scene_cubature_read). NULL members: built here. */
typedef struct {
    const rk_basis *basis;
    const rk_cubature_set *cubature;
    int cubature_poses;
} rk_scene_rom_given;
/* rk_scene_rom_build with parts given (g may be NULL): the same model from the same numbers. */
int rk_scene_rom_build_given(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e,
                             const double *frames, int T, const rk_scene_rom_given *g, rk_scene_rom *out, rk_error *err);
void rk_scene_rom_free(rk_scene_rom *r);
/* A split bake's files (stage_files.c): a basis step's U (n x 3 x r float64 .npy, as romkit basis
 * --basis writes it; exact) read as a basis of the given type; the cubature R trained written as
 * JSON (elements, weights, relative_error, reached, greedy_count, poses; exact) and read back. */
int rk_scene_basis_read(const char *path, rk_basis_type type, rk_basis *b, rk_error *err);
int rk_scene_cubature_write(const char *path, const rk_scene_rom *R, rk_error *err);
int rk_scene_cubature_read(const char *path, rk_cubature_set *s, int *poses, rk_error *err);
/* rom.volume "projected" (volume.c): sets the pressure space of R's quadrature from rom.pressure
 * (after any cubature: the projection is over the points the model integrates with). */
int rk_scene_rom_volume(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *o, rk_scene_rom *R, rk_error *err);
/* The source of an asset bake (asset.h) for a built scene and its reduced model. */
rk_asset_rom rk_scene_asset_rom(const rk_scene_sim *sim, const rk_scene_rom *R);
/* The reduced velocity at t = 0 (r values into *v0, malloc'd) of the scene's initial velocities:
 * their M-orthogonal projection onto the basis, as romkit compare starts its free run (a point
 * cloud, which has no mass matrix, by least squares over its points). *v0 = NULL when nothing
 * moves. *residual: |U v0 - v|_M / |v|_M, the part of the motion the basis cannot hold. */
int rk_scene_rom_velocity0(const rk_scene_sim *sim, const rk_scene_rom *R, double **v0, double *residual, rk_error *err);

/* ---- a point cloud's Gaussian splats moved by the reduced simulator (splats.c) ---- */

/* Object k (a point cloud) of a built scene, its splats as the reduced simulator moves them: the
 * source file's splats (rk_splats_read: every attribute), each at its point (the object's first
 * vertices, in file order) with F = I + G q from the basis's weights and gradients there
 * (rk_skin_points_G, as the mesh-free integration forms F), written by rk_splats_write. What
 * romkit run --splats writes from an asset, for scenes the runtime cannot step (several objects).
 * The object's scale s multiplies F: the file's covariances are in its own units. */
typedef struct {
    int object, v0;            /* the object and its first vertex in the scene */
    double scale;
    rk_splats splats;
    rk_skin_points points;     /* the splat centres' weights and gradients (rk_scene_object_weights) */
    double *x, *F, *G;         /* 3 n, 9 n, 9 r scratch */
} rk_scene_splats;
/* Fails, saying why, when object k is not a point cloud, its file holds no splat attributes, or the
 * basis is not rkpm_skinning. */
int rk_scene_splats_open(const rk_scene *scene, const rk_scene_sim *sim, const rk_scene_rom *R, int k,
                         rk_scene_splats *o, rk_error *err);
/* The splats at reduced coordinates q (R->model.r) with x (3 nv) the scene's positions there
 * (rk_rom_positions), as a 3DGS PLY at path. */
int rk_scene_splats_write(rk_scene_splats *o, const rk_scene_rom *R, const double *q, const double *x,
                          const char *path, rk_error *err);
void rk_scene_splats_free(rk_scene_splats *o);

#endif
