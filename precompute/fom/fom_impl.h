/* Private to precompute/fom: the state behind rk_fom_impl and the pieces the step, the static
 * solve and init share. */
#ifndef RK_FOM_IMPL_H
#define RK_FOM_IMPL_H

#include <cholmod.h>

#include "contact/contact.h"
#include "fom/fom.h"
#include "solver/solver.h"



/* What CHOLMOD factors (matrix.c): the elements' pattern, the obstacle vertices that are unknowns
 * (their 3 x 3 diagonal blocks after the mesh's dofs), and the vertex pairs contact couples. */
typedef struct {
    int nmesh, nobs;        /* mesh vertices; obstacle vertices among the unknowns (0: none) */
    rk_sparse A;
    int *base_map;          /* the elements' pattern entry k is A entry base_map[k] */
    int npairs, *pairs;     /* vertex pairs (a < b) beyond the elements' pattern */
    int nblocks, capblocks, overflow;
    rk_contact_block *blocks;/* this iteration's contact blocks */
} rk_newton_matrix;

int rk_newton_matrix_init(rk_newton_matrix *N, const rk_sparse *base, int nobs, rk_error *err);
void rk_newton_matrix_free(rk_newton_matrix *N);
/* The contact stage's Hessian sink: records a block (ctx: the rk_newton_matrix); obstacle vertex k
 * is matrix vertex nmesh + k when obstacles are unknowns, else dropped. */
void rk_newton_matrix_record(void *ctx, const int *id, int npoints, const double *H);
/* Rebuilds A's pattern when the recorded blocks couple a different set of vertex pairs. */
int rk_newton_matrix_couple(rk_newton_matrix *N, const rk_sparse *base, int *changed, rk_error *err);
/* A = base (values) plus the recorded blocks. */
void rk_newton_matrix_fill(rk_newton_matrix *N, const rk_sparse *base);

/* Contact on an embedded surface (contact_view.c, rk_fom_contact_surface): the map y = W x + o
 * copied, and scratch in contact space. on = 0 (a mesh's own boundary): y is x, nothing here is
 * allocated and every wrapper hands x to the contact stage as it is. */
typedef struct {
    int on, nv;             /* nv contact vertices */
    int *vertex;            /* 4 nv */
    double *weight, *offset;/* 4 nv, 3 nv */
    double *y, *dy, *g, *gb;/* 3 nv each: positions, a direction, the gradient, the barrier's alone */
} rk_fom_embedding;

/* The moving obstacles' augmented-Lagrangian stiffness at the start of each solve, times 1/h^2
 * and the average vertex mass: a thousand times the inertia's pull. */
#define RK_FOM_AL_KAPPA 1e3

struct rk_fom_impl {
    int n;                  /* 3 nv */
    rk_sparse M;            /* inertia mass: consistent or lumped (opt.lumped_mass) */
    rk_sparse C;            /* Rayleigh damping a M + b K0; val NULL when a = b = 0 */
    rk_sparse H;            /* the elements' Hessian, rebuilt each iteration on their pattern */
    rk_newton_matrix N;     /* H plus contact: what CHOLMOD factors */
    int exact_elastic;      /* the elements' dP/dF unprojected in the next Newton matrix (newton.c) */
    double *f_ext;          /* gravity (lumped masses) + opt.force */
    char *prescribed_dof;   /* ndof: 1 where a dof is prescribed (static obstacles' vertices too) */
    /* The Newton unknowns: the mesh (n) and, when an obstacle moves, every obstacle vertex (3 nobs);
     * moving ones are pulled to their targets by an augmented Lagrangian (IPC, Sec. 4.6). */
    int nobs, ndof;
    double *y;              /* ndof */
    double *obs_target, *al_lambda; /* 3 nobs: the obstacles' targets, the multipliers */
    double *og;             /* 3 onv: the obstacle points' gradient (opt.obstacle_progress) */
    double al_kappa, al_mass;
    /* Owned copies of what opt pointed to (s->opt points here after init). */
    rk_prescribed *groups;
    rk_chamber *chambers;   /* opt.nchambers, their faces copied */
    double *force;
    /* Contact (when obstacles, several objects or self-contact): the model, this evaluation's pairs,
     * the barrier's gradient alone (for kappa). */
    int has_contact;
    rk_contact contact;
    rk_contact_set pairs;
    double *g_barrier;
    rk_fom_embedding emb;
    rk_stepper stepper;     /* backward Euler / BDF2: prediction and history */
    double *newton_work;    /* RK_NEWTON_WORK(ndof) */
    double *work, *work2;   /* scratch, n each */
    double tol_static;      /* |d|_inf (m) */
    /* N.A factored (fem.h, rk_chol): symbolic analysis when its pattern changes (once without
     * contact), numeric per iteration. */
    rk_chol chol;
    long analyses;          /* symbolic analyses so far (init's included) and their seconds */
    double seconds_analyze, seconds_analyze_init;
    /* Each Newton iteration's seconds (from its Hessian evaluation to the next one's, or to the end
     * of its solve) and its numeric factorization's (timing.c); recording stops, silently, when
     * the arrays cannot grow. */
    long niter, capiter;
    double *iter_seconds, *iter_factor;
    int iter_open;
    double iter_start;
};

/* Per-iteration timing (timing.c): an iteration starts at its potential evaluation with Hessian
 * (at t0), its factorization adds its seconds, and it ends at the next start or when the Newton
 * solve returns. */
void rk_fom_iteration_start(rk_fom_impl *im, double t0);
void rk_fom_iteration_factor(rk_fom_impl *im, double seconds);
void rk_fom_iteration_end(rk_fom_impl *im);
/* The counters kept in the impl (analyses) copied into s->stats. */
void rk_fom_sync_stats(rk_fom *s);

/* Sets every prescribed vertex of x to its target at time t (fixed: rest; twist: rest rotated by
 * rate t about the axis through center, Rodrigues; translate: rest + velocity t). */
void rk_fom_prescribe(const rk_fom *s, double t, double *x);
/* Prescribed dofs out of the Newton matrix: zero rows and columns with 1 on the diagonal of H
 * (the pattern stays as it is; the solver zeroes their gradient). */
void rk_fom_eliminate(const rk_fom *s, rk_sparse *H);

/* Keyed chambers take their pressure at time t (rk_chamber_pressure_at). */
void rk_fom_pressure_at(rk_fom *s, double t);

/* The moving obstacles' targets at time t for the next solves (multipliers reset). */
void rk_fom_obstacle_targets(rk_fom *s, double t);

/* Moves the prescribed vertices to where they are at time t and solves solve() after each move: in
 * one move when nothing is in the way, else in as many as CCD allows (each Newton solve pushes the
 * free vertices clear before the next). */
typedef int (*rk_fom_solve_fn)(rk_fom *s, void *ctx, rk_error *err);
int rk_fom_advance_kinematics(rk_fom *s, double t, rk_fom_solve_fn solve, void *ctx, rk_error *err);

/* rk_fom_newton: fom.h (another solver may hand a step to it). */
/* The potential as the solver's problem (ctx: a rk_fom_problem_ctx that outlives its use). */
typedef struct {
    rk_fom *s;
    const rk_fom_terms *T;
    const double *y;        /* where the last Newton matrix was built */
    rk_error failure;       /* set when the contact stage failed inside a callback */
} rk_fom_problem_ctx;
void rk_fom_problem(rk_fom_problem_ctx *ctx, rk_newton_problem *p);

/* Full order's contact through the embedding (contact_view.c), every call with the simulator's
 * positions x (3 nv, mesh only; obstacle points as the contact stage has them): */
int rk_fom_embedding_init(rk_fom_embedding *e, const rk_fom_contact_surface *cs, int nv_mesh, rk_error *err);
void rk_fom_embedding_free(rk_fom_embedding *e);
/* The contact positions at x (x itself without an embedding; else e->y) and a direction dx's
 * (e->dy: the map's linear part, so a straight step in x is a straight path of y and CCD on y is
 * exact). */
const double *rk_fom_contact_x(rk_fom_impl *im, const double *x);
const double *rk_fom_contact_dx(rk_fom_impl *im, const double *dx);
/* Where the contact stage adds its gradient: g itself, or e->g zeroed (NULL for NULL); then
 * rk_fom_contact_pull adds W^T of it into g (nothing without an embedding). */
double *rk_fom_contact_gradient(rk_fom_impl *im, double *g);
void rk_fom_contact_pull(rk_fom_impl *im, const double *gy, double *g);
/* The Hessian sink into N: rk_newton_matrix_record, or a wrapper recording W^T B W for each block. */
rk_hessian_sink rk_fom_contact_sink(rk_fom_impl *im, void **ctx);
/* rk_contact_max_step, friction start and lag, intersections, min distance and measure at x. */
double rk_fom_contact_ccd(rk_fom_impl *im, const double *x, const double *dx, const double *odx, rk_error *err);
int rk_fom_friction_start(rk_fom_impl *im, const double *x, rk_error *err);
int rk_fom_friction_lag(rk_fom_impl *im, const double *x, rk_error *err);
int rk_fom_intersections(rk_fom_impl *im, const double *x, rk_error *err);
double rk_fom_min_distance(rk_fom_impl *im, const double *x, rk_error *err);

/* CHOLMOD on impl->H: analysis (init), factorization and solve of H d = -g. */
int rk_fom_chol_analyze(rk_fom_impl *im, rk_error *err);
/* Redoes the symbolic analysis after N.A's pattern changed. */
int rk_fom_chol_reanalyze(rk_fom_impl *im, rk_error *err);
/* 0, -1 on failure, RK_FOM_NOT_POSDEF (no message set) when the matrix is not positive definite
 * and im->exact_elastic says it may not be. */
#define RK_FOM_NOT_POSDEF 1
int rk_fom_chol_factor(rk_fom *s, rk_error *err);
/* The Newton matrix N.A at y again, the elements' dP/dF projected this time (potential.c). */
int rk_fom_newton_matrix_projected(rk_fom *s, const rk_fom_terms *T, const double *y, rk_error *err);
int rk_fom_chol_solve(rk_fom *s, const double *g, double *d, rk_error *err);
void rk_fom_chol_free(rk_fom_impl *im);

#endif
