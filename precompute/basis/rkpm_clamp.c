/* The clamp mask of RKPM shape functions (basis.h, rk_rkpm_set_clamp): Kantorovich's way of
 * imposing an essential condition on shape functions that do not interpolate (Rvachev's R-functions,
 * Hollig's WEB-splines, Shapiro & Tsukanov): every phi_k becomes d(X) phi_k with d = 0 on the fixed
 * region and rising to 1 over the length `rise`, so any combination of them, every skinning
 * weight, vanishes there exactly, and the eigen-weights of Eq. 15 assembled on the masked functions
 * are the optimal ones of that space.
 *
 *   e(X) = distance from X to the fixed region,  t = clamp(e / rise, 0, 1),  d = t^2 (3 - 2 t),
 * C^1 (zero slope where it leaves the region and where it meets 1), piecewise smooth, enough for
 * the H^1 energy of Prop. 1. Why not a d that rises linearly, like a distance function (the
 * R-function literature's choice)? Its gradient jumps at the region's face, and a grid of
 * integration points with a layer on the face (the 5 x 1 x 1 beam's 5,000-point grid has one: its
 * points there are in the region, d = 0, gradient 0, while half their cell is free) cannot see the
 * strain of a hinge there: with d = 1 - (1 - t)^3 the beam of test_pipeline_meshfree_beam sagged
 * 112% / 161% / 87% of beam theory at 5,000 / 6,000 / 10,000 points (m = 16), the energy of its
 * first 0.1 m past the clamp a sixteenth of an 80,000-point check; with the smoothstep 99.6% /
 * 88% / 94% (the penalty clamp: 90% / 79% at 5,000 / 7,000), and 99% at 20,000 for both.
 * The rise: 2 mean kernel radii (RK_RKPM_CLAMP_RISE; 1 and 3 measured 95-98% on that beam).
 *
 * The region. On a mesh: the union of its simplices whose vertices are all fixed (tets, their
 * triangles, and the fixed vertices themselves), the region P1 finite elements hold still: e = 0
 * inside a fixed tet, else the distance to the nearest fixed triangle or vertex. Points alone would
 * leave the clamp's face free between its vertices (measured: the beam above 32% softer than beam
 * theory with balls around its vertices). Without tets (a point cloud, or a mesh's vertices taken as
 * one): balls around the fixed points, radius rho_i = max(0, b_i - n_i) (b_i the distance to the
 * nearest free point, n_i to the nearest other point): 0 at the region's boundary points, about a
 * spacing a layer deeper, so the balls fill the inside without reaching into the free part.
 * (The scene pipeline does not clamp clouds yet, precompute/pipeline/basis.c says why: integrated
 * at their own points, a mask that is flat at the fixed points hides a hinge there.) */
#include "basis/rkpm_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double dist(const double *a, const double *b)
{
    double e0 = a[0] - b[0], e1 = a[1] - b[1], e2 = a[2] - b[2];
    return sqrt(e0 * e0 + e1 * e1 + e2 * e2);
}

/* ---- nearest point of a set (for the balls' radii) ---- */

typedef struct {
    const double *P, *q;
    int exclude;
    double e;
} nearest_ctx;

static int visit_nearest(int i, void *ctx)
{
    nearest_ctx *c = ctx;
    if (i != c->exclude) c->e = fmin(c->e, dist(c->q, &c->P[3 * (size_t)i]));
    return 0;
}

/* Distance from q to the nearest of the grid's n points P other than `exclude`: boxes of growing
 * half-width R until the nearest found lies within R (then no point outside the box is nearer). */
static double nearest(const rk_rkpm_grid *g, const double *P, int n, const double q[3], int exclude)
{
    if (n < 1) return INFINITY;
    double R = g->h, span = g->h * (g->dim[0] + g->dim[1] + g->dim[2]);
    for (;;) {
        nearest_ctx c = {P, q, exclude, INFINITY};
        double lo[3], hi[3];
        for (int d = 0; d < 3; d++) lo[d] = q[d] - R, hi[d] = q[d] + R;
        rkpm_grid_visit(g, lo, hi, visit_nearest, &c);
        if (c.e <= R || R > span) return c.e; /* (a box past the span visits every cell) */
        R *= 2;
    }
}

/* rho_i = max(0, b_i - n_i) for the balls of a region known by its points only. */
static int ball_radii(rk_rkpm_clamp *c, const double *X, int n, const unsigned char *fixed, rk_error *err)
{
    int nf = c->n, rc = -1;
    double *freeX = rk_calloc(3 * (size_t)(n - nf), sizeof(double), err);
    rk_rkpm_grid gall = {0}, gfree = {0};
    if (!freeX) return -1;
    for (int i = 0, b = 0; i < n; i++)
        if (!fixed[i]) memcpy(&freeX[3 * (size_t)b++], &X[3 * (size_t)i], 3 * sizeof(double));
    if (rkpm_grid_build(&gall, X, n, 0, err) || rkpm_grid_build(&gfree, freeX, n - nf, 0, err)) goto out;
    for (int i = 0, a = 0; i < n; i++)
        if (fixed[i]) {
            double b = nearest(&gfree, freeX, n - nf, &X[3 * (size_t)i], -1);
            double own = nearest(&gall, X, n, &X[3 * (size_t)i], i);
            c->reach[a++] = fmax(0, b - own);
        }
    rc = 0;
out:
    free(freeX);
    rkpm_grid_free(&gall);
    rkpm_grid_free(&gfree);
    return rc;
}

/* The mesh's tets and triangles with every vertex fixed (a triangle shared by two fixed tets
 * comes twice: harmless, the distance is a minimum). */
static int fixed_simplices(rk_rkpm_clamp *c, const double *X, const unsigned char *fixed, const int *tets, int nt,
                           rk_error *err)
{
    static const int face[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    int ntet = 0, ntri = 0;
    for (int t = 0; t < nt; t++) {
        const int *v = &tets[4 * (size_t)t];
        int nfix = fixed[v[0]] + fixed[v[1]] + fixed[v[2]] + fixed[v[3]];
        ntet += nfix == 4;
        for (int f = 0; f < 4; f++) ntri += fixed[v[face[f][0]]] && fixed[v[face[f][1]]] && fixed[v[face[f][2]]];
    }
    c->tet = rk_calloc(12 * (size_t)ntet + 1, sizeof(double), err);
    c->tri = rk_calloc(9 * (size_t)ntri + 1, sizeof(double), err);
    if (!c->tet || !c->tri) return -1;
    for (int t = 0; t < nt; t++) {
        const int *v = &tets[4 * (size_t)t];
        if (fixed[v[0]] && fixed[v[1]] && fixed[v[2]] && fixed[v[3]])
            for (int a = 0; a < 4; a++)
                memcpy(&c->tet[12 * (size_t)c->ntet + 3 * a], &X[3 * (size_t)v[a]], 3 * sizeof(double));
        c->ntet += fixed[v[0]] && fixed[v[1]] && fixed[v[2]] && fixed[v[3]];
        for (int f = 0; f < 4; f++)
            if (fixed[v[face[f][0]]] && fixed[v[face[f][1]]] && fixed[v[face[f][2]]]) {
                for (int a = 0; a < 3; a++)
                    memcpy(&c->tri[9 * (size_t)c->ntri + 3 * a], &X[3 * (size_t)v[face[f][a]]], 3 * sizeof(double));
                c->ntri++;
            }
    }
    return 0;
}

/* Each piece's centre and the largest reach from a centre, then the hash over the centres. */
static int hash_pieces(rk_rkpm_clamp *c, rk_error *err)
{
    int np = c->n + c->ntri + c->ntet;
    c->centre = rk_calloc(3 * (size_t)np, sizeof(double), err);
    if (!c->centre) return -1;
    c->extent = 0;
    for (int i = 0; i < np; i++) {
        double *m = &c->centre[3 * (size_t)i];
        const double *P;
        int corners;
        if (i < c->n) P = &c->X[3 * (size_t)i], corners = 1;
        else if (i < c->n + c->ntri) P = &c->tri[9 * (size_t)(i - c->n)], corners = 3;
        else P = &c->tet[12 * (size_t)(i - c->n - c->ntri)], corners = 4;
        for (int d = 0; d < 3; d++) {
            m[d] = 0;
            for (int a = 0; a < corners; a++) m[d] += P[3 * a + d] / corners;
        }
        for (int a = 0; a < corners; a++) c->extent = fmax(c->extent, dist(m, &P[3 * a]));
        if (i < c->n) c->extent = fmax(c->extent, c->reach[i]);
    }
    return rkpm_grid_build(&c->hash, c->centre, np, c->rise, err);
}

void rkpm_clamp_free(rk_rkpm_clamp *c)
{
    free(c->X);
    free(c->reach);
    free(c->tri);
    free(c->tet);
    free(c->centre);
    rkpm_grid_free(&c->hash);
    memset(c, 0, sizeof *c);
}

int rkpm_region_build(rk_rkpm_clamp *c, const double *X, int n, const unsigned char *fixed, const int *tets, int nt,
                      double rise, rk_error *err)
{
    rkpm_clamp_free(c);
    int nf = 0;
    for (int i = 0; i < n; i++) nf += fixed[i] != 0;
    if (nf == 0) return 0;
    if (nf == n) return rk_fail(err, "clamp: all %d points are fixed, nothing is left to move", n);
    if (!(rise > 0) || !isfinite(rise)) return rk_fail(err, "clamp: the rise length must be positive, got %g", rise);
    int bad = rkpm_first_nonfinite(X, n);
    if (bad >= 0) return rk_fail(err, "clamp: point %d is not finite", bad);
    for (int t = 0; tets && t < 4 * nt; t++)
        if (tets[t] < 0 || tets[t] >= n) return rk_fail(err, "clamp: tet %d names vertex %d of %d", t / 4, tets[t], n);
    c->X = rk_calloc(3 * (size_t)nf, sizeof(double), err);
    c->reach = rk_calloc((size_t)nf, sizeof(double), err);
    if (!c->X || !c->reach) goto fail;
    for (int i = 0, a = 0; i < n; i++)
        if (fixed[i]) memcpy(&c->X[3 * (size_t)a++], &X[3 * (size_t)i], 3 * sizeof(double));
    c->n = nf;
    c->rise = rise;
    if (tets ? fixed_simplices(c, X, fixed, tets, nt, err) : ball_radii(c, X, n, fixed, err)) goto fail;
    if (hash_pieces(c, err)) goto fail;
    return 0;
fail:
    rkpm_clamp_free(c);
    return -1;
}

int rk_rkpm_set_clamp(rk_rkpm *k, const double *X, int n, const unsigned char *fixed, const int *tets, int nt,
                      double rise, rk_error *err)
{
    return rkpm_region_build(&k->clamp, X, n, fixed, tets, nt, rise, err);
}

/* The point of triangle abc nearest to p (Ericson, Real-Time Collision Detection, 5.1.5: by the
 * Voronoi region of p among the corners, edges and face). */
static void closest_on_triangle(const double p[3], const double *a, const double *b, const double *c, double q[3])
{
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    for (int i = 0; i < 3; i++) ab[i] = b[i] - a[i], ac[i] = c[i] - a[i], ap[i] = p[i] - a[i], bp[i] = p[i] - b[i],
                                cp[i] = p[i] - c[i];
#define DOT(u, v) ((u)[0] * (v)[0] + (u)[1] * (v)[1] + (u)[2] * (v)[2])
    double d1 = DOT(ab, ap), d2 = DOT(ac, ap), d3 = DOT(ab, bp), d4 = DOT(ac, bp), d5 = DOT(ab, cp), d6 = DOT(ac, cp);
#undef DOT
    double s = 0, t = 0; /* q = a + s ab + t ac */
    double va = d3 * d6 - d5 * d4, vb = d5 * d2 - d1 * d6, vc = d1 * d4 - d3 * d2;
    if (d1 <= 0 && d2 <= 0) s = t = 0;
    else if (d3 >= 0 && d4 <= d3) s = 1, t = 0;
    else if (d6 >= 0 && d5 <= d6) s = 0, t = 1;
    else if (vc <= 0 && d1 >= 0 && d3 <= 0) s = d1 / (d1 - d3), t = 0;
    else if (vb <= 0 && d2 >= 0 && d6 <= 0) s = 0, t = d2 / (d2 - d6);
    else if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
        double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        s = 1 - w, t = w;
    } else {
        double den = 1 / (va + vb + vc);
        s = vb * den, t = vc * den;
    }
    for (int i = 0; i < 3; i++) q[i] = a[i] + s * ab[i] + t * ac[i];
}

/* Whether p lies in the tet (corners P, 12 coordinates; either orientation). */
static int inside_tet(const double p[3], const double *P)
{
    double sgn = 0;
    static const int face[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    for (int f = 0; f < 4; f++) {
        const double *a = &P[3 * face[f][0]], *b = &P[3 * face[f][1]], *c = &P[3 * face[f][2]];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        double s = n[0] * (p[0] - a[0]) + n[1] * (p[1] - a[1]) + n[2] * (p[2] - a[2]);
        if (f == 0) sgn = s;
        else if (s * sgn < 0) return 0;
        if (sgn == 0) sgn = s;
    }
    return 1;
}

/* The distance e from X to the region, and the region's point nearest to X (for the gradient). */
typedef struct {
    const rk_rkpm_clamp *c;
    const double *X;
    double e, near[3];
    int inside;
} region_ctx;

static int visit_piece(int i, void *ctx)
{
    region_ctx *r = ctx;
    const rk_rkpm_clamp *c = r->c;
    double q[3], e;
    if (i < c->n) {
        memcpy(q, &c->X[3 * (size_t)i], sizeof q);
        e = dist(r->X, q) - c->reach[i];
    } else if (i < c->n + c->ntri) {
        const double *T = &c->tri[9 * (size_t)(i - c->n)];
        closest_on_triangle(r->X, T, T + 3, T + 6, q);
        e = dist(r->X, q);
    } else {
        if (inside_tet(r->X, &c->tet[12 * (size_t)(i - c->n - c->ntri)])) {
            r->inside = 1;
            r->e = 0;
            return 1; /* d = 0: nothing nearer matters */
        }
        return 0; /* outside: its faces are among the triangles */
    }
    if (e < r->e) {
        r->e = e;
        memcpy(r->near, q, sizeof q);
    }
    return 0;
}

double rkpm_region_distance(const rk_rkpm_clamp *c, const double X[3], double range, double grad[3])
{
    grad[0] = grad[1] = grad[2] = 0;
    double R = range + c->extent, lo[3], hi[3];
    for (int d = 0; d < 3; d++) lo[d] = X[d] - R, hi[d] = X[d] + R;
    region_ctx r = {c, X, INFINITY, {0, 0, 0}, 0};
    rkpm_grid_visit(&c->hash, lo, hi, visit_piece, &r);
    if (r.inside || r.e <= 0) return 0;
    if (r.e >= range) return r.e; /* (also: no piece within reach, INFINITY) */
    double len = dist(X, r.near);
    for (int d = 0; d < 3; d++) grad[d] = (X[d] - r.near[d]) / len; /* the unit direction away from the region */
    return r.e;
}

double rkpm_clamp_at(const rk_rkpm_clamp *c, const double X[3], double grad[3])
{
    double g[3], e = rkpm_region_distance(c, X, c->rise, g);
    grad[0] = grad[1] = grad[2] = 0;
    if (e <= 0) return 0;
    if (e >= c->rise) return 1;
    double t = e / c->rise, a = 6 * t * (1 - t) / c->rise; /* d'(t) / rise */
    for (int d = 0; d < 3; d++) grad[d] = a * g[d];
    return t * t * (3 - 2 * t);
}
