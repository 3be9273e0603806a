/* NumPy .npy files (format version 1.0), float64 little-endian, C order.
 * Writes are atomic: a temporary file beside the target, then rename. */
#ifndef RK_NPY_H
#define RK_NPY_H

#include "util/atomic_file.h"
#include "util/error.h"

/* shape has ndim entries (1..4). */
int rk_npy_write(const char *path, const double *data, int ndim, const long *shape, rk_error *err);
/* Streaming writer for arrays too large to hold (e.g. T x n x 3 snapshots): the shape is fixed
 * up front, rows are appended, and commit checks that exactly the promised count arrived. */
typedef struct {
    rk_atomic_file file;
    size_t expected, written;
} rk_npy_stream;
int rk_npy_stream_open(rk_npy_stream *st, const char *path, int ndim, const long *shape, rk_error *err);
void rk_npy_stream_append(rk_npy_stream *st, const double *data, size_t count);
int rk_npy_stream_commit(rk_npy_stream *st, rk_error *err);
void rk_npy_stream_abort(rk_npy_stream *st);

/* Reads a float64 (or float32, converted) array.*data is malloc'ed; shape gets up to 4 dims. */
int rk_npy_read(const char *path, double **data, int *ndim, long shape[4], rk_error *err);

#endif
