/* precompute/pipeline: the scene file parsed once into typed options for every stage, and the
 * whole-scene orchestration that romkit build, compare, basis and fom, the benches and the tests
 * share.
 *
 *   rk_scene_load      the scene file (JSON, DESIGN.md "Scene file") into rk_scene: objects,
 *                      obstacles, time, damping, and every rom entry with its basis, cubature,
 *                      Koopman and asset options (each the stage's own option struct). Strict:
 *                      unknown keys, wrong types and nonsense values are errors naming the file and
 *                      the JSON path, e.g. "beam.json: objects[0].material.poisson: must be in
 *                      (-1, 0.5), got 0.5". Only this stage sees JSON.
 *   rk_scene_build     meshes loaded and placed, materials per element, the FEM model and the
 *                      full-order options: rk_scene_sim
 *   rk_scene_fom_run   the full-order run of a built scene, frame by frame
 *   rk_scene_basis     an entry's basis (constraints, materials, training frames from the scene)
 *   rk_scene_rom_build an entry's reduced model (basis, exact integration or trained cubature)
 *   rk_scene_koopman   an entry's Koopman operator (the scene's training runs, the fit)
 *   rk_scene_bake      an entry end to end into a .rombin asset and its report
 *
 * Adding a method's scene keys touches parse_rom.c (its keys into the method's option struct,
 * declared in that method's stage) and that stage only. */
#ifndef RK_PIPELINE_H
#define RK_PIPELINE_H

#include <cjson/cJSON.h>

#include "asset/asset.h"
#include "basis/basis.h"
#include "cubature/cubature.h"
#include "fem/fem.h"
#include "fom/fom.h"
#include "adaptive/adaptive.h"
#include "grassmann/grassmann.h"
#include "koopman/koopman.h"
#include "mesh/mesh.h"
#include "rom/rom.h"
#include "util/util.h"

/* ---- JSON reports (report.c): written atomically, numbers with full precision ---- */

int rk_json_write_file(const char *path, const cJSON *root, rk_error *err);
/* cJSON array from n doubles. */
cJSON *rk_json_array(const double *v, int n);

/* ---- the scene description (parse.c, parse_rom.c) ---- */

typedef struct {
    rk_box box;
    rk_material material;  /* fields the region leaves out are inherited from the object */
} rk_scene_region;

typedef struct {
    rk_box box;
    rk_motion_kind kind;   /* fixed, twist or translate */
    double axis[3];
    double center[3];
    int has_center;        /* otherwise the rest centroid of the selected vertices */
    double rate;           /* rad/s */
    double velocity[3];
} rk_scene_motion;

typedef struct {
    rk_box box;
    double force[3];       /* total force (N), shared among the selected vertices by mass */
} rk_scene_force;

typedef enum { RK_SHAPE_FILE = 0, RK_SHAPE_BOX = 1, RK_SHAPE_POINTS = 2 } rk_shape_kind;

typedef struct {
    rk_shape_kind shape;
    char file[4096];       /* tet or surface mesh, or point cloud; resolved against the scene folder */
    double box_size[3];
    int box_cells[3];
    double scale;
    double translate[3];
    double quality;        /* surface meshes: tetgen radius-edge bound */
    double max_volume;     /* surface meshes: tetgen volume bound (m^3), 0 = none */
    int refine;            /* uniform 1:8 refinements of the tets (rk_mesh_refine), 0 = none */
    double proxy_voxel;    /* point cloud: voxel edge (m) of its contact proxy (rk_points_proxy);
                            * 0: 1/RK_PROXY_VOXELS of the cloud's bounding-box diagonal, or twice
                            * the points' median spacing where that is more */
    rk_material material;
    int nregions;
    rk_scene_region *regions;
    int nmotions;          /* "fixed" entries come first, as kind RK_MOTION_FIXED */
    rk_scene_motion *motions;
    int nloads;
    rk_scene_force *loads;
    double velocity[3];
} rk_scene_object;

/* An obstacle as the scene names it: plane, sphere, capsule, box or a triangle mesh file, with an
 * optional motion ("translate" or "twist", as an object's moving boxes). */
typedef struct {
    rk_obstacle shape;     /* kind, geometry and motion; a mesh's arrays come with rk_scene_build */
    char file[4096];       /* mesh: the surface file, resolved against the scene folder */
    double scale, translate[3]; /* mesh: placed like an object's mesh */
} rk_scene_obstacle;

/* rom[i].koopman: one training run of the scene with what it names changed. */
typedef struct {
    int has_gravity, has_velocity;
    double gravity[3], velocity[3];
    double load_scale;               /* 1: as the scene says */
} rk_koopman_variation;

#define RK_KOOPMAN_MAX_TRAJECTORIES 32

/* rom[i].koopman: {"rank": 24 | "energy": 0.999999, "clamp": true, "project": true,
 *                  "trajectories": [{"gravity": [0, -9.81, 0], "velocity": [0, 0, 1], "load_scale": 1}, ...]}
 * No trajectory listed: the scene as written, once. */
typedef struct {
    rk_koopman_options fit;          /* h comes from the scene's time step */
    int project;                     /* fit on the entry's basis coordinates (default 0: full displacements) */
    int ntraj;
    rk_koopman_variation traj[RK_KOOPMAN_MAX_TRAJECTORIES];
} rk_koopman_entry;

/* rom.mesh_free: the elastic energy and the mass integrated at points (freeform paper Eq. 22)
 * instead of over the tets, with an rkpm_skinning basis: {"sampling": "grid" | "random" | "cloud",
 * "points": 5000, "seed": 1}. Grid: a uniform grid clipped to the object (its tets, or the
 * tetrahedralized closed surface, as the inside test); random: uniform inside it (Table 4);
 * cloud: a point cloud's own points, downsampled (the default, and the only one, for clouds). */
typedef enum { RK_SAMPLING_GRID = 0, RK_SAMPLING_RANDOM = 1, RK_SAMPLING_CLOUD = 2 } rk_sampling;
typedef struct {
    int enabled;
    rk_sampling sampling;
    int sampling_given;              /* else: cloud for a point cloud, grid for a mesh */
    int points;                      /* how many (grid: about; default 5000, the paper's Table 4) */
    unsigned long long seed;         /* random sampling */
    double volume;                   /* m^3, the integration weights' sum when known (a point cloud's
                                      * occupancy estimate overshoots on sparse clouds); 0: sampled */
} rk_mesh_free_options;

/* The most training runs a rom entry lists. */
#define RK_MAX_TRAINING 32

/* How a rom entry simulates (DESIGN.md: rom[i].method). */
typedef enum { RK_METHOD_FIXED = 0, RK_METHOD_ADAPTIVE_SUBSPACE = 1, RK_METHOD_ADAPTIVE_LINEAR = 2 } rk_rom_method;

/* One entry of the scene's rom section. */
typedef struct {
    int index;                       /* its place in the list */
    char path[32];                   /* "rom" or "rom[i]": names it in messages */
    char name[96];                   /* rom.name, or "<basis>-<size|tol>[-cubature]" */
    rk_rom_method method;
    rk_basis_options basis;          /* basis, size, tolerance, modes, kernels, integration_points */
    rk_mesh_free_options mesh_free;  /* rom.mesh_free (point clouds: always) */
    int cubature;                    /* 0: exact integration over every element */
    rk_cubature_options cub;         /* rom.cubature.{tolerance, max_points, poses, sample} */
    int koopman;                     /* a koopman section: the entry is (also) a Koopman operator */
    rk_koopman_entry koop;
    /* method adaptive_subspace: the basis above is the candidate basis (block: 12 columns per
     * skinning weight, else 1); keys eps_g_modal, eps_g_nodal, eps_e, eps_d, subdomains,
     * initial_size (columns active from the start: default one block, or the rigid modes of a
     * modes basis), downdate, modal, nodal, hessian ("bfgs" or "exact"), pcg_tol */
    rk_adaptive_options adaptive;
    int adaptive_initial_size;       /* 0: the default above */
    /* method adaptive_linear: size is r; keys history (m, 20), lambda (0.2), decoder ("quadratic":
     * linear modes and their modal derivatives, no training; "crom": trained on the scene's
     * full-order frames with the options of the "crom" key) */
    rk_alrom_options alrom;
    int crom;                        /* decoder "crom" */
    int quadratic_pod;               /* decoder "quadratic_pod": the training frames' POD modes and a
                                      * quadratic term fitted to them (rk_quadratic_fit) */
    rk_crom_options crom_opt;
    /* "training": what the data-driven parts (a POD basis, a CROM) train on instead of the scene's
     * own full-order run: other scenes of the same object (each run at full order, one job each)
     * and snapshot files of such runs (romkit fom --snapshots), merged in list order */
    int ntraining;
    struct {
        int snapshots;               /* 1: file is a .npy of (T + 1) x nv x 3 positions; 0: a scene */
        char file[1024];             /* resolved against the scene folder */
    } training[RK_MAX_TRAINING];
    rk_asset_options asset;          /* rom.asset.{precision, compress, show, groups} */
    double pin_stiffness;            /* rom.pin_stiffness: the reduced penalty on prescribed vertices in
                                      * units of (lambda + 2 mu) / (rho L^2); 0: RK_ROM_PIN_STIFFNESS */
    double reference_nmse;           /* rom.reference.normalized_mse: a published value to print beside ours; NAN if none */
    char reference_source[96];       /* rom.reference.source */
} rk_rom_entry;

typedef struct {
    char path[4096];
    int nobjects;
    rk_scene_object *objects;
    double gravity[3];
    int nobstacles;
    rk_scene_obstacle *obstacles;
    rk_contact_options contact;  /* "contact": {"dhat", "friction", "self", "kappa"}; dhat 0: 1e-3 of the diagonal */
    double h;
    double duration;
    rk_integrator integrator;
    int is_static;
    int lumped_mass;
    double damping_mass, damping_stiffness; /* Rayleigh a, b */
    double newton_tol;     /* 0 = the simulator's default */
    int newton_max_iter;   /* 0 = the simulator's default */
    int nentries;          /* the rom section: one for an object, the list's length, 0 when absent */
    rk_rom_entry *entries;
    int reference_refine;  /* "reference": {"refine": k}: romkit compare measures every method against
                            * a full-order run with each object's mesh refined k more times
                            * (rk_scene_build_reference), at the scene mesh's vertices; 0 (the
                            * default): against the full-order run on the scene's own mesh */
} rk_scene;

int rk_scene_load(const char *path, rk_scene *s, rk_error *err);
/* Parses JSON text; `path` names it in messages and anchors relative file names. */
int rk_scene_parse(const char *text, const char *path, rk_scene *s, rk_error *err);
void rk_scene_free(rk_scene *s);
/* Entry k, or an error naming the scene and the range when there is none. */
int rk_scene_entry(const rk_scene *s, int k, const rk_rom_entry **out, rk_error *err);

/* The material at rest point p of an object: its own, overridden by the last region whose box
 * holds p (for elements, p is the centroid; for point clouds, the point). */
rk_material rk_scene_material_at(const rk_scene_object *o, const double p[3]);

/* ---- the built scene (build.c) ---- */

/* A scene built into something to simulate. Objects are concatenated into one mesh;
 * object_first_vertex[k] / object_first_tet[k] say where object k starts. */
/* A point cloud's default contact-proxy voxel: this fraction of its bounding-box diagonal. */
#define RK_PROXY_VOXELS 40

typedef struct {
    rk_mesh mesh;
    rk_mesh_report mesh_report; /* the joined mesh measured, plus what each object's own check
                                 * repaired: reoriented, unused_removed, flat_dropped, ghosts,
                                 * orphans_removed */
    rk_material *materials;   /* one per tet */
    rk_fem fem;
    rk_fom_options options;   /* points into arrays owned here */
    rk_obstacle *obstacles;   /* the scene's, meshes loaded (options.obstacles) */
    rk_surface *obstacle_meshes; /* one per obstacle (empty unless a mesh) */
    int steps;
    int *object_first_vertex; /* nobjects + 1 */
    int *object_first_tet;    /* nobjects + 1 */
    int cloud_points;         /* point-cloud objects: how many points they have in all; each object's
                               * points are its first vertices, in file order, the rest its contact
                               * proxy's corners (rk_points_proxy); 0 for meshes */
    int *object_points;       /* nobjects: each point-cloud object's points (NULL for meshes) */
} rk_scene_sim;

int rk_scene_build(const rk_scene *s, rk_scene_sim *out, rk_error *err);

/* Object k of a built scene on its own: its vertices (mesh.X borrowed: global positions), its tets
 * renumbered from 0 (mesh.tets owned: free it), its first vertex and tet in the scene, and for a
 * point cloud how many of its vertices are its points (the rest: its contact proxy). */
typedef struct {
    rk_mesh mesh;
    int v0, t0, points;
} rk_object_view;
int rk_scene_object_view(const rk_scene_sim *sim, int k, rk_object_view *ov, rk_error *err);
void rk_scene_sim_free(rk_scene_sim *out);
/* The scene built again with every object's mesh refined `levels` more times (1:8 each,
 * rk_mesh_refine, after its own mesh.refine), everything else as the scene says: materials,
 * regions, fixed and moving boxes, loads and obstacles selected on the refined mesh as
 * rk_scene_build selects them on any mesh. sim is the scene built as written; *map (sim->mesh.nv
 * entries, malloc'd) gives for each of its vertices the refined mesh's vertex at the same rest
 * position (refinement numbers an object's old vertices first; this checks it, bit for bit, and
 * fails naming the vertex where a mesh check renumbered them). */
int rk_scene_build_reference(const rk_scene *s, const rk_scene_sim *sim, int levels, rk_scene_sim *out, int **map,
                             rk_error *err);

/* ---- full-order runs (run.c) ---- */

/* Called after every step (and once for the start, step 0) of a full-order run with the state
 * and the step's seconds (0 for the start); non-zero stops the run with that error. */
typedef int (*rk_frame_fn)(void *ctx, int step, rk_fom *fom, double seconds, rk_error *err);

/* The built scene run at full order: options as the scene says (opt NULL) or as given, the static
 * solve or every time step, with progress under `label`. stats (may be NULL) gets the run's. */
int rk_scene_fom_run(const rk_scene_sim *sim, const rk_fom_options *opt, const char *label, rk_frame_fn frame,
                     void *ctx, rk_fom_stats *stats, rk_error *err);
/* The scene's own full-order run as displacement frames after each step (*D: 3 nv x *T,
 * column-major, malloc'd): what bases, cubature and Koopman fits train on. */
int rk_scene_training_frames(const rk_scene_sim *sim, double **D, int *T, rk_error *err);

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
    int cubature_points;           /* 0 for exact integration */
    double cubature_error;         /* relative force error on the training poses (NAN: exact) */
    int cubature_reached, cubature_poses;
    double seconds_basis, seconds_cubature;
    char basis_reason[256];        /* which option bound the basis size, with the numbers */
    char cubature_reason[256];     /* which option bound the cubature size */
} rk_scene_rom;

/* Builds entry e's reduced model for the built scene sim. frames: the scene's full-order
 * displacements (3 nv x T, column-major) when they have been run, else NULL (then bases that need
 * them run their own, and the cubature trains on random poses only). */
int rk_scene_rom_build(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e, const double *frames,
                       int T, rk_scene_rom *out, rk_error *err);
void rk_scene_rom_free(rk_scene_rom *r);
/* The source of an asset bake (asset.h) for a built scene and its reduced model. */
rk_asset_rom rk_scene_asset_rom(const rk_scene_sim *sim, const rk_scene_rom *R);

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

/* ---- an adaptive subspace entry (adaptive.c) ---- */

/* Entry e (method adaptive_subspace) on the built scene: its candidate basis built as rk_scene_basis
 * builds it (frames as there), grouped in blocks (a skinning weight's 12 columns, else single
 * columns), the initial columns (initial_size, or one block, or a modes basis's rigid modes), and
 * rk_adaptive_init under the scene's options. *seconds_basis (may be NULL): the basis's time. */
int rk_scene_adaptive_init(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e,
                           const double *frames, int T, rk_adaptive *ad, double *seconds_basis, rk_error *err);

/* ---- an entry's training set (training.c) ---- */

/* Entry e's training displacements (*D: 3 nv x *T, column-major, malloc'd): every scene of its
 * "training" list run at full order (each must be the same object: the same vertices at the same
 * rest positions, checked) and every snapshot file (frames after the first, as displacements from
 * sim's rest positions), in list order, so the set is the same however the runs were produced.
 * Fails naming the item. */
int rk_scene_training_set(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e, double **D, int *T,
                          rk_error *err);

/* ---- an adaptive linear ROM entry (alrom.c, bake_alrom.c) ---- */

/* The quadratic-manifold decoder's parts for entry e, both column-major and the caller's to free:
 * Phi (3 nv x r) and Psi (3 nv x r(r+1)/2). Decoder "quadratic": Phi its r linear modes with the
 * fixed vertices held, Psi their modal derivatives (the pairs of rigid modes zero); decoder
 * "quadratic_pod": Phi the POD modes of the frames (3 nv x T displacements, needed), Psi the
 * quadratic term fitted to them. */
int rk_scene_quadratic_parts(const rk_scene_sim *sim, const rk_rom_entry *e, const double *frames, int T,
                             double **Phi, double **Psi, rk_error *err);

/* Entry e (method adaptive_linear) on the built scene: its decoder into *dec (a quadratic manifold
 * from the entry's size r linear modes with the fixed vertices held and their modal derivatives,
 * or a CROM trained on frames: the scene's full-order displacements, 3 nv x T, run here when NULL)
 * and rk_alrom_init under the scene's options (dec must outlive s; free both). *seconds_decoder (may
 * be NULL): the decoder's build time. */
int rk_scene_alrom_init(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e, const double *frames,
                        int T, rk_alrom *s, rk_decoder *dec, double *seconds_decoder, rk_error *err);
/* With rom.cubature: the elements and weights (multiplying each element's energy) of a cubature
 * trained, as a fixed basis's is, for the POD basis of the same frames at the same r; none (count
 * 0) without. malloc'd. */
int rk_scene_alrom_cubature(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e, const double *frames,
                            int T, int **element, double **weight, int *count, rk_error *err);
/* The decoder alone (rk_scene_alrom_init's first half). */
int rk_scene_alrom_decoder(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e, const double *frames,
                           int T, rk_decoder *dec, rk_error *err);

/* ---- an entry's Koopman operator (koopman.c) ---- */

/* The forcing as an acceleration of every degree of freedom (3 nv values): gravity plus each load
 * (force, N, 3 nv or NULL) over its vertex's lumped mass: what a trajectory runs under and what an
 * asset steps along, as impulses (Eq. 19). */
void rk_koopman_scene_accel(const rk_scene_sim *sim, const double gravity[3], const double *force, double *accel);
/* The frame before a start at rest positions moving at vel (3 nv, or NULL: at rest): u_{-1} = -h v. */
void rk_koopman_frame_before(const rk_scene_sim *sim, const double *vel, double *u_prev);

/* A trajectory of the built scene's full-order run, as the fit takes it (owning its arrays):
 * displacement frames u_{-1} = -h v_0, u_0 = 0, then one per step, so that X_0 = [0; h v_0]
 * starts it; accel: gravity plus each load over its vertex's lumped mass. */
typedef struct {
    rk_koopman_trajectory t;
    double *u, *accel;
} rk_koopman_run;
/* The scene run again with what v changes (v NULL: as written). */
int rk_koopman_scene_run(const rk_scene_sim *sim, const rk_koopman_variation *v, rk_koopman_run *out, rk_error *err);
/* The same trajectory from the scene's full-order run already done: frames (3 nv x T) are the
 * displacements after each of its T steps (rk_scene_training_frames). */
int rk_koopman_scene_run_frames(const rk_scene_sim *sim, const double *frames, int T, rk_koopman_run *out,
                                rk_error *err);
void rk_koopman_run_free(rk_koopman_run *r);

typedef struct {
    int trajectories, frames;        /* runs and frames in all */
    double seconds_fom, seconds_fit;
    int projected;                   /* observables are basis coordinates (d = basis columns) */
    int reused;                      /* the given frames (the scene as written) were a trajectory */
    rk_basis_type basis_type;        /* when projected: the basis and its build time */
    int basis_columns;
    double seconds_basis;
} rk_koopman_scene_info;

/* Runs every trajectory of ko and fits the operator on their (projected) displacements. basis:
 * the entry's basis when ko->project, else NULL. frames (may be NULL): the scene's own run,
 * already done, used for each trajectory that changes nothing. */
int rk_koopman_scene_fit(const rk_scene_sim *sim, const rk_koopman_entry *ko, const rk_basis *basis,
                         const double *frames, int T, rk_koopman *k, rk_koopman_scene_info *info, rk_error *err);

/* An entry's Koopman operator and what baking it needs: the scene's constant acceleration, the
 * start (where the training runs start: X_0 = [0; h v_0]) and the boundary to show. */
typedef struct {
    rk_koopman k;
    rk_koopman_scene_info info;
    double *accel, *u0, *u_prev;
    int *tris, ntris;                /* the boundary (source numbers) */
    rk_koopman_geometry geometry;    /* points into the arrays above */
} rk_scene_koopman;

/* Entry e end to end: the basis when it asks for a projection, the training runs, the fit and the
 * asset geometry. frames (3 nv x T, may be NULL): the scene's own full-order run, already done;
 * when NULL and something needs it, it is run here. */
int rk_scene_koopman_build(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e,
                           const double *frames, int T, rk_scene_koopman *out, rk_error *err);
void rk_scene_koopman_free(rk_scene_koopman *p);
/* What an asset of the built scene shows and steps along: the boundary, the scene's forcing, the
 * start (p's accel, u0, u_prev, tris and geometry; its operator k left alone, freed with p). */
int rk_scene_koopman_geometry(const rk_scene_sim *sim, rk_scene_koopman *p, rk_error *err);
/* The report's "koopman" object: rank, max_abs_eigenvalue, eigenvalues [[re, im], ...],
 * residuals, clamped, data_grows, stabilized, stabilize_shift, max_abs_eigenvalue_before_refit,
 * step_residual [Galerkin, returned], singular values, observables, h. */
cJSON *rk_koopman_report(const rk_koopman *k);

/* ---- a family of meshes for the neural, shape-conditioned DMD (family.c; romkit neural-dmd) ----
 *
 * A family file (JSON): {"members": [{"scene": "a.json", "snapshots": "a.npy", "gamma": [0.14]}, ...],
 * "rank": R, "network": {"hidden", "depth", "eig_hidden", "eig_depth"}, "training": {"pretrain_epochs",
 * "epochs", "learning_rate", "window", "init_member"}, "seed": S}. Each member is a scene (its mesh,
 * material, fixed vertices, forcing and time step, built as every command builds one), that
 * scene's full-order run as romkit fom --snapshots writes it (T x nv x 3 positions, the rest
 * state first) and its shape code gamma (g numbers, the same g for every member; absent or null:
 * g = 0). Paths are relative to the family file's folder. Every key but "members" and "rank" is
 * optional (rk_koopman_neural_default_options). "shape": {"scene": "s.json", "size": [x, y, z],
 * "size_per_gamma": [[x, y, z], ...]} (g rows) says how a code maps to a mesh, for the shape
 * optimisation: the scene's first object is a box of size size + sum_j gamma_j size_per_gamma[j]. */
typedef struct {
    char scene[4096], snapshots[4096];
    double gamma[RK_KOOPMAN_SHAPE_MAX];
    rk_scene sc;
    rk_scene_sim sim;
    rk_koopman_run run;
    int built, ran;
} rk_family_member;

typedef struct {
    int nmembers, g;
    rk_family_member *member;
    rk_koopman_neural_mesh *mesh;        /* nmembers training meshes over the members' runs */
    rk_koopman_neural_options options;   /* the file's; h the scenes' (all the same) */
    int has_shape;                       /* "shape": {"scene", "size", "size_per_gamma"}: the mesh of any code */
    char shape_scene[4096];
    double size[3], size_per_gamma[RK_KOOPMAN_SHAPE_MAX][3];
} rk_family;

/* Parses the family file, builds each member's scene and reads its snapshots, checking them
 * (shape T x nv x 3 with T >= 2, the scene's nv, finite, the first frame the scene's rest
 * positions, one time step for all). Messages name the file and the JSON path. */
int rk_family_load(const char *path, rk_family *f, rk_error *err);
void rk_family_free(rk_family *f);
/* The family's "shape" for code gamma (g values): its scene with the first object's box of size
 * size + sum_j gamma_j size_per_gamma[j] (g rows of 3). Fails without "shape", when the first
 * object is not a box, or on a size that is not positive (naming gamma). */
int rk_family_shape_scene(const rk_family *f, const double *gamma, rk_scene *out, rk_error *err);

/* ---- following a target trajectory with forces on named groups (control.c) ---- */

/* One controlled input: a force along one axis on one of the entry's named vertex groups
 * (rom.asset.groups), spread over the group's vertices by mass (a uniform acceleration), C newtons
 * in all. */
typedef struct {
    int group;                       /* index into e->asset.groups */
    int axis;                        /* 0, 1, 2: x, y, z */
} rk_control_input;

#define RK_CONTROL_MAX_INPUTS 64

typedef struct {
    int ninputs;
    rk_control_input input[RK_CONTROL_MAX_INPUTS];
    int nfollow;                     /* groups whose vertices follow the target; 0: the inputs' groups */
    int follow[RK_ASSET_MAX_GROUPS];
    double train_force;              /* N held during each input's training run; 0: the group's weight */
    int horizon;                     /* rk_koopman_track's H (>= 1) */
    int nonnegative;
    double regularize;               /* rho of rk_lstsq_tikhonov (>= 0; 0: plain least squares) */
} rk_control_options;

typedef struct {
    int T, inputs, trajectories, rank, follow_values;
    double *C;                       /* inputs x (T - 1), column-major, N */
    double *u_model;                 /* 3 nv x T: the Koopman model under C (displacements) */
    double *u_fom;                   /* 3 nv x T: the full-order model under C */
    double seconds_training, seconds_fit, seconds_solve, seconds_fom;
    double max_abs_eigenvalue;
} rk_control_result;

/* Entry e's Koopman operator (rom.koopman, unprojected) trained on the entry's trajectories and one
 * run per input holding train_force, then the inputs that make the followed vertices track target
 * (3 nv x T displacements from the rest positions, frame 0 the scene's start; the scene's time
 * step between frames) by rk_koopman_track, and the full-order run under those inputs
 * (rk_fom_set_force each step). */
int rk_scene_control(const rk_scene_sim *sim, const rk_rom_entry *e, const rk_control_options *o,
                     const double *target, int T, rk_control_result *out, rk_error *err);
void rk_control_result_free(rk_control_result *r);

/* ---- an entry baked (bake.c) ---- */

typedef struct {
    /* The scene's full-order run as romkit fom --snapshots writes it (steps + 1 frames of every
     * vertex's position, the start first: snapshot_dims = 3, shape steps + 1, nv, 3), trained on
     * instead of running the scene again; NULL: run when something needs it. */
    const double *snapshots;
    int snapshot_dims;
    long snapshot_shape[4];
    int has_real_type;               /* real_type overrides rom.asset.precision */
    int real_type;
    int compress;                    /* deflate, beside rom.asset.compress */
} rk_bake_request;

typedef struct {
    unsigned char *data;             /* the asset (malloc'd) */
    size_t bytes;
    cJSON *report;                   /* DESIGN.md's keys: vertices, tets, basis.*, cubature.*, koopman.*, asset.* */
    char summary[512];               /* one line for a terminal */
} rk_baked;

/* Entry e of the scene end to end: the full-order run when something trains on it, the basis, the
 * cubature, the Koopman operator, baked into one asset (reduced model, Koopman operator or both).
 * Nothing is written; the caller saves data. */
int rk_scene_bake(const rk_scene *scene, const rk_rom_entry *e, const rk_bake_request *req, rk_baked *out,
                  rk_error *err);
void rk_baked_free(rk_baked *b);
/* rk_scene_bake of an adaptive_linear entry (bake_alrom.c): the decoder's asset (quadratic, fitted
 * quadratic or CROM) with the chunks the runtime's adaptive step reads (formats/ROMBIN.md). */
int rk_scene_bake_alrom(const rk_scene *scene, const rk_rom_entry *e, const rk_asset_options *ao, rk_baked *out,
                        rk_error *err);
/* A Koopman operator k over geometry g baked alone (romkit dmd's outside snapshots, and a Koopman
 * entry without cubature): the asset, its report's "koopman" and "asset" objects, the summary. */
int rk_bake_koopman(const rk_koopman *k, const rk_koopman_geometry *g, const rk_asset_options *ao, const char *info,
                    rk_baked *out, rk_error *err);
/* The asset's chunks, precision and sizes as report keys under a (formats/ROMBIN.md). */
void rk_asset_report(cJSON *a, const unsigned char *data, size_t bytes, const rk_asset_summary *sum);

#endif
