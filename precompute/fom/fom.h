/* precompute/fom: the full-order simulator, the ground truth every reduced model is judged
 * against. Incremental-potential time stepping (adaptive-subspace paper, Sec. 3.1, Eq. 1-3):
 *
 *   x_{t+1} = argmin_x  1/2 |x - x~|_M^2 + alpha h^2 (Psi(x) + B(x) + D(x) - f_ext . x)
 *
 * backward Euler: x~ = x_t + h v_t, alpha = 1, v_{t+1} = (x_{t+1} - x_t) / h
 * BDF2 (footnote 9): x~ = (4 x_t - x_{t-1})/3 + 2h/9 (4 v_t - v_{t-1}), alpha = 4/9,
 *                    v_{t+1} = (3 x_{t+1} - 4 x_t + x_{t-1}) / (2h); the first step is backward Euler.
 * Psi elastic, B the ground-plane barrier, D Rayleigh damping as the quadratic potential
 * 1/(2h) (x - x_t)^T (a M + b K0) (x - x_t) with K0 the rest stiffness. The solver minimises
 * this divided by alpha h^2 (same minimiser, Hessian scaled like a stiffness). M is the
 * consistent mass (or lumped, opt.lumped_mass) in both inertia and damping; gravity is m_v g
 * per vertex with the lumped masses (the consistent mass's row sums, so the same forces).
 * Newton with PSD-projected element Hessians, CHOLMOD (symbolic analysis once, numeric
 * factorization per iteration), backtracking line search on the incremental potential,
 * termination on |d|_inf / h <= tol (Sec. 3.10). Contact is IPC (precompute/contact): the
 * barrier in the potential, every line search step filtered by CCD, kappa adapted. Prescribed
 * vertices (fixed, twisted, translated) and obstacles move to their targets at the start of each
 * step (in several moves, each followed by a solve, when CCD finds something in the way) and the
 * prescribed degrees of freedom are removed from the Newton system. */
#ifndef RK_FOM_H
#define RK_FOM_H

#include "contact/contact.h"
#include "fem/fem.h"
#include "solver/solver.h"
#include "util/util.h"

/* A group of prescribed vertices. */
typedef struct {
    rk_motion_kind kind;
    int count;
    int *verts;
    double axis[3];      /* twist: unit axis */
    double center[3];    /* twist: a point on the axis, used as given (the scene builder fills in
                          * the group's rest centroid when the scene names none) */
    double rate;         /* twist: radians per second */
    double velocity[3];  /* translate: m/s */
} rk_prescribed;

/* A pneumatic chamber (pressure.c; koopman-dmd-log-linear paper, Sec. 7.3): the closed surface of
 * an interior void, as boundary faces of the mesh oriented outward of the solid (into the void),
 * under a gauge pressure that pushes its walls out of the void. The load is the follower force
 * -P n2 / 6 on each vertex of a face (n2: twice the deformed face's area times its normal), the
 * gradient of -P V(x), V the void's deformed volume, so it enters the incremental potential as
 * -P V (exact gradient; its stiffness joins the exact Newton matrix, lagged elsewhere: pressure.c). */
typedef struct {
    int nf;
    int *tris;           /* 3 nf vertex indices, counter-clockwise seen from the void */
    double pressure;     /* Pa */
    int nkeys;           /* > 0: the pressure follows keys instead, each step taking its value at the
                          * step's end time */
    double *keys;        /* 2 nkeys: (t, P) pairs, times increasing, linear between them and held
                          * before the first and after the last */
} rk_chamber;

/* Face (xa, xb, xc)'s force at pressure P on each of its three vertices (f, 3 values: the same on
 * all three) and, with J (27 values), its derivative: J[9 w + 3 i + j] = d f_i / d x_w,j for
 * w = a, b, c (non-symmetric per face; symmetric summed over a closed chamber). */
void rk_pressure_face(const double *xa, const double *xb, const double *xc, double P, double f[3], double J[27]);
/* f (3 nv) += the chamber's force at positions x under scale times its pressure. */
void rk_chamber_force(const rk_chamber *c, const double *x, double scale, double *f);
/* H (upper-stored, a pattern holding every face's vertex pairs) += the Hessian of -scale P V at x,
 * the load stiffness -d f / dx (symmetric summed over the closed chamber; indefinite). */
void rk_chamber_add_stiffness(const rk_chamber *c, const double *x, double scale, rk_sparse *H);
/* The void's volume at x (m^3; positive for a chamber of faces pointing into it). */
double rk_chamber_volume(const rk_chamber *c, const double *x);
/* The chamber's pressure at time t (its keys, or its constant pressure). */
double rk_chamber_pressure_at(const rk_chamber *c, double t);
/* A chamber of nv-vertex mesh: faces given, vertices in range, finite pressure and keys (times
 * increasing), and a closed,
 * consistently oriented surface (every edge shared by two faces in opposite directions; names the
 * first edge that is not). */
int rk_chamber_check(const rk_chamber *c, int nv, rk_error *err);

/* Where a group's vertices are at time t: x = R X + shift (fixed: R = I, shift = 0; translate:
 * shift = velocity t; twist: rotation by rate t about the axis through center, Rodrigues). */
void rk_prescribed_transform(const rk_prescribed *p, double t, double R[9], double shift[3]);

/* Contact on a surface embedded in the elements (a point cloud's march surface in its full-order
 * body, docs/cloud_march.md): contact vertex j is at y_j = offset_j + sum_a weight[4j + a]
 * x[vertex[4j + a]], a fixed linear map of the simulated positions x, and the contact model
 * (precompute/contact) runs on y: mesh's boundary (its tets and ghost tets, mesh.X = y at rest)
 * is the contact surface and object k owns its vertices [object_first_vertex[k],
 * object_first_vertex[k + 1]) (rk_fom_options.nobjects + 1 entries). rk_fom_init copies it. */
typedef struct {
    rk_mesh mesh;
    const int *vertex;        /* 4 nv */
    const double *weight;     /* 4 nv */
    const double *offset;     /* 3 nv */
    const int *object_first_vertex;
} rk_fom_contact_surface;

/* y = W x (+ o when offset is not NULL): the nv contact vertices' positions from the simulated
 * positions x, as above (full order's contact view and the pipeline's rest positions alike). */
void rk_fom_embed(int nv, const int *vertex, const double *weight, const double *offset, const double *x, double *y);

typedef struct {
    double h;                 /* time step (s) */
    int steps;                /* number of steps to run */
    rk_integrator integrator;
    int is_static;            /* static equilibrium solve instead of dynamics */
    int lumped_mass;          /* lumped instead of consistent mass in the inertia term */
    double gravity[3];        /* m/s^2 */
    double *force;            /* 3*nv extra external forces (N), or NULL */
    double *velocity0;        /* 3*nv initial velocities, or NULL for rest */
    double *position0;        /* 3*nv initial positions, or NULL for the rest positions (may be
                                 inverted: stable Neo-Hookean recovers) */
    double rayleigh_mass;     /* a in (a M + b K0) */
    double rayleigh_stiffness;/* b */
    int nobstacles;           /* planes, spheres, capsules, boxes, meshes (contact.h), static or moving */
    const rk_obstacle *obstacles;
    rk_contact_options contact; /* dhat (0: 1e-3 of the rest bounding-box diagonal), kappa, friction, self */
    int nobjects;             /* objects collide with each other: object k owns vertices */
    const int *object_first_vertex; /* [first[k], first[k + 1]) (nobjects + 1 entries; NULL: one object) */
    int nprescribed;
    rk_prescribed *prescribed;
    double newton_tol;        /* on |d|_inf / h (m/s); static: on |d|_inf (m); <= 0: default */
    double pin_stiffness;     /* reduced models only: the penalty holding prescribed vertices, in
                               * units of (lambda + 2 mu) / (rho L^2) (rom.h); <= 0: RK_ROM_PIN_STIFFNESS */
    int lift_group, lift_handle; /* reduced models only (rom.clamp "lifted", rom.h): prescribed group
                               * lift_group - 1 moves with skinning handle lift_handle - 1, whose 12
                               * coordinates are its motion, set and not solved for (no penalty on
                               * it); 0: none */
    int newton_max_iter;      /* Newton iterations a solve may take; 0: the default (rk_fom_max_iter) */
    int nchambers;            /* pneumatic chambers under pressure (rk_chamber), full order only */
    const rk_chamber *chambers;
    int obstacle_progress;    /* moving obstacles are not unknowns of the full-order Newton: the solver
                               * given to rk_fom_step_with moves them by their progress along the
                               * step's way (contact.h, rk_obstacle_way; precompute/adaptive), with
                               * the obstacle points' gradient in rk_fom_view's og */
    const rk_fom_contact_surface *contact_surface; /* NULL: contact on the mesh's own boundary */
} rk_fom_options;

/* Relative Newton tolerance used when newton_tol <= 0: rk_fom_init sets
 * newton_tol = RK_FOM_DEFAULT_TOL * (rest bounding-box diagonal) per second (and a static
 * solve then uses newton_tol * h metres). */
#define RK_FOM_DEFAULT_TOL 1e-5

/* Newton iterations a solve may take when newton_max_iter is 0. Full order (time steps, static
 * load increments, the P2 reference): RK_FOM_DEFAULT_MAX_ITER. On contact scenes where a body
 * balances on a curved obstacle, projected Newton creeps sideways along the barrier with full
 * steps of nearly the same size (docs/methods.md, "Full order at the default tolerance"), and
 * a step there took up to 205 iterations to the default tolerance (issue 34; 50 left 7 and 9 of
 * 10 steps unconverged and mm off); steps that converge stop where they converge, so the
 * limit costs only where 50 would have been wrong. The reduced solvers (precompute/rom, the
 * adaptive subspace and adaptive linear ROM solves) and the assets' runtime, whose HEAD
 * carries the limit, keep RK_REDUCED_DEFAULT_MAX_ITER: their solves are what the runtime does,
 * and the full-order default must not change the runtime's. A scene's newton.max_iterations
 * sets both. */
#define RK_FOM_DEFAULT_MAX_ITER 500
#define RK_REDUCED_DEFAULT_MAX_ITER 50
/* o->newton_max_iter, or when it is 0 the full-order default (reduced = 0) or the reduced one. */
int rk_fom_max_iter(const rk_fom_options *o, int reduced);

/* Fills defaults: h 0.01, 100 steps, backward Euler, consistent mass, no gravity, no damping,
 * no obstacles, nothing prescribed, newton_tol 0 (= RK_FOM_DEFAULT_TOL relative, above),
 * newton_max_iter 0 (rk_fom_max_iter). */
void rk_fom_default_options(rk_fom_options *o);

/* The incremental potential being minimised (fom.h, paper Eq. 2 divided by alpha h^2):
 *   E(x) = w_inertia/2 |x - xtilde|_M^2 + Psi(x) + B(x) + w_damping/2 |x - xt|_C^2 - load f.x
 *          - load sum_c P_c V_c(x)    (the chambers' pressure work, rk_chamber)
 * with C = a M + b K0. Dynamics: w_inertia = 1/(alpha h^2), w_damping = 1/h, load = 1.
 * Static: w_inertia = w_damping = 0, load in (0, 1] (load stepping) and a tiny mass-proportional
 * shift `reg` added to the Hessian only (free rigid modes, projected-away directions). */
typedef struct {
    double w_inertia;
    const double *xtilde;
    double w_damping;
    const double *xt;
    double load;
    double reg;
    int friction;           /* add the lagged friction potential (dynamics with contact.friction > 0) */
    int no_elastic;         /* leave Psi and its gradient out: a caller that adds them itself, element by
                             * element (precompute/adaptive); not with the Newton matrix */
} rk_fom_terms;

/* A contact pair's Hessian block as the contact stage hands it over (mesh vertex ids; obstacle
 * vertex k as -1 - k, dropped from the Newton matrix, or matrix vertex nv + k when the obstacles
 * are its unknowns). */
typedef struct {
    int np, id[4];
    double H[144];
} rk_contact_block;

/* Counters and seconds of the steps and static solves so far. The seconds below seconds_total
 * are disjoint parts of it (what they leave is the rest: predictor, prescribed motion, checks),
 * except seconds_hessian, a part of seconds_assemble, and seconds_analyze_init, before any step. */
typedef struct {
    long steps;
    long newton_iterations;
    long line_search_halvings;
    long unconverged_steps;   /* steps that hit newton_max_iter */
    long analyses;            /* CHOLMOD symbolic analyses, init's included (more only with contact) */
    long projected_hessians;  /* time-step Newton iterations whose exact Newton matrix was not
                               * positive definite, so the elements' dP/dF was projected (newton.c) */
    double seconds_total;
    double seconds_analyze_init; /* rk_fom_init's analysis (the ordering included) */
    double seconds_analyze;   /* the analyses in steps: contact changed the matrix's pattern */
    double seconds_factor;    /* CHOLMOD numeric factorization */
    double seconds_solve;     /* triangular solves */
    double seconds_assemble;  /* the Newton iterations' potential with gradient and Newton matrix
                               * (elastic, inertia, damping, the matrix fill), contact excluded */
    double seconds_hessian;   /* the elastic element Hessians (dP/dF exact or projected to PSD), in assemble */
    double seconds_line_search; /* the line search's potential values, contact excluded */
    double seconds_contact;   /* the contact terms in the potential, CCD and the pattern updates */
} rk_fom_stats;

typedef struct rk_fom_impl rk_fom_impl;

typedef struct {
    const rk_fem *fem;
    rk_fom_options opt;
    double t;          /* current time */
    double *x;         /* 3*nv current positions */
    double *v;         /* 3*nv current velocities */
    rk_fom_stats stats;
    rk_fom_impl *impl; /* CHOLMOD state, scratch */
} rk_fom;

/* Checks options against a mesh of nv vertices (positive step, known integrator, finite
 * loads and start, sane damping and obstacles): the full-order and the reduced models share it. */
int rk_fom_check_options(const rk_fom_options *o, int nv, rk_error *err);

/* Starts at opt.position0 (or the rest positions X), velocity opt.velocity0 (or 0), t = 0. Copies what opt points to
 * (force, prescribed groups, planes; s->opt then points at the copies, velocity0 and position0 are NULL), so
 * the caller's arrays need not outlive the call; fem must. Fails on bad options and on a vertex
 * starting on or behind a plane. newton_tol <= 0 is resolved here (RK_FOM_DEFAULT_TOL). */
int rk_fom_init(rk_fom *s, const rk_fem *fem, const rk_fom_options *opt, rk_error *err);
/* One time step. Fails (with the step number) on NaN or a Newton system CHOLMOD rejects; a
 * step that hits newton_max_iter (or whose line search stalls) is kept and counted in
 * stats.unconverged_steps. */
int rk_fom_step(rk_fom *s, rk_error *err);
/* Static equilibrium under gravity, forces and prescribed vertices (at time opt.steps*h),
 * from the current x; on success x is the equilibrium and v = 0 (t is left as it is). Load
 * stepping when the full load does not converge; fails when even that does not. */
int rk_fom_static(rk_fom *s, rk_error *err);
/* Total kinetic energy 1/2 v^T M v (the inertia mass: consistent, or lumped per opt) and
 * elastic energy Psi(x) at the current state. */
double rk_fom_kinetic_energy(const rk_fom *s);
double rk_fom_elastic_energy(const rk_fom *s);
void rk_fom_free(rk_fom *s);

/* Puts the state back to (x, v) at time t (obstacles where they are then), with (x_prev, v_prev)
 * as BDF2's history (both NULL: none, the next step is backward Euler): the online-error
 * realignment of a method built on this simulator. */
void rk_fom_set_state(rk_fom *s, const double *x, const double *v, const double *x_prev, const double *v_prev,
                      double t);

/* Replaces the extra external forces (N, 3 nv values, copied; NULL: none) from the next step on,
 * gravity kept: a load that changes between steps (a controller's input) without restarting the
 * integrator (BDF2 keeps its history, as a fresh rk_fom_init per step would not). */
void rk_fom_set_force(rk_fom *s, const double *force);

/* Replaces the chambers' pressures (Pa, nchambers values; their keys dropped) from the next step on:
 * a controller's input, as rk_fom_set_force. */
void rk_fom_set_pressure(rk_fom *s, const double *pressure);

/* ---- the step's potential, for a solver of the step other than the full-order Newton ----
 * (precompute/adaptive solves each time step's minimisation itself, on the same potential, the
 * same contact and the same prescribed motion.) */

/* What rk_fom_potential computes with its Hessian. */
enum { RK_FOM_NO_HESSIAN = 0, RK_FOM_NEWTON_MATRIX = 1, RK_FOM_CONTACT_BLOCKS = 2 };
/* E(y) over the unknowns y (ndof: the mesh, then the obstacle vertices when they are unknowns);
 * with g, also its gradient; with hessian = RK_FOM_NEWTON_MATRIX, also the Newton matrix N.A
 * (PSD-projected elastic and contact parts, the prescribed dofs eliminated; its pattern follows the
 * contact pairs); with RK_FOM_CONTACT_BLOCKS only the contact and friction pairs' Hessian blocks
 * (rk_fom_view's blocks) and kappa's adaptation. With magnitude, also the sum of the terms'
 * absolute values: the scale of E's round-off. With contact, the pairs are gathered at y, kappa
 * adapts at each Hessian, and moving obstacles add their augmented Lagrangian. */
double rk_fom_potential(rk_fom *s, const rk_fom_terms *T, const double *y, double *g, int hessian,
                        double *magnitude, rk_error *err);

/* The constant parts of the potential and the contact blocks of its last Hessian. */
typedef struct {
    int n;                      /* 3 nv: the mesh's unknowns */
    int nobs;                   /* obstacle vertices among the unknowns (moving obstacles); 0 otherwise */
    const rk_sparse *M, *C;     /* inertia mass; Rayleigh damping (C->val NULL: none) */
    const double *f_ext;        /* gravity and forces (n) */
    const char *prescribed;     /* n flags: the dofs the prescribed motion holds */
    int has_contact;
    int nblocks;                /* the last rk_fom_potential(..., hessian != 0)'s contact blocks */
    const rk_contact_block *blocks;
    rk_contact *contact;        /* NULL without contact */
    const double *og;           /* 3 onv: with opt.obstacle_progress and a moving obstacle, the obstacle
                                 * points' gradient of the last rk_fom_potential with g (else NULL) */
} rk_fom_view;
void rk_fom_view_get(const rk_fom *s, rk_fom_view *v);
/* Each of v's contact blocks sandwiched in a subspace: out (a x a, column-major) += A_p^T H_b A_p,
 * A_p the rows of A (n x a, column-major) at the block's points (an obstacle's point: zero rows).
 * work: 12 a doubles. */
void rk_fom_contact_sandwich(const rk_fom_view *v, int n, int a, const double *A, double *work, double *out);

/* A solver of the step's minimisation: from s->x (prescribed dofs already where they are due),
 * minimise T's potential in place to |d|_inf <= tol_d (m); *converged as rk_newton_solve's. */
typedef int (*rk_fom_newton_fn)(void *ctx, rk_fom *s, const rk_fom_terms *T, double tol_d, int *converged,
                                rk_error *err);
/* One time step as rk_fom_step takes it (prediction, friction lagging, prescribed motion in
 * CCD-safe moves, velocity update), each minimisation by newton(ctx, ...). */
int rk_fom_step_with(rk_fom *s, rk_fom_newton_fn newton, void *ctx, rk_error *err);
/* Minimises the potential from s->x and the obstacles where they are (both updated in place) with
 * the solver's Newton (CHOLMOD on the projected Hessian, CCD step filtering), converged when
 * |d|_inf <= tol_d; with moving obstacles, in augmented-Lagrangian rounds until they are at their
 * targets. Public so that another solver given to rk_fom_step_with may finish a step by it
 * (the adaptive simulator's full_fraction). */
int rk_fom_newton(rk_fom *s, const rk_fom_terms *T, double tol_d, int *converged, rk_error *err);
/* The Newton matrix of the last rk_fom_potential(..., RK_FOM_NEWTON_MATRIX) (upper-stored, the
 * prescribed dofs eliminated), and d = -H^-1 g by CHOLMOD on it (numeric factorization, solve):
 * the full-space solve another solver is measured against. */
const rk_sparse *rk_fom_newton_matrix(const rk_fom *s);
int rk_fom_newton_direction(rk_fom *s, const double *g, double *d, rk_error *err);
/* The largest alpha in (0, 1] that keeps the surfaces apart moving x by alpha d (1 without contact);
 * -1 on failure. */
double rk_fom_max_step(rk_fom *s, const double *x, const double *d, rk_error *err);

/* The seconds of every Newton iteration so far, in order (from its evaluation of the potential
 * with gradient and Newton matrix to the next one's, or to the end of its solve: factorization,
 * solve and line search included), and of each one's numeric factorization (*factor_seconds);
 * returns the count. The arrays belong to s and move when it steps. */
long rk_fom_iterations(const rk_fom *s, const double **seconds, const double **factor_seconds);

/* Contact at the current state (0 and INFINITY without contact): exact crossings of its surfaces
 * (0 for a valid state) and the smallest distance between them (m). */
int rk_fom_contact_measure(rk_fom *s, int *intersections, double *min_distance, rk_error *err);
/* The contact stage's counters (pairs, broad phase, CCD and barrier seconds), or NULL without contact. */
const rk_contact_stats *rk_fom_contact_stats(const rk_fom *s);

/* ---- full order on quadratic tets (p2_fom.c): a dynamic reference converged where P1 is not ----
 * fem's mesh with a node on every edge (rk_p2_mesh), its materials per tet, run as opt says with the
 * same potential, Newton, integrator and tolerance as rk_fom_step: gravity (consistent load),
 * Rayleigh damping, prescribed groups (an edge node moves with a group holding both its ends), a
 * start at opt's position0 / velocity0 (edge nodes midway), extra forces on the vertex nodes.
 * Contact, obstacles, several objects, a lumped mass and a static solve are refused by name. After
 * the start (step 0) and every step, frame gets x and v over the P2 nodes (3 nn; the mesh's vertices
 * first, in its numbering) and the step's seconds. stats gets steps, Newton iterations, halvings,
 * unconverged steps, projected Hessians and seconds (total, analysis, assembly, factorization,
 * solves). */
typedef int (*rk_p2_frame_fn)(void *ctx, int step, const double *x, const double *v, double seconds, rk_error *err);
int rk_p2_fom_run(const rk_fem *fem, const rk_fom_options *opt, rk_p2_frame_fn frame, void *ctx, rk_fom_stats *stats,
                  rk_error *err);

#endif
