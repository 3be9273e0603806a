/* Private to precompute/rom: the terms of one minimisation and the pieces step and Newton share. */
#ifndef RK_ROM_IMPL_H
#define RK_ROM_IMPL_H

#include "rom/rom.h"

/* The potential being minimised (rom.h), like rk_fom_terms: dynamics w_inertia = 1/(alpha h^2),
 * w_damping = 1/h, load 1; static w_inertia = w_damping = 0, load in (0, 1] and a small
 * mass-proportional shift reg on the Hessian only. pin_b: the penalty's target term at the
 * time being solved for. */
typedef struct {
    double w_inertia;
    const double *qtilde;
    double w_damping;
    const double *qt;
    double load;
    double reg;
    const double *pin_b;
    int friction;              /* add the lagged friction potential (dynamics with contact.friction > 0) */
} rk_rom_terms;

/* rk_rom.work: vectors of r (indices below; NEWTON is RK_NEWTON_WORK(r) long), then the r x r
 * Newton matrix. */
enum { RK_ROM_WORK_PIN, RK_ROM_WORK_TMP, RK_ROM_WORK_TMP2, RK_ROM_WORK_NEWTON,
       RK_ROM_WORK_VECTORS = RK_ROM_WORK_NEWTON + 3 };

/* The potential at q; with g its gradient, with H its Hessian (r x r, both triangles).
 * +INFINITY where undefined; NAN (err set) when the contact stage failed. */
double rk_rom_potential(rk_rom *s, const rk_rom_terms *T, const double *q, double *g, double *H,
                        double *magnitude, rk_error *err);
void rk_rom_pin_target(const rk_rom_model *m, double t, double *b);
/* A lifted model's 12 prescribed coordinates at time t (rk_rom_lift). */
void rk_rom_lift_values(const rk_rom_model *m, double t, double ql[12]);

/* newton.c: the RMS displacement of a step d of q, sqrt(d^T M_r d / mass); d = -H^-1 g by Cholesky
 * of the n x n H (upper triangle, overwritten), failing with what the matrix is of. */
double rk_rom_step_rms(rk_rom *s, const double *d);
int rk_rom_dense_solve(double *H, int n, const double *g, double *d, const char *what, rk_error *err);

/* The scene's moving obstacles to where they are at t, solved for with the body (obstacle_solve.c);
 * *behind: they stopped short (the body was in the way). */
int rk_rom_obstacles_solve(rk_rom *s, const rk_rom_terms *T, double t, int *converged, int *behind, rk_error *err);

/* Whether the contact model is in the step: the scene's contact, or a surface built for the app's
 * shapes alone once one of them is its obstacle (rk_rom_contact_for_colliders). */
static inline int rk_rom_contact_on(const rk_rom_model *m)
{
    return m->has_contact || (m->colliders_contact && m->contact.nobstacles > 0);
}

/* Contact in the subspace (contact.c). */
int rk_rom_contact_init(rk_rom_model *m, const rk_fem *fem, const rk_fom_options *opt, const double *U, rk_error *err);
void rk_rom_contact_positions(rk_rom *s, const double *q);
/* The collision vertices at q into s->x and their move U_v dq into s->dx (dq NULL: 0). */
void rk_rom_contact_move(rk_rom *s, const double *q, const double *dq);
/* The barrier at q (and, with friction, the lagged friction potential of a step of h): value,
 * g += its reduced gradient, H += its reduced Hessian (g, H may be NULL). */
double rk_rom_contact_energy(rk_rom *s, const double *q, int friction, double *g, double *H, rk_error *err);
/* H += J^T B J for a block B over its points' rows J (mesh vertex ids; obstacle points have
 * none): the contact stage's Hessian sink (ctx: rk_rom_reduce_ctx). */
typedef struct {
    const rk_rom_model *m;
    double *H;      /* r x r, column-major (both triangles) */
    double *JB;     /* 12 x r scratch */
    /* a joint solve moving the obstacles (obstacle_solve.c), or NULL: their way D, and the block's
     * d2/dq ds (r x way->n) and d2/ds2 (way->n x way->n) added into hqs and hss */
    const rk_obstacle_way *way;
    double *hqs, *hss;
} rk_rom_reduce_ctx;
void rk_rom_reduce_block(void *ctx, const int *id, int npoints, const double *B);
/* s->gx zeroed at the collision vertices; g += the rows' pull of s->gx. */
void rk_rom_clear_vertex_gradient(rk_rom *s);
void rk_rom_pull_vertex_gradient(rk_rom *s, double *g);

/* The app's colliders (colliders.c): their barrier and lagged friction at q; the largest step
 * along s->dx from s->x (positions and step set); whether one has somewhere to go; friction's
 * records (positions in s->x). */
double rk_rom_colliders_energy(rk_rom *s, const double *q, int friction, double *g, double *H);
double rk_rom_colliders_max_step(rk_rom *s);
int rk_rom_colliders_pending(const rk_rom *s);
/* For collider `slot` at s_k on its path from `from` to its target (its pose now set there):
 * g_s, H_ss (may be NULL) and H_qs (r, may be NULL) += the derivatives of its terms in s_k. */
void rk_rom_colliders_path_terms(rk_rom *s, const double *q, int slot, const double *from, double sk, double *gs,
                                 double *hss, double *hqs);
/* The step's solve with every moved collider's progress along its path as an unknown
 * (collider_solve.c); the colliders end where it leaves them. */
int rk_rom_colliders_solve(rk_rom *s, const rk_rom_terms *T, int *converged, rk_error *err);
/* The app's spheres, capsules and boxes on a model with a collision surface (collider_obstacles.c):
 * slot's collider set to c (NULL: gone) among the contact model's obstacles, placed clear of the
 * body or refused with nothing changed; after a step, the ones that arrived at their poses. */
int rk_rom_collider_obstacles(rk_rom *s, int slot, const rk_collider *c, rk_error *err);
/* Slot `slot` now holds c, standing at its pose (exact: as an obstacle; colliders.c). */
void rk_rom_collider_take(rk_rom *s, int slot, const rk_collider *c, int exact);
void rk_rom_collider_obstacles_arrived(rk_rom *s);
void rk_rom_colliders_friction_start(rk_rom *s);
void rk_rom_colliders_friction_lag(rk_rom *s);

/* Friction's step start (positions at q) and its lag at q (contact.h). */
int rk_rom_friction_start(rk_rom *s, const double *q, rk_error *err);
int rk_rom_friction_lag(rk_rom *s, const double *q, rk_error *err);
/* The largest alpha in [0, 1] CCD allows along q + alpha dq (dq NULL: still) with the obstacles
 * moving toward time t (NAN: still); -1 on failure. */
double rk_rom_contact_max_step(rk_rom *s, const double *q, const double *dq, double t, rk_error *err);
/* Exact crossings at q (rk_contact_intersections). */
int rk_rom_contact_intersections(rk_rom *s, const double *q, rk_error *err);

/* The reduced potential as the solver's problem: dense Cholesky (LAPACK) for the direction,
 * contact step filtering, and sqrt(dq^T M_r dq / mass) as the step size (an RMS displacement, m). */
typedef struct {
    rk_rom *s;
    const rk_rom_terms *T;
    rk_error failure;          /* set when the contact stage failed inside a callback */
    const double *q;           /* where the last Hessian was asked for (the solve may need it again) */
} rk_rom_problem_ctx;
void rk_rom_problem(rk_rom_problem_ctx *ctx, rk_newton_problem *p);
/* Minimises the potential from s->q (in place) with the solver's Newton; converged when the step
 * size above is <= tol_d. */
int rk_rom_newton(rk_rom *s, const rk_rom_terms *T, double tol_d, int *converged, rk_error *err);

#endif
