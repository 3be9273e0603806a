/* precompute/koopman: a Koopman operator learned from trajectories by dynamic mode decomposition
 * (koopman-dmd-log-linear paper, Sec. 3-4), in a real form that steps, jumps N steps in O(1)
 * per mode, changes time step and damping without leaving real arithmetic.
 *
 * State (Eq. 18): X_t = [u_t; u_t - u_{t-1}] (2d numbers for d observables per frame). Pairs
 * (X_t, X_{t+1}) from every trajectory are fitted jointly: X' ~ K X. With the truncated SVD
 * X = U_r S_r V_r^T the reduced operator is K' = U_r^T X' V_r S_r^-1 (Eq. 13), r x r, and the
 * reduced state is z = U_r^T X. K' = phi Lambda phi^-1 (Eq. 14); in real form K' = W B W^-1 with
 * W the real and imaginary parts of the eigenvectors and B block diagonal: a 1 x 1 block per real
 * eigenvalue, [[a, b], [-b, a]] per complex pair a +- ib (Sec. 5.2's realified operator, with the
 * imaginary part never leaving the reduced space). Powers, time-step rescaling (Eq. 21) and the
 * damping edit act on the blocks in polar form. */
#ifndef RK_KOOPMAN_H
#define RK_KOOPMAN_H

#include "util/error.h"

/* One trajectory: u holds `frames` frames of d observables (column-major: frame t at u + d t),
 * frames >= 3 (two frames make the first state, a third its successor). accel (d values, or
 * NULL for none) is the constant acceleration acting on it throughout (gravity, a load over the
 * mass, m/s^2): each training pair is then (X_t + [0; a h^2], X_{t+1}) (Eq. 19), so the operator
 * learns the unforced dynamics and takes forces as impulses. */
typedef struct {
    const double *u;
    int frames;
    const double *accel;
} rk_koopman_trajectory;

typedef struct {
    int rank;            /* r; 0: by energy */
    double energy;       /* when rank is 0: the smallest r whose singular values keep this
                          * fraction of sum sigma^2 (default 0.999999) */
    int clamp;           /* scale every |lambda| > 1 down to 1 (stable rollouts) */
    double h;            /* the data's time step (s) */
} rk_koopman_options;

void rk_koopman_default_options(rk_koopman_options *o);

typedef struct {
    int n;               /* values per frame given to the fit (= d without a projection) */
    double *P_in;        /* d x n: observables from values (P_in u), or NULL (identity) */
    double *P_out;       /* n x d: values from observables, or NULL (identity) */
    int d;               /* observables per frame */
    int r;
    double h;
    double *U;           /* 2d x r, column-major: the lifted state's basis U_r */
    double *K;           /* r x r, column-major: K' (Eq. 13) */
    double *lambda_re, *lambda_im; /* r discrete-time eigenvalues (clamped if asked) */
    double *residual;    /* r: |X' xi - lambda X xi| / |X xi| over the data for each mode's xi
                          * = V_r S_r^-1 phi: how far the data is from following the mode */
    double *W, *Winv;    /* r x r: real eigenvector matrix and its inverse */
    int *block;          /* r: 1 for a real eigenvalue, 2 at the first of a complex pair, 0 at its second */
    int nsingular;
    double *singular;    /* the data's singular values, descending */
    int clamped;         /* eigenvalues scaled down to |lambda| = 1 */
} rk_koopman;

/* Fits the operator to ntraj trajectories of d values per frame, jointly. Fails with a message
 * on rank above the data's numerical rank, non-finite data, or a trajectory too short. */
int rk_koopman_fit(const rk_koopman_trajectory *traj, int ntraj, int d, const rk_koopman_options *o, rk_koopman *out,
                   rk_error *err);
/* The same on projected observables (a POD basis first, Sec. 4.1's optional reduction): the
 * trajectories hold n values per frame, the fit sees P_in u (d per frame, P_in d x n) and reads
 * values back as P_out y (P_out n x d). Both are copied. With a mass-orthonormal POD basis Q,
 * P_in = Q^T M and P_out = Q. */
int rk_koopman_fit_projected(const rk_koopman_trajectory *traj, int ntraj, int n, const double *P_in,
                             const double *P_out, int d, const rk_koopman_options *o, rk_koopman *out, rk_error *err);
void rk_koopman_free(rk_koopman *k);

/* All of the following take and give the n values per frame (projected as the fit was). */
/* z = U_r^T X for X = [u; u - u_prev]. */
void rk_koopman_lift(const rk_koopman *k, const double *u, const double *u_prev, double *z);
/* u from z: the first d rows of U_r z. */
void rk_koopman_positions(const rk_koopman *k, const double *z, double *u);
/* z <- K'^n z through the real blocks: cost O(r^2), whatever n (n >= 0). dt_scale rescales the
 * time step (h' = dt_scale h, Eq. 21) and damping multiplies every |lambda| by (1 - damping)
 * (Sec. 7.2); 1 and 0 leave the operator as fitted. */
void rk_koopman_advance(const rk_koopman *k, double *z, long long n, double dt_scale, double damping);
/* An external push during one step as an impulse on the velocity part, [0; a h^2] (Eq. 19), added
 * to z; a is the acceleration it causes (force over mass, m/s^2), so a h^2 is a displacement. */
void rk_koopman_impulse(const rk_koopman *k, const double *a, double *z);

/* The operator in its real eigen-coordinates y = W^-1 z, where one step is y <- B y with B's
 * 1 x 1 and 2 x 2 blocks (block[]), as the runtime steps it:
 *   out (n x r, column-major): values u = out y;
 *   in  (r x n, column-major): y += in a h^2 is the impulse of an acceleration a (n values);
 *   y0 (r): the lift of [u; u - u_prev] into y (when u, u_prev are given; else skipped). */
int rk_koopman_real_form(const rk_koopman *k, double *out, double *in, const double *u, const double *u_prev,
                         double *y0, rk_error *err);
/* y <- B y: one step in those coordinates, O(r). */
void rk_koopman_real_step(const rk_koopman *k, double *y);

#endif
