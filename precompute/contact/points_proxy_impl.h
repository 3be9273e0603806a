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

/* The voxel surface before it moves in: rk_points_proxy's mesh (the n points, then the corners of
 * the well-composed voxels of edge g, 6 Kuhn ghost tets per voxel, voxel by voxel) with the
 * lattice's origin in lo. */
int rk_proxy_lattice(const double *X, int n, double g, rk_mesh *out, double lo[3], rk_error *err);

/* The cloud's points bucketed by lattice cell: key[i] sorted, idx[i] the point. */
typedef struct {
    const double *X;
    int n;
    double g, lo[3];
    int64_t *key;
    int *idx;
} rk_proxy_grid;

int rk_proxy_grid_build(rk_proxy_grid *G, const double *X, int n, double g, const double lo[3], rk_error *err);
void rk_proxy_grid_free(rk_proxy_grid *G);
/* The distance from x to the nearest point in the cells within r of x's (INFINITY if none), that
 * point in *at (may be NULL). */
double rk_proxy_nearest_at(const rk_proxy_grid *G, const double *x, int r, const double **at);

/* A surface's faces on a grid of cells of edge h (proxy_outside.c): cell c lists face[start[c] ..
 * start[c + 1] - 1], every face whose box (6 numbers a face in boxes: lo, hi) grown by pad meets
 * it. */
typedef struct {
    double h, lo[3];
    long dim[3];
    size_t *start;
    int *face;
} rk_proxy_face_grid;

/* Each triangle's box at x (6 nf: min xyz, max xyz), what rk_proxy_face_grid_build takes. */
void rk_proxy_face_boxes(const double *x, const int *tris, int nf, double *boxes);
int rk_proxy_face_grid_build(rk_proxy_face_grid *F, const double *boxes, int nf, double pad, double h, rk_error *err);
void rk_proxy_face_grid_free(rk_proxy_face_grid *F);
/* The faces listed in p's cell (a superset of those within pad of p): face[*first .. end - 1]. */
size_t rk_proxy_faces_near(const rk_proxy_face_grid *F, const double *p, size_t *first);
/* The distance from p to the triangle a b c. */
double rk_proxy_face_distance(const double *p, const double *a, const double *b, const double *c);

/* Whether closed triangles ta and tb (vertex ids into x) meet anywhere but the vertices and edge
 * they share, exactly (proxy_inset.c; the one crossing check of the contact surfaces built here). */
int rk_proxy_faces_cross(const int *ta, const int *tb, const double *x);
/* Face t's normal over positions x, (x1 - x0) x (x2 - x0): twice its area long (proxy_march.c). */
void rk_proxy_face_normal(const double *x, const int *t, double *nrm);

/* Rounds of the second stage of rk_proxy_inset (straight toward the nearest point, to tau): on
 * the donut capture 4 rounds left the mean vertex 2.1 s off, 8 rounds 1.9 s (s its spacing). */
#define RK_PROXY_PULL_ROUNDS 8
/* Rounds of the last stage (rk_proxy_near) per colour of vertices (it moves one colour a round):
 * 8, as the second's pull to tau; 16 took the donut capture's 95th percentile from 2.4 s to 2.2 s
 * at 1.5x the time. */
#define RK_PROXY_NEAR_ROUNDS 8

/* Moves the surface vertices of m (rk_mesh_boundary of its ghost tets; its first n vertices are the
 * cloud's points, the rest the lattice corners of origin lo, edge g) in toward the points: first
 * each along its normal to about tau1 = max(tau, RK_PROXY_INSET g) from its nearest point, then
 * (where tau is nearer) straight toward it, to about tau, backing a vertex off (halving
 * its move, then none) wherever a face would turn over, cross another face (exact test), or sweep
 * over a point on its way. The surface stays closed, 2-manifold and free of crossings, and every
 * point stays inside it: what the voxels' surface was. */
int rk_proxy_inset(rk_mesh *m, int n, double g, double tau, const double lo[3], rk_error *err);
/* The last stage, on m as it is (after rk_proxy_inset; lattice: m->X before it, the voxel faces
 * the turn and shrink checks compare with): the vertices (one colour of them a round, no face
 * with two of a colour) farther than 1.05 tau from the points straight toward their nearest
 * point, to tau, under the
 * same checks but one: a point may end outside the surface by at most outside (> 0), measured
 * (rk_proxy_face_distance) for every point a moved face swept over or that was within outside of
 * the surface before, at every pass. Every point that was inside or within outside of the
 * surface still is. */
int rk_proxy_near(rk_mesh *m, const double *lattice, int n, double g, double tau, double outside, const double lo[3],
                  rk_error *err);

/* The march surface's slivers removed (proxy_march_tidy.c): short edges collapsed, caps' long
 * edges flipped, each only where the surface stays closed, 2-manifold, free of crossings and its
 * local worst quality improves; S's vertices renumbered (those left keep their places); counts in
 * rep->collapsed and rep->flipped. s: the points' spacing. */
int rk_march_tidy(rk_surface *S, double s, rk_points_march_report *rep, rk_error *err);

#endif
