/* precompute/contact: incremental potential contact (IPC, Li et al. 2020), once, for the full-order
 * simulator and the simulators built on it.
 *
 *   distances       point-triangle and edge-edge, reduced to the closest feature pair (point-point,
 *                   point-edge, point-plane, line-line), squared, with gradients and Hessians;
 *                   the edge-edge mollifier for nearly parallel edges (Sec. 4.3)
 *   barrier         b(d^2 - xi^2, dhat^2 + 2 xi dhat) of physics/physics.h (the one barrier, shared with
 *                   the runtime); xi is a thickness: 0 between meshes, the radius of a sphere or
 *                   capsule obstacle (a point or a segment with a thickness)
 *   broad phase     a spatial hash over the boundary primitives' boxes, grown by dhat, or swept
 *                   along a step
 *   CCD             additive CCD (Li et al. 2021): the largest step along a direction that keeps
 *                   every pair apart, so no line search trial ever intersects
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
#include "util/util.h"

/* ---- distances (distance.c) ---- */

typedef enum {
    RK_DIST_POINT_POINT = 0, /* v[0], v[1] */
    RK_DIST_POINT_EDGE = 1,  /* point v[0], edge v[1] v[2] */
    RK_DIST_POINT_PLANE = 2, /* point v[0], the plane of triangle v[1] v[2] v[3] */
    RK_DIST_LINE_LINE = 3    /* line v[0] v[1], line v[2] v[3] */
} rk_distance_kind;

/* Which feature pair of a stencil is closest: v[] index the stencil's four points. */
typedef struct {
    rk_distance_kind kind;
    int v[4];
} rk_distance_case;

/* Point x[0] against triangle x[1..3]; edge x[0] x[1] against edge x[2] x[3]. */
rk_distance_case rk_point_triangle_case(const double *const x[4]);
rk_distance_case rk_edge_edge_case(const double *const x[4]);
/* The squared distance of case c over the stencil's four points, with its gradient (12, in the
 * order of x) and Hessian (144, row-major) when g, H are not NULL. */
double rk_contact_distance2(rk_distance_case c, const double *const x[4], double *g, double *H);
/* The edge-edge mollifier of x[0] x[1] against x[2] x[3] with threshold eps (1e-3 |ea|^2 |eb|^2 at
 * rest), with gradient and Hessian. */
double rk_edge_edge_mollifier(const double *const x[4], double eps, double *g, double *H);

/* ---- continuous collision detection (ccd.c) ---- */

/* Additive CCD of one stencil (point-triangle, or edge_edge) from positions x moving by dx over
 * t in [0, tmax], the stencil kept xi apart: 1 with *toi a conservative time of impact (the
 * stencil at toi is still at least 10% of its starting gap apart), 0 when it stays apart. A
 * stencil that starts within xi reports toi 0. */
int rk_ccd_stencil(int edge_edge, const double *const x[4], const double *const dx[4], double xi, double tmax,
                   double *toi);

/* ---- broad phase (broad.c) ---- */

/* The pairs (a, b) of boxes that overlap, a from boxes_a (na boxes, 6 numbers each: min xyz, max
 * xyz) and b from boxes_b: *pairs (2 *npairs ints, malloc'd, sorted, each pair once). */
int rk_broad_phase(const double *boxes_a, int na, const double *boxes_b, int nb, int **pairs, int *npairs,
                   rk_error *err);

/* ---- exact predicates (exact.c, intersect.c) ---- */

/* The sign (-1, 0, 1) of det[a - d; b - d; c - d], exactly (positive when d lies below the plane
 * of a, b, c seen counterclockwise from above). */
int rk_orient3d_sign(const double *a, const double *b, const double *c, const double *d);
/* Whether the closed segment pq and the closed triangle abc share a point, exactly (touching
 * counts; coplanar pieces are tested in the plane). */
int rk_segment_triangle_intersect(const double *p, const double *q, const double *a, const double *b, const double *c);

#endif
