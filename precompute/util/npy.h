/* NumPy .npy files (format version 1.0), float64 little-endian, C order.
 * Writes are atomic: a temporary file beside the target, then rename. */
#ifndef RK_NPY_H
#define RK_NPY_H

#include "util/error.h"

/* shape has ndim entries (1..4). */
int rk_npy_write(const char *path, const double *data, int ndim, const long *shape, rk_error *err);
/* Reads a float64 (or float32, converted) array.*data is malloc'ed; shape gets up to 4 dims. */
int rk_npy_read(const char *path, double **data, int *ndim, long shape[4], rk_error *err);

#endif
