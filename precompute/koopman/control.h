/* precompute/koopman, control: the inputs that drive a fitted Koopman model to a goal after N
 * steps, by fast time stepping (koopman-dmd-log-linear paper, Sec. 7.3, Eq. 25).
 *
 * With the impulse convention of Eq. 19 (the push is added before each propagation), a constant
 * acceleration a held for N steps from z0 gives
 *
 *   z_N = K'^N z0 + sum_{t=1}^N K'^t g(a),    g(a) = U_r^T [0; P_in a h^2],
 *
 * and sum_{t=1}^N K'^t = W S_N W^-1 with S_N = sum_{t=1}^N B^t, which has a closed form on each
 * real block and complex pair (the "time-integrated propagator" of Eq. 25). With a = a_g + A C
 * (a_g gravity, A the k input acceleration fields as columns) z_N is affine in C, so C follows
 * from a least-squares fit of selected final values to goals; A may depend on the final state,
 * so it is re-evaluated from the latest prediction and the fit repeated (Sec. 7.3: 5 times). */
#ifndef RK_KOOPMAN_CONTROL_H
#define RK_KOOPMAN_CONTROL_H

#include "koopman/koopman.h"

/* s = sum_{t=1}^N lambda^t for lambda = re + i im and N >= 0 (N = 0 gives 0). Evaluated as
 * lambda (lambda^N - 1) / (lambda - 1) with lambda - 1 formed exactly and lambda^N - 1 as
 * expm1(N log lambda) (log through log1p), so that it keeps its relative precision as lambda
 * approaches 1; exactly N at lambda = 1. */
void rk_koopman_power_sum(double re, double im, long long N, double *s_re, double *s_im);

/* y <- S_N y on the real eigen-coordinates y = W^-1 z (k->block as in koopman.h): a real block
 * scales by its power sum s; a pair's block [[a, b], [-b, a]] stands for the complex number
 * a + ib, so its sum is [[Re s, Im s], [-Im s, Re s]] with s the power sum of a + ib. Uses the
 * (clamped) eigenvalues that rk_koopman_advance uses. */
void rk_koopman_summed_propagator(const rk_koopman *k, long long N, double *y);

/* z <- sum_{t=1}^N K'^t z = W S_N W^-1 z (r values). An eigenvalue above 1 in magnitude may
 * overflow to inf over many steps; rk_koopman_control checks for that, these do not. */
int rk_koopman_summed_apply(const rk_koopman *k, long long N, double *z, rk_error *err);

/* The forced N-step map: z <- K'^N z + sum_{t=1}^N K'^t g(a), i.e. N times "add the impulse of
 * the acceleration a (n values, or NULL for none), then step" (Eq. 19), in O(r^2). */
int rk_koopman_forced(const rk_koopman *k, long long N, const double *a, double *z, rk_error *err);

/* A goal on one value of the final frame: value `index` (0..n-1, as the fit's trajectories hold
 * values: displacements) should end at `goal`. */
typedef struct {
    int index;
    double goal;
} rk_koopman_target;

/* Input field j (0..k-1) as n accelerations (force over mass, m/s^2) into a, given u, the current
 * estimate of the final frame's n values; C_j scales it. Returns 0, or non-zero to stop the
 * solve (it then fails, naming the input). */
typedef int (*rk_koopman_input_fn)(void *ctx, const double *u, int j, double *a);

typedef struct {
    long long steps;                 /* N >= 1 */
    const double *z0;                /* r: the reduced state to start from, or NULL: rest (z = 0) */
    const double *accel;             /* n: a constant acceleration on every step (gravity), or NULL */
    int inputs;                      /* k >= 1 */
    rk_koopman_input_fn input_field;
    void *ctx;
    const rk_koopman_target *targets;
    int ntargets;                    /* >= 1 */
    double velocity_weight;          /* >= 0: adds rows weight * (u_N - u_{N-1}) = 0, the quasi-static
                                      * requirement of Sec. 7.3 (the velocity part of X_N, metres per
                                      * step, weighed against the goals in metres); 0: none */
    int velocity_all;                /* those rows for every value (1) or for the targets' (0) */
    int nonnegative;                 /* C >= 0 by non-negative least squares (Sec. 7.3) */
    int iterations;                  /* >= 1: solves, each with A re-evaluated (paper: 5) */
} rk_koopman_control_problem;

/* Zero everything, iterations 5. steps, inputs, input_field and targets must still be set. */
void rk_koopman_control_default(rk_koopman_control_problem *p);

/* Solves for the k inputs C. The first A is evaluated at the final frame the model predicts with
 * C = 0 (gravity and z0 only); each iteration then fits C to
 *   rows  u_N(C)[index] = goal             (one per target)
 *         w v_N(C)[i]   = 0                (velocity rows, when velocity_weight > 0)
 * by least squares (LAPACK dgelsd: singular values below 1e-12 of the largest count as zero, so
 * more inputs than rows, or dependent inputs, give the minimum-norm C) or, with nonnegative, by
 * Lawson-Hanson NNLS (one of the non-negative minimisers when it is not unique), predicts the
 * final frame under that C and hands it to the next evaluation of A.
 * C: k values out. residual (iterations values, or NULL): |rows C - rhs|_2 of each iteration's
 * system (the weighted misfit of the goals and velocity rows the model predicts). z_final (r, or
 * NULL): the predicted final reduced state under the returned C. */
int rk_koopman_control(const rk_koopman *k, const rk_koopman_control_problem *p, double *C, double *residual,
                       double *z_final, rk_error *err);

/* Dense solvers (lstsq.c); A is m x n, column-major, left unchanged.
 * x = the minimum-norm least-squares solution of A x ~ b (dgelsd, relative singular value cut 1e-12). */
int rk_lstsq(int m, int n, const double *A, const double *b, double *x, rk_error *err);
/* x = argmin |A x - b|_2 subject to x >= 0 (the cubature stage's Lawson-Hanson, on A^T A). */
int rk_nnls(int m, int n, const double *A, const double *b, double *x, rk_error *err);

#endif
