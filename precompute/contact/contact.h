/* precompute/contact: incremental potential contact (IPC, Li et al. 2020), once, for the full-order
 * simulator and the simulators built on it.
 *
 *   distances       point-triangle and edge-edge, reduced to the closest feature pair (point-point,
 *                   point-edge, point-plane, line-line), squared, with gradients and Hessians;
 *                   the edge-edge mollifier for nearly parallel edges (Sec. 4.3): per stencil in
 *                   physics/contact_impl.h, written once with the runtime
 *   barrier         b(d^2 - xi^2, dhat^2 + 2 xi dhat) of physics/physics.h (the one barrier, shared with
 *                   the runtime); xi is a thickness: 0 between meshes, the radius of a sphere or
 *                   capsule obstacle (a point or a segment with a thickness)
 *   broad phase     a spatial hash over the boundary primitives' boxes, grown by dhat, or swept
 *                   along a step
 *   CCD             additive CCD (Li et al. 2021): the largest step along a direction that keeps
 *                   every pair apart, so no line search trial ever intersects (one stencil's in
 *                   physics/contact_impl.h)
 *   stiffness       kappa set and adapted as IPC does (supplement, Sec. 3.3)
 *   friction        smoothed Coulomb (Sec. 5) with lagged normal forces and tangent bases
 *   intersections   an exact test (orientation predicates in exact arithmetic) of whether any
 *                   segment crosses any triangle: the check the tests and reports run
 *
 * The collision geometry is the objects' boundary surface (vertices, edges, triangles; the
 * positions are degrees of freedom) and the obstacles (planes, spheres, capsules and triangle
 * meshes, boxes included, whose positions are prescribed in time). A stencil names up to four
 * points by id: id >= 0 is collision vertex id, id < 0 is obstacle vertex -1 - id. */
#ifndef RK_CONTACT_H
#define RK_CONTACT_H

#include "fem/fem.h"
#include "mesh/mesh.h"
#include "physics/physics.h"
#include "util/util.h"

/* The per-stencil math (distances, the mollifier, one pair's barrier, CCD of one stencil) is
 * physics/physics.h's rk_point_triangle_case ... rk_ccd_stencil, shared with the runtime. */

/* ---- broad phase (broad.c) ---- */

/* The pairs (a, b) of boxes that overlap, a from boxes_a (na boxes, 6 numbers each: min xyz, max
 * xyz) and b from boxes_b: *pairs (2 *npairs ints, malloc'd, sorted, each pair once). */
int rk_broad_phase(const double *boxes_a, int na, const double *boxes_b, int nb, int **pairs, int *npairs,
                   rk_error *err);

/* Whether boxes a and b (min xyz, max xyz) overlap (touching counts), the broad phase's test. */
int rk_boxes_overlap(const double *a, const double *b);

/* ---- the collision geometry (collision.c) ---- */

typedef enum {
    RK_OBSTACLE_PLANE = 0,   /* an infinite half-space boundary: point, unit normal toward the free side */
    RK_OBSTACLE_SPHERE = 1,  /* a solid ball: center, radius */
    RK_OBSTACLE_CAPSULE = 2, /* a solid capsule: the segment center..end, radius */
    RK_OBSTACLE_BOX = 3,     /* a solid axis-aligned box: min, max (its 12 triangles) */
    RK_OBSTACLE_MESH = 4     /* a triangle surface, open or closed: X (3 nv), tris (3 nf) */
} rk_obstacle_kind;

/* An obstacle: static, or moving by a prescribed motion (fom.h's kinds: translate or twist). */
typedef struct {
    rk_obstacle_kind kind;
    double point[3], normal[3];    /* plane */
    double center[3], radius;      /* sphere; capsule (center and end) */
    double end[3];
    double min[3], max[3];         /* box */
    int nv, nf;                    /* mesh */
    const double *X;
    const int *tris;
    rk_motion_kind motion;         /* RK_MOTION_FIXED: static */
    double axis[3], motion_center[3], rate, velocity[3];
    /* an app's collider (rk_contact_set_app_obstacles): its geometry above in its own frame, and
     * at every time where the pose puts it (position 3, rotation 9 row-major: physics.h's
     * collider layout), the motion ignored */
    int posed;
    double pose[12];
} rk_obstacle;

typedef struct {
    double dhat;                   /* barrier activation distance (m) */
    double kappa;                  /* barrier stiffness (J); 0: adaptive, as IPC */
    double friction;               /* Coulomb coefficient mu (0: frictionless) */
    double eps_v;                  /* friction smoothing speed (m/s): static below it */
    int friction_iterations;       /* lagging iterations per step */
    int self;                      /* self-contact of each object */
} rk_contact_options;

/* Defaults: dhat 0 (the caller sets it: 1e-3 of the scene's bounding-box diagonal), adaptive kappa,
 * no friction, eps_v 1e-3 m/s, 3 lagging iterations, no self-contact. */
void rk_contact_default_options(rk_contact_options *o);

typedef enum { RK_PAIR_POINT_TRIANGLE = 0, RK_PAIR_EDGE_EDGE = 1, RK_PAIR_POINT_PLANE = 2 } rk_pair_kind;

/* A stencil: id >= 0 a mesh vertex (a degree of freedom), id < 0 obstacle vertex -1 - id; a
 * point-plane pair is (vertex, plane obstacle index). */
typedef struct {
    rk_pair_kind kind;
    int id[4];
    double xi;                     /* thickness */
    double eps;                    /* edge-edge mollifier threshold (0: none) */
} rk_contact_pair;

typedef struct {
    int n, cap;
    rk_contact_pair *pairs;
} rk_contact_set;

/* A friction pair, lagged (friction.c): its points (stencil ids; one point against a plane), the
 * closest-point weights, the tangent basis (two orthonormal rows) and the normal force (N). */
typedef struct {
    int np, id[4];
    double w[4];
    double T[6];
    double lambda;
} rk_friction_pair;

typedef struct {
    long steps, gathers, pairs, max_pairs, ccd_calls; /* pairs: summed over the gathers */
    double seconds_broad, seconds_ccd, seconds_potential;
} rk_contact_stats;

/* The contact model of a mesh: its boundary surface (the collision vertices, edges and triangles;
 * positions are the mesh's, x[3 v]) split by object, and the obstacles with their own vertices. */
typedef struct {
    rk_contact_options opt;
    int nmesh;                     /* mesh vertices: x has 3 nmesh entries */
    int nv, *vertex;               /* collision vertices: their mesh vertex ids */
    int *object;                   /* nmesh: the object of every mesh vertex */
    int mesh_pairs;                /* the mesh can touch itself: several objects, or self-contact */
    int ne, *edges;                /* 2 ne mesh vertex ids */
    int nf, *faces;                /* 3 nf mesh vertex ids, outward */
    double *X;                     /* 3 nmesh rest positions (the mollifier's rest edge lengths) */
    int nobstacles;
    rk_obstacle *obstacles;        /* copies (mesh arrays owned below) */
    int onv;                       /* obstacle vertices: oX at rest, ox at the time set */
    double *oX, *ox;
    int *overt_obstacle;           /* onv: its obstacle */
    /* the scene's obstacles come first (these counts of obstacles, vertices, edges, triangles),
     * the app's after them (rk_contact_set_app_obstacles) */
    int scene_obstacles, scene_onv, scene_one, scene_onf;
    int one, *oedges, onf, *ofaces;/* obstacle vertex ids */
    double *othick;                /* nobstacles: the thickness xi (sphere, capsule radius; else 0) */
    double *oplane;                /* nobstacles x 6: a plane's point and unit normal where it is now */
    double *ox_to, *oplane_to;     /* scratch: where the obstacles are going (rk_contact_max_step) */
    double kappa, kappa_min, kappa_max;
    int kappa_set;                 /* adaptive kappa initialized */
    double min_distance_last;      /* the smallest distance at the last kappa update (NAN: none yet) */
    double bbox_diagonal;
    int exact_hessian;             /* tests: hand over the Hessian blocks unprojected */
    int obstacle_dofs;             /* the simulator moves obstacle vertices as unknowns (their Hessian rows count) */
    /* The gather's candidates (a Verlet list): stencils within 2 dhat where the surfaces were at
     * cache_x / cache_ox, good while nothing has moved dhat / 2 since. */
    rk_contact_set cache;
    double *cache_x, *cache_ox;    /* 3 nv (collision vertices), 3 onv */
    int cache_valid;
    rk_contact_stats stats;
    /* Friction: the lagged pairs, and where the mesh and the obstacles were when the step began. */
    int nfriction, capfriction;
    rk_friction_pair *friction;
    rk_contact_set friction_pairs;
    double *fx0, *fox0;            /* 3 nmesh, 3 onv */
} rk_contact;

/* Builds the contact model of mesh (its rest positions X, its boundary) whose objects start at
 * object_first_vertex[0..nobjects] (NULL: one object), against the obstacles, with average vertex
 * mass average_mass (IPC's kappa bounds). Checks every obstacle (finite, positive radius, non-zero
 * normal, a mesh's indices) and names the first bad one. */
int rk_contact_init(rk_contact *c, const rk_mesh *mesh, const int *object_first_vertex, int nobjects,
                    const rk_obstacle *obstacles, int nobstacles, const rk_contact_options *o, double average_mass,
                    rk_error *err);
void rk_contact_free(rk_contact *c);
/* The app's colliders as obstacles after the scene's (replacing the ones there), each posed
 * (rk_obstacle.posed) and standing at its pose; the scene's obstacles stay where they are. The
 * Verlet list and the lagged friction pairs are dropped (the obstacle vertex ids may change). A
 * bad one is named by its index in apps; on failure c is unchanged. */
int rk_contact_set_app_obstacles(rk_contact *c, const rk_obstacle *apps, int n, rk_error *err);
/* Where app obstacle k (an index into c->obstacles) is due: it goes there as the scene's moving
 * obstacles go to where they are at a time (rk_contact_set_time, rk_obstacle_way). */
void rk_contact_pose_obstacle(rk_contact *c, int k, const double pose[12]);
/* Moves the obstacles to where their motions put them at time t (ox, oplane). */
void rk_contact_set_time(rk_contact *c, double t);
/* Where the obstacle vertices are at time t, into out (3 onv), without moving them. */
void rk_contact_obstacles_at(const rk_contact *c, double t, double *out);

/* ---- contact pairs and the barrier potential (pairs.c, potential.c) ---- */

void rk_contact_set_free(rk_contact_set *s);
/* The pairs of c closer than dhat (plus their thickness) at mesh positions x, obstacles where
 * rk_contact_set_time put them. */
int rk_contact_gather(rk_contact *c, const double *x, rk_contact_set *s, rk_error *err);

/* Called with each pair's Hessian block: ids of its npoints points (obstacle ids negative) and
 * the 3 npoints x 3 npoints block (row-major, PSD-projected). */
typedef void (*rk_hessian_sink)(void *ctx, const int *id, int npoints, const double *H);

/* The barrier kappa sum_k m_k b(d_k^2 - xi^2, dhat^2 + 2 xi dhat) over the pairs of s at x (m_k
 * the mollifier of edge-edge pairs): its value (+INFINITY when a pair touches or a point is
 * behind a plane), with g (3 nmesh, may be NULL) and og (3 onv, the obstacle vertices, may be
 * NULL) += its gradient and each pair's projected Hessian to sink (may be NULL). *min_distance
 * (may be NULL): the smallest distance of the pairs. */
double rk_contact_energy(rk_contact *c, const rk_contact_set *s, const double *x, double *g, double *og,
                         rk_hessian_sink sink, void *ctx, double *min_distance);

/* Each pair's barrier energy (as rk_contact_energy counts it) shared equally among its mesh
 * points, added into e (nmesh; +INFINITY where a pair touches): the per-vertex energies the
 * adaptive subspace oracle's progress measure sums over one-rings. */
void rk_contact_point_energy(const rk_contact *c, const rk_contact_set *s, const double *x, double *e);

/* ---- friction (friction.c) ---- */

/* Records the step's start: mesh positions x and the obstacles where they are (friction's x^t). */
int rk_contact_friction_start(rk_contact *c, const double *x, rk_error *err);
/* Lags the friction pairs at x (obstacles where they are): every pair inside dhat with its normal
 * force kappa |db/dd|, its tangent basis and closest-point weights (nothing without friction). */
int rk_contact_friction_lag(rk_contact *c, const double *x, rk_error *err);
/* The lagged friction potential mu sum_k lambda_k f0(|u_k|) at x (obstacles where they are) for a
 * step of h seconds, with g and og += its gradient and each pair's Hessian block (PSD without
 * projection) to sink; both may be NULL. */
double rk_contact_friction_energy(const rk_contact *c, const double *x, double h, double *g, double *og,
                                  rk_hessian_sink sink, void *ctx);

/* ---- stiffness (stiffness.c) ---- */

/* A fixed kappa for simulators that cannot adapt it (the reduced model and the runtime step the
 * same asset): a point at dhat / 2 from a surface pushes back with 10 times `weight` (N; a vertex's
 * weight, m g). */
double rk_contact_holding_kappa(double dhat, double weight);

/* Adaptive kappa (IPC supplement Sec. 3.3): on the first call with pairs, kappa balances the
 * barrier's gradient gb (at the current kappa) against the rest of the potential's ge (n entries
 * each: the simulator's unknowns, 3 nmesh or, through an embedded contact surface, the
 * simulator's own), clamped to
 * [kappa_min, kappa_max]; later calls double it, up to kappa_max, while the smallest distance keeps
 * shrinking below 1e-9 of the bounding-box diagonal. A fixed opt.kappa is left alone. */
void rk_contact_adapt_kappa(rk_contact *c, const double *ge, const double *gb, int n, double min_distance);

/* ---- the feasible step (ccd.c) ---- */

/* The largest alpha in [0, 1] such that moving the mesh by alpha dx (3 nmesh) and the obstacle
 * vertices by alpha odx (3 onv, NULL: still; planes do not move) keeps every pair and every
 * point-plane distance at least 10% of where it starts: additive CCD over the broad phase's swept
 * boxes. -1 on failure (out of memory). */
double rk_contact_max_step(rk_contact *c, const double *x, const double *dx, const double *odx, rk_error *err);
/* Moves the obstacles the fraction (0, 1] of the way from where they are to where they are at
 * time t (fraction 1: exactly there, rk_contact_set_time). */
void rk_contact_move_obstacles(rk_contact *c, double t, double fraction);

/* ---- moving obstacles solved for with the body (progress.c) ----
 * Over a step the obstacle vertices go on straight lines x_o(s_k) = from + s_k D_o to where they
 * are due, and the progress s_k of each obstacle k that moves this step is one more Newton unknown
 * beside the body's (n of them, in the obstacles' order), pulled to 1 by
 * w_k/2 (1 - s_k)^2 - lambda_k (1 - s_k), w_k = RK_COLLIDER_PULL mass L_k^2 / h^2 (L_k the longest
 * D_o of obstacle k), lambda_k raised in rounds of the method of multipliers (RK_OBSTACLE_ROUNDS
 * at most). The contact terms depend on s_k through obstacle k's points alone: d/ds_k = og . D_k,
 * and each Hessian block B (the obstacle points as degrees of freedom: c->obstacle_dofs set) gives
 * d2/ds_k ds_l = D_k.B D_l and the coupling B D_k with the body's points (D_k: the way at k's
 * points, 0 elsewhere). The reduced and the adaptive simulators share this. Progress vectors s, ds
 * have n entries; matrices hss are n x n with leading dimension ld. */
typedef struct {
    int onv, n;                    /* obstacle vertices; the unknowns s_k (obstacles moving this step) */
    double *from, *way, *odx;      /* 3 onv: where they start, D, scratch */
    int *unit;                     /* onv: the unknown its obstacle moves with, -1 when it stays */
    double *L, *w, *lambda, *short_by; /* n: the longest way, the pull, its multiplier, the last shortfall */
    double *gs;                    /* n: scratch */
    int *near;                     /* n: scratch (arrive) */
} rk_obstacle_way;
/* The way from where c's obstacles are to where they are at t, for a body of the given mass and a
 * step of h seconds: the number of unknowns (obstacles that move), 0 when nothing moves, -1 out of
 * memory (freed then). */
int rk_obstacle_way_init(rk_obstacle_way *p, const rk_contact *c, double t, double mass, double h, rk_error *err);
void rk_obstacle_way_free(rk_obstacle_way *p);
/* c's obstacle vertices at progress s. */
void rk_obstacle_way_place(const rk_obstacle_way *p, rk_contact *c, const double *s);
/* The pulls at s: their value; d/ds_k added into gs[k] and d2/ds_k^2 into hss[k + ld k] (each may
 * be NULL). */
double rk_obstacle_way_pull(const rk_obstacle_way *p, const double *s, double *gs, double *hss, int ld);
/* d/ds of the contact terms from their obstacle-vertex gradient og (3 onv), og . D_k, added into
 * gs (n). */
void rk_obstacle_way_gradient(rk_obstacle_way *p, const double *og, double *gs);
/* A Hessian block (ids as the sink gets them) in s: the unknowns whose obstacle has points in it
 * (at most 4) into units, for each j BD + 12 j (3 np) = B D_units[j], and D_k.B D_l added into
 * hss[k + ld l] for each pair of them; returns how many (0: no moving obstacle point). */
int rk_obstacle_way_block(const rk_obstacle_way *p, const int *id, int np, const double *B, int *units, double *BD,
                          double *hss, int ld);
/* The largest alpha in [0, 1] for the joint step: the body by alpha dx from x (3 nmesh), s by
 * alpha ds within [0, 1], CCD-filtered (the obstacles placed at s); 0 when CCD fails. */
double rk_obstacle_way_max_step(rk_obstacle_way *p, rk_contact *c, const double *x, const double *dx, const double *s,
                                const double *ds, rk_error *err);
/* A step's size in s as metres along the way: the largest |ds_k| L_k. */
double rk_obstacle_way_step_norm(const rk_obstacle_way *p, const double *ds);
/* After a solve left the progress at s: 1 when another round is due (some lambda_k raised by its
 * shortfall), 0 when every s_k is within tol (m) or did not halve its shortfall in the last round
 * (pinned: the multiplier would only press harder). */
int rk_obstacle_way_round(rk_obstacle_way *p, const double *s, double tol);
/* The obstacles at s after the solve: all at time t (rk_contact_set_time) when each is within tol
 * (m) of it and CCD lets their last bits go with the body still at x (still: 3 nmesh zeros); else
 * each whose rest of the way CCD lets go on its own, in turn, at t, the others at s (a pinned
 * one's rest runs into the body). *behind: one stopped short. */
int rk_obstacle_way_arrive(rk_obstacle_way *p, rk_contact *c, const double *x, const double *still, const double *s,
                           double t, double tol, int *behind, rk_error *err);

/* ---- prescribed motion under contact (advance.c) ---- */

/* The fraction (0, 1] of the rest of the prescribed motion to time t that CCD allows from here;
 * -1 on failure. */
typedef double (*rk_advance_fraction)(void *ctx, double t, rk_error *err);
/* Makes that fraction of the move (1: exactly to the targets at t) and solves for the free
 * degrees of freedom. */
typedef int (*rk_advance_move)(void *ctx, double t, double fraction, rk_error *err);
/* Moves in as many safe moves as it takes; fails, naming t, when the motion is locked. */
int rk_contact_advance(void *ctx, double t, rk_advance_fraction fraction, rk_advance_move move, rk_error *err);

/* ---- a point cloud's contact surface (points_proxy.c, proxy_inset.c) ---- */

/* A closed surface around a point cloud (X, n points) for contact, as ghost tets (Kuhn's 6 per
 * voxel, faces matching between neighbours) over the corners of the voxels of edge g that hold a
 * point, grown where two meet only along an edge or at a corner (so the surface is a 2-manifold);
 * out has the n points first (no tets, nothing uses them), then the corners, and rk_mesh_boundary
 * gives the surface: the voxels' outward faces with each of their vertices moved in along its
 * normal to about g / 2 from its nearest point, then on toward it to about s / 2 (s the points'
 * median nearest-neighbour spacing; 0: g / 2 only), where that is safe (proxy_inset.c), then on to
 * s / 2 where only the points-inside check held a vertex back, letting a point end outside by at
 * most RK_PROXY_OUTSIDE s (rk_proxy_near). The surface is closed, 2-manifold, free of crossings,
 * and holds every point inside or within RK_PROXY_OUTSIDE s of it (s = 0: every point inside); its
 * triangles are the voxels' faces (no more of them). Fails on n < 1, g not positive and finite, s negative or
 * not finite, a non-finite point (named), or a cloud more than 2^20 voxels across. */
int rk_points_proxy(const double *X, int n, double g, double s, rk_mesh *out, rk_error *err);
/* The target distance of a contact surface vertex to its nearest point: first in voxel edges, then
 * in the points' spacings. */
#define RK_PROXY_INSET 0.5
#define RK_PROXY_SPACING_INSET 0.5
/* How far outside the contact surface a point may lie, in the points' spacings (proxy_inset.c's
 * last stage): s, the "within its points' spacing" (a splat overlaps what it rests on by
 * at most its spacing). */
#define RK_PROXY_OUTSIDE 1.0

/* A point cloud's full-order body (proxy_body.c): rk_points_proxy's ghost tets as elements over its
 * corners (body vertex c is the proxy's vertex n + c), the surface moved in to about tau from the
 * points (sqrt(3) / 2 of the points' spacing s gives the body the cloud's volume; the contact
 * surface, rk_points_proxy at spacing s, goes on to s / 2), each tet kept at RK_BODY_MIN_VOLUME of its lattice volume or more by cutting back the
 * inset moves of its vertices where needed (so none inverts or flattens). tet_point[t]: the point
 * nearest tet t's centroid (its material's and tag's source); proxy_X: where rk_points_proxy puts
 * the corners (3 per corner), before any cut-back. rep: what was cut back and the smallest tet. */
typedef struct {
    int points;
    int backed_off;          /* surface vertices whose inset move was cut back */
    double min_volume_ratio; /* the smallest tet's volume over the lattice tet's g^3 / 6 */
} rk_points_body_report;
int rk_points_body(const double *X, int n, double g, double s, double tau, rk_mesh *body, int **tet_point, double **proxy_X,
                   rk_points_body_report *rep, rk_error *err);

/* A point cloud's contact surface that follows the capture (proxy_march.c): marching tetrahedra
 * on the Kuhn lattice of edge h (RK_MARCH_LATTICE proxy voxels), its nodes outside where they are
 * farther than RK_MARCH_REACH h from every point and reachable from the lattice's border through
 * such nodes (the cloud's reach, holes under about h closed), its vertices where a lattice edge
 * first comes within that reach of a point from its outside node, then each moved straight to
 * RK_PROXY_SPACING_INSET s from its nearest point (s the points' spacing), backed off (halved,
 * down to none) where a face would cross another (exact test). The
 * surface (out: outward triangles over its own vertices, no points) is closed, 2-manifold and free
 * of crossings (exact test). rep: what it measured; rep->outside_points counts the points neither
 * inside (the exact parity of a ray's crossings) nor within RK_PROXY_OUTSIDE s of a face, which the
 * caller must refuse (issue 30's bound). Fails on n < 1, h or s not positive and finite, a
 * non-finite point (named), or a lattice of more than 2^24 nodes. */
typedef struct {
    int backed_off;        /* vertices whose move was cut back */
    int rounds;            /* back-off rounds until nothing crossed */
    int outside_points;    /* points outside by more than RK_PROXY_OUTSIDE s (must be 0) */
    double max_outside;    /* the farthest a point outside lies from the surface (m) */
    int collapsed, flipped; /* slivers' short edges collapsed and long edges flipped (rk_march_tidy) */
    int untidy;            /* 1: the tidied surface left a point past RK_PROXY_OUTSIDE s, the untidied one kept */
} rk_points_march_report;
int rk_points_march(const double *X, int n, double h, double s, rk_surface *out, rk_points_march_report *rep, rk_error *err);
/* The same surface as rk_points_proxy gives the voxel one (proxy_cone.c): out has the n points
 * first, then the surface's vertices, and ghost tets only (each triangle coned to point 0), so
 * rk_mesh_boundary gives exactly the surface's outward triangles. rep as rk_points_march's; the
 * caller refuses rep->outside_points > 0. Fails as rk_points_march does. */
int rk_points_march_mesh(const double *X, int n, double h, double s, rk_mesh *out, rk_points_march_report *rep, rk_error *err);
/* The lattice edge in proxy voxels, and the reach in lattice edges: just over the Kuhn tet's
 * circumradius sqrt(3) / 2 h, so a point's tet has a node within reach of it (inside). Donut
 * capture (g = 10 s): at 1.0 g 18,000 triangles, at 1.5 g 8,556 (voxel surface 6,364), at 2.0 g
 * 5,148 but 14 points more than s outside. */
#define RK_MARCH_LATTICE 1.5
#define RK_MARCH_REACH 0.87
/* Passes of proxy_march.c's retries of the vertices backed off (all the way, then half of what is
 * left, ...), one colour of vertices at a time. */
#define RK_MARCH_RETRIES 3
/* proxy_march_tidy.c: a sliver is a face of quality 4 sqrt(3) A / sum l^2 under RK_MARCH_SLIVER;
 * its edges up to RK_MARCH_TIDY_EDGE points' spacings are collapsed (and caps flipped where the
 * surface moves no more than that), in up to RK_MARCH_TIDY_PASSES sweeps over the faces. */
#define RK_MARCH_SLIVER 0.1
#define RK_MARCH_TIDY_EDGE 0.5
#define RK_MARCH_TIDY_PASSES 8

/* ---- measures (intersect.c) ---- */

/* Edge-triangle crossings at x, exactly: between objects, within an object when self-contact is
 * on (edges and triangles that share no vertex), and against obstacle meshes and boxes; and
 * points behind planes or inside spheres and capsules. 0 for a valid state. */
int rk_contact_intersections(rk_contact *c, const double *x, rk_error *err);
/* The smallest distance between the surfaces at x (m; INFINITY when nothing can touch). */
double rk_contact_min_distance(rk_contact *c, const double *x, rk_error *err);

/* ---- a run's contact measures (measure.c) ---- */

/* What the reports' contact.* keys say of a run: frames measured, exact crossings summed over them
 * (rk_contact_intersections), frames with at least one, and the smallest distance of any frame. */
typedef struct {
    long frames, intersections, intersecting_frames;
    double min_distance;           /* INFINITY before a frame, or when nothing can touch */
} rk_contact_tally;

void rk_contact_tally_init(rk_contact_tally *t);
/* One frame's measures (crossings, smallest distance) into the tally. */
void rk_contact_tally_add(rk_contact_tally *t, int intersections, double min_distance);
/* One frame at x, obstacles where rk_contact_set_time put them: *intersections (exact crossings)
 * and *min_distance, the functions above; -1 on failure (out of memory). */
int rk_contact_measure(rk_contact *c, const double *x, int *intersections, double *min_distance, rk_error *err);

/* ---- exact predicates (exact.c, intersect.c) ---- */

/* The sign (-1, 0, 1) of det[a - d; b - d; c - d], exactly (positive when d lies below the plane
 * of a, b, c seen counterclockwise from above). */
int rk_orient3d_sign(const double *a, const double *b, const double *c, const double *d);
/* Whether the closed segment pq and the closed triangle abc share a point, exactly (touching
 * counts; coplanar pieces are tested in the plane). */
int rk_segment_triangle_intersect(const double *p, const double *q, const double *a, const double *b, const double *c);

#endif
