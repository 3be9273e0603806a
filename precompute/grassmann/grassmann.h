/* precompute/grassmann: the adaptive linear ROM (the adaptive-linear-rom-grassmann paper): a
 * linear ROM in incremental form whose basis follows the state,
 *
 *   p = e(u(t-1))                       encoder (Eq. 7)
 *   U = dg/dp (p)                       the decoder's Jacobian at the vertices (Eq. 8)
 *   Phi = D P^T (P P^T + 1e-8 I)^-1     the history basis of the last m steps (Eq. 13)
 *   U_interp = Grassmann(Phi, U, lambda) (Algorithm 4)
 *   u(t) = u(t-1) + U_interp q,  q minimising the incremental potential (Eq. 5-6, 9-12)
 *
 * on the full-order step's own potential (fom.h: the same contact, integrators and prescribed
 * motion), Newton on q with the reduced gradient U^T g and Hessian U^T H U: exactly (every
 * element's PSD-projected Hessian), or with the elastic part by a cubature (options: the elements
 * and weights a fixed basis trained; inertia, damping, loads and contact stay exact).
 *
 * A decoder is an interface: a quadratic manifold g(p) = Phi p + 1/2 sum_ij Psi_ij p_i p_j from
 * linear modes and modal derivatives (no training, rk_quadratic_decoder), or a CROM network. */
#ifndef RK_GRASSMANN_H
#define RK_GRASSMANN_H

#include "fem/fem.h"
#include "fom/fom.h"
#include "util/util.h"

/* ---- Grassmann interpolation and the history basis (interpolate.c, history.c) ---- */

/* Algorithm 4: the point at lambda on the Grassmann geodesic from span(Phi) (lambda = 0) to
 * span(U) (lambda = 1), n x r column-major each, as an orthonormal basis out (n x r). Fails when
 * either has rank below r (naming which) or the two spans are orthogonal somewhere (a principal
 * angle of pi/2: no unique geodesic). */
int rk_grassmann_interpolate(int n, int r, const double *Phi, const double *U, double lambda, double *out,
                             rk_error *err);
/* The principal angles (radians, ascending) between span(A) and span(B), n x r each. */
int rk_principal_angles(int n, int r, const double *A, const double *B, double *theta, rk_error *err);

/* Eq. 13: Phi = D P^T (P P^T + reg I)^-1 for displacements D (n x m) and latent codes P (r x m),
 * both column-major; reg = 1e-8 in the paper. With ridge > 0 (issue 33, history.c) the ridge
 * regression toward the decoder's basis U (n x r): Phi = (D P^T + rho U)(P P^T + (rho + reg) I)^-1,
 * rho = ridge tr(P P^T); U is not read when ridge is 0 (the paper's). */
int rk_history_basis(int n, int r, int m, const double *D, const double *P, const double *U, double ridge, double reg,
                     double *Phi, rk_error *err);

/* ---- decoders ---- */

typedef struct {
    int n, r;         /* displacement dofs (3 nv), latent size */
    void *ctx;
    /* p = e(u) */
    int (*encode)(void *ctx, const double *u, double *p, rk_error *err);
    /* U = dg/dp at p: n x r, column-major */
    int (*jacobian)(void *ctx, const double *p, double *U, rk_error *err);
    /* u = g(p) */
    int (*decode)(void *ctx, const double *p, double *u, rk_error *err);
    void (*destroy)(void *ctx);
} rk_decoder;

/* The quadratic manifold g(p) = Phi p + 1/2 sum_ij Psi_ij p_i p_j: Phi (n x r) linear modes, Psi
 * their modal derivatives (n x r(r+1)/2, pairs i <= j row-major, rk_modal_derivatives' layout;
 * rigid modes have none: their columns are zero). The encoder minimises |g(p) - u|_M over p by
 * Gauss-Newton from the mass projection (M: the fem's mass, upper-stored). Copies what it needs. */
typedef struct rk_quadratic rk_quadratic;
int rk_quadratic_decoder(int n, int r, const double *Phi, const double *Psi, const rk_sparse *M, rk_decoder *dec,
                         rk_error *err);
/* A quadratic manifold fitted to data (no modal derivatives): given r mass-orthonormal columns V
 * (n x r, a POD basis of the frames) and T displacement frames D (n x T), Psi (n x r(r+1)/2, the
 * decoder's layout) is the ridge least-squares fit of the frames' residuals u - V p by the pairs
 * p_i p_j of their codes p = V^T M u (relative ridge 1e-6 of the pairs' largest energy). The
 * fraction of the frames' energy the linear part misses and the fit still misses, into
 * *linear_miss and *fit_miss (may be NULL). */
int rk_quadratic_fit(int n, int r, const double *V, const rk_sparse *M, const double *D, int T, double *Psi,
                     double *linear_miss, double *fit_miss, rk_error *err);
/* Frees the decoder's context (destroy) and zeroes it. */
void rk_decoder_free(rk_decoder *dec);
/* Psi (n x r(r+1)/2, the decoder's pairs) from rk_modal_derivatives' raw output (the pairs of the
 * r - nrigid non-rigid modes, i <= j row-major); the pairs of rigid modes zero. */
void rk_quadratic_pairs(int n, int r, int nrigid, const double *raw, double *Psi);

/* The CROM decoder (crom.c; Sec. 3.2): an encoder MLP e(u) (3 nv inputs, encoder_layers hidden
 * layers of encoder_width, r outputs) and a decoder MLP g(p, X) (r + 3 inputs, decoder_layers x
 * decoder_width, 3 outputs), ELU, trained jointly on T displacement snapshots D (3 nv x T,
 * column-major) at rest positions X: each step snapshots_per_batch snapshots, each at `points`
 * random vertices, Adam at rk_lr_phased(base_lr) (neural.h), MSE. The paper's sizes are 2 x 128 and
 * 8 x 128; the defaults here, 2 x 128 and 4 x 64, keep a bench object's training within minutes on
 * 2 cores. Deterministic for a seed. Fails on T < r, a non-finite snapshot (naming it), all-zero
 * data, or a loss that diverges. */
typedef struct rk_crom rk_crom;
typedef struct {
    int encoder_width, encoder_layers, decoder_width, decoder_layers;
    int epochs, snapshots_per_batch, points;
    double base_lr;
    unsigned long long seed;
} rk_crom_options;
void rk_crom_default_options(rk_crom_options *o);
typedef struct {
    double first_loss, final_loss;   /* the first and last epoch's mean squared error (m^2 per component) */
    double seconds;
    long steps, encoder_params, decoder_params;
} rk_crom_report;
int rk_crom_train(const double *D, int T, const double *X, int nv, int r, const rk_crom_options *o, rk_decoder *out,
                  rk_crom_report *report, rk_error *err);

/* A trained CROM's parts, for the bake (borrowed from the decoder): the encoder's and decoder's
 * sizes and parameters (neural.h's layout), the displacement scale and the normalised rest
 * positions (3 nv) the decoder takes. -1 when dec is not a CROM. */
typedef struct {
    int enc_layers, dec_layers;          /* L of each */
    const int *enc_sizes, *dec_sizes;    /* L + 1 each */
    const double *enc_params, *dec_params;
    long enc_count, dec_count;
    double u_scale;
    const double *Xn;
} rk_crom_parts;
int rk_crom_parts_of(const rk_decoder *dec, rk_crom_parts *out);

/* ---- the simulator (alrom.c) ---- */

typedef struct {
    int history;       /* m: the steps the history basis spans (20) */
    double lambda;     /* the interpolation parameter (0.2): 1 is the decoder's basis alone */
    double reg;        /* P P^T's regularisation (1e-8) */
    double ridge;      /* the history basis' ridge toward the decoder's basis, times tr(P P^T)
                        * (history.c; 0: the paper's Eq. 13, which amplifies errors) */
    double budget;     /* what the history may add to a step's growth factor: the ridge is at
                        * least h |v| / (budget |u|) (alrom.c; 0: no such bound) */
    int cadence;       /* K: the basis (encoder, history entry, Grassmann point) formed every K steps
                        * and held between, a linear ROM's step there (1: every step, the paper's) */
    int encoder_iterations; /* the runtime encoder's Gauss-Newton iterations at most (20; the asset's
                             * ALRH: the precompute's decoder keeps its own 20) */
    /* the elastic energy by a cubature (An et al. 2008) instead of every element: ncub elements
     * with weights (multiplying each element's energy); 0: every element. Borrowed. */
    int ncub;
    const int *cub_element;
    const double *cub_weight;
} rk_alrom_options;
void rk_alrom_default_options(rk_alrom_options *o);

typedef struct {
    long steps, newton_iterations, history_used; /* steps whose basis blended the history */
    double seconds_total, seconds_basis;         /* the basis (encoder, Jacobian, history, Grassmann) */
} rk_alrom_stats;

typedef struct rk_alrom_impl rk_alrom_impl;

typedef struct {
    rk_fom fom;            /* the state: fom.x = X + u */
    rk_alrom_options opt;
    rk_alrom_stats stats;
    rk_alrom_impl *impl;
} rk_alrom;

/* dec is borrowed (it must outlive the simulator). Fails on bad options (history < 1, lambda
 * outside [0, 1]) naming the key, and on a decoder of the wrong size. */
int rk_alrom_init(rk_alrom *s, const rk_fem *fem, const rk_fom_options *fo, const rk_decoder *dec,
                  const rk_alrom_options *o, rk_error *err);
int rk_alrom_step(rk_alrom *s, rk_error *err);
/* The online-error realignment: the state put back to (x, v) at t (BDF2 history as
 * rk_fom_set_state); the basis history records it as the step's state. */
void rk_alrom_set_state(rk_alrom *s, const double *x, const double *v, const double *x_prev, const double *v_prev,
                        double t);
/* dst takes src's state: positions, velocities, time and the basis history (both made on the same
 * fem, options and decoder; backward Euler: BDF2's previous step is not carried). For measuring
 * what one step does to a perturbation (the growth test, bench_alrom_step_growth). */
void rk_alrom_copy_state(rk_alrom *dst, const rk_alrom *src);
void rk_alrom_free(rk_alrom *s);
/* The basis of the last step taken (U_interp: n x r, orthonormal columns, zero on the prescribed
 * dofs), NULL before the first; for diagnostics (bench_alrom_freerun). Borrowed. */
const double *rk_alrom_step_basis(const rk_alrom *s);
/* One step of A, and what it does to a perturbation (growth.c): pre and probe are simulators on
 * the same fem, options and decoder (scratch; their state is overwritten). The largest ratio of
 * |(du', dv')| to |(du, dv)| after one step over ndir directions of a power iteration from a
 * random one (seed), in the energy norm dv^T M dv + du^T K du (M mass, K rest stiffness, both
 * upper-stored), the perturbation eps times the state's own norm. */
int rk_alrom_step_growth(rk_alrom *A, rk_alrom *pre, rk_alrom *probe, const rk_sparse *M, const rk_sparse *K, int ndir,
                         double eps, uint64_t *seed, double *growth, rk_error *err);

#endif
