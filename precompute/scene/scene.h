/* precompute/scene: the scene file (JSON, DESIGN.md "Scene file") parsed strictly into a
 * description, then built into a simulation: meshes loaded and placed, materials per element,
 * the FEM model and the full-order options. Every error names the scene file and the JSON path
 * of the offending key, e.g. "beam.json: objects[0].material.poisson: must be in (-1, 0.5), got 0.5". */
#ifndef RK_SCENE_H
#define RK_SCENE_H

#include <cjson/cJSON.h>

#include "fem/fem.h"
#include "fom/fom.h"
#include "mesh/mesh.h"
#include "scene/json_get.h"
#include "util/error.h"

typedef struct {
    double min[3], max[3];
} rk_box;

/* "box": [[xmin, ymin, zmin], [xmax, ymax, zmax]] under obj (required), for the stages that read
 * their own part of the scene. */
int rk_json_box(const rk_json_ctx *c, const cJSON *obj, const char *path, rk_box *b);
/* Whether p lies in b grown by slack on every side. */
int rk_box_contains(const rk_box *b, const double *p, double slack);

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
    rk_material material;
    int nregions;
    rk_scene_region *regions;
    int nmotions;          /* "fixed" entries come first, as kind RK_MOTION_FIXED */
    rk_scene_motion *motions;
    int nloads;
    rk_scene_force *loads;
    double velocity[3];
} rk_scene_object;

typedef struct {
    char path[4096];
    int nobjects;
    rk_scene_object *objects;
    double gravity[3];
    int nplanes;
    rk_plane *planes;
    double h;
    double duration;
    rk_integrator integrator;
    int is_static;
    int lumped_mass;
    double damping_mass, damping_stiffness; /* Rayleigh a, b */
    double newton_tol;     /* 0 = the simulator's default */
    int newton_max_iter;   /* 0 = the simulator's default */
    cJSON *rom;            /* the "rom" section as written (object or array), for later stages; may be NULL */
} rk_scene;

int rk_scene_load(const char *path, rk_scene *s, rk_error *err);
/* Parses JSON text; `path` names it in messages and anchors relative file names. */
int rk_scene_parse(const char *text, const char *path, rk_scene *s, rk_error *err);
void rk_scene_free(rk_scene *s);

/* The material at rest point p of an object: its own, overridden by the last region whose box
 * holds p (for elements, p is the centroid; for point clouds, the point). */
rk_material rk_scene_material_at(const rk_scene_object *o, const double p[3]);

/* A scene built into something to simulate. Objects are concatenated into one mesh;
 * object_first_vertex[k] / object_first_tet[k] say where object k starts. */
typedef struct {
    rk_mesh mesh;
    rk_mesh_report mesh_report;
    rk_material *materials;   /* one per tet */
    rk_fem fem;
    rk_fom_options options;   /* points into arrays owned here */
    int steps;
    int *object_first_vertex; /* nobjects + 1 */
    int *object_first_tet;    /* nobjects + 1 */
} rk_scene_sim;

int rk_scene_build(const rk_scene *s, rk_scene_sim *out, rk_error *err);
void rk_scene_sim_free(rk_scene_sim *out);

#endif
