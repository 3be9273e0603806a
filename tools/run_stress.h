/* romkit run --stress T.npy: every frame's largest principal Cauchy stress (Pa) at each shown
 * vertex, through the same rk_cauchy_stress as romkit fom --stress (FreeForm Fig. 8): a point
 * cloud's from the runtime's deformation gradients at its points (GRAD) and the scene's materials
 * (--scene); a mesh's from its tets, as romkit fom --stress takes them (rk_fem_principal_stress over
 * the scene's elements), which needs every vertex shown (asset.show "all"). */
#ifndef ROMKIT_RUN_STRESS_H
#define ROMKIT_RUN_STRESS_H

#include "run_scene.h"

typedef struct {
    rk_npy_stream out;
    int open, n;
    rk_material_model *model;  /* n: each shown vertex's material */
    double *mu, *lambda;
    double *sigma;             /* n: the frame's stresses */
    romrt_real *F;             /* 9 n from the runtime (a cloud), or NULL (a mesh) */
    const run_scene *S;        /* a mesh: its elements */
    double *x, *sigma_all;     /* a mesh: 3 nv positions (all shown), nv stresses */
} run_stress;

/* Opens path for frames x n float64; fails, saying why, for a mesh asset that does not show every
 * vertex. */
int run_stress_open(run_stress *o, const char *path, long frames, const run_scene *S, const romrt_model *m,
                    rk_error *err);
/* Frame k's stresses appended (xyz: its shown positions). */
int run_stress_frame(run_stress *o, const romrt_model *m, long k, const romrt_real *xyz, rk_error *err);
/* Writes the file (0), or drops it (close alone). */
int run_stress_commit(run_stress *o, rk_error *err);
void run_stress_close(run_stress *o);

#endif
