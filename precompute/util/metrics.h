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
#ifndef RK_METRICS_H
#define RK_METRICS_H

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

/* The bounding-box diagonal of n points (3 n coordinates). */
double rk_points_diagonal(const double *X, int n);
/* max_i |lambda_i| of n complex numbers re_i + i im_i (0 for n = 0). */
double rk_max_abs_eigenvalue(const double *re, const double *im, int n);

#endif
