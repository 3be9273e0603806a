/* precompute/adaptive: adaptive subspace simulation with an oracle and nodal enrichment (the
 * adaptive-subspace paper, Trusty et al.). A full-order-quality simulator: the full positions x
 * are the state (Sec. 3.2), and each time step's minimisation of the incremental potential (the
 * full-order simulator's own, fom.h: the same contact, friction lagging, prescribed motion and
 * integrators) is solved in a running reduced model that the oracle updates inside the Newton
 * iterations:
 *
 *   x <- x + alpha (B_a d_q + S_x d_x)     B_a: the active columns U_a of a candidate basis U,
 *                                           masked (zero) at enriched and prescribed dofs;
 *                                           S_x: the enriched vertices' selection (Sec. 3.6)
 *
 *   error     G_i = ||g_i|| / s_i, s_i = h^2 A_i psi_i (Eq. 5, 10); modes: Eq. 12, 14, 16; by default
 *             s_i = m_i tol / (alpha h) instead (rk_adaptive_tolerance_scale: G_i <= 1 everywhere bounds
 *             the full-space residual's mass-weighted RMS by the method's own tolerance tol,
 *             rk_adaptive_own_tolerance, from the accuracy target)
 *   progress  E_i = dE_i / c_i, c_i = h^2 V_i psi_i (Eq. 7, 8, 11); modes: Eq. 13, 15, 17
 *             dE_i: the one-ring potential's decrease along the active subspace's line-searched
 *             Newton direction (Eq. 18)
 *   oracle    activates every candidate with G > eps_G and E < eps_E (Sec. 3.7); a vertex
 *             enriches its whole METIS part (Sec. 3.6)
 *   system    Eq. 19 by its Schur complement on the enriched dofs: H_q factored (dense
 *             Cholesky), block-Jacobi PCG to a relative residual (Eq. 21-22, Sec. 3.10)
 *   H_q       exact inertia, damping and contact; elasticity by one BFGS matrix per subdomain
 *             (Eq. 20), exact in subdomains that hold an enriched vertex (Sec. 3.9)
 *   downdate  after the step, modes and vertices whose displacement did not pay (Sec. 3.11)
 *   full      a step whose enrichment passes opt.full_fraction is finished by full order's Newton: not
 *             in the paper; the enriched rows cost more per vertex than full order's (docs/methods.md)
 *   residual  after each solve the full-space Newton step |d_full|_inf / h (CHOLMOD); above the
 *             method's tolerance, the parts of the vertices where it is are enriched and the step
 *             solved again (opt.residual_rounds times at most): not in the paper, whose G does not
 *             bound it (romkit's measurements, docs/methods.md)
 *
 * The paper's scaling: its potential is K + alpha h^2 (Psi + ...); romkit's solver minimises that
 * divided by alpha h^2, so the paper's gradient and energy changes are alpha h^2 times ours and
 * G_i = alpha |g_i| / (A_i psi_i), E_i = alpha dE_i / (V_i psi_i) here.
 *
 * Where the paper is silent (each said again where it is implemented):
 *  - an element belongs to the METIS part of its first vertex; a subdomain is the set of elements
 *    of one part, and its secant pair is its own elastic energy's gradient (the paper averages
 *    the gradient at interface vertices instead; both sum to the whole);
 *  - BFGS matrices start each time step (and each change of the active modes) at the exact
 *    subspace Hessians of their subdomains;
 *  - the initial blocks are never downdated, so the model always keeps its rigid motion;
 *  - the oracle's per-vertex energies split each element's energy equally among its four
 *    vertices, the consistent mass's quadratic form by rows, a contact pair's barrier equally
 *    among its mesh points; lagged friction is left out of them (it is in the system);
 *  - moving obstacles go by their progress s along the step's straight way, one more unknown
 *    pulled to 1 (the reduced simulator's, contact.h rk_obstacle_way) beside x, Eq. 19 bordered
 *    by it (obstacles.c); full order makes each obstacle vertex an unknown instead. Moving planes
 *    and static solves are refused. */
#ifndef RK_ADAPTIVE_H
#define RK_ADAPTIVE_H

#include "fem/fem.h"
#include "fom/fom.h"
#include "util/util.h"

typedef struct {
    int block;              /* columns per candidate (skinning: 12, one weight's affine handle; modes: 1) */
    int initial_blocks;     /* the first blocks of U, active from the start and never downdated (1) */
    double eps_g_modal;     /* error thresholds (1, 1): G in units of the method's tolerance
                             * (rk_adaptive_tolerance_scale), or with paper_units */
    double eps_g_nodal;
    int paper_units;        /* 1: G is the paper's dimensionless one (Eq. 5, 10; its Table 2: 0.5, 0.5) */
    double eps_e;           /* progress threshold (1: E in squared tolerances; with paper_units the
                             * paper's E, whose threshold it gives as 1e-4, Sec. 4) */
    double eps_d;           /* downdating threshold (0.1) */
    int subdomains;         /* METIS parts (0: one per 250 tets, at least 2) */
    int downdate;           /* 1: downdate after each step (Sec. 3.11) */
    int modal, nodal;       /* 1: the oracle may add modes / enrich vertices */
    int exact_hessian;      /* 1: every subdomain exact (no BFGS): the ablation and the tests' reference */
    double pcg_tol;         /* relative residual of the Schur PCG (1e-5) */
    int pcg_max_iter;       /* 10000 */
    int residual;           /* 1 (default): after each solve, the full-space Newton step at its answer,
                             * |d_full|_inf / h (m/s; CHOLMOD, one factorization): the paper's accuracy
                             * measure (Fig. 12), checked against the method's tolerance */
    int residual_rounds;    /* with residual: while |d_full|_inf / h exceeds the method's tolerance, enrich the
                             * METIS parts of the vertices where |d_full_i| / h does and solve again, at most
                             * this many times a step (8; 0: report only) */
    double accuracy;        /* the target a of the run's position error over the bounding-box diagonal (1e-3):
                             * sets the method's own tolerance (rk_adaptive_own_tolerance) that the
                             * thresholds' units, the residual check and its Newton iterations use; 0: full
                             * order's Newton tolerance instead */
    double full_fraction;   /* a step whose enrichment passes this share of the free vertices (by the oracle or
                             * the residual check) is finished by full order's own Newton (rk_fom_newton, CHOLMOD)
                             * at the method's tolerance, from where it got to (0.25; 1: never): past it the
                             * subspace's dense products and the Schur PCG cost more than full order's whole
                             * step (measured: docs/methods.md). The next steps go straight to full order,
                             * 1, 2, 4, 8 of them after each further step that passes it (0 once one does not);
                             * a step that tries the subspace after them goes to full order as soon as the
                             * oracle adds a mode or a vertex */
    int probe;              /* 1: at the next Newton iteration, also solve the full-space system at the same
                             * iterate by CHOLMOD and by block-Jacobi CG (rk_adaptive_probe; for make bench) */
} rk_adaptive_options;

/* One Newton iteration's linear solve three ways, on the same iterate (the paper's Table 3). */
typedef struct {
    int done;
    int modes, enriched_dofs, coupled_dofs;
    double schur_seconds;     /* ours: H_q's factorization, the Schur PCG and the back-substitution */
    int schur_iterations;
    long schur_nnz;           /* H_q (dense), C (dense, coupled columns) and H_x's non-zeros */
    double cholmod_seconds;   /* the full Newton matrix: numeric factorization and solve */
    double bjcg_seconds;      /* the full Newton matrix by block-Jacobi CG to the same relative residual */
    int bjcg_iterations;
    long full_nnz;            /* the full Newton matrix's non-zeros (both triangles) */
    double direction_difference; /* |d_ours - d_full|_inf / |d_full|_inf */
} rk_adaptive_probe;

void rk_adaptive_default_options(rk_adaptive_options *o);

typedef struct {
    long steps, newton_iterations, pcg_iterations, solves;
    long oracle_modes_added, oracle_nodes_added, modes_downdated, nodes_downdated;
    long bfgs_updates, bfgs_skipped;
    double sum_modes, sum_nodes;  /* active columns and enriched vertices at each step's end, summed */
    int max_modes, max_nodes;
    double seconds_total;
    double seconds_potential;     /* the full-space potential and gradient (contact included) */
    double seconds_oracle;        /* the measures, the subspace direction and its line search */
    double seconds_hessian;       /* the subspace Hessian: BFGS updates, exact subdomains, inertia */
    double seconds_system;        /* the enriched rows and the coupling */
    double seconds_pcg;           /* the Schur complement PCG (with H_q's factorization) */
    double seconds_line_search;
    double seconds_residual;      /* the full-space residual check: full order's Newton matrix and solve */
    rk_adaptive_probe probe;      /* with opt.probe */
    double residual_last, residual_max, residual_sum; /* with opt.residual: per step, |d_full|_inf / h */
    long residual_over;           /* steps that ended with it above the method's tolerance (after the rounds) */
    long steps_full;              /* steps finished by full order's Newton (opt.full_fraction) */
    long residual_rounds;         /* enrichment rounds the residual asked for, and their vertices */
    long residual_nodes_added;
    long obstacle_rounds;         /* moving obstacles: extra rounds of the method of multipliers on their pull */
    long obstacles_behind;        /* solves that left them short of where they were due (the body in the way) */
} rk_adaptive_stats;

typedef struct rk_adaptive_impl rk_adaptive_impl;

typedef struct {
    rk_fom fom;             /* the full-space state (fom.x, fom.v, fom.t) and its potential */
    rk_adaptive_options opt;
    rk_adaptive_stats stats;
    int modes;              /* active columns now */
    int nodes;              /* enriched vertices now */
    double tolerance;       /* its own tolerance on |d|_inf / h (m/s): rk_adaptive_own_tolerance */
    const char *enriched;   /* nv flags */
    rk_adaptive_impl *impl;
} rk_adaptive;

/* The simulator of fem under the full-order options fo (dynamics; no moving obstacle) with the
 * candidate basis U (3 nv x r, column-major; r a multiple of o->block; copied). Fails, naming
 * the key, on a threshold <= 0, more subdomains than vertices, a basis of the wrong shape. */
int rk_adaptive_init(rk_adaptive *a, const rk_fem *fem, const rk_fom_options *fo, const double *U, int r,
                     const rk_adaptive_options *o, rk_error *err);
int rk_adaptive_step(rk_adaptive *a, rk_error *err);
/* What the oracle did in the last step, per vertex (out: 3 nv, vertex by vertex): enriched when its
 * solve ended (0 or 1; before downdating), the nodal error G_i and progress E_i (in the thresholds'
 * units) at the oracle's last evaluation, the step's last Newton iteration (all 0 before the first
 * step; G and E 0 with opt.nodal off; NaN on a step handed to full order at once, which runs no
 * oracle). */
void rk_adaptive_fields(const rk_adaptive *a, double *out);
void rk_adaptive_free(rk_adaptive *a);

/* ---- the measures (measures.c), public for the tests ---- */

/* Per vertex: psi_bar (the rest energy density Hessian's 2-norm averaged over the vertex's
 * elements: 2 mu + 3 lambda for every model, which share the linear tangent at rest), A (the
 * area of the faces opposite the vertex in its elements: its one-ring's surface) and V (a
 * quarter of each element's volume). nv each. */
void rk_adaptive_vertex_scales(const rk_fem *f, double *psi_bar, double *area, double *volume);
/* The oracle's error scale in units of a tolerance tol (opt.paper_units 0: the method's own): s_i with
 * G_i = alpha |g_i| / s_i = alpha h |g_i| / (m_i tol), the velocity the unbalanced force g_i would give the
 * vertex's own lumped mass m_i over the step, over the tolerance tol (m/s). Why it bounds the
 * residual: romkit's Newton matrix is H = M / (alpha h^2) + K + B (elastic and contact parts PSD
 * after projection), so H >= M / (alpha h^2) and d = H^-1 g has |d|_M <= alpha h^2 |g|_{M^-1}: with
 * G_i <= 1 at every vertex the mass-weighted RMS of |d_full_i| / h is at most tol. No mesh size or
 * material in it (g_i and m_i both scale with the vertex's volume). s: nv.
 * The progress the same way, p_i = m_i tol^2 / 2 with E_i = alpha dE_i / p_i: romkit's potential
 * holds the kinetic term |x - x~|_M^2 / (2 alpha h^2), so a velocity error dv_i at vertex i is
 * worth m_i dv_i^2 / (2 alpha) of it, and E_i = (dv_i / tol)^2 for the velocity error dv_i whose
 * removal the subspace's own step bought there. p: nv. */
void rk_adaptive_tolerance_scale(const rk_fem *f, double h, double tol, double *s, double *p);
/* The method's own tolerance on the full-space residual |d|_inf / h (m/s), from the accuracy target a
 * (the run's position error over the bounding-box diagonal L) for a run of N steps of h. A step that
 * ends with residual v leaves its answer about h v from the step's minimiser; the error stays in the
 * state (positions, and the velocity the integrator reads from them), so in free motion an error made
 * at step k moves every later position by as much again each step: after N steps at most
 * sum_k h v (N - k + 1) = h v N (N + 1) / 2. Its bound a L gives v = 2 a L / (h N (N + 1)): no mesh
 * size or material in it (L and the duration are the scene's). Never below full order's own
 * tolerance newton_tol (its answer is no closer than that); a <= 0: newton_tol. */
double rk_adaptive_own_tolerance(double accuracy, double diagonal, double h, int steps, double newton_tol);
/* Nodal error (Eq. 10): G_i = alpha |g_i| / (A_i psi_i) for gradient g (3 nv). */
void rk_adaptive_nodal_error(int nv, const double *g, const double *area, const double *psi_bar, double alpha,
                             double *G);
/* Modal error of a block of k columns Um (3 nv x k, column-major; Eq. 12, 14, 16):
 * max_i alpha |(sum_j u_j u_j^T g / u_j^T u_j)_i| / (A_i psi_i). work: 3 nv. */
double rk_adaptive_modal_error(int nv, const double *Um, int k, const double *g, const double *area,
                               const double *psi_bar, double alpha, double *work);
/* Modal progress (Eq. 13, 15, 17): with ubar_j the per-vertex average of u_j's three coordinates,
 * sum_i alpha (sum_j ubar_j ubar_j^T dE / ubar_j^T ubar_j)_i / (V_i psi_i). */
double rk_adaptive_modal_progress(int nv, const double *Um, int k, const double *dE, const double *volume,
                                  const double *psi_bar, double alpha);

/* ---- the baseline of the linear-solve comparison (baseline.c) ---- */

/* Conjugate gradients with a 3 x 3 block-Jacobi preconditioner on the full-space system A d = -g
 * (A upper-stored symmetric, the full-order Newton matrix): the paper's IPC-CG. Returns the
 * iterations (max_iter when it did not reach tol); d starts at 0. */
int rk_block_jacobi_cg(const rk_sparse *A, const double *g, double *d, double tol, int max_iter, rk_error *err);

#endif
