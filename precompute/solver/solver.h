/* precompute/solver: the one Newton of the precompute, and the time integrators around it.
 *
 * Every simulator of romkit (full order, the fixed-basis reduced model, and the methods built on
 * them) takes a time step by minimising an incremental potential (adaptive-subspace paper,
 * Sec. 3.1, Eq. 1-3):
 *
 *   x_{t+1} = argmin_x  1/2 |x - x~|_M^2 + alpha h^2 (Psi(x) + B(x) + D(x) - f_ext . x)
 *
 * backward Euler: x~ = x_t + h v_t, alpha = 1, v_{t+1} = (x_{t+1} - x_t) / h
 * BDF2 (footnote 9): x~ = (4 x_t - x_{t-1})/3 + 2h/9 (4 v_t - v_{t-1}), alpha = 4/9,
 *                    v_{t+1} = (3 x_{t+1} - 4 x_t + x_{t-1}) / (2h); the first step is backward Euler.
 *
 * A simulator hands the potential over as callbacks (rk_newton_problem): its value and gradient,
 * a linear solve with its PSD-projected Hessian (CHOLMOD, a dense Cholesky, or PCG on
 * Hessian-vector products: the solver does not care), a largest feasible step for barriers and
 * continuous collision detection, and the degrees of freedom it prescribes. rk_newton_solve is
 * projected Newton with a backtracking line search; rk_stepper holds the integrator's prediction,
 * history and velocity update. The constants (Armijo, halvings, round-off floor) are in
 * physics/physics.h, which the runtime's own C99 loop includes too. */
#ifndef RK_SOLVER_H
#define RK_SOLVER_H

#include "physics/physics.h"
#include "util/util.h"

typedef enum { RK_BACKWARD_EULER = 0, RK_BDF2 = 1 } rk_integrator;

typedef struct {
    int n;                  /* unknowns */
    void *ctx;              /* handed to every callback */
    const char *what;       /* names the potential in messages ("incremental potential") */
    /* E(x); with g (n values), also its gradient; with hessian != 0, also prepares what solve()
     * needs (the PSD-projected Hessian at x). *magnitude (may be NULL): the sum of the terms'
     * absolute values, the scale of E's round-off. Not finite (or +INFINITY) where E is not
     * defined (a barrier crossed, an element inverted past recovery). */
    double (*energy)(void *ctx, const double *x, double *g, int hessian, double *magnitude);
    /* d = -H^-1 g with the Hessian of the last energy(..., hessian != 0) call. */
    int (*solve)(void *ctx, const double *g, double *d, rk_error *err);
    /* Largest alpha in (0, 1] with x + alpha d feasible (barriers, CCD); NULL: always 1. */
    double (*max_step)(void *ctx, const double *x, const double *d);
    /* The size of a Newton step d that is compared with the tolerance; NULL: |d|_inf. */
    double (*step_norm)(void *ctx, const double *d);
    /* n flags or NULL: prescribed entries of x, which never move (g and d are zero there; the
     * Hessian the solve uses must keep them out of the system). */
    const char *prescribed;
} rk_newton_problem;

typedef struct {
    long iterations;        /* Newton directions computed */
    long halvings;          /* line-search halvings */
} rk_newton_stats;

/* Scratch rk_newton_solve needs: 3 n doubles. */
#define RK_NEWTON_WORK(n) (3 * (size_t)(n))

/* Minimises p's potential from x (updated in place): projected Newton, the direction from
 * p->solve, a line search that starts at p->max_step and halves until the Armijo condition holds
 * (or the change is round-off), and termination when step_norm(d) <= tol, checked before the line
 * search (near the solution the decrease drowns in round-off, and a step that small is the
 * answer anyway). *converged: whether it terminated so within max_iter iterations; a line search
 * that finds no decrease stops it unconverged. Fails on a potential, gradient or direction that is
 * not finite, and on a failed solve, naming the iteration. stats (may be NULL) are added to. */
int rk_newton_solve(const rk_newton_problem *p, double *x, double tol, int max_iter, double *work,
                    int *converged, rk_newton_stats *stats, rk_error *err);

/* Load stepping for a static equilibrium: the full load, or when Newton does not converge, the load
 * ramped over 4, 16 and then 64 equal increments, each minimised from the one before, every attempt
 * starting again from x as given. increment(ctx, lambda, x, converged, err) minimises the potential
 * at load fraction lambda in (0, 1] from x, in place (the caller moves its prescribed targets with
 * lambda). On return x is the last attempt's answer and *converged whether it converged; *used (may
 * be NULL) the increments of that attempt. Errors of increment are passed on, naming the increment. */
typedef int (*rk_load_increment)(void *ctx, double lambda, double *x, int *converged, rk_error *err);
int rk_load_stepping(int n, double *x, rk_load_increment increment, void *ctx, int *converged, int *used,
                     rk_error *err);

/* The time integrator of a simulator with n unknowns: the prediction of each step and the
 * history BDF2 keeps. */
typedef struct {
    int n;
    rk_integrator integrator;
    double h;
    double *xt;             /* the step's start x_t */
    double *xtilde;         /* its inertial prediction x~ */
    double w_inertia;       /* 1 / (alpha h^2) of the step being taken */
    double *x_prev, *v_prev;/* x_{t-1}, v_{t-1} (BDF2) */
    int have_prev;          /* BDF2 history exists (else the step is backward Euler) */
    double *scratch;        /* n */
} rk_stepper;

int rk_stepper_init(rk_stepper *s, int n, rk_integrator integrator, double h, rk_error *err);
void rk_stepper_free(rk_stepper *s);
/* Forgets the history: the next step is backward Euler (a restart, a realigned state). */
void rk_stepper_forget(rk_stepper *s);
/* Begins a step from (x, v): x_t, x~ and w_inertia. */
void rk_stepper_predict(rk_stepper *s, const double *x, const double *v);
/* Where Newton starts: x~ when the problem's max_step (if any) lets x_t reach it, else x_t. */
void rk_stepper_start(rk_stepper *s, const rk_newton_problem *p, double *x);
/* Ends the step at x: v becomes v_{t+1}, and x_t, v_t become the history. */
void rk_stepper_finish(rk_stepper *s, const double *x, double *v);

/* Preconditioned conjugate gradients on a symmetric positive definite operator: apply(ctx, x, y)
 * sets y = A x, precondition(ctx, r, z) sets z = P^-1 r (NULL: z = r). Solves A x = b from the x
 * given, until |r| <= tol |b| or max_iter iterations; *relres (may be NULL) gets |r| / |b|.
 * Returns the iterations taken. work: 4 n. A breakdown (p^T A p <= 0: not positive definite)
 * stops it where it is. The one CG of the precompute: the adaptive subspace method's Schur
 * complement solve and the full-space block-Jacobi baseline. */
/* Solves H z = b for a small dense symmetric H (n x n, column-major) by Cholesky into L (n x n,
 * lower, for later dpotrs solves); when H is not positive definite, by H + s I with s = 1e-10, 1e-8,
 * ... times its largest diagonal entry, up to `attempts` tries in all (the first unshifted).
 * -1 when none factors. */
int rk_spd_solve_shifted(int n, const double *H, double *L, const double *b, double *z, int attempts);

typedef struct {
    int n;
    void *ctx;
    void (*apply)(void *ctx, const double *x, double *y);
    void (*precondition)(void *ctx, const double *r, double *z);
} rk_pcg_problem;
int rk_pcg(const rk_pcg_problem *p, const double *b, double *x, double tol, int max_iter, double *work,
           double *relres);

#endif
