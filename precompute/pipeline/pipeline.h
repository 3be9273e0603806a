/* precompute/pipeline: the scene file parsed once into typed options for every stage, and the
 * whole-scene orchestration that romkit build, compare, basis and fom, the benches and the tests
 * share. This header is the scene; each method has its own (method.h: the table of operations;
 * method_fixed.h, method_koopman.h, method_adaptive_subspace.h, method_adaptive_linear.h), and
 * family.h and control.h the two workflows on Koopman models.
 *
 *   rk_scene_load      the scene file (JSON, DESIGN.md "Scene file") into rk_scene: objects,
 *                      obstacles, time, damping, and every rom entry with its method, basis,
 *                      cubature and asset options (each the stage's own option struct) and its
 *                      method's own options. Strict: unknown keys, wrong types and nonsense values
 *                      are errors naming the file and the JSON path, e.g. "beam.json:
 *                      objects[0].material.poisson: must be in (-1, 0.5), got 0.5". Only this
 *                      stage sees JSON.
 *   rk_scene_build     meshes loaded and placed, materials per element, the FEM model and the
 *                      full-order options: rk_scene_sim
 *   rk_scene_fom_run   the full-order run of a built scene, frame by frame
 *   rk_scene_bake      an entry end to end into a .rombin asset and its report (its method's bake)
 *
 * Adding a method touches its own module (method_<name>.c and .h) and one line of methods.c. */
#ifndef RK_PIPELINE_H
#define RK_PIPELINE_H

#include <stddef.h>

#include <cjson/cJSON.h>

#include "asset/asset.h"
#include "basis/basis.h"
#include "cage/cage.h"
#include "cubature/cubature.h"
#include "fem/fem.h"
#include "fom/fom.h"
#include "mesh/mesh.h"
#include "util/util.h"

/* ---- JSON reports (report.c): written atomically, numbers with full precision ---- */

int rk_json_write_file(const char *path, const cJSON *root, rk_error *err);
/* cJSON array from n doubles. */
cJSON *rk_json_array(const double *v, int n);
/* A run's contact.* keys (romkit fom, adaptive, run): min_distance (m), intersections (exact
 * crossings summed over the frames), intersecting_frames, frames: one tally, one wording. */
void rk_contact_tally_report(cJSON *obj, const rk_contact_tally *t);

/* ---- the scene description (parse.c, parse_rom.c) ---- */

typedef struct {
    rk_box box;            /* the tets whose centroid it holds, unless by_tag or by_ball */
    int by_tag, tag;       /* by_tag: the tets the mesh file tags `tag` (Gmsh physical group,
                            * MEDIT ref, TetGen region, VTK "tag"), kept through refinement */
    int by_ball;           /* by_ball: the tets whose centroid lies within radius of center (layers of
                            * a ball as nested balls, outermost first: the last region wins) */
    double center[3], radius;
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

/* A pneumatic chamber (fom.h, rk_chamber): the object's boundary faces whose centroid lies in box,
 * a closed surface (the walls of a void, mesh.voids), under a pressure held from the start. */
#define RK_CHAMBER_NAME 64
typedef struct {
    char name[RK_CHAMBER_NAME]; /* unique in the scene: romkit control's inputs name it */
    rk_box box;
    double pressure;       /* Pa */
    int nkeys;             /* "pressure": [[t, P], ...] instead: keys (rk_chamber's), 0: constant */
    double *keys;          /* 2 nkeys */
} rk_scene_chamber;

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
    int cage_tets;         /* mesh.cage.max_tets: a surface file simulated on a cage of at most this
                            * many tets (precompute/cage), the surface embedded in it; 0 = none */
    double proxy_voxel;    /* point cloud: the spacing g (m) of its contact surface (rk_points_proxy:
                            * g / 2, then s / 2 from the points, s their spacing); 0: 1/RK_PROXY_VOXELS of the cloud's
                            * bounding-box diagonal, or the spacing its RKPM sampling uses (twice
                            * the points' median spacing) where that is more */
    int proxy_voxels;      /* point cloud: mesh.proxy "voxels": the voxel surface moved in
                            * (rk_points_proxy) instead of the default "march" (rk_points_march) */
    rk_material material;
    int nregions;
    rk_scene_region *regions;
    int nmotions;          /* "fixed" entries come first, as kind RK_MOTION_FIXED */
    rk_scene_motion *motions;
    int nloads;
    rk_scene_force *loads;
    int nvoids;            /* mesh.voids: the tets whose centroid lies in a box are cut out (rk_mesh_carve,
                            * after scale, translate and refine) */
    rk_box *voids;
    int nchambers;
    rk_scene_chamber *chambers;
    double velocity[3];
} rk_scene_object;

/* An obstacle as the scene names it: plane, sphere, capsule, box or a triangle mesh file, with an
 * optional motion ("translate" or "twist", as an object's moving boxes). */
typedef struct {
    rk_obstacle shape;     /* kind, geometry and motion; a mesh's arrays come with rk_scene_build */
    char file[4096];       /* mesh: the surface file, resolved against the scene folder */
    double scale, translate[3]; /* mesh: placed like an object's mesh */
} rk_scene_obstacle;

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

/* A method's own options, kept in the entry (method.h says why a block); its module reads them. */
#define RK_METHOD_OWN_BYTES 4096

/* One entry of the scene's rom section. */
/* rom.volume: how the reduced elastic energy treats lambda's volume term (cubature.h, "the projected
 * volume"): at each point (pointwise, locks at nu -> 1/2 in a skinning subspace), or on its L2
 * projection onto a pressure space (rom.pressure). */
enum { RK_VOLUME_PROJECTED = 0, RK_VOLUME_POINTWISE = 1 };
enum { RK_PRESSURE_WEIGHTS = 0, RK_PRESSURE_CONSTANT = 1, RK_PRESSURE_WEIGHTS_AFFINE = 2 };

typedef struct {
    int index;                       /* its place in the list */
    char path[32];                   /* "rom" or "rom[i]": names it in messages */
    char name[96];                   /* rom.name, or the method's default name */
    const struct rk_method *method;  /* rom[i].method (method.h), or the method its keys imply */
    rk_basis_options basis;          /* basis, size, tolerance, modes, kernels, integration_points */
    rk_mesh_free_options mesh_free;  /* rom.mesh_free (point clouds: always) */
    int cubature;                    /* 0: exact integration over every element */
    rk_cubature_options cub;         /* rom.cubature.{tolerance, max_points, poses, sample} */
    /* "training": what the data-driven parts (a POD basis, a CROM) train on instead of the scene's
     * own full-order run: other scenes of the same object (each run at full order, one job each)
     * and snapshot files of such runs (romkit fom --snapshots), merged in list order */
    int ntraining;
    struct {
        int snapshots;               /* 1: file is a .npy of (T + 1) x nv x 3 positions; 0: a scene */
        char file[1024];             /* resolved against the scene folder */
    } training[RK_MAX_TRAINING];
    rk_asset_options asset;          /* rom.asset.{precision, compress, show, groups} */
    int volume;                      /* rom.volume: RK_VOLUME_* (a scene default resolved in parse_rom.c) */
    int pressure;                    /* rom.pressure: RK_PRESSURE_*, the projected volume's pressure space */
    double pin_stiffness;            /* rom.pin_stiffness: the reduced penalty on prescribed vertices in
                                      * units of (lambda + 2 mu) / (rho L^2); 0: RK_ROM_PIN_STIFFNESS */
    double reference_nmse;           /* rom.reference.normalized_mse: a published value to print beside ours; NAN if none */
    char reference_source[96];       /* rom.reference.source */
    /* the method's own options (its header's accessor: rk_koopman_of, rk_adaptive_subspace_of, ...) */
    _Alignas(max_align_t) unsigned char own[RK_METHOD_OWN_BYTES];
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
    int reference_order;   /* "reference": {"order": 2}: that run on quadratic tets (rk_p2_fom_run,
                            * also with refine 0); 1 (the default): linear tets */
} rk_scene;

int rk_scene_load(const char *path, rk_scene *s, rk_error *err);
/* Parses JSON text; `path` names it in messages and anchors relative file names. */
int rk_scene_parse(const char *text, const char *path, rk_scene *s, rk_error *err);
void rk_scene_free(rk_scene *s);
/* Entry k, or an error naming the scene and the range when there is none. */
int rk_scene_entry(const rk_scene *s, int k, const rk_rom_entry **out, rk_error *err);

/* The material at rest point p of an object: its own, overridden by the last region whose box
 * holds p (a point cloud's point; regions by tag select tets, not points). */
rk_material rk_scene_material_at(const rk_scene_object *o, const double p[3]);

/* How many of the scene's objects are point clouds (mesh.points); the others are tet meshes, and
 * one scene may hold both. */
int rk_scene_clouds(const rk_scene *s);

/* ---- the built scene (build.c) ---- */

/* A scene built into something to simulate. Objects are concatenated into one mesh;
 * object_first_vertex[k] / object_first_tet[k] say where object k starts. */
/* A point cloud's contact-surface spacing at least: this fraction of its bounding-box diagonal. */
#define RK_PROXY_VOXELS 40

/* A full-order run's vertices taken back to the scene's vertices as rk_scene_build numbers them:
 * vertex j is offset[j] + sum_a weight[4j + a] x[vertex[4j + a]] (a cloud's point: its body tet's
 * four vertices at its barycentric coordinates; any other: one vertex, weight 1). The offset is a
 * body vertex's rest position less the contact surface's where rk_points_body cut its inset back,
 * else 0. */
typedef struct {
    int nv;              /* 0: the run's vertices are the scene's */
    int *vertex;         /* 4 nv */
    double *weight;      /* 4 nv */
    double *offset;      /* 3 nv */
} rk_scene_layout;

/* Layout vertex j at run positions x; all nv of them into out (3 nv). */
void rk_scene_layout_at(const rk_scene_layout *L, const double *x, int j, double out[3]);
void rk_scene_layout_apply(const rk_scene_layout *L, const double *x, double *out);

typedef struct {
    rk_mesh mesh;
    rk_mesh_report mesh_report; /* the joined mesh measured, plus what each object's own check
                                 * repaired: reoriented, unused_removed, flat_dropped, ghosts,
                                 * orphans_removed */
    rk_material *materials;   /* one per tet */
    int *tet_tag;             /* one per tet: the mesh file's tag (0 for a file without), or NULL */
    int *point_tag;           /* one per vertex: a point cloud's PLY "tag" at its points, else 0 */
    rk_fem fem;
    rk_fom_options options;   /* points into arrays owned here */
    char (*chamber_name)[RK_CHAMBER_NAME]; /* options.nchambers: the chambers' names, objects in order */
    rk_obstacle *obstacles;   /* the scene's, meshes loaded (options.obstacles) */
    rk_surface *obstacle_meshes; /* one per obstacle (empty unless a mesh) */
    int steps;
    int *object_first_vertex; /* nobjects + 1 */
    int *object_first_tet;    /* nobjects + 1 */
    int cloud_points;         /* point-cloud objects: how many points they have in all; each object's
                               * points are its first vertices, in file order, the rest its contact
                               * surface's (rk_points_proxy); 0 for meshes */
    int *object_points;       /* nobjects: each point-cloud object's points (NULL for meshes) */
    /* Caged objects (mesh.cage): their original surfaces, placed, embedded in the scene's tets (what
     * an asset shows; nv = 0 without a cage), and the other objects' boundaries beside them, in
     * object order (a scene with a cage has no point cloud). */
    rk_embedded_surface embedded;
    int *embedded_first;      /* nobjects + 1: where each object's vertices start in embedded (NULL
                               * without a cage) */
    int embedded_outside;     /* surface vertices in no tet (exact test): embedded in the nearest tet,
                               * clamped, and warned about */
    double embedded_worst;    /* the farthest of those from the cage's boundary (m) */
    rk_cage_report cage;      /* the (last) cage made */
    /* rk_scene_build_full_order of a scene with point clouds: each cloud's body (rk_points_body)
     * in its place, and the layout that takes the run back to rk_scene_build's vertices (points,
     * then contact surface) for whatever a run writes; layout.nv = 0 and these 0 without a cloud */
    rk_scene_layout layout;
    int body_points;          /* the clouds' points, embedded in their bodies */
    int body_outside;         /* of those, in no tet (exact test): carried by the nearest, warned about */
    double body_worst_distance;
    int body_surface_outside; /* the clouds' march contact surfaces' vertices in no body tet (carried by the nearest) */
    int body_backed_off;      /* body vertices whose inset move was cut back (no inverted, flat tet) */
    double body_min_volume_ratio; /* the smallest body tet over its lattice tet's volume */
    double body_mass_scale;   /* the largest density factor that made a body weigh its cloud */
    double body_volume;       /* the bodies' rest volume (m^3) */
    double body_mass;         /* the clouds' mass, which the bodies weigh (kg) */
    /* full order with a cloud colliding through its march surface: the contact surface (arrays owned
     * here; options.contact_surface points to it), else mesh.nv = 0 (contact on the tets' boundary) */
    rk_fom_contact_surface contact;
} rk_scene_sim;

int rk_scene_build(const rk_scene *s, rk_scene_sim *out, rk_error *err);
/* The scene as the full-order simulator runs it: as rk_scene_build, but each point cloud as its
 * full-order body (rk_points_body: the tets filling its contact surface, with the cloud's mass and
 * its points' materials), its points embedded, and out->layout giving rk_scene_build's vertices
 * (what romkit fom writes and romkit compare measures). A scene without a cloud builds as
 * rk_scene_build builds it. */
int rk_scene_build_full_order(const rk_scene *s, rk_scene_sim *out, rk_error *err);

/* Object k of a built scene on its own: its vertices (mesh.X borrowed: global positions), its tets
 * renumbered from 0 (mesh.tets owned: free it), its first vertex and tet in the scene, and for a
 * point cloud how many of its vertices are its points (the rest: its contact proxy). */
typedef struct {
    rk_mesh mesh;
    int v0, t0, points;
} rk_object_view;
int rk_scene_object_view(const rk_scene_sim *sim, int k, rk_object_view *ov, rk_error *err);
/* The material at sample i of object k (RKPM integration or kernel points): its tet's for points
 * sampled in tets, a tet around it for a mesh's vertex, the regions' boxes for a cloud's point.
 * One rule for the basis's kernels and the mesh-free integration points, tags included. */
rk_material rk_scene_sample_material(const rk_scene *s, const rk_scene_sim *sim, int k, const rk_rkpm_points *pts, int i);
/* The material at vertex v of object k (a point cloud's point): the regions' boxes at it and its tag. */
rk_material rk_scene_point_material(const rk_scene *s, const rk_scene_sim *sim, int k, int v);
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

/* ---- an entry's training set (training.c) ---- */

/* Entry e's training displacements (*D: 3 nv x *T, column-major, malloc'd): every scene of its
 * "training" list run at full order (each must be the same object: the same vertices at the same
 * rest positions, checked) and every snapshot file (frames after the first, as displacements from
 * sim's rest positions), in list order, so the set is the same however the runs were produced.
 * Fails naming the item. */
int rk_scene_training_set(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e, double **D, int *T,
                          rk_error *err);
/* The same set with item k read from files[k] where files[k] is not NULL: the snapshots of item k's
 * run (romkit fom --snapshots of its scene, a job of its own: romkit plan), or the item's own file. */
int rk_scene_training_set_from(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e,
                               const char *const *files, double **D, int *T, rk_error *err);


/* ---- an entry baked (bake.c) ---- */

typedef struct {
    /* The scene's full-order run as romkit fom --snapshots writes it (steps + 1 frames of every
     * vertex's position, the start first: snapshot_dims = 3, shape steps + 1, nv, 3), trained on
     * instead of running the scene again; NULL: run when something needs it. */
    const double *snapshots;
    int snapshot_dims;
    long snapshot_shape[4];
    /* The entry's training list item by item from these files (ntraining_runs = the list's length;
     * rk_scene_training_set_from), run as separate jobs; 0: the items are run here. */
    const char *const *training_runs;
    int ntraining_runs;
    /* A Koopman entry's trajectories from these files (romkit fom --trajectory I --snapshots), one
     * per trajectory (one for an entry listing none); 0: run here. */
    const char *const *trajectory_runs;
    int ntrajectory_runs;
    /* A split bake's parts (romkit plan): the basis and the cubature from their steps' files
     * (rk_scene_rom_given); NULL: built here. Fixed-basis entries only. */
    const rk_basis *basis;
    const rk_cubature_set *cubature;
    int cubature_poses;
    int has_real_type;               /* real_type overrides rom.asset.precision */
    int real_type;
    int compress;                    /* deflate, beside rom.asset.compress */
} rk_bake_request;

typedef struct {
    unsigned char *data;             /* the asset (malloc'd) */
    size_t bytes;
    cJSON *report;                   /* DESIGN.md's keys: vertices, tets, basis.*, cubature.*, koopman.*, asset.* */
    char summary[1024];              /* a line (or a few) for a terminal */
} rk_baked;

/* Entry e of the scene end to end: the full-order run when something trains on it, the basis, the
 * cubature, the Koopman operator, baked into one asset (reduced model, Koopman operator or both).
 * Nothing is written; the caller saves data. */
/* The full-order frames (3 nv x *T displacements, malloc'd; *D NULL when nothing needs them) that
 * entry e's reduced model trains on as rk_scene_bake trains it: the request's snapshots, the
 * training list (from req->training_runs, or run here) or the scene's own run, where the basis
 * (unless req->basis) or the cubature (unless req->cubature) needs frames. *trained_on says which. */
int rk_scene_entry_frames(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e,
                          const rk_bake_request *req, double **D, int *T, const char **trained_on, rk_error *err);
int rk_scene_bake(const rk_scene *scene, const rk_rom_entry *e, const rk_bake_request *req, rk_baked *out,
                  rk_error *err);
void rk_baked_free(rk_baked *b);
/* The asset's chunks, precision and sizes as report keys under a (formats/ROMBIN.md). */
void rk_asset_report(cJSON *a, const unsigned char *data, size_t bytes, const rk_asset_summary *sum);

#endif
