/* A cloud's contact proxy (points_proxy.c): the lattice it is built on, shared with the step that
 * moves its surface in toward the points (proxy_inset.c). */
#ifndef RK_CONTACT_POINTS_PROXY_IMPL_H
#define RK_CONTACT_POINTS_PROXY_IMPL_H

#include <stddef.h>
#include <stdint.h>

#include "contact/contact.h"

/* Voxel (and corner) (i, j, k) of the lattice of origin lo and edge g is the key i + S (j + S k). */
#define RK_PROXY_S ((int64_t)1 << 20)

/* The first of the n sorted keys k not below key (n if none). */
size_t rk_proxy_lower_bound(const int64_t *k, size_t n, int64_t key);

/* Moves the surface vertices of m (rk_mesh_boundary of its ghost tets; its first n vertices are the
 * cloud's points, the rest the lattice corners of origin lo, edge g) in toward the points, each
 * along its normal to about RK_PROXY_INSET g from its nearest point, backing a vertex off (halving
 * its move, then none) wherever a face would turn over, cross another face (exact test), or sweep
 * over a point on its way. The surface stays closed, 2-manifold and free of crossings, and every
 * point stays inside it: what the voxels' surface was. */
int rk_proxy_inset(rk_mesh *m, int n, double g, const double lo[3], rk_error *err);

/* The target distance of a surface vertex to its nearest point, in voxel edges. */
#define RK_PROXY_INSET 0.5

#endif
