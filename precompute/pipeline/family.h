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

#endif
