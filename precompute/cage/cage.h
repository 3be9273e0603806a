/* precompute/cage: a coarse simulation cage around a detailed closed surface, and the surface's
 * vertices embedded in it (issue 32: a 43k-vertex scan simulated on a few thousand tets, the way
 * Houdini's, Unreal's and Ziva's soft bodies carry a render mesh in a coarse tet cage).
 *
 * The cage (build.c): the surface simplified with meshoptimizer's meshopt_simplify (Debian's
 * libmeshoptimizer), tetrahedralized with TetGen (rk_tetrahedralize, as romkit mesh does; radius-edge
 * 2), the simplification target chosen so that TetGen's count is at most max_tets; then the tet
 * mesh's boundary moved outward (inflate.c): each boundary vertex along its area-weighted normal by
 * the margin plus how far the original surface rises above its faces (offset.c), the interior
 * following harmonically, a move cut back where it would crush a tet; every original vertex is then
 * located in the cage exactly (embed.c), and where some are outside, the faces under them move out
 * further (up to six rounds). Those still outside after that are reported, never dropped.
 *
 * The embedding (embed.c): each point gets the cage tet that contains it, by exact orientation
 * predicates (contact.h, rk_orient3d_sign: Shewchuk's adaptive test), and its barycentric
 * coordinates there. A point in no tet is not dropped: it gets the tet of the nearest boundary face
 * with its barycentrics clamped to [0, 1] and renormalized, and is counted, with the worst distance. */
#ifndef RK_CAGE_H
#define RK_CAGE_H

#include "mesh/mesh.h"
#include "util/util.h"

typedef struct {
    int max_tets;          /* the cage has at most this many tets (>= 100) */
    double margin;         /* added to every outward offset, as a fraction of the surface's
                            * bounding-box diagonal; 0: RK_CAGE_MARGIN */
    double quality;        /* TetGen radius-edge bound; 0: 2 (build.c says why not 1.4) */
} rk_cage_options;

#define RK_CAGE_MARGIN 5e-4
#define RK_CAGE_MIN_TETS 100

typedef struct {
    int triangles;         /* the simplified surface's (the cage's boundary) */
    int vertices;          /* the cage's */
    int tets;
    double simplify_error; /* meshopt_simplify's reported error, in the surface's units */
    double max_offset;     /* the largest outward move of a cage vertex */
    double max_volume;     /* TetGen's volume bound when one was used to fill the budget, else 0 */
    int tetgen_runs;       /* TetGen runs in all */
    int inflate_rounds;    /* rounds of moving the boundary out (rk_cage_inflate) */
    int outside;           /* original vertices still outside the cage (0 unless it gave up) */
    double worst_distance; /* the farthest of those from the cage's boundary */
} rk_cage_report;

/* A cage of at most o->max_tets tets around closed surface s (checked and oriented outward by the
 * caller: rk_surface_check_and_orient). Fails when TetGen fails at every simplification tried or
 * no cage within max_tets is found (the message says what was tried). rep may be NULL. On failure
 * *cage is empty. */
int rk_cage_build(const rk_surface *s, const rk_cage_options *o, rk_mesh *cage, rk_cage_report *rep, rk_error *err);

/* Points embedded in a tet mesh. */
typedef struct {
    int n;
    int *tet;              /* n: the containing tet (or the nearest, for a point outside) */
    double *bary;          /* 4n: barycentric coordinates in it, summing to 1 */
    double *distance;      /* n: a point's distance to the mesh's boundary when outside, else 0 */
    int outside;           /* points in no tet (exact test) */
    double worst_distance; /* the largest distance of those to the mesh's boundary (0 when none) */
    int worst_point;       /* which (-1 when none) */
} rk_embedding;

/* Locates each of the n points X (3n) in m's tets (m checked: positively oriented). Points outside
 * every tet are embedded in the nearest boundary face's tet with clamped barycentrics and counted
 * (never silently). Fails only on a mesh without tets or out of memory. */
int rk_cage_embed(const rk_mesh *m, const double *X, int n, rk_embedding *e, rk_error *err);
void rk_embedding_free(rk_embedding *e);

/* Whether p lies in the closed tet (a, b, c, d), exactly (any orientation). */
int rk_point_in_tet(const double *p, const double *a, const double *b, const double *c, const double *d);

#endif
