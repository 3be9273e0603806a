/* precompute/rom: the reduced simulator, in double precision; the reference the runtime is
 * checked against. Positions live in a subspace x = X + U q (any basis of precompute/basis:
 * skinning bases through their affine handles, Eq. 1 of the freeform paper), and each step
 * minimises the same incremental potential as the full-order model (fom.h) restricted to it:
 *
 *   q_{t+1} = argmin_q  w/2 |q - q~|_{M_r}^2 + E(q) + B(q) + 1/(2h) |q - q_t|_{C_r}^2 - f_r . q + P(q, t)
 *
 * with M_r = U^T M U, C_r = U^T (a M + b K0) U, f_r = U^T f_ext, E the elastic energy integrated
 * by a quadrature (all elements, or a cubature; cubature.h), B the contact barrier (IPC,
 * precompute/contact: the boundary vertices x_v = X_v + U_v q against the scene's obstacles, the
 * other objects and, with self-contact, itself), and P a penalty that pulls prescribed vertices
 * to their targets where the basis does not already hold them (its rows there are not all zero):
 *
 *   P(q, t) = k/2 sum_i m_i |X_i + B_i q - target_i(t)|^2,   k = RK_ROM_PIN_STIFFNESS (lambda+2mu)/(rho L^2),
 *
 * L the bounding-box diagonal. A lifted model (rom.clamp "lifted", rkpm_lift.c) holds its moving
 * group exactly instead: the weights vanish there but the lifting handle's, whose 12 coordinates are
 * the group's motion at the time solved for, so x(q, t) = X + w_L (T(t) X - X) + U q and the
 * potential above (inertia, elastic energy, damping) is minimised over the other coordinates. Backward Euler or BDF2 as in fom.h, projected Newton on a dense
 * r x r Cholesky, Armijo backtracking, every step filtered by CCD like full order, moving
 * obstacles advanced as far as CCD allows before each solve. Nothing per step costs
 * O(vertices) except contact (O(boundary vertices x r), only with something to collide with).
 * The barrier stiffness is fixed (the runtime steps the same model): the scene's contact.kappa,
 * or rk_contact_holding_kappa of the average vertex's weight. */
#ifndef RK_ROM_H
#define RK_ROM_H

#include "cubature/cubature.h"
#include "fem/fem.h"
#include "fom/fom.h"
#include "util/util.h"

/* The penalty stiffness relative to the stiffest material's wave speed over the object's size:
 * large against every elastic and inertial stiffness the subspace can see, small enough to keep
 * the r x r Newton matrix well conditioned in double precision. */
#define RK_ROM_PIN_STIFFNESS 1e4 /* the default; a scene's rom.pin_stiffness (rk_fom_options) replaces it */

/* A prescribed group in the subspace: k sum_i m_i B_i^T (target_i(t) - X_i) = T (r x 12) times
 * the 12 numbers vec(R(t) - I), shift(t) of rk_prescribed_transform. */
typedef struct {
    rk_prescribed motion;      /* verts not used */
    double *T;                 /* r x 12, column-major */
} rk_rom_pin;

typedef struct {
    int r;
    int nv;                    /* full-order vertices */
    double h;
    double static_time;        /* a static model's equilibrium is at steps h */
    rk_integrator integrator;
    int is_static;
    double *M;                 /* r x r, U^T M U (column-major) */
    double *M_chol;            /* its Cholesky factor (upper), for projections onto the subspace */
    double *M_proj_chol;       /* mesh-free models: the factor of U^T M U with the fem's vertex mass, which
                                * rk_rom_project's full-order states are measured in (M_r is the points'
                                * mass); NULL: M_chol is that */
    double *C;                 /* r x r, U^T (a M + b K0) U, or NULL without damping */
    double *f;                 /* r, U^T f_ext (gravity with the lumped masses, plus forces) */
    double pin_k;              /* k of the penalty */
    double *A;                 /* r x r, k sum_i m_i B_i^T B_i over the penalised vertices */
    int npins;
    rk_rom_pin *pins;
    int pinned_vertices;       /* prescribed vertices held by the penalty (0: the basis holds them all) */
    /* rom.clamp "lifted" (rkpm_lift.c): 1 + the handle whose 12 coordinates are the moving group's
     * prescribed motion vec(R(t) - I), s(t), set at the time solved for (rk_rom_lift) and kept out
     * of every Newton step (zero gradient, identity rows of the Hessian); 0: none */
    int lift_handle;
    rk_prescribed lift_motion; /* verts not used */
    double *lift_fix;          /* r x 12: -P_ff^-1 P_fL (P the projection's mass, f the other coordinates):
                                * how a projected state's other coordinates follow when its lifted ones
                                * are set to their prescribed values (rk_rom_reset) */
    /* The collision vertices (the boundary: what the scene's contact and an app's colliders act
     * on), always, and their rows; the contact model when the scene has something to collide. */
    int ncv, *cv;              /* ascending mesh vertex ids */
    double *cv_rows;           /* 3 ncv x r, row-major: U's rows at the collision vertices */
    double *cv_X;              /* 3 ncv: their rest positions */
    int *cv_of;                /* nv: collision vertex index of a mesh vertex, or -1 */
    rk_contact_options contact_options; /* dhat and kappa resolved: the barrier of contact and colliders */
    int has_contact;
    /* the model has a collision surface (a scene obstacle other than a plane, several objects or
     * self-contact, or the surface for the app's shapes: what the asset's OBHD records): the app's
     * spheres, capsules and boxes are then obstacles of the contact model, exact against its
     * triangles (collider_obstacles.c) */
    int surface;
    /* the contact model was built for the app's shapes alone (rk_rom_contact_for_colliders): the
     * scene has no contact, and the model is in the step only while a shape is one of its obstacles */
    int colliders_contact;
    rk_contact contact;
    double mass;               /* total mass (kg) */
    double newton_tol;         /* on sqrt(dq^T M_r dq / mass) (m), per step */
    int newton_max_iter;
    rk_quadrature quad;        /* the elastic energy's points (owned) */
} rk_rom_model;

/* Builds the reduced model of a full-order setup (fem and options exactly as the full-order
 * model gets them) in the subspace U (3 nv x r, column-major), with the elastic energy over
 * quad (taken over: the model owns and frees it, also on failure). points (may be NULL): a
 * mesh-free model (freeform paper Eq. 22), U linear blend skinning over points->H handles: the
 * mass, gravity and rest stiffness (damping) are integrated at these points instead of over the
 * fem's elements (the vertices' masses then only weigh the penalty and the loads). */
int rk_rom_model_init(rk_rom_model *m, const rk_fem *fem, const rk_fom_options *opt, const double *U,
                      int r, rk_quadrature *quad, const rk_skin_points *points, rk_error *err);
void rk_rom_model_free(rk_rom_model *m);
/* The app's spheres, capsules and boxes on the collision surface's triangles, as the runtime meets
 * them on an asset baked with the surface for its colliders (rom.asset.colliders true, the default:
 * bake_obstacles.c): a model without a surface of its own gets one (the contact model with no
 * obstacle, built as that bake builds it), which stays out of the step until a shape is placed
 * (runtime/contact.c's rt_surface_on). Nothing to do on a model with a surface or no boundary. */
int rk_rom_contact_for_colliders(rk_rom_model *m, const rk_fem *fem, rk_error *err);
/* That surface into *out (freed by the caller with rk_contact_free; nothing to free on failure):
 * the contact stage's boundary of fem, the one rk_rom_contact_init took the model's collision
 * vertices from, with no obstacle, one object and the model's barrier. */
int rk_rom_colliders_surface(const rk_rom_model *m, const rk_fem *fem, rk_contact *out, rk_error *err);

typedef struct {
    long steps, newton_iterations, line_search_halvings, unconverged_steps;
    long projected_hessians;   /* iterations whose exact Hessian was not positive definite (newton.c) */
    double seconds_total;
} rk_rom_stats;

/* An application's collider (physics.h: a kind and its RK_COLLIDER_REALS reals). */
typedef struct {
    rk_collider_kind kind;
    double shape[RK_COLLIDER_REALS];
} rk_collider;

/* A collider slot of the simulator: where the collider is, where the app wants it, where it was
 * when the step began and when friction was lagged. */
typedef struct {
    int active;
    rk_collider_kind kind;
    double now[RK_COLLIDER_REALS], target[RK_COLLIDER_REALS], start[RK_COLLIDER_REALS], lag[RK_COLLIDER_REALS];
    int exact;                 /* an obstacle of the contact model (model->surface), not on the vertices */
    int obstacle;              /* then its index among the contact model's obstacles */
} rk_rom_collider;

typedef struct {
    rk_rom_model *model;
    double t;
    rk_rom_collider colliders[RK_MAX_COLLIDERS];
    int ncolliders;            /* active slots */
    int colliders_behind;      /* the last step left a collider short of its pose (the body was in the way) */
    double *xs, *xl;           /* 3 nv: collision vertices where the step began and where friction was lagged */
    double *x, *dx, *gx;       /* 3 nv contact scratch: positions, a step, a gradient */
    double *odx;               /* 3 obstacle vertices: their way over a step */
    /* a joint solve moving the obstacles (obstacle_solve.c): their way (NULL outside one), the
     * contact terms' gradient at the obstacle vertices (3 onv), and their derivatives in the
     * obstacles' progress s (n = obs_way->n of them: d/ds n, d2/ds2 n x n, d2/dq ds r x n, all
     * column-major) */
    rk_obstacle_way *obs_way;
    double *ogx, *obs_gs, *obs_hss, *obs_hqs;
    double *jb;                /* 12 x r contact scratch */
    rk_contact_set pairs;      /* this evaluation's contact pairs */
    double *q, *v;             /* reduced positions and velocities */
    rk_stepper stepper;        /* backward Euler / BDF2: prediction and history */
    rk_rom_stats stats;
    double *work;              /* scratch */
    int exact_hessian;         /* the elements' dP/dF unprojected (newton.c's first try each iteration) */
} rk_rom;

/* Starts at q, v (NULL: rest), t = 0. */
int rk_rom_init(rk_rom *s, rk_rom_model *m, const double *q0, const double *v0, rk_error *err);
/* One time step (or, for a static model, the equilibrium at the end time steps*h). */
int rk_rom_step(rk_rom *s, rk_error *err);
/* Puts the state back to (q, v) at time t, with no BDF2 history (the online-error realignment). */
void rk_rom_reset(rk_rom *s, const double *q, const double *v, double t);
/* rk_rom_reset for a state that may not be reachable: with contact, the model moves from where it
 * is (a valid state at time t) toward q only as far as CCD allows, since a full-order state
 * projected onto the subspace can put boundary vertices behind an obstacle. The fraction of the
 * way it got (1: exactly q) into *reached; -1 on failure. */
int rk_rom_realign(rk_rom *s, const double *q, const double *v, double t, double *reached, rk_error *err);
void rk_rom_free(rk_rom *s);
/* An application's colliders (the runtime's romrt_set_collider, in double): slot 0 ..
 * RK_MAX_COLLIDERS - 1. A collider of the slot's kind and size moves there in the next step, its
 * progress along the way solved for with the body (collider_solve.c); where the body cannot give
 * way it stops short (colliders_behind) and goes on the step after. A new one, or a new kind or
 * size, must be placed clear of the body. They act on the collision vertices with the barrier of
 * the scene's planes and, with contact.friction, its friction; on a model with a collision surface
 * (model->surface) a sphere, capsule or box is instead an obstacle of the contact model, moved
 * with the scene's moving obstacles (as the runtime's, shape_collider.c). A bad collider is
 * refused, naming what, and changes nothing. */
int rk_rom_set_collider(rk_rom *s, int slot, const rk_collider *c, rk_error *err);
int rk_rom_remove_collider(rk_rom *s, int slot, rk_error *err);
/* Contact at the current state, as rk_fom_contact_measure: exact crossings of the reduced surfaces
 * (0 for a valid state) and their smallest distance (INFINITY without contact). */
int rk_rom_contact_measure(rk_rom *s, int *intersections, double *min_distance, rk_error *err);

/* A lifted model's prescribed coordinates of q set to their values at time t (nothing without). */
void rk_rom_lift(const rk_rom_model *m, double t, double *q);

/* q = argmin |X + U q - x|_M, the M-orthogonal projection of a full-order state onto the subspace
 * (x - X for positions, or a velocity with X = NULL); M is the model's inertia mass. */
int rk_rom_project(const rk_rom_model *m, const rk_sparse *M, const double *U, int ndof, const double *X,
                   const double *x, double *q, rk_error *err);
/* x = X + U q, all 3 nv coordinates. */
void rk_rom_positions(const double *U, int ndof, int r, const double *X, const double *q, double *x);

#endif
