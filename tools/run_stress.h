/* romkit run --stress T.npy: every frame's largest principal Cauchy stress (Pa) at each shown
 * vertex, from the runtime's deformation gradients there (GRAD: a point cloud's) and the scene's
 * materials (--scene), through the same rk_cauchy_stress as romkit fom --stress (FreeForm Fig. 8). */
#ifndef ROMKIT_RUN_STRESS_H
#define ROMKIT_RUN_STRESS_H

#include "run_scene.h"

typedef struct {
    rk_npy_stream out;
    int open, n;
    rk_material_model *model;  /* n: each shown vertex's material */
    double *mu, *lambda;
    double *sigma;             /* n: the frame's stresses */
    romrt_real *F;             /* 9 n from the runtime */
} run_stress;

/* Opens path for frames x n float64; fails, saying why, when the asset stores no deformation
 * gradients (a mesh's: romkit fom --stress gives those). */
int run_stress_open(run_stress *o, const char *path, long frames, const run_scene *S, const romrt_model *m,
                    rk_error *err);
/* Frame k's stresses appended. */
int run_stress_frame(run_stress *o, const romrt_model *m, long k, rk_error *err);
/* Writes the file (0), or drops it (close alone). */
int run_stress_commit(run_stress *o, rk_error *err);
void run_stress_close(run_stress *o);

#endif
