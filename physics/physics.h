/* physics: the one source of truth for per-element physics, written once and compiled for
 * both precisions (DESIGN.md). Pure C99, only <math.h> and <string.h>; used by precompute/fem
 * (double) and by the runtime (float, or double with ROMRT_DOUBLE).
 *
 * How "written once" works: physics_impl.h holds the code, parameterised by
 *   PHYS_REAL       the scalar type
 *   PHYS_FN(name)   the public name of each function
 * and a consumer includes it once per precision it needs, in one .c file, e.g.
 *   #define PHYS_REAL double
 *   #define PHYS_FN(name) rk_##name
 *   #include "physics/physics_impl.h"
 * precompute gets the rk_* double versions from physics/physics_double.c (declared below);
 * the runtime builds its own prefixed copy, so the two can be linked together.
 *
 * Conventions: 3x3 matrices are row-major, F[3*i + j] = F_ij. Fourth-order tensors are 9x9
 * row-major: dPdF[9*(3*i + j) + (3*k + l)] = dP_ij / dF_kl. A tet's vertices are a, b, c, d;
 * Ds = [b-a, c-a, d-a] (columns), F = Ds * Dm^-1 with Dm the rest Ds. */
#ifndef RK_PHYSICS_H
#define RK_PHYSICS_H

typedef enum {
    RK_MAT_LINEAR = 0,     /* small-strain linear elasticity */
    RK_MAT_COROTATED = 1,  /* corotated linear: mu |F - R|^2 + lambda/2 tr(R^T F - I)^2 */
    RK_MAT_STVK = 2,       /* St. Venant-Kirchhoff */
    RK_MAT_NEOHOOKEAN = 3  /* stable Neo-Hookean, Eq. 16 of the freeform paper (Smith et al. 2018) */
} rk_material_model;

/* How a prescribed group moves (fom.h's rk_prescribed, the runtime's PINS chunk). */
typedef enum { RK_MOTION_FIXED = 0, RK_MOTION_TWIST = 1, RK_MOTION_TRANSLATE = 2 } rk_motion_kind;

/* The Newton solver's constants, written once for the precompute's solver (precompute/solver) and
 * the runtime's own C99 loop (runtime/step.c), so the two cannot drift apart:
 *   RK_ARMIJO_C            sufficient decrease: E(x + a d) <= E(x) + c a g.d
 *   RK_MAX_HALVINGS        backtracking halvings before a direction is given up (a down to ~1e-12,
 *                          below which the direction is useless)
 *   RK_ENERGY_NOISE_*      energy differences below this fraction of the terms' magnitude are
 *                          round-off: near the solution the true decrease (~ d^T H d) falls under it,
 *                          and a plain Armijo test would then reject every step and stall Newton
 *                          short of a tight tolerance. Double: 1e-13 (about 450 epsilons, for sums
 *                          over many elements); float: 64 epsilons. */
#define RK_ARMIJO_C 1e-4
#define RK_MAX_HALVINGS 40
#define RK_ENERGY_NOISE_DOUBLE 1e-13
#define RK_ENERGY_NOISE_FLOAT 7.6e-6f

/* Lame parameters from Young's modulus and Poisson's ratio. */
void rk_lame(double young, double poisson, double *mu, double *lambda);

/* Energy density Psi(F) (J/m^3). */
double rk_psi(rk_material_model model, double mu, double lambda, const double F[9]);
/* The same on the displacement gradient Hd = F - I, which keeps small strains exact (F's
 * entries are ~1 and their differences lose digits, in float above all). */
double rk_psi_h(rk_material_model model, double mu, double lambda, const double Hd[9]);
void rk_pk1_h(rk_material_model model, double mu, double lambda, const double Hd[9], double P[9]);
/* First Piola-Kirchhoff stress P = dPsi/dF. */
void rk_pk1(rk_material_model model, double mu, double lambda, const double F[9], double P[9]);
/* dP/dF (9x9); projected to positive semi-definite when project != 0: by the energy's analytic
 * eigensystem (Smith et al. 2019), or with project == RK_PROJECT_JACOBI by a Jacobi eigen-solve
 * of the 9 x 9 matrix (the reference the tests hold the analytic one to). */
#define RK_PROJECT_JACOBI 2
void rk_dpdf(rk_material_model model, double mu, double lambda, const double F[9],
             double dPdF[81], int project);
/* The volume measure theta of a model on Hd = F - I, with dtheta/dF (9): tr eps (linear), tr E
 * (StVK), sum s_i - 3 (corotated), J - 1 (stable Neo-Hookean). Every model splits as
 * Psi(mu, lambda; F) = Psi(mu, 0; F) + lambda/2 theta^2 (physics_impl.h says why for each), which
 * is what a pressure projection evaluates on a projected theta (cubature.h, rk_quadrature_volume). */
double rk_volume_h(rk_material_model model, const double Hd[9], double dtheta[9]);
/* The Hessian of Psi(mu, lambda; F) + pres theta(F) (rk_dpdf with a pressure pres on theta),
 * projected as rk_dpdf's when asked: a projected pressure's point term. */
void rk_dpdf_p(rk_material_model model, double mu, double lambda, double pres, const double F[9],
               double dPdF[81], int project);

/* Tet element kernels. x: 12 (a, b, c, d positions). Dm_inv: 9. vol: rest volume.
 * rk_tet_F: deformation gradient. rk_tet_energy: vol * Psi. rk_tet_gradient: 12 (added
 * into g). rk_tet_hessian: 12x12 row-major (written), from dP/dF (projected if asked). */
void rk_tet_F(const double x[12], const double Dm_inv[9], double F[9]);
double rk_tet_energy(rk_material_model model, double mu, double lambda, const double x[12],
                     const double Dm_inv[9], double vol);
void rk_tet_gradient(rk_material_model model, double mu, double lambda, const double x[12],
                     const double Dm_inv[9], double vol, double g[12]);
void rk_tet_hessian(rk_material_model model, double mu, double lambda, const double x[12],
                    const double Dm_inv[9], double vol, double H[144], int project);

/* Determinant of a 3x3 matrix (row-major); det F <= 0 marks an inverted element. */
double rk_det3(const double A[9]);

/* Rest data of a tet: Dm^-1 and signed volume det(Dm)/6. Returns the signed volume. */
double rk_tet_rest(const double X[12], double Dm_inv[9]);

/* The IPC log barrier b(d) = -(d - dhat)^2 log(d / dhat), 0 < d < dhat, with b' and b'' when asked
 * (d1, d2 may be NULL). */
double rk_barrier(double d, double dhat, double *d1, double *d2);
/* A point's barrier at signed distance d from a surface (physics_impl.h): b(d^2, dhat^2) with its
 * first derivative in d and the second, clamped at 0. */
double rk_barrier_distance(double d, double dhat, double *f1, double *f2);
/* A prescribed group's rigid motion at time t: x = R X + shift (physics_impl.h). */
void rk_motion(rk_motion_kind kind, const double axis[3], const double center[3], double rate,
               const double velocity[3], double t, double R[9], double shift[3]);

/* Colliders an application owns (collider_impl.h): planes, spheres, capsules and boxes acting on
 * points. A collider is a kind and RK_COLLIDER_REALS reals: position (3), rotation (9, row-major,
 * local to world), radius (sphere, capsule), half length (capsule, along its local x), half
 * extents (box, 3). A plane passes through the position, its normal the local z. */
typedef enum { RK_COLLIDER_PLANE = 0, RK_COLLIDER_SPHERE = 1, RK_COLLIDER_CAPSULE = 2, RK_COLLIDER_BOX = 3 } rk_collider_kind;
#define RK_COLLIDER_REALS 17
/* A box's 12 outward triangles over its 8 corners (bit a of a corner's index: the max side on
 * axis a): the scene's box obstacles (precompute/contact/collision.c), the app's boxes on the
 * exact path in the reduced simulator (the same code) and in the runtime (shape_collider.c). */
#define RK_BOX_TRIANGLES {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5}
/* The most vertices an app collider brings as an obstacle: a box's 8 corners (a sphere or capsule
 * brings 1 or 2, a plane none). */
#define RK_COLLIDER_MAX_VERTICES 8
/* Collider slots (the runtime's default ROMRT_MAX_COLLIDERS), and the pull of a moved collider
 * toward where the app put it, over the whole mass's inertia along its path (rom.h). */
#define RK_MAX_COLLIDERS 8
#define RK_COLLIDER_PULL 1e3
/* The scene's moving obstacles solved for with the body (precompute/rom/obstacle_solve.c,
 * runtime/contact_progress.c): the same pull on their progress s, and at most this many rounds of
 * the method of multipliers on it, until they arrive within the solve's tolerance (the pull alone
 * leaves them a h^2 / 1000 short while they push the body at acceleration a), or a round fails to
 * halve the shortfall (the body pinned: the multiplier would only press harder). */
#define RK_OBSTACLE_ROUNDS 8
/* The scene's moving obstacles at most in an asset (the runtime's default
 * ROMRT_MAX_MOVING_OBSTACLES): each is its own progress unknown in a step's joint solve. */
#define RK_MAX_MOVING_OBSTACLES 8
/* rk_collider_check's answers (0: a valid collider). */
enum { RK_COLLIDER_NOT_FINITE = 1, RK_COLLIDER_UNKNOWN_KIND, RK_COLLIDER_BAD_SIZE, RK_COLLIDER_NOT_ROTATION };
int rk_collider_check(int kind, const double *shape);
/* Signed distance of point x from the collider's surface (positive outside), the outward unit
 * normal n there (its gradient) and the closest surface point in the collider's own frame (n,
 * closest may be NULL). */
double rk_collider_distance(int kind, const double *shape, const double x[3], double n[3], double closest[3]);
/* The largest alpha in [0, 1] such that the point moving by alpha dx keeps at least 10% of its
 * starting distance (conservative advancement; exact for a plane), 0 when it starts on or inside. */
double rk_collider_step(int kind, const double *shape, const double x[3], const double dx[3]);
/* The pose a fraction s (clamped to [0, 1]) of the way from `from` to `to`: the position along
 * the line, the rotation by the shortest turn; the size is to's. */
void rk_collider_pose_at(const double *from, const double *to, double s, double *out);
/* d/ds of where the collider's own point `local` is on that path at s. */
void rk_collider_path_velocity(const double *from, const double *to, double s, const double local[3], double v[3]);
/* The largest alpha in [0, 1] such that the point moving by alpha dx while the collider goes from
 * s to s + alpha ds on the path keeps at least 10% of its starting distance (conservative
 * advancement). rk_collider_motion_step: the collider's whole way (s 0, ds 1) past a still point. */
double rk_collider_joint_step(int kind, const double *from, const double *to, double s, double ds, const double x[3],
                              const double dx[3]);
double rk_collider_motion_step(int kind, const double *from, const double *to, const double x[3]);
/* Two orthonormal rows orthogonal to the unit normal n (friction's tangent plane). */
void rk_tangent_basis(const double n[3], double T[6]);
/* Friction's smoothed |u| (IPC Eq. 14-15) for a tangential slip u over a step with threshold
 * eps = eps_v h: f0(|u|), f1(|u|) / |u| and M = d(f1 u / |u|) / du (2 x 2, PSD). */
double rk_friction_smoothed(const double u[2], double eps, double *f1_over_y, double M[4]);

/* Contact between surfaces (contact_impl.h), per stencil: IPC's (Li et al. 2020) distances,
 * barrier and CCD, shared by the precompute's contact (precompute/contact) and the runtime. A
 * stencil is four points x[0..3]: point x[0] against triangle x[1..3], or edge x[0] x[1] against
 * edge x[2] x[3]. */
typedef enum {
    RK_DIST_POINT_POINT = 0, /* v[0], v[1] */
    RK_DIST_POINT_EDGE = 1,  /* point v[0], edge v[1] v[2] */
    RK_DIST_POINT_PLANE = 2, /* point v[0], the plane of triangle v[1] v[2] v[3] */
    RK_DIST_LINE_LINE = 3    /* line v[0] v[1], line v[2] v[3] */
} rk_distance_kind;
/* Which feature pair of a stencil is closest: v[] index the stencil's four points (-1: unused). */
typedef struct {
    rk_distance_kind kind;
    int v[4];
} rk_distance_case;
/* The closest feature pair of point x[0] against triangle x[1..3]; of edge x[0] x[1] against
 * edge x[2] x[3]. */
rk_distance_case rk_point_triangle_case(const double *const x[4]);
rk_distance_case rk_edge_edge_case(const double *const x[4]);
/* The squared distance of case c over the stencil's four points, with its gradient (12, in the
 * order of x) and Hessian (144, row-major) when g, H are not NULL (exact, by automatic
 * differentiation). */
double rk_contact_distance2(rk_distance_case c, const double *const x[4], double *g, double *H);
/* The closest points' weights: sum_i w[i] x[i] is the vector from the second feature's closest
 * point to the first's (point minus triangle, edge a minus edge b), the contact normal's direction
 * and what friction's relative motion is measured on. */
void rk_contact_closest_weights(rk_distance_case c, const double *const x[4], double w[4]);
/* The edge-edge mollifier of x[0] x[1] against x[2] x[3] with threshold eps (1e-3 |ea|^2 |eb|^2 at
 * rest), with gradient and Hessian (may be NULL). */
double rk_edge_edge_mollifier(const double *const x[4], double eps, double *g, double *H);
/* One pair's barrier b(d^2 - xi^2, dhat^2 + 2 xi dhat) (rk_barrier), times the edge-edge
 * mollifier when edge_edge and eps > 0, unscaled by kappa: d the stencil's distance, xi its
 * thickness (0 between meshes, a sphere's or capsule's radius). Gradient (12) and Hessian (144,
 * row-major, unprojected) when g, H are not NULL; *dist (may be NULL) = d - xi. +INFINITY when
 * d <= xi (g, H untouched); 0 beyond reach (d - xi >= dhat), g and H zeroed. */
double rk_pair_barrier(int edge_edge, const double *const x[4], double xi, double dhat, double eps, double *g,
                       double *H, double *dist);
/* Projects a pair's Hessian H (12 x 12) to PSD on the points that take part (a non-zero row) and
 * are unknowns (dof[k] != 0); the other rows and columns are zeroed. */
void rk_pair_project(const int dof[4], double *H);
/* Friction's lagged frame of one pair (IPC Sec. 5): returns its normal force kappa m |db/dd|
 * (d the distance, m the mollifier as rk_pair_barrier takes them), with the closest points'
 * weights w (rk_contact_closest_weights) and the tangent basis T (2 orthonormal rows) of the
 * normal sum_i w_i x_i; 0 when the pair exerts no force (out of reach, touching, or no normal). */
double rk_pair_friction_lag(int edge_edge, const double *const x[4], double xi, double dhat, double eps,
                            double kappa, double w[4], double T[6]);
/* Smoothed Coulomb friction of one lagged pair whose closest points moved by rel (3) since the
 * step began: scale f0(|u|), u = T rel (rk_friction_smoothed, threshold eps = eps_v h; scale = mu
 * lambda), with its gradient in rel g = scale f1/|u| T^T u (3) and Hessian B = scale T^T M T
 * (3 x 3, PSD) when g, B are not NULL. */
double rk_friction_slip(const double T[6], const double rel[3], double eps, double scale, double g[3], double B[9]);
/* Additive CCD of one stencil (point-triangle, or edge_edge) from positions x moving by dx over
 * t in [0, tmax], the stencil kept xi apart: 1 with *toi a conservative time of impact (the
 * stencil at toi is still at least 10% of its starting gap apart), 0 when it stays apart. A
 * stencil that starts within xi reports toi 0. */
int rk_ccd_stencil(int edge_edge, const double *const x[4], const double *const dx[4], double xi, double tmax,
                   double *toi);

/* Symmetric eigen-decomposition (cyclic Jacobi) of an n x n matrix, n <= 12: A = V diag(w) V^T,
 * V's columns are eigenvectors (row-major storage). A is not modified. */
void rk_sym_eig(int n, const double *A, double *w, double *V);
/* Clamps negative eigenvalues of a symmetric n x n matrix to zero, in place. */
void rk_project_psd(int n, double *A);

#endif
