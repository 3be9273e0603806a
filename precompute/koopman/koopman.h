/* precompute/koopman: a Koopman operator learned from trajectories by dynamic mode decomposition
 * (koopman-dmd-log-linear paper, Sec. 3-4), in a real form that steps, jumps N steps in O(1)
 * per mode, changes time step and damping without leaving real arithmetic.
 *
 * State (Eq. 18): X_t = [u_t; u_t - u_{t-1}] (2d numbers for d observables per frame), its
 * velocity block scaled to the displacement block's energy before the fit (k->vscale). Pairs
 * (X_t, X_{t+1}) from every trajectory are fitted jointly: X' ~ K X. With the truncated SVD
 * X = U_r S_r V_r^T the reduced operator is K' = U_r^T X' V_r S_r^-1 (Eq. 13), r x r, and the
 * reduced state is z = U_r^T X. K' = phi Lambda phi^-1 (Eq. 14); in real form K' = W B W^-1 with
 * W the real and imaginary parts of the eigenvectors and B block diagonal: a 1 x 1 block per real
 * eigenvalue, [[a, b], [-b, a]] per complex pair a +- ib (Sec. 5.2's realified operator, with the
 * imaginary part never leaving the reduced space). Powers, time-step rescaling (Eq. 21) and the
 * damping edit act on the blocks in polar form. */
#ifndef RK_KOOPMAN_H
#define RK_KOOPMAN_H

#include "neural/neural.h"
#include "util/util.h"

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
    double energy;       /* when rank is 0: the smallest r for which the rank-r SVD keeps this
                          * fraction of each block's energy, displacements and (scaled)
                          * velocities alike (default 0.999999) */
    int clamp;           /* scale every |lambda| > 1 down to 1 (stable rollouts) */
    int stabilize;       /* when the fit has an |lambda| > 1: 0 (default) refit the eigenvalues
                          * under |lambda| <= 1 if the training data does not grow (fit.c,
                          * stabilize), -1 never, 1 whether or not it grows */
    int unbalanced;      /* 0 (default): the velocity block scaled to the displacements' energy
                          * before the SVD (fit.c's balance_blocks); 1: as recorded, which can fit
                          * a smooth single run better at a fixed rank but truncates the velocity
                          * directions of livelier data away (scene key "balance": false) */
    double h;            /* the data's time step (s) */
    int displacement_only; /* the ablation of Sec. 4.2 / Fig. 4: the state is X_t = u_t alone (the
                          * velocity block held at zero, so U_r, the lift and the operator see u
                          * only) and a force enters as the displacement a h^2 added to u_t before
                          * the step, Eq. 19's impulse moved to the only block there is. Only for
                          * measuring what the momentum term buys (test_koopman_momentum.c). */
} rk_koopman_options;

void rk_koopman_default_options(rk_koopman_options *o);

typedef struct {
    int n;               /* values per frame given to the fit (= d without a projection) */
    double *P_in;        /* d x n: observables from values (P_in u), or NULL (identity) */
    double *P_out;       /* n x d: values from observables, or NULL (identity) */
    int d;               /* observables per frame */
    int r;
    double h;
    double vscale;       /* beta: the fit saw the state as [u; beta (u - u_prev)], both blocks of equal
                          * energy (fit.c, balance_blocks); U, K, W and the residuals are in those
                          * coordinates, the functions below take and give unscaled values */
    double *U;           /* 2d x r, column-major: the (scaled) lifted state's basis U_r */
    double *K;           /* r x r, column-major: K' (Eq. 13), or W B W^-1 after a refit (stabilized) */
    double *lambda_re, *lambda_im; /* r discrete-time eigenvalues (clamped if asked) */
    double *residual;    /* r: |X' xi - lambda X xi| / |X xi| over the (scaled) data for each mode's xi
                          * = V_r S_r^-1 phi: how far the data is from following the mode */
    double *W, *Winv;    /* r x r: real eigenvector matrix and its inverse */
    int *block;          /* r: 1 for a real eigenvalue, 2 at the first of a complex pair, 0 at its second */
    int nsingular;
    double *singular;    /* the (scaled) data's singular values, descending */
    int clamped;         /* eigenvalues scaled down to |lambda| = 1 */
    int data_grows;      /* the training data's last states hold more (scaled) energy than its
                          * first (fit.c, data_grows): a growth the default keeps */
    int stabilized;      /* eigenvalues outside the unit circle before the stability-constrained
                          * refit (fit.c, stabilize; 0: not refitted). The refit moves every
                          * eigenvalue a little (the modes are coupled), and K, lambda and the
                          * residuals are then the refitted ones */
    double stabilize_shift;  /* the refit's largest |lambda_new - lambda_old| */
    double stabilize_top;    /* the largest |lambda| before the refit */
    double step_residual[2]; /* one-step training residual |X' - U_r K' U_r^T X|_F / |X'|_F over the
                              * (scaled) pairs: [0] of the Galerkin fit (Eq. 13), [1] as returned */
    int displacement_only; /* fitted with rk_koopman_options.displacement_only */
} rk_koopman;

/* Fits the operator to ntraj trajectories of d values per frame, jointly. Fails with a message
 * on rank above the data's numerical rank (the singular values above its rounding noise, fit.c),
 * non-finite data, or a trajectory too short. */
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
/* z = U_r^T X for X = [u; beta (u - u_prev)]. */
void rk_koopman_lift(const rk_koopman *k, const double *u, const double *u_prev, double *z);
/* u from z: the first d rows of U_r z. */
void rk_koopman_positions(const rk_koopman *k, const double *z, double *u);
/* u - u_prev from z: the last d rows of U_r z over beta (in metres per data step h). */
void rk_koopman_velocities(const rk_koopman *k, const double *z, double *v);
/* z <- K'^n z through the real blocks: cost O(r^2), whatever n (n >= 0). dt_scale rescales the
 * time step (h' = dt_scale h, Eq. 21) and damping multiplies every |lambda| by (1 - damping)
 * (Sec. 7.2); 1 and 0 leave the operator as fitted. */
void rk_koopman_advance(const rk_koopman *k, double *z, long long n, double dt_scale, double damping);
/* An external push during one step as an impulse on the velocity part, [0; a h^2] (Eq. 19), added
 * to z (as U_r^T [0; beta a h^2]); a is the acceleration it causes (force over mass, m/s^2), so
 * a h^2 is a displacement. */
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

/* precompute/koopman, control: the inputs that drive a fitted Koopman model to a goal after N
 * steps, by fast time stepping (koopman-dmd-log-linear paper, Sec. 7.3, Eq. 25).
 *
 * With the impulse convention of Eq. 19 (the push is added before each propagation), a constant
 * acceleration a held for N steps from z0 gives
 *
 *   z_N = K'^N z0 + sum_{t=1}^N K'^t g(a),    g(a) = U_r^T [0; beta P_in a h^2],
 *
 * and sum_{t=1}^N K'^t = W S_N W^-1 with S_N = sum_{t=1}^N B^t, which has a closed form on each
 * real block and complex pair (the "time-integrated propagator" of Eq. 25). With a = a_g + A C
 * (a_g gravity, A the k input acceleration fields as columns) z_N is affine in C, so C follows
 * from a least-squares fit of selected final values to goals; A may depend on the final state,
 * so it is re-evaluated from the latest prediction and the fit repeated (Sec. 7.3: 5 times). */


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

/* The rollout of k from trajectory t's start (u_{-1}, u_0) under its acceleration, one forced step
 * (Eq. 19) at a time, against t (n values per frame): 100 sum_s |u_s - u_t,s|^2 / sum_s |u_t,s|^2
 * over every frame after the start (the Koopman paper's % MSE) in *pct, and the largest per-frame
 * |u - u_t| / max_s |u_t,s| in *peak. Fails when either is not finite. */
int rk_koopman_rollout_error(const rk_koopman *k, const rk_koopman_trajectory *t, double *pct, double *peak,
                             rk_error *err);
/* The same, and the rollout's frames as positions X + u against the trajectory's X + u_t in e
 * (util's rk_run_error, started here over the n / 3 points of rest positions X): its relative error
 * and normalized MSE at every vertex, as romkit run --reference measures at the shown ones. */
int rk_koopman_rollout_run_error(const rk_koopman *k, const rk_koopman_trajectory *t, const double *X, rk_run_error *e,
                                 double *pct, double *peak, rk_error *err);

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
    double regularize;               /* rho >= 0: adds lambda^2 |C|^2 to the misfit, lambda = rho times
                                      * the system's largest singular value (rk_lstsq_tikhonov); 0: none */
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
 * Lawson-Hanson NNLS (one of the non-negative minimisers when it is not unique), either with
 * regularize's Tikhonov term on C (rk_lstsq_tikhonov), predicts the
 * final frame under that C and hands it to the next evaluation of A.
 * C: k values out. residual (iterations values, or NULL): |rows C - rhs|_2 of each iteration's
 * system (the weighted misfit of the goals and velocity rows the model predicts). z_final (r, or
 * NULL): the predicted final reduced state under the returned C. */
int rk_koopman_control(const rk_koopman *k, const rk_koopman_control_problem *p, double *C, double *residual,
                       double *z_final, rk_error *err);

/* Following a target trajectory (track.c; Sec. 7.3, Figs. 14-15: the user draws a path and the
 * inputs that make the model follow it are solved for). Receding horizon on rk_koopman_control:
 * at each frame t the input C_t is the constant input that, held for H steps from the model's
 * current state, brings the chosen values to their goals at frame t + H (Eq. 25 over H steps;
 * the horizon shrinks at the end); only its first step is applied (the forced step of Eq. 19),
 * and the next frame solves again from where the model then is. */
typedef struct {
    int frames;                      /* T >= 2: goal frames; frame 0 is the start (no input acts before it) */
    int horizon;                     /* H >= 1 */
    int m;                           /* values that follow the goals */
    const int *index;                /* m value indices (0..n-1) */
    const double *goal;              /* m x T, column-major: goal[m t + i] for value index[i] at frame t */
    const double *z0;                /* r: the start, or NULL: rest */
    const double *accel;             /* n: constant acceleration (gravity, loads), or NULL */
    int inputs;                      /* k >= 1 */
    rk_koopman_input_fn input_field; /* as rk_koopman_control's; evaluated at the predicted goal frame */
    void *ctx;
    int nonnegative;
    double regularize;               /* rho, as rk_koopman_control's, each frame's solve */
    int iterations;                  /* >= 1 per frame */
} rk_koopman_track_problem;

/* C: k x (T - 1), column-major (C[k t + j]: input j during the step from frame t to t + 1).
 * u (n x T, or NULL): the model's values at every frame under those inputs. */
int rk_koopman_track(const rk_koopman *k, const rk_koopman_track_problem *p, double *C, double *u, rk_error *err);

/* Sparse to dense (markers.c; Sec. 7.5, learning from video): marker trajectories, the
 * displacements of k tracked vertices (3 values each, as optical flow on dots would give them),
 * become coordinates of a basis of the whole mesh:
 *   q_t = argmin |S Phi q - m_t|^2 + lambda^2 |W q|^2,
 * S the rows of the k vertices, W = diag(weight) (NULL: I), lambda = ridge sigma_max(S Phi W^-1)
 * (rk_lstsq_tikhonov in p = W q; ridge 0: plain least squares, rk_lstsq, weight unused). The
 * ridge trades a bias towards q = 0 for less amplified tracking noise where few markers barely
 * tell some basis directions apart; for linear modes, weight_j = omega_j / omega_1 makes the
 * penalty the elastic energy (the least strained deformation that explains the markers), which
 * keeps the low modes the motion lives in. DMD is then fitted on q (rk_koopman_fit with d = b)
 * and Phi q is the dense deformation. Phi: n3 x b, column-major; vertex: k indices; markers:
 * 3k x T, column-major (frame t's markers at 3k t, vertex by vertex); q: b x T out. Fails when
 * 3k < b (fewer equations than coordinates), a vertex is out of range, ridge is negative or a
 * weight is not positive. */
int rk_koopman_marker_coords(const double *Phi, int n3, int b, const int *vertex, int k, const double *markers, int T,
                             double ridge, const double *weight, double *q, rk_error *err);
/* The same for markers at surface points (a video's dots, romkit dmd --tracks): marker i's row of
 * the basis is the barycentric mix bary[3i..3i+2] of the rows of vertices tri[3i..3i+2]; bary NULL:
 * tri holds one vertex per marker (rk_koopman_marker_coords is this with bary NULL). */
int rk_koopman_surface_coords(const double *Phi, int n3, int b, const int *tri, const double *bary, int k,
                              const double *markers, int T, double ridge, const double *weight, double *q, rk_error *err);

/* ---- Neural, discretization-agnostic DMD (neural.c; koopman-dmd-log-linear paper, Sec. 5, Fig. 6)
 *
 * The modes are a field over the rest position and the shape code: an MLP (precompute/neural)
 * phi: R^{3+g} -> R^{6r} of [x; gamma] gives, at a point x of the object of shape gamma (g >= 0
 * values, the training codes' range normalised to [-1, 1] per component), for each of the r real
 * eigen-coordinates j the six values of
 * mode j there: its displacement part and its velocity part, the latter scaled by beta as the
 * classical fit scales it (the momentum state X_t = [u_t; beta (u_t - u_{t-1})], Eq. 18). On a
 * mesh of any resolution, the modes evaluated at its vertices form Phi (6 nv x r: rows 0..3nv-1
 * displacements, 3nv..6nv-1 scaled velocities), and the reduced coordinates of a state are its
 * least-squares projection y = Phi^* X = (Phi^T Phi)^-1 Phi^T X (Eq. 22-23: "(Phi)^* is
 * implemented through a least-squares solve"; every vertex weighs the same, no mass weighting).
 * The paper's complex modes appear in their realified form (Sec. 5.2): one real column per real
 * eigenvalue and the (Re, Im) column pair per complex pair, the eigenvalues as the blocks B of
 * the classical real form ([[a, b], [-b, a]] per pair, 1 x 1 per real one), parametrised so that
 * |lambda| < 1 holds by construction (Eq. 24):
 *   real:  lambda = tanh(s);
 *   pair:  a + ib = rho (cos theta, sin theta), rho = sigmoid(s), theta = pi sigmoid(t) in (0, pi).
 * They depend on no mesh (Sec. 5: the spectrum is the continuous operator's, meshes only
 * approximate it), only on the shape: with g = 0 (one object, several discretizations) the raw
 * parameters (s, t) are free; with g > 0 they are the output of a second MLP of gamma,
 * Lambda(gamma) (Sec. 5, "Eigenvalue Representation"), fed through the same bounded maps, so
 * |lambda| < 1 holds for every gamma. Every mesh of the family carries its own gamma.
 *
 * Training (Eq. 22-23, Fig. 6) minimises, over every mesh m and every pair of successive states
 * of its trajectories, with X^+_t = X_t + [0; beta a h^2] the forced state (Eq. 19),
 *   L = sum_m (1 / (F_m E_m)) sum_t |Phi y_t - X^+_t|^2 + |Phi B y_t - X_{t+1}|^2,  y_t = Phi^* X^+_t,
 * F_m the mesh's pairs and E_m its mean |X_{t+1}|^2 (every resolution weighs the same), Phi and B
 * those of the mesh's vertices and code, Phi(gamma_m, X_m) and Lambda(gamma_m): Eq. 22's
 * reconstruction, and Eq. 23's one-step prediction measured after lifting (Phi B y_t against
 * X_{t+1}, what a rollout is judged by). The gradient runs through the least-squares projection
 * exactly (neural.c), then through the network in reverse mode; Adam with the phased rate. Start:
 * a classical DMD (rk_koopman_fit) at rank r of one training mesh gives the block structure, the
 * first eigenvalues and beta, and the network is first regressed onto its modes at that mesh's
 * vertices (rk_mlp_train). With g > 0 that regression sees the start mesh's code; the modes
 * network is then made independent of gamma (its first layer's gamma weights folded into the
 * bias) and the eigenvalue network starts constant at the classical spectrum, so every shape
 * starts from one consistent basis and training learns how it bends with gamma. */
typedef struct {
    const double *X;                     /* 3 nv rest positions */
    int nv;
    const rk_koopman_trajectory *traj;   /* ntraj trajectories of 3 nv displacements per frame */
    int ntraj;
    const double *gamma;                 /* the shape code of this mesh (options' shape_dim values;
                                          * NULL when that is 0) */
} rk_koopman_neural_mesh;

#define RK_KOOPMAN_SHAPE_MAX 64

typedef struct {
    int rank;             /* r >= 1 */
    int hidden, depth;    /* the modes' MLP: `depth` hidden ELU layers of `hidden` units (64, 3) */
    int init_mesh;        /* the mesh whose classical fit starts the training (-1, default: the last) */
    int pretrain_epochs;  /* the regression onto those classical modes (default 300) */
    int epochs;           /* full-batch Adam steps on L (default 400) */
    double base_lr;       /* rk_lr_phased's base for those steps (default 2e-4) */
    int polish;           /* then L-BFGS iterations on the same full-batch L (rk_lbfgs_minimize, memory
                           * 10; default 0): where Adam's rate-limited steps stall, a quasi-Newton
                           * method on the exact gradient goes on down (beyond the paper) */
    double h;             /* the data's time step (s) */
    unsigned long long seed;
    int window;           /* K >= 1: the step term rolls out K forced steps from each projected state,
                           * (1/K) sum_k |Phi a_k - X_{t+k}|^2 with a_1 = B y_t, a_{k+1} = B (a_k + Phi^* F)
                           * (Eq. 19); 1 (default) is Eq. 23 itself, more is beyond the paper */
    int shape_dim;        /* g, 0 .. RK_KOOPMAN_SHAPE_MAX: the shape code's values (0, default: none) */
    int eig_hidden, eig_depth; /* with g > 0 the eigenvalue MLP gamma -> r: `eig_depth` hidden ELU layers
                           * of `eig_hidden` units (32, 2); it starts constant at the classical
                           * start's spectrum (output weights zero) */
    int vertices;         /* the most vertices of one mesh the training sees (default 4096; 0: all):
                           * a mesh with more trains on a fixed uniform sample of that many
                           * (rk_koopman_neural_sample), so a step costs O(vertices) whatever the
                           * resolution; the classical start too. Meshes at or under it: all, as before */
} rk_koopman_neural_options;

void rk_koopman_neural_default_options(rk_koopman_neural_options *o);

typedef struct {
    int r, window;        /* window: the training's K (options) */
    int g;                /* the shape code's values */
    double h, vscale;     /* beta */
    int *block;           /* r: 1 real, 2 first of a pair, 0 its second (as rk_koopman's) */
    double *eig;          /* r raw parameters: s for a real block; (s, t) for a pair (g = 0; with
                           * g > 0 the classical start's, which the eigenvalue network starts at) */
    rk_mlp net;           /* 3 + g -> 6 r: output 6 j + c is mode j's component c (0-2 u, 3-5 beta v) */
    rk_mlp eignet;        /* g > 0: g -> r raw parameters at gamma */
    double center[3], scale; /* network input (x - center) / scale */
    double *gamma_lo, *gamma_hi; /* g > 0: the training codes' range per component; the inputs
                           * see gamma as (gamma - mid) / half of it */
} rk_koopman_neural;

typedef struct {
    double pretrained_loss, final_loss; /* L after the regression onto the classical modes, after training */
    double adam_loss;     /* L after the Adam steps (before the L-BFGS polish; final_loss without one) */
    int polish_iterations; /* L-BFGS steps taken */
    double seconds;
} rk_koopman_neural_report;

/* The trained model as a file (neural_io.c: versioned binary with a CRC-32), written atomically
 * with its training report (rep may be NULL), and read back with every count and value checked;
 * the model read is the one written, bit for bit, and its report the one saved. */
int rk_koopman_neural_write(const rk_koopman_neural *nk, const rk_koopman_neural_report *rep, const char *path,
                            rk_error *err);
int rk_koopman_neural_read(const char *path, rk_koopman_neural *nk, rk_koopman_neural_report *rep, rk_error *err);

/* Trains on nmesh meshes (each >= 1 trajectory). Deterministic for the options' seed. */
int rk_koopman_neural_train(const rk_koopman_neural_mesh *mesh, int nmesh, const rk_koopman_neural_options *o,
                            rk_koopman_neural *out, rk_koopman_neural_report *report, rk_error *err);
void rk_koopman_neural_free(rk_koopman_neural *nk);
/* The eigenvalues' trainable parameters: nk->eig (count r) with g = 0, the eigenvalue network's
 * params (rk_mlp_params(&nk->eignet)) with g > 0. */
double *rk_koopman_neural_eig_params(rk_koopman_neural *nk, long *count);
/* L (above) of a trained or partly trained model on the meshes given, and when grad_net is not
 * NULL its gradient: grad_net (rk_mlp_params(&nk->net) values, overwritten) and grad_eig (the
 * count rk_koopman_neural_eig_params gives, overwritten). */
int rk_koopman_neural_loss(rk_koopman_neural *nk, const rk_koopman_neural_mesh *mesh, int nmesh, double *grad_net,
                           double *grad_eig, double *loss, rk_error *err);
/* Eigenvalues at shape code gamma (g values; NULL when g = 0), r each, as rk_koopman's lambda_re /
 * lambda_im (a pair: +b at its first, -b at its second). */
int rk_koopman_neural_eigenvalues(const rk_koopman_neural *nk, const double *gamma, double *re, double *im,
                                  rk_error *err);
/* A training mesh restricted to `count` of its vertices (all when count <= 0 or >= nv), drawn
 * uniformly without replacement from the seed and kept in the mesh's order (neural_sample.c): mesh
 * is the sampled mesh (X and every trajectory's frames and accel at those vertices, its gamma the
 * original's), index the original vertex of each. Memory: 3 count (frames + 2) doubles per
 * trajectory. */
typedef struct {
    rk_koopman_neural_mesh mesh;
    int *index;
    double *X;
    rk_koopman_trajectory *traj;
} rk_koopman_neural_sample;
int rk_koopman_neural_sample_init(const rk_koopman_neural_mesh *m, int count, unsigned long long seed,
                                  rk_koopman_neural_sample *s, rk_error *err);
void rk_koopman_neural_sample_free(rk_koopman_neural_sample *s);
/* Phi (6 nv x r, column-major) at rest positions X (3 nv) of shape gamma (as above); the network
 * runs over blocks of RK_KOOPMAN_NEURAL_BLOCK vertices, so its workspace does not grow with nv. */
#define RK_KOOPMAN_NEURAL_BLOCK 4096
int rk_koopman_neural_modes(const rk_koopman_neural *nk, const double *X, int nv, const double *gamma, double *Phi,
                            rk_error *err);
/* The model on one mesh of shape gamma (g values; NULL when g = 0; any finite code, outside the
 * training range too) as a classical operator: Phi = Phi(gamma, X) = Q R (thin QR), U_r = Q,
 * W = R, W^-1 = R^-1, the blocks as trained and the eigenvalues Lambda(gamma), so that
 * rk_koopman_lift gives z = Q^T X and W^-1 z = Phi^* X, the least-squares coordinates; every
 * rk_koopman function (rollouts, jumps, real form) and the asset bake (rk_asset_bake_koopman)
 * then work on it unchanged. */
int rk_koopman_neural_operator(const rk_koopman_neural *nk, const double *X, int nv, const double *gamma,
                               rk_koopman *out, rk_error *err);

/* Shape optimisation through the Koopman jump (shape_opt.c; Sec. 7.4, Fig. 16): find the shape
 * code gamma, inside the training range of a model trained with g >= 1, for which one value of the
 * final frame after N steps from rest reaches a target. For each gamma the caller's `shape`
 * gives the mesh of that shape; the objective is its position
 *   f(gamma) = X[index] + u_N[index],  u_N from z_N = K'(gamma)^N 0 + sum_{t=1}^N K'(gamma)^t g(a)
 * (rk_koopman_forced on rk_koopman_neural_operator's form: Eq. 19's impulses, the closed form of
 * Eq. 25, O(r^2) whatever N). The gradient of f is by central differences with the paper's step
 * (eps = 1e-4, Sec. 7.4) on each component, taken in units of the component's training
 * half-range; the iteration is Gauss-Newton on the residual f - target (for g = 1 Newton's method
 * on f(gamma) = target) with the step halved until |f - target| decreases and gamma clamped to the
 * training range. The paper runs gradient descent (rate 0.025, 150 steps) on a loss it maximises;
 * a target on one value has a root, which Newton finds in a few steps.
 *
 * The lift objective (Fig. 16's frog, a finger's tip): with a region (nregion vertices) the
 * objective is instead the mean displacement along `axis` of the region's vertices at step N,
 *   f(gamma) = (1 / |R|) sum_{v in R} u_N[3 v + axis],
 * and rk_koopman_shape_maximize raises it (below). */
typedef struct {
    const double *X;      /* 3 nv rest positions of the shape; valid until the next call */
    int nv;
    const double *accel;  /* 3 nv: the constant acceleration (gravity, loads), or NULL */
    int index;            /* 0 .. 3 nv - 1: the value whose final position is the objective */
    const int *region;    /* nregion > 0: the lift objective over these vertices (index unused) */
    int nregion, axis;
} rk_koopman_shape;

/* Fills s for shape code gamma (g values); returns non-zero (with err set) to stop. */
typedef int (*rk_koopman_shape_fn)(void *ctx, const double *gamma, rk_koopman_shape *s, rk_error *err);

typedef struct {
    const rk_koopman_neural *nk; /* g >= 1 */
    rk_koopman_shape_fn shape;
    void *ctx;
    long long steps;      /* N >= 1: the objective's time N h after the start at rest */
    double target;        /* the position f should reach (m) */
    double tolerance;     /* > 0: stop when |f - target| <= tolerance (m) */
    double epsilon;       /* > 0: the central difference's step (default 1e-4, the paper's) */
    int max_iterations;   /* >= 1 (default 50) */
    const double *fd_step; /* g values > 0: the central difference's steps in gamma's own units
                           * instead (NULL: epsilon times each half-range). A family whose mesh is
                           * piecewise constant in the code (remeshed, or keys moved in whole cells)
                           * needs steps that reach across one of its mesh's changes, or the
                           * difference sees the network's code input alone. Either way a
                           * difference that would leave the training range is taken one-sided. */
} rk_koopman_shape_problem;

/* tolerance 1e-5 m, epsilon 1e-4, max_iterations 50; nk, shape, steps and target must be set. */
void rk_koopman_shape_default(rk_koopman_shape_problem *p);

#define RK_KOOPMAN_SHAPE_HISTORY 201
typedef struct {
    int iterations;       /* Gauss-Newton (or ascent) steps taken */
    int evaluations;      /* objective evaluations (operators built and jumped) */
    double value;         /* f at the returned gamma */
    double seconds;
    double history[RK_KOOPMAN_SHAPE_HISTORY]; /* rk_koopman_shape_maximize: f at the start, then
                                                 after each iteration (iterations + 1 values) */
} rk_koopman_shape_report;

/* f(gamma) (above) for one code. Fails on a non-finite gamma or objective, naming them. */
int rk_koopman_shape_objective(const rk_koopman_shape_problem *p, const double *gamma, double *value, rk_error *err);
/* gamma (g values): the start in, the optimum out. Fails with a message on bad input (a start
 * that is not finite or outside the training range, naming the component; a non-finite target;
 * bad settings), a non-finite objective (naming gamma), or no convergence within max_iterations
 * (gamma then holds the best code found and report its value). report may be NULL. */
int rk_koopman_shape_optimize(const rk_koopman_shape_problem *p, double *gamma, rk_koopman_shape_report *report,
                              rk_error *err);
/* Maximises f (the lift objective, or any f above) over the training range: projected gradient
 * ascent as the paper's (Sec. 7.4: central differences with eps = 1e-4, in units of each
 * component's half-range), but with the step chosen by backtracking instead of its fixed rate
 * 0.025: each iteration tries a step of length `step` (in those units, initially half the range,
 * so that a mesh piecewise constant in the code changes) along the gradient, projected onto the
 * range, halving it until f rises (Armijo: by at
 * least 1e-4 of the gradient's prediction), and doubling it after a success. It stops when no
 * projected step of 1e-6 half-ranges or more raises f (a corner of the range, or a maximum), or after
 * max_iterations (at most RK_KOOPMAN_SHAPE_HISTORY - 1). target is unused. gamma: the start in,
 * the best code out; report (may be NULL) its value and the history. */
int rk_koopman_shape_maximize(const rk_koopman_shape_problem *p, double *gamma, rk_koopman_shape_report *report,
                              rk_error *err);

/* Dense solvers (lstsq.c); A is m x n, column-major, left unchanged.
 * x = the minimum-norm least-squares solution of A x ~ b (dgelsd, relative singular value cut 1e-12). */
int rk_lstsq(int m, int n, const double *A, const double *b, double *x, rk_error *err);
/* x = argmin |A x - b|_2 subject to x >= 0 (the cubature stage's Lawson-Hanson, on A^T A). */
int rk_nnls(int m, int n, const double *A, const double *b, double *x, rk_error *err);
/* Tikhonov-regularised: x = argmin |A x - b|^2 + lambda^2 |x|^2 (x >= 0 too when nonnegative), with
 * lambda = rho sigma_max(A), so that rho is relative (free of the units of x and b): a direction
 * of x that A moves by a singular value s is shrunk by s^2 / (s^2 + lambda^2), so rho << 1 leaves
 * the well-determined directions alone and keeps the nearly unobservable ones near zero. Solved
 * as [A; lambda I] x ~ [b; 0] by rk_lstsq or rk_nnls; rho = 0 is exactly those. lambda: out, or
 * NULL. Why |x| and not |x - x_prev| for the tracking loop: an input the model barely sees is then
 * pulled to zero at every frame instead of left wherever earlier frames' model error pushed it
 * (measured with |C - C_prev| on cli_control.sh's beams: the axial input still drifts, and the
 * 10x softer beam diverges at rho 0.1-3 where |C| keeps it bounded). */
int rk_lstsq_tikhonov(int m, int n, const double *A, const double *b, double rho, int nonnegative, double *x,
                      double *lambda, rk_error *err);

#endif
