/* romkit run --splats DIR: the asset's Gaussian splats (SPLY) moved with the runtime's positions
 * and deformation gradients (GRAD), one 3DGS PLY per frame. */
#ifndef ROMKIT_RUN_SPLATS_H
#define ROMKIT_RUN_SPLATS_H

#include <stddef.h>

#include "mesh/mesh.h"
#include "runtime/romrt.h"

typedef struct {
    const char *dir;
    rk_splats splats;
    double *x, *F;         /* 3n centres and 9n deformation gradients, double for the writer */
    romrt_real *Fr;        /* 9n from the runtime */
} run_splats;

/* Reads the splats stored in the asset; fails, saying why, without SPLY or GRAD or when their
 * count is not the asset's shown points. Creates dir. */
int run_splats_open(run_splats *o, const char *dir, const unsigned char *asset, size_t bytes, const romrt_model *m,
                    rk_error *err);
/* DIR/frame_NNNNN.ply for frame k (0: the start) with the shown positions xyz. */
int run_splats_frame(run_splats *o, const romrt_model *m, long k, const romrt_real *xyz, rk_error *err);
void run_splats_close(run_splats *o);

#endif
