/* precompute/util: what every stage shares, below them all.
 *
 *   errors       rk_error, rk_fail, rk_calloc: every failure names what and where; rk_warn
 *   timers       a monotonic clock, progress lines on a terminal
 *   threads      the one thread count (ROMKIT_THREADS) for OpenBLAS, CHOLMOD and romkit's loops
 *   sorting      one comparator, one median
 *   files        atomic output (a temporary file, then rename) and NumPy .npy arrays
 *   metrics      the errors of a run against a reference: normalized MSE, relative and online
 *                error, max |lambda|, each defined once
 *   random       the project's one seeded generator (header-only) */
#ifndef RK_UTIL_H
#define RK_UTIL_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* ==== errors (error.c) ==== */

/* Error reporting shared by every precompute stage.
 * A function that can fail returns int (0 on success, -1 on failure) and, on failure,
 * fills an rk_error with one message naming what failed and where (file and line,
 * element index, JSON key). Callers add context with rk_error_prefix. */

typedef struct {
    char msg[1024];
} rk_error;

/* Writes the message (printf format) and returns -1, so callers can `return rk_fail(...)`. */
int rk_fail(rk_error *err, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Puts "context: " in front of an existing message. Returns -1. */
int rk_error_prefix(rk_error *err, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void rk_error_clear(rk_error *err);

/* Allocation that reports failure through err instead of crashing. */
void *rk_calloc(size_t count, size_t size, rk_error *err);

/* "warning: <message>" on stderr, for something the toolchain changed on its own that the user
 * must hear about (a flat tet dropped from a model). Never silenced, --quiet included: a quiet
 * run may skip progress, not a change to the user's data. */
void rk_warn(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* ==== timers and progress (timer.c) ==== */

/* Wall-clock timing and terminal progress for long stages. */

/* Seconds from a monotonic clock. */
double rk_now(void);

/* Progress on stderr, only when stderr is a terminal and not silenced (DESIGN.md: quiet otherwise).
 * rk_progress redraws one line ("stage: k/N (pct%)", or "stage: k" when total <= 0,
 * for loops of unknown length) at most every 0.1 s, so it may be called every iteration;
 * rk_progress_done ends the line. */
void rk_progress_set_quiet(int quiet);
void rk_progress(const char *stage, long done, long total);
void rk_progress_done(const char *stage);
/* Ends a progress line left open (a stage failed part-way), so what follows starts on its own
 * line; rk_fail calls it. */
void rk_progress_break(void);

/* ==== threads (threads.c) ==== */

/* How many threads romkit uses, set in one place: ROMKIT_THREADS (1 to RK_THREADS_MAX), or by
 * default the CPUs this process may run on (affinity, cgroup quota), at most
 * RK_THREADS_DEFAULT_MAX. The count goes to OpenBLAS (openblas_set_num_threads, over
 * OPENBLAS_NUM_THREADS) and to romkit's own loops (rk_parallel_for). Every OpenMP region runs on
 * one thread: CHOLMOD's supernodal factorization asks for a fixed 4 OpenMP threads for
 * memory-bound loops that gain nothing from them, and those threads spinning beside OpenBLAS's
 * made the factorization 2 to 15 times slower on 2 cores (threads.c).
 *
 * rk_threads_init: called at start-up by the command line and the benches; fails (naming the
 * variable) on a ROMKIT_THREADS that is not a count, after setting the default. rk_threads: the
 * count, set by rk_threads_init first if nothing has (the simulators call it, so tests and other
 * programs linking the library get the same settings). */
#define RK_THREADS_MAX 256
#define RK_THREADS_DEFAULT_MAX 16
int rk_threads_init(rk_error *err);
int rk_threads(void);
/* OpenBLAS's threads for what follows, n clamped to 1..rk_threads(); returns the count before, to
 * put back. For a caller that knows its BLAS calls are too small to gain from threads. */
int rk_threads_blas(int n);

/* body(ctx, begin, end) over [0, n) in chunks of `chunk` indices, on up to rk_threads() threads:
 * the caller's and workers that sleep between loops, dynamically scheduled (a core busy with
 * something else takes fewer chunks). A body must write only what belongs to its own indices, so
 * that the result does not depend on the thread count or the schedule; sums over indices go to a
 * buffer and are added in index order afterwards. One loop at a time: a loop started while
 * another runs (inside a body, or from another thread) runs on its caller's thread alone. */
typedef void (*rk_range_fn)(void *ctx, long begin, long end);
void rk_parallel_for(long n, long chunk, rk_range_fn body, void *ctx);
/* The same, with first(first_ctx) run by the calling thread while the workers start on the
 * chunks (then it joins them): serial work that can overlap the loop, such as adding up what the
 * previous loop computed. With one thread, first runs before the loop. */
void rk_parallel_for_beside(long n, long chunk, rk_range_fn body, void *ctx, void (*first)(void *), void *first_ctx);

/* ==== sorting (sort.c) ==== */

/* Sorting doubles: one comparator for qsort, and the median of timings and distances. */

/* qsort comparator, ascending. */
int rk_cmp_double(const void *a, const void *b);
/* Sorts v[0..n) in place and returns its median; NAN when n is 0. */
double rk_median(double *v, int n);

/* ==== atomic files (atomic_file.c) ==== */

/* Atomic file output: nothing is ever written half-way (DESIGN.md, Errors).
 * rk_atomic_open creates PATH.tmp.PID beside the target; rk_atomic_commit flushes and renames
 * it onto PATH; rk_atomic_abort removes it. Every writer in the toolchain goes through this. */

typedef struct {
    char final_path[4096];
    char tmp_path[4160];
    FILE *fp;
} rk_atomic_file;

int rk_atomic_open(rk_atomic_file *f, const char *path, rk_error *err);
int rk_atomic_commit(rk_atomic_file *f, rk_error *err);
void rk_atomic_abort(rk_atomic_file *f);

/* ==== .npy arrays (npy.c) ==== */

/* NumPy .npy files (format version 1.0), float64 little-endian, C order.
 * Writes are atomic: a temporary file beside the target, then rename. */

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

/* ==== metrics (metrics.c) ==== */

/* precompute/util/metrics: the error of a run against a reference run, and the other numbers the
 * reports compare, each defined once (DESIGN.md, "Report keys"). A run is a sequence of frames of
 * n points (3 n coordinates each) beside the reference's frames at the same times, both after the
 * start; X is the rest shape of the same n points, L its bounding-box diagonal.
 *
 *   normalized MSE         mean over frames and points of |x - x_ref|^2, divided by L^2 (the
 *                          FreeForm paper's metric, Sec. 4 and Table 1)
 *   normalized max error   max over frames and points of |x - x_ref|, divided by L
 *   relative error         sqrt(sum |x - x_ref|^2 / sum |x_ref - X|^2) over every frame and point
 *   relative online error  sum_t |x_t - x_ref,t| / sum_t |x_ref,t - X| (norms over all points of a
 *                          frame): the Grassmann paper's total relative online error (Sec. 5.1),
 *                          meaningful for a run that restarts each step from the reference state
 *                          before it (per-step realignment), so that drift does not dominate */

typedef struct {
    int n;                  /* points per frame */
    const double *X;        /* 3 n rest positions (not owned; must outlive the accumulation) */
    double L;               /* bounding-box diagonal of X */
    long frames;
    double sum_sq;          /* sum |x - x_ref|^2 */
    double sum_ref_sq;      /* sum |x_ref - X|^2 */
    double max_dist;        /* max |x - x_ref| */
    double online_num, online_den; /* sum_t |x_t - x_ref,t|, sum_t |x_ref,t - X| */
} rk_run_error;

/* Starts an accumulation over n points with rest positions X. */
void rk_run_error_init(rk_run_error *e, const double *X, int n);
/* Adds one frame: x and x_ref, 3 n coordinates each. */
void rk_run_error_add(rk_run_error *e, const double *x, const double *ref);
/* The metrics above of the frames added so far (NAN before any frame, or where a denominator is 0). */
double rk_normalized_mse(const rk_run_error *e);
double rk_normalized_max_error(const rk_run_error *e);
double rk_relative_error(const rk_run_error *e);
double rk_relative_online_error(const rk_run_error *e);

/* One frame's error |a - b| over its n points: sqrt(sum over points of |a_v - b_v|^2), b NULL: the
 * norm of a (a displacement frame's size). The relative online error sums these (rk_run_error_add
 * adds the same terms, in the same order); reports of a tracked trajectory give it per frame. */
double rk_frame_error(const double *a, const double *b, int n);

/* The bounding-box diagonal of n points (3 n coordinates). */
double rk_points_diagonal(const double *X, int n);
/* max_i |lambda_i| of n complex numbers re_i + i im_i (0 for n = 0). */
double rk_max_abs_eigenvalue(const double *re, const double *im, int n);

/* ==== random numbers ==== */

/* The project's one seeded generator: splitmix64 (Steele, Lea & Flood 2014, "Fast splittable
 * pseudorandom number generators"), tiny, and the same sequence on every platform and C library
 * (libc rand() is neither). Used by the cubature's subset draws and training poses, and by the
 * tests and benches that need random input.
 *
 * Header-only (static inline) on purpose: any stage, test or bench can include it without
 * linking util (the physics tests link only the physics stage). */

/* One splitmix64 step: advances *state and returns the next 64 random bits. */
static inline uint64_t rk_splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

/* Uniform in [0, 1): the top 53 bits of one step, times 2^-53 (every value a multiple of 2^-53). */
static inline double rk_uniform(uint64_t *state)
{
    return (double)(rk_splitmix64(state) >> 11) * (1.0 / 9007199254740992.0);
}

#endif
