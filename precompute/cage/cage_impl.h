/* Private to precompute/cage: the steps rk_cage_build chains. */
#ifndef RK_CAGE_IMPL_H
#define RK_CAGE_IMPL_H

#include "cage/cage.h"

/* s simplified toward `target` triangles by meshopt_simplify (no error limit: the target decides),
 * its kept vertices compacted into out (a new surface); *error is meshopt's reported error scaled
 * to the surface's units (its relative error times meshopt_simplifyScale). */
int rk_cage_simplify(const rk_surface *s, int target, rk_surface *out, double *error, rk_error *err);

/* The squared distance from p to the closest point of triangle abc (found by the region of the
 * triangle's Voronoi diagram p is in: a vertex, an edge or the face). */
double rk_cage_triangle_distance2(const double *p, const double *a, const double *b, const double *c);

/* Where each original vertex sits above the simplified surface c: the nearest vertex of c, then
 * of that vertex's triangles the nearest one, and p's signed height above its plane. */
typedef struct {
    int n;
    int *tri;        /* n: c's triangle each original vertex is measured against */
    double *height;  /* n: its height above that triangle's plane, along the face normal (may be < 0) */
} rk_cage_heights;

int rk_cage_heights_measure(const rk_surface *c, const rk_surface *orig, rk_cage_heights *h, rk_error *err);
void rk_cage_heights_free(rk_cage_heights *h);

/* c's vertices moved outward along their area-weighted normals (into out, a copy of c): vertex v by
 * margin + extra[v] + the most any original vertex rises above a triangle of v (its height over
 * n_v . n_f, so that the triangle's plane rises by at least that height there). *max_offset gets
 * the largest move. */
int rk_cage_offset(const rk_surface *c, const rk_cage_heights *h, double margin, const double *extra, rk_surface *out,
                   double *max_offset, rk_error *err);

/* The boundary vertices of m (a tetrahedralized simplification of orig) moved outward: each by the
 * margin and the most the original rises above its faces (rk_cage_offset, from m's rest), cut back
 * where a tet around it would keep less than a fifth of its volume; then every vertex of orig is
 * located (rk_cage_embed) and the faces under those still outside move out further, up to six
 * rounds; the round that left the fewest outside is kept. rep gets max_offset, outside, worst_distance and inflate_rounds. */
int rk_cage_inflate(rk_mesh *m, const rk_surface *orig, double margin, rk_cage_report *rep, rk_error *err);

#endif
