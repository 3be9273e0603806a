/* precompute/pipeline: a family of scenes for romkit neural-dmd (family.c). */
#ifndef RK_PIPELINE_FAMILY_H
#define RK_PIPELINE_FAMILY_H

#include "pipeline/method_koopman.h"

/* ---- a family of meshes for the neural, shape-conditioned DMD (family.c; romkit neural-dmd) ----
 *
 * A family file (JSON): {"members": [{"scene": "a.json", "snapshots": "a.npy", "gamma": [0.14]}, ...],
 * "rank": R, "network": {"hidden", "depth", "eig_hidden", "eig_depth"}, "training": {"pretrain_epochs",
 * "epochs", "learning_rate", "window", "init_member", "polish", "vertices"}, "seed": S}. Each member is a scene (its mesh,
 * material, fixed vertices, forcing and time step, built as every command builds one), that
 * scene's full-order run as romkit fom --snapshots writes it (T x nv x 3 positions, the rest
 * state first) and its shape code gamma (g numbers, the same g for every member; absent or null:
 * g = 0). Paths are relative to the family file's folder. Every key but "members" and "rank" is
 * optional (rk_koopman_neural_default_options). A member with "held_out": true is not trained on,
 * only measured (its rollout error: the model's own error on an unseen member).
 *
 * "shape" says how a code maps to a mesh, for the shape optimisation, in either or both of two
 * forms over its scene s.json: "size": [x, y, z], "size_per_gamma": [[x, y, z], ...] (g rows):
 * the scene's first object is a box of size size + sum_j gamma_j size_per_gamma[j]; and "keys":
 * [{"key": "objects[0].mesh.voids[0].box[1][0]", "per_gamma": [g numbers], "range": [lo, hi]}, ...]:
 * each key, a number in s.json named by its JSON path, takes its value there plus
 * sum_j gamma_j per_gamma[j] (so a pneumatic finger's chamber length, wall thickness or offset are
 * codes: move the void's and the chamber's box corners together). "range" (optional) bounds the
 * key's value over every code in the members' range, checked when the file is read. "step"
 * (optional, > 0) rounds the offset to whole steps: a carved void (carve.c takes the tets whose
 * centroid lies in its box) whose wall moves by whole cells keeps whole-cell walls, so its mesh is
 * piecewise constant in the code, as a remeshed family's is (Sec. 7.4 meshes each shape anew). */
typedef struct {
    char scene[4096], snapshots[4096];
    double gamma[RK_KOOPMAN_SHAPE_MAX];
    rk_scene sc;
    rk_scene_sim sim;
    rk_koopman_run run;
    int built, ran, held_out;
} rk_family_member;

/* "shape.keys[i]": a number of the shape's scene that moves with the code. */
typedef struct {
    char key[256];                       /* its JSON path, as written */
    double base;                         /* its value in the scene */
    double per_gamma[RK_KOOPMAN_SHAPE_MAX];
    double step;                         /* > 0: the offset rounded to whole steps (0: none) */
} rk_family_key;

typedef struct {
    int nmembers, g;
    rk_family_member *member;
    rk_koopman_neural_mesh *mesh;        /* nmembers meshes over the members' runs */
    int ntrain;                          /* the members not held out, */
    rk_koopman_neural_mesh *train;       /* their meshes: what the model is trained on */
    rk_koopman_neural_options options;   /* the file's; h the scenes' (all the same) */
    int has_shape;                       /* "shape": {"scene", "size", "size_per_gamma"}: the mesh of any code */
    char shape_scene[4096];
    int has_size;                        /* the box-size form */
    double size[3], size_per_gamma[RK_KOOPMAN_SHAPE_MAX][3];
    int nkeys;                           /* the keys form */
    rk_family_key *keys;
    char *shape_text;                    /* the shape scene's JSON, read with the family */
} rk_family;

/* Parses the family file, builds each member's scene and reads its snapshots, checking them
 * (shape T x nv x 3 with T >= 2, the scene's nv, finite, the first frame the scene's rest
 * positions, one time step for all). Messages name the file and the JSON path. */
int rk_family_load(const char *path, rk_family *f, rk_error *err);
void rk_family_free(rk_family *f);
/* The family's "shape" for code gamma (g values): its scene with each key moved, then the first
 * object's box of size size + sum_j gamma_j size_per_gamma[j] (g rows of 3). Fails without
 * "shape", when the box form's first object is not a box, on a size that is not positive, or on
 * a scene the moved keys make invalid (naming the code). */
int rk_family_shape_scene(const rk_family *f, const double *gamma, rk_scene *out, rk_error *err);
/* The same scene as JSON text (malloc'd; the keys moved, the box form's size written into its
 * first object's mesh.box.size), for romkit fom at that code. NULL with err set on failure. */
char *rk_family_shape_text(const rk_family *f, const double *gamma, rk_error *err);
/* The lower and upper ends of each code value over the members (held out or not). */
void rk_family_range(const rk_family *f, double *lo, double *hi);

#endif
