/* precompute/cubature: the reduced elastic energy, integrated exactly (every element) or by a
 * cubature (a few weighted elements), and the training that picks the cubature.
 *
 * In a subspace x = X + U q the deformation gradient of every P1 tet (and of every RKPM
 * integration sample under linear blend skinning) is affine in q: F_i = I + G_i q, with G_i a
 * 9 x r matrix fixed at precompute time. The reduced energy is then a weighted sum over points,
 *
 *   E(q) = sum_i w_i Psi_i(I + G_i q),  f(q) = -sum_i w_i G_i^T P_i,  K(q) = sum_i w_i G_i^T dP/dF_i G_i,
 *
 * exact when the points are all the elements with w_i their rest volumes, and approximate (An et
 * al. 2008, "Optimizing cubature for efficient integration of subspace deformations") when they
 * are a few elements with trained non-negative weights. Neither costs anything per vertex. */
#ifndef RK_CUBATURE_H
#define RK_CUBATURE_H

#include "fem/fem.h"
#include "util/util.h"

/* ==== choosing cubature points and non-negative weights (nnls.c, greedy.c) ====
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
    unsigned long long seed;   /* the subset draws (rk_splitmix64, util/util.h):
                                  same seed, same result */
    int prune;                 /* after reaching the tolerance, drop points while the rest, re-fitted,
                                  still meets it (greedy.c) */
    /* Optional (both or neither): what a candidate costs beside those selected, >= 1; the score
     * is divided by it. cost_begin(ctx, selected indices, count) before each pick's scoring. */
    void (*cost_begin)(void *ctx, const int *selected, int count);
    double (*cost)(void *ctx, int candidate);
} rk_cubature_problem;

typedef struct {
    int count;                 /* selected points */
    int *index;                /* count candidate indices, ascending */
    double *weight;            /* count weights, all > 0 */
    double relative_error;     /* |A_S w - b| / |b| at the end, computed from the columns */
    int reached;               /* 1 when relative_error <= tolerance */
    int iterations;            /* greedy iterations (picks re-fitted, a final undone one included) */
    int greedy_count;          /* points the greedy selection ended with, before any pruning */
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

/* ==== quadrature and the cubature trainer ==== */

typedef struct {
    int r;                     /* reduced coordinates */
    int count;                 /* points */
    double *G;                 /* count blocks of 9 x r, row-major: row 3a+b of block i is dF_ab/dq */
    double *weight;            /* count: rest volume (m^3) times the cubature weight */
    rk_material_model *model;  /* count */
    double *mu, *lambda;       /* count, Lame parameters */
    int *source;               /* count: the element (or integration sample) each point is */
    double *scratch;           /* F, P (9 count each) and w dP/dF G (9 r count) */
    int skin_H;                /* rk_quadrature_points: G is skinning-structured over this many handles,
                                * and N (count x 3 x 4H: row b of point i's N[(j, c), b]) holds its
                                * non-zeros, so the Hessian costs a fifth (quadrature.c); 0 otherwise */
    double *N;
    double *skin_scratch;      /* with skin_H: 81 count (each point's dP/dF) + (4H)^2 (one Hessian block) */
    /* The projected volume (rk_quadrature_volume; vol_k = 0: every point's own, Psi(F_i)): count x
     * vol_k reduced pressure functions Phi (row-major), and the evaluation's scratch. */
    int vol_k;
    double *vol_phi;
    double *vol_scratch;
} rk_quadrature;

/* Mesh-free integration points under a linear-blend-skinning basis (freeform paper Eq. 21-22):
 * H weights W_j with their gradients at each point. With q holding each handle's affine map
 * row by row (column 12 j + 4 a + c, as rk_skinning_to_U), u(X) = sum_j W_j(X) A_j (X, 1) and
 *
 *   dF_ab/dA_j[a][c] = X̄_c dW_j/dX_b + W_j delta_cb   (X̄ = (X, 1), delta_3b = 0),
 *
 * so G_i has 4 H non-zeros per row and no element is involved: a point cloud integrates its own
 * elastic energy, E = sum_i v_i Psi(F(X_i)) (Eq. 22). */
typedef struct {
    int n, H;
    double *X;                 /* 3n */
    double *W;                 /* n x H, column-major */
    double *dW;                /* 3n x H, column-major: dW[3 i + b + 3 n j] = dW_j/dX_b at point i */
    double *volume;            /* n integration weights (m^3) */
    double *density;           /* n (kg/m^3): the mass the points carry, rho_i v_i */
    rk_material_model *model;  /* n */
    double *mu, *lambda;       /* n */
} rk_skin_points;

void rk_skin_points_free(rk_skin_points *P);
/* Row 3a + b (columns 0..r-1, r = 12 H) of G at point i into G (9 x r, row-major). */
void rk_skin_points_G(const rk_skin_points *P, int i, double *G);

/* The points `index` (NULL: all n, in order) of P, each weighted by its volume times weights[k]
 * (NULL: 1): as rk_quadrature_elements, with source[k] the point's index in P. */
int rk_quadrature_points(const rk_skin_points *P, int count, const int *index, const double *weights,
                         rk_quadrature *Q, rk_error *err);

/* The points of `count` elements of f (elements NULL: all nt, in order) in the subspace U (3 nv x r,
 * column-major), each weighted by its rest volume times weights[k] (NULL: 1). */
int rk_quadrature_elements(const rk_fem *f, const double *U, int r, int count, const int *elements,
                           const double *weights, rk_quadrature *Q, rk_error *err);
void rk_quadrature_free(rk_quadrature *Q);
/* The arrays of a quadrature of count points in r columns, zeroed, for its constructors
 * (rk_quadrature_elements, rk_quadrature_points); skin_H > 0 adds the skinning structure's (N and
 * its scratch). On failure Q is empty and err names `what` (e.g. "integration points"). */
int rk_quadrature_alloc(rk_quadrature *Q, int r, int count, int skin_H, const char *what, rk_error *err);

/* Elastic energy at q; with g, adds its gradient; with H (r x r, column-major), adds its Hessian
 * (each point's dP/dF projected to PSD when project != 0, like the full-order model). Returns
 * +INFINITY when a value is not finite. Uses Q->scratch, so one call at a time per Q. */
double rk_quadrature_eval(rk_quadrature *Q, const double *q, double *g, double *H, int project);

/* ==== the projected volume (volume.c) ====
 * Volumetric locking: a subspace whose F_i cannot keep theta_i = 0 (J - 1, or tr eps) at every
 * point while it bends pays lambda/2 theta_i^2 at each, and lambda >> mu makes it stiff. The mixed
 * u-p formulation statically condensed (B-bar / F-bar: Hughes 1980; de Souza Neto et al. 1996;
 * for reproducing-kernel particles Chen, Yoon, Wang & Liu 2000, CMAME 181, Sec. 3) evaluates the
 * lambda part on the L2 projection of theta onto a small pressure space psi (k functions):
 *
 *   theta_bar = Psi G^-1 Psi^T W theta,  G = Psi^T W Psi,  W = diag(w_i),
 *   E = sum_i w_i Psi(mu, 0; F_i) + sum_i w_i lambda_i / 2 theta_bar_i^2      (physics.h's split)
 *     = sum_i w_i Psi(mu, 0; F_i) + 1/2 |Phi^T W theta|^2,
 *
 * with Phi Phi^T = Psi S Psi^T, S = G^+ (Psi^T W Lambda Psi) G^+ (PSD; G^+ the pseudo-inverse,
 * so a pressure function the points cannot tell apart from the others adds nothing). Then with
 * c = Phi^T W theta and the projected pressure p_i = Phi_i . c:
 *   dE/dq  = sum_i w_i G_i^T (P(mu, 0; F_i) + p_i dtheta_i/dF),
 *   d2E/dq2 = sum_i w_i G_i^T (dP/dF(mu, 0) + p_i d2theta/dF2)_i G_i + C^T C,
 *   C = Phi^T W T,  row i of T = (G_i^T dtheta_i)^T:
 * the point terms have rk_dpdf_p's form, the coupling is rank k. lambda = 0 everywhere leaves S = 0
 * and the quadrature pointwise (vol_k = 0): nothing changes. */
/* Sets Q's pressure space: psi (count x k, row-major) its k functions at the points. Fails on
 * non-finite values or allocation. */
int rk_quadrature_volume(rk_quadrature *Q, int k, const double *psi, rk_error *err);
/* The evaluation's pieces (quadrature.c): 1/2 |c|^2 at the points' F (9 count), leaving each
 * point's dtheta/dF and pressure p_i in the scratch (rk_quadrature_volume_pressure); and H += C^T C. */
double rk_quadrature_volume_energy(rk_quadrature *Q, const double *F);
const double *rk_quadrature_volume_pressure(const rk_quadrature *Q, const double **dtheta);
void rk_quadrature_volume_hessian(rk_quadrature *Q, double *H);

/* One point's reduced internal force contribution -w_i G_i^T P_i(I + G_i q) is
 * rk_quadrature_point_force(Q, i, F, out) with F = I + G_i q precomputed: out (r) = w_i G_i^T P. */
void rk_quadrature_point_force(const rk_quadrature *Q, int i, const double F[9], double *out);
/* F (9) of point i at q. */
void rk_quadrature_point_F(const rk_quadrature *Q, int i, const double *q, double F[9]);

typedef struct {
    double tolerance;     /* relative force error over the training poses (default 0.01) */
    int max_points;       /* 0: no limit but the element count */
    int poses;            /* training poses (default 100): up to half from snapshots, the rest random */
    int sample;           /* candidates scored per greedy iteration (default 1000; 0: all) */
    double amplitude;     /* RMS displacement (m) of the random poses; 0: the largest snapshot's */
    unsigned long long seed;
    int prune;            /* drop points the tolerance does without (greedy.c; default 0) */
    double vertex_cost;   /* rk_cubature_train_moving only: what a vertex the selection does not use
                           * yet costs against an element (default 8; 0: elements alone), moving.c */
} rk_cubature_options;

void rk_cubature_default_options(rk_cubature_options *o);

/* Trains a cubature for the exact quadrature `exact` (all elements, rk_quadrature_elements with
 * weights NULL): poses from the reduced snapshots (r x nsnapshots, column-major; may be 0) and
 * random ones (An et al. 2008, Sec. 3), the exact reduced forces there as targets, then greedy
 * NNLS selection (above) until the relative force error is under o->tolerance. Mr = U^T M U and
 * the total mass measure pose sizes. out->index are element numbers and out->weight multiply
 * their rest volumes (rk_quadrature_elements takes both as they are). Not reaching the
 * tolerance within max_points is not an error: out->reached = 0. */
int rk_cubature_train(rk_quadrature *exact, const double *Mr, double mass, const double *snapshots,
                      int nsnapshots, const rk_cubature_options *o, rk_cubature_set *out, int *poses_used,
                      rk_error *err);

/* ==== a cubature for a moving basis (moving.c; issue 33) ====
 * The adaptive linear ROM integrates each step's forces in the basis that step forms. Pose t
 * (0 <= t < poses) gives a displacement u (3 nv) and its own basis U (3 nv x r, column-major,
 * zero on the rows the method holds); the training columns are each element's U_t^T f_e(u_t),
 * every pose's block divided by the norm of its exact total (An et al. Eq. 5), and the greedy NNLS
 * above picks elements to o->tolerance (o->poses, o->amplitude: unused; the poses are the caller's),
 * each candidate's score divided by 1 + o->vertex_cost x (its vertices no selected element has) / 4.
 * Every fourth pose (t % 4 == 3) is held out of the fit, and the weights' relative force error
 * over those is measured. out->index are element numbers, out->weight multiply their rest
 * volumes. Poses whose exact force vanishes (rest) are dropped. Fails on bad input, a non-finite
 * force (naming the pose and element), the callback's failure, or allocation. */
typedef struct {
    int poses;
    int (*pose)(void *ctx, int t, double *u, double *U, rk_error *err);
    void *ctx;
} rk_moving_poses;

typedef struct {
    int poses, heldout_poses;     /* those kept (nonzero force) in the fit, and held out */
    double train_error;           /* |A_S w - b| / |b| over the fitted poses */
    double heldout_error;         /* the same over the held-out ones (NaN when there are none) */
} rk_moving_fit;

int rk_cubature_train_moving(const rk_fem *f, int r, const rk_moving_poses *P, const rk_cubature_options *o,
                             rk_cubature_set *out, rk_moving_fit *fit, rk_error *err);

#endif
