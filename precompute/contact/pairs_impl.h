/* Private to precompute/contact: the candidate stencils that proximity, CCD and the measures
 * share (pairs.c). */
#ifndef RK_CONTACT_PAIRS_IMPL_H
#define RK_CONTACT_PAIRS_IMPL_H

#include "contact/contact.h"

/* The primitive sets of the broad phase. */
enum { OBJ_POINTS, OBJ_EDGES, OBJ_FACES, OBS_POINTS, OBS_EDGES, OBS_FACES };

/* Where everything is, and where it moves over a step (dx, odx NULL: still). */
typedef struct {
    const double *x, *dx;    /* mesh positions (3 nmesh) and their displacement */
    const double *ox, *odx;  /* obstacle vertex positions (3 onv) and their displacement */
} rk_motion_frame;

/* Position of stencil point id: mesh vertex id, or obstacle vertex -1 - id. */
const double *rk_contact_point(const rk_contact *c, const double *x, const double *ox, int id);
/* The stencils whose primitives' boxes (over x and x + dx) come within grow (plus their thickness)
 * of each other: point-triangle and edge-edge pairs, into s (emptied first). Points against
 * planes are not among them. */
int rk_contact_candidates(rk_contact *c, const rk_motion_frame *f, double grow, rk_contact_set *s, rk_error *err);
/* rk_broad_phase of two sets of mesh primitives (boxes, and size mesh vertex ids each). Without
 * self-contact only primitives of different objects may touch, so it runs per pair of objects:
 * a voxel proxy's every face and edge lies within 2 dhat of its neighbours', and hashing one
 * object's primitives against their own only to drop the pairs afterwards made the broad phase
 * most of a step's time (a 5,703-splat donut on a block of points, test_pipeline_donut_collide).
 * The pairs come sorted as rk_broad_phase sorts them: with self-contact off, the pairs of
 * different objects rk_broad_phase would have given, in the same order. */
int rk_contact_object_broad_phase(const rk_contact *c, const double *boxes_a, const int *ids_a, int size_a, int na,
                                  const double *boxes_b, const int *ids_b, int size_b, int nb, int **pairs, int *np,
                                  rk_error *err);

/* The candidates of a step (f's dx, odx) as rk_contact_candidates(c, f, 0, s) would list them, the
 * same pairs in the same order, taken from the gather's cache (a Verlet list grown by 2 dhat) when
 * the step and what moved since the cache stay within its growth: 1 when it served s, 0 when the
 * caller must run the broad phase, -1 out of memory. The creeping Newton iterations of a contact
 * step move far less than dhat, and each ran a broad phase for its CCD. */
int rk_contact_step_candidates_cached(rk_contact *c, const rk_motion_frame *f, rk_contact_set *s, rk_error *err);
/* The smallest distance less thickness over the pairs whose boxes grown by reach overlap at x (what
 * rk_contact_min_distance measures), from the cache when it decides it; NAN when it does not. */
double rk_contact_cached_closest(const rk_contact *c, const double *x, double reach);

/* The stencil's four points at x (mesh) and ox (obstacles). */
void rk_contact_stencil(const rk_contact *c, const rk_contact_pair *p, const double *x, const double *ox,
                        const double *out[4]);
/* Squared distance of a point-triangle or edge-edge pair (its thickness not subtracted). */
double rk_contact_pair_distance2(const rk_contact *c, const rk_contact_pair *p, const double *x, const double *ox);
/* Signed distance of point p from plane obstacle `plane` where it is now. */
double rk_contact_plane_distance(const rk_contact *c, int plane, const double *p);

/* c's obstacles (arrays allocated, geometry, edges, positions at time 0, the scene counts) from
 * n obstacles, each checked and named by its index on failure (collision.c). */
int rk_contact_build_obstacles(rk_contact *c, const rk_obstacle *obstacles, int n, rk_error *err);
/* Where the obstacles are at time t into ox_to and oplane_to (collision.c). */
void rk_contact_obstacle_targets(rk_contact *c, double t);

#endif
