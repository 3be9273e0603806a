/* precompute/cubature: choosing cubature points and non-negative weights.
 *
 *   rk_nnls_normal      non-negative least squares on the normal equations (Lawson & Hanson 1974,
 *                       "Solving Least Squares Problems", Ch. 23, algorithm NNLS), nnls.c
 *   rk_cubature_greedy  greedy point selection with an NNLS re-fit after every pick (An, Kim &
 *                       James 2008, "Optimizing cubature for efficient integration of subspace
 *                       deformations", Sec. 4), greedy.c
 *
 * The cubature problem is  b ~ A_S w,  w > 0: column c of A is what candidate point c
 * contributes to the training quantities (for instance reduced forces over a set of poses) and b
 * is the exact total. Columns come from a callback because all of A rarely fits in memory. */
#ifndef RK_CUBATURE_SELECT_H
#define RK_CUBATURE_SELECT_H

#include "util/error.h"

/* Non-negative least squares, min |A w - b|^2 subject to w >= 0, Lawson-Hanson active set,
 * given through the normal equations of the k candidate columns: gram = A^T A (k x k,
 * column-major, full symmetric) and atb = A^T b. w (k) is the starting point on entry (all zero,
 * or a previous solution to warm-start: entries > 0 form the initial passive set, the others are
 * taken as 0) and the solution on exit. Fails only on bad input (non-finite values, k < 0) or
 * allocation; stops after max_iter outer iterations (0 = 3k) keeping the best feasible w (the
 * iterates are feasible and lower the objective monotonically, so that is the last one).
 * A column whose addition makes the passive Gram block numerically singular is left at 0. */
int rk_nnls_normal(int k, const double *gram, const double *atb, double *w, int max_iter,
                   rk_error *err);

typedef struct {
    int rows;                  /* length of b */
    int candidates;            /* how many columns there are to choose from */
    /* Writes column `candidate` (rows values) into col; returns 0, or -1 with err filled. */
    int (*column)(void *ctx, int candidate, double *col, rk_error *err);
    void *ctx;
    const double *b;           /* target (rows), not zero */
    double tolerance;          /* stop when |A_S w - b| / |b| <= tolerance */
    int max_points;            /* stop after this many selected (>= 1; more than candidates
                                  means all of them) */
    int sample;                /* candidates scored per iteration (a fresh random subset of the
                                  unselected ones each time), 0 or >= candidates: all of them */
    unsigned long long seed;   /* the subset draws (rk_splitmix64, util/random.h):
                                  same seed, same result */
} rk_cubature_problem;

typedef struct {
    int count;                 /* selected points */
    int *index;                /* count candidate indices, ascending */
    double *weight;            /* count weights, all > 0 */
    double relative_error;     /* |A_S w - b| / |b| at the end, computed from the columns */
    int reached;               /* 1 when relative_error <= tolerance */
    int iterations;            /* greedy iterations (picks re-fitted, a final undone one included) */
} rk_cubature_set;

/* Greedy cubature (An et al. 2008, Sec. 4): residual r = b; each iteration scores the sampled
 * unselected candidates by (a_c . r) / |a_c| and adds the best (zero columns are skipped; stops
 * when no candidate has a positive score), then re-solves the NNLS over the selected columns
 * (normal equations, warm-started from the previous weights; the Gram matrix grows by one
 * row/column per iteration, computed from the stored selected columns) and drops points whose
 * weight became 0. Stops at the tolerance, at max_points, or when an iteration no longer lowers
 * the error (that last pick is then undone). Not reaching the tolerance is NOT an error:
 * reached = 0 says so and the caller decides. Fails on bad input (non-finite b or column
 * entries, b = 0, rows/candidates/max_points < 1, sample < 0, a negative or NaN tolerance),
 * allocation, or a failing column callback (its message, prefixed with the candidate). */
int rk_cubature_greedy(const rk_cubature_problem *p, rk_cubature_set *out, rk_error *err);
void rk_cubature_set_free(rk_cubature_set *s);

#endif
