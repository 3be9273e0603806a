/* rk_proxy_inset (points_proxy_impl.h): a cloud's voxel surface moved in toward its points.
 *
 * A voxel's faces lie anywhere from 0 to g off the points it holds, and its corners up to sqrt(3) g,
 * so a cloud rested up to a voxel above what it touched. Each surface vertex goes in along its
 * area-weighted normal to the first place within tau1 = max(tau, RK_PROXY_INSET g) of a point (or,
 * where that ray passes between the points, the place along it nearest one), then those still
 * farther straight toward their nearest point, to tau1 and then on to tau (for contact half the
 * points' spacing s: issue 30 asks for the surface within s of the points). The connectivity
 * stays the voxels' (same triangles, no more of them: a level set of the distance on a finer
 * lattice had 5-10x the triangles, which the runtime's contact pays every step). A move is kept
 * only where it is safe,
 * checked exactly (contact.h's orientation and segment-triangle predicates):
 *   - no face turns over or collapses (its normal within ~87 degrees of its voxel face's, its area
 *     at least 1/20 of it);
 *   - no two faces cross or touch, but along the edges and corners they share;
 *   - no point lies in the convex hull of a face before and after its move: the faces pass over no
 *     point on the straight way from the voxel surface, which held every point inside, so every
 *     point is still inside (its winding number changes only when a face crosses it).
 * A vertex of a face that fails has its move halved, down to none; the checks run again until none
 * fails. The voxel surface itself passes them all, so this ends.
 *
 * rk_proxy_near, the last stage (issue 30): on a dense capture the voxel is capped (1/40 of the
 * diagonal, about 10 s on the donut capture), and the last check held a vertex back wherever any
 * move swept over one of the noisy shell's outer splats between vertices 10 s apart (donut: 95th
 * percentile 5.0 s). There the same pull to tau runs with that check relaxed to the bound the
 * issue asks of the surface: a point may end outside it, by at most t = RK_PROXY_OUTSIDE s (the
 * points are what is drawn, the surface is what collides: a splat overlaps what it rests on by at
 * most t, within its spacing). Every point a moved face sweeps over (in the hull of the face before
 * and after), and every point already within t of the surface, has its distance to the faces near
 * it (proxy_outside.c's face grid) measured at every pass where one of them changed; where it is
 * over t, the moved faces within t of it back off like any bad face. At zero moves the surface
 * is the last accepted one, where the bound held, so this ends too; a point never swept over is
 * inside as before (its winding number did not change). This stage moves one colour of vertices
 * a round (no face has two vertices of one colour), so a face that fails backs off the one vertex
 * that moved and not its neighbours too: moving them all at once left the donut's 95th percentile
 * at 4.99 s, by colours 2.39 s (a dense jittered shell at g = 10 s: 4.70 s, 0.52 s). What stays
 * far on the donut is held by the turn and shrink checks, a staircase's riser that would turn
 * over or collapse on the smooth capture; the voxels' triangles cannot go nearer there. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "contact/points_proxy_impl.h"

typedef rk_proxy_grid point_grid;

static int64_t cell_key(const long c[3]) { return c[0] + RK_PROXY_S * (c[1] + RK_PROXY_S * c[2]); }

static void cell_of(const point_grid *G, const double *x, long c[3])
{
    for (int d = 0; d < 3; d++) c[d] = (long)floor((x[d] - G->lo[d]) / G->g);
}

/* Cell q's points: G->idx[*first .. end - 1] (an empty range for a cell off the lattice). */
static size_t cell_points(const point_grid *G, const long q[3], size_t *first)
{
    if (q[0] < 0 || q[1] < 0 || q[2] < 0) return *first = 0;
    int64_t key = cell_key(q);
    size_t end = *first = rk_proxy_lower_bound(G->key, (size_t)G->n, key);
    while (end < (size_t)G->n && G->key[end] == key) end++;
    return end;
}

static int in_box(const double *p, const double lo[3], const double hi[3])
{
    int in = 1;
    for (int d = 0; d < 3 && in; d++) in = p[d] >= lo[d] && p[d] <= hi[d];
    return in;
}

double rk_proxy_nearest_at(const point_grid *G, const double *x, int r, const double **at)
{
    long c[3], q[3];
    cell_of(G, x, c);
    double best = INFINITY;
    for (q[2] = c[2] - r; q[2] <= c[2] + r; q[2]++)
        for (q[1] = c[1] - r; q[1] <= c[1] + r; q[1]++)
            for (q[0] = c[0] - r; q[0] <= c[0] + r; q[0]++) {
                size_t i, end = cell_points(G, q, &i);
                for (; i < end; i++) {
                    const double *p = G->X + 3 * G->idx[i];
                    double d2 = 0;
                    for (int d = 0; d < 3; d++) d2 += (p[d] - x[d]) * (p[d] - x[d]);
                    if (d2 < best) {
                        best = d2;
                        if (at) *at = p;
                    }
                }
            }
    return sqrt(best);
}

static double nearest(const point_grid *G, const double *x, int r) { return rk_proxy_nearest_at(G, x, r, NULL); }

typedef struct {
    int64_t key;
    int idx;
} keyed_point;

static int by_cell(const void *a, const void *b)
{
    const keyed_point *x = a, *y = b;
    if (x->key != y->key) return x->key < y->key ? -1 : 1;
    return (x->idx > y->idx) - (x->idx < y->idx);
}

int rk_proxy_grid_build(point_grid *G, const double *X, int n, double g, const double lo[3], rk_error *err)
{
    G->X = X, G->n = n, G->g = g;
    memcpy(G->lo, lo, sizeof G->lo);
    keyed_point *k = rk_calloc((size_t)n, sizeof *k, err);
    G->key = rk_calloc((size_t)n, sizeof *G->key, err);
    G->idx = rk_calloc((size_t)n, sizeof *G->idx, err);
    if (!k || !G->key || !G->idx) {
        free(k), free(G->key), free(G->idx);
        G->key = NULL, G->idx = NULL;
        return -1;
    }
    for (int i = 0; i < n; i++) {
        long c[3];
        cell_of(G, X + 3 * i, c);
        k[i].key = cell_key(c), k[i].idx = i;
    }
    qsort(k, (size_t)n, sizeof *k, by_cell);
    for (int i = 0; i < n; i++) G->key[i] = k[i].key, G->idx[i] = k[i].idx;
    free(k);
    return 0;
}

void rk_proxy_grid_free(rk_proxy_grid *G)
{
    free(G->key), free(G->idx);
    G->key = NULL, G->idx = NULL;
}

static void cross(const double *a, const double *b, const double *c, double *nrm)
{
    double u[3], v[3];
    for (int d = 0; d < 3; d++) u[d] = b[d] - a[d], v[d] = c[d] - a[d];
    nrm[0] = u[1] * v[2] - u[2] * v[1], nrm[1] = u[2] * v[0] - u[0] * v[2], nrm[2] = u[0] * v[1] - u[1] * v[0];
}

static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* How far in along -nrm (unit) from x to go: the first t in [0, sqrt(3) g] with a point within
 * tau (bisected to g/256), else the sampled t nearest a point if nearer than at x, else 0. */
static double inset_depth(const point_grid *G, const double *x, const double *nrm, double tau)
{
    double g = G->g, step = g / 8, best_t = 0, best_d = nearest(G, x, 2);
    if (best_d <= tau) return 0;
    for (int k = 1; k * step <= 1.75 * g; k++) {
        double t = k * step, y[3];
        for (int d = 0; d < 3; d++) y[d] = x[d] - t * nrm[d];
        double dist = nearest(G, y, 2);
        if (dist <= tau) {
            double a = t - step, b = t; /* dist(a) > tau >= dist(b) */
            for (int it = 0; it < 5; it++) {
                double m = 0.5 * (a + b);
                for (int d = 0; d < 3; d++) y[d] = x[d] - m * nrm[d];
                if (nearest(G, y, 1) <= tau) b = m;
                else a = m;
            }
            return b;
        }
        if (dist < best_d) best_d = dist, best_t = t;
    }
    return best_t;
}

/* Whether closed triangles A and B (vertex ids ta, tb; positions x) meet anywhere but the vertices
 * and edge they share, exactly. Two that share no vertex meet iff an edge of one meets the other.
 * Sharing one vertex s: they overlap past s iff the edge of one opposite s meets the other (their
 * common line leaves both through such an edge, or runs along an edge from s that ends in the other
 * or is crossed by its opposite edge). Sharing an edge: iff they are coplanar and fold onto one
 * another (on one side of it). */
int rk_proxy_faces_cross(const int *ta, const int *tb, const double *x)
{
    int shared = 0, sa[3] = {0, 0, 0}, sb[3] = {0, 0, 0};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            if (ta[i] == tb[j]) shared++, sa[i] = sb[j] = 1;
    const double *A[3] = {x + 3 * ta[0], x + 3 * ta[1], x + 3 * ta[2]}, *B[3] = {x + 3 * tb[0], x + 3 * tb[1], x + 3 * tb[2]};
    if (shared == 0) {
        for (int i = 0; i < 3; i++)
            if (rk_segment_triangle_intersect(A[i], A[(i + 1) % 3], B[0], B[1], B[2]) ||
                rk_segment_triangle_intersect(B[i], B[(i + 1) % 3], A[0], A[1], A[2]))
                return 1;
        return 0;
    }
    if (shared == 1) {
        int i = sa[0] ? 0 : sa[1] ? 1 : 2, j = sb[0] ? 0 : sb[1] ? 1 : 2;
        return rk_segment_triangle_intersect(A[(i + 1) % 3], A[(i + 2) % 3], B[0], B[1], B[2]) ||
               rk_segment_triangle_intersect(B[(j + 1) % 3], B[(j + 2) % 3], A[0], A[1], A[2]);
    }
    if (shared == 2) {
        int i = !sa[0] ? 0 : !sa[1] ? 1 : 2, j = !sb[0] ? 0 : !sb[1] ? 1 : 2; /* the unshared ones */
        const double *s = A[(i + 1) % 3], *t = A[(i + 2) % 3];
        if (rk_orient3d_sign(s, t, A[i], B[j]) != 0) return 0;
        double na[3], nb[3];
        cross(s, t, A[i], na);
        cross(s, t, B[j], nb);
        return dot(na, nb) > 0;
    }
    return 0;
}

/* Whether both faces' vertices moved from base by one vector: then they meet as they met at base,
 * where they did not (coplanar neighbours on a flat side, whose exact tests are the slow ones). */
static int same_shift(const int *ta, const int *tb, const double *base, const double *x)
{
    int v0 = ta[0];
    for (int k = 0; k < 6; k++) {
        int v = k < 3 ? ta[k] : tb[k - 3];
        for (int d = 0; d < 3; d++)
            if (x[3 * v + d] - base[3 * v + d] != x[3 * v0 + d] - base[3 * v0 + d]) return 0;
    }
    return 1;
}

/* Whether a point of the grid lies in the convex hull of the 6 positions v (a face before and after
 * its move), exactly: p is outside iff some plane through 3 of them has all 6 on one side and p
 * strictly on the other (a facet of the hull; a flat hull has none, and p is then outside iff it is
 * off its plane, which the same test finds). */
/* Whether p lies in the prism a b c (v6[0..2]) translated to v6[3..5], exactly: between the two
 * triangles' planes and inside the three side planes. -1 when the prism is flat (the move runs
 * along the triangle's plane). The general test below finds the same, slower: a prism's sides are
 * quads, four points in a plane, whose exact zeros take the predicates' slow path. */
static int prism_holds(const double *const v6[6], const double *p)
{
    int s1 = rk_orient3d_sign(v6[0], v6[1], v6[2], p), s2 = rk_orient3d_sign(v6[3], v6[4], v6[5], p);
    if (s1 && s2 && s1 == s2) return 0;
    for (int e = 0; e < 3; e++) {
        const double *a = v6[e], *b = v6[(e + 1) % 3], *c = v6[(e + 2) % 3], *a2 = v6[3 + e];
        int in = rk_orient3d_sign(a, b, a2, c);
        if (in == 0) return -1;
        int sp = rk_orient3d_sign(a, b, a2, p);
        if (sp && sp != in) return 0;
    }
    return 1;
}

/* (mark NULL: whether any point is in it; else every such point i gets mark[i] = 1, and the
 * return says whether there was one) */
static int hull_holds_point(const point_grid *G, const double *const v6[6], char *mark)
{
    int prism = 1, found = 0; /* every vertex moved by the same vector (a face moved along its own normal) */
    for (int k = 1; k < 3 && prism; k++)
        for (int d = 0; d < 3; d++) prism = prism && v6[3 + k][d] - v6[k][d] == v6[3][d] - v6[0][d];
    if (prism && (v6[3][0] != v6[0][0] || v6[3][1] != v6[0][1] || v6[3][2] != v6[0][2])) {
        double lo[3], hi[3];
        for (int d = 0; d < 3; d++) {
            lo[d] = hi[d] = v6[0][d];
            for (int l = 1; l < 6; l++) lo[d] = fmin(lo[d], v6[l][d]), hi[d] = fmax(hi[d], v6[l][d]);
        }
        long c0[3], c1[3], q[3];
        cell_of(G, lo, c0);
        cell_of(G, hi, c1);
        int flat = 0;
        for (q[2] = c0[2]; q[2] <= c1[2] && !flat; q[2]++)
            for (q[1] = c0[1]; q[1] <= c1[1] && !flat; q[1]++)
                for (q[0] = c0[0]; q[0] <= c1[0] && !flat; q[0]++) {
                    size_t a, end = cell_points(G, q, &a);
                    for (; a < end; a++) {
                        const double *p = G->X + 3 * G->idx[a];
                        if (!in_box(p, lo, hi)) continue;
                        int h = prism_holds(v6, p);
                        if (h == 1) {
                            if (!mark) return 1;
                            mark[G->idx[a]] = 1, found = 1;
                        }
                        if (h < 0) flat = 1;
                    }
                }
        if (!flat) return found;
    }
    const double *v[6];
    int nvert = 0, facet[20][4], nfacet = -1; /* i, j, k and the side of the others; -1: not yet */
    for (int l = 0; l < 6; l++) { /* an unmoved vertex once: exact zeros are the predicates' slow path */
        int dup = 0;
        for (int a = 0; a < nvert && !dup; a++) dup = v[a][0] == v6[l][0] && v[a][1] == v6[l][1] && v[a][2] == v6[l][2];
        if (!dup) v[nvert++] = v6[l];
    }
    double lo[3], hi[3];
    for (int d = 0; d < 3; d++) {
        lo[d] = hi[d] = v[0][d];
        for (int l = 1; l < nvert; l++) lo[d] = fmin(lo[d], v[l][d]), hi[d] = fmax(hi[d], v[l][d]);
    }
    long c0[3], c1[3], q[3];
    cell_of(G, lo, c0);
    cell_of(G, hi, c1);
    for (q[2] = c0[2]; q[2] <= c1[2]; q[2]++)
        for (q[1] = c0[1]; q[1] <= c1[1]; q[1]++)
            for (q[0] = c0[0]; q[0] <= c1[0]; q[0]++) {
                size_t a, end = cell_points(G, q, &a);
                for (; a < end; a++) {
                    const double *p = G->X + 3 * G->idx[a];
                    int in = in_box(p, lo, hi);
                    if (in && nfacet < 0) { /* the facets, once a point lies in the hull's box */
                        nfacet = 0;
                        for (int i = 0; i < nvert; i++)
                            for (int j = i + 1; j < nvert; j++)
                                for (int k = j + 1; k < nvert; k++) {
                                    int pos = 0, neg = 0;
                                    for (int l = 0; l < nvert; l++) {
                                        if (l == i || l == j || l == k) continue;
                                        int sg = rk_orient3d_sign(v[i], v[j], v[k], v[l]);
                                        pos += sg > 0, neg += sg < 0;
                                    }
                                    if (pos && neg) continue;
                                    facet[nfacet][0] = i, facet[nfacet][1] = j, facet[nfacet][2] = k;
                                    facet[nfacet++][3] = pos ? 1 : neg ? -1 : 0;
                                }
                    }
                    for (int f = 0; f < nfacet && in; f++) {
                        int s = rk_orient3d_sign(v[facet[f][0]], v[facet[f][1]], v[facet[f][2]], p);
                        /* all others on side facet[f][3] (0: all in the plane, either side) */
                        if (facet[f][3] >= 0 && s < 0) in = 0;
                        if (facet[f][3] <= 0 && s > 0) in = 0;
                    }
                    if (in) {
                        if (!mark) return 1;
                        mark[G->idx[a]] = 1, found = 1;
                    }
                }
            }
    return found;
}

/* The last stage's bound (NULL in the others): a point may lie outside by at most t. loose[i]: point
 * i was swept over by a face in an accepted state (and is within t of the surface); swept and far
 * are settle's scratch (one a point). */
typedef struct {
    double t;
    char *loose, *swept, *far;
} outside_bound;

/* Whether p lies in box (lo, hi: 6 numbers) grown by pad. */
static int near_box(const double *p, const double *box, double pad)
{
    int in = 1;
    for (int d = 0; d < 3 && in; d++) in = p[d] >= box[d] - pad && p[d] <= box[3 + d] + pad;
    return in;
}

/* The relaxed check (O): every point swept over (O->swept, loose ones included) whose surface near
 * it changed (a dirty face within t of its box) must lie within O->t of a face; where one does not,
 * the moved faces near it are bad. Its distance is measured to every face whose box, grown by t,
 * holds it (the face grid F lists a superset): a face not listed is farther than t. */
static void check_outside(const outside_bound *O, const rk_proxy_face_grid *F, const point_grid *G, const int *tris,
                          const double *x, const double *boxes, const char *dirty, const char *moved, char *bad)
{
    for (int i = 0; i < G->n; i++) {
        if (!O->swept[i]) continue;
        const double *p = G->X + 3 * i;
        size_t first, end = rk_proxy_faces_near(F, p, &first);
        int changed = 0;
        for (size_t k = first; k < end && !changed; k++) changed = dirty[F->face[k]] && near_box(p, boxes + 6 * F->face[k], O->t);
        if (!changed) continue;
        double dmin = INFINITY;
        for (size_t k = first; k < end && dmin > O->t; k++) {
            const int f = F->face[k], *t = tris + 3 * f;
            if (near_box(p, boxes + 6 * f, O->t))
                dmin = fmin(dmin, rk_proxy_face_distance(p, x + 3 * t[0], x + 3 * t[1], x + 3 * t[2]));
        }
        O->far[i] = !(dmin <= O->t);
        if (!O->far[i]) continue;
        for (size_t k = first; k < end; k++)
            if (moved[F->face[k]] && near_box(p, boxes + 6 * F->face[k], O->t)) bad[F->face[k]] = 1;
    }
}

/* Moves each surface vertex v of m from base toward base + dir (alpha[v] of the way, 1 to start)
 * and backs off (halving alpha, then 0) the vertices of every face that would turn over against
 * its voxel face (Xv), collapse, cross another, or sweep over a point (in the hull of its faces at
 * base and moved; with O, leave a point it swept over farther than O->t from every face), until
 * none does. base must pass these checks itself. */
static int settle(rk_mesh *m, const int *tris, int nf, const point_grid *G, const double *Xv, const double *base,
                  const double *dir, double *alpha, double *boxes, char *bad, char *moved, int n,
                  const outside_bound *O, rk_error *err)
{
    rk_proxy_face_grid F = {0};
    size_t nv = (size_t)m->nv;
    int *pairs = NULL, npairs = 0;
    /* a face is checked again only when one of its vertices backed off (dirty); the rest passed */
    double *last = rk_calloc(nv, sizeof *last, err);
    char *dirty = rk_calloc((size_t)nf, 1, err);
    if (!last || !dirty) {
        free(last), free(dirty);
        return -1;
    }
    /* the pairs of faces that can meet anywhere along the moves: their boxes from base to base + dir */
    for (int f = 0; f < nf; f++)
        for (int d = 0; d < 3; d++) {
            boxes[6 * f + d] = INFINITY, boxes[6 * f + 3 + d] = -INFINITY;
            for (int k = 0; k < 3; k++) {
                double b = base[3 * tris[3 * f + k] + d], e = b + dir[3 * tris[3 * f + k] + d];
                boxes[6 * f + d] = fmin(boxes[6 * f + d], fmin(b, e));
                boxes[6 * f + 3 + d] = fmax(boxes[6 * f + 3 + d], fmax(b, e));
            }
        }
    if (rk_broad_phase(boxes, nf, boxes, nf, &pairs, &npairs, err) ||
        (O && rk_proxy_face_grid_build(&F, boxes, nf, O->t, G->g, err))) {
        free(last), free(dirty), free(pairs);
        return -1;
    }
    if (O) memcpy(O->swept, O->loose, (size_t)n), memset(O->far, 0, (size_t)n);
    for (int pass = 0;; pass++) {
        for (size_t v = (size_t)n; v < nv; v++)
            for (int d = 0; d < 3; d++) m->X[3 * v + d] = base[3 * v + d] + alpha[v] * dir[3 * v + d];
        int nbad = 0;
        memset(bad, 0, (size_t)nf);
        for (int f = 0; f < nf; f++) {
            const int *t = tris + 3 * f;
            dirty[f] = pass == 0 || alpha[t[0]] != last[t[0]] || alpha[t[1]] != last[t[1]] || alpha[t[2]] != last[t[2]];
            moved[f] = 0;
            for (int k = 0; k < 3; k++)
                for (int d = 0; d < 3; d++) moved[f] |= m->X[3 * t[k] + d] != base[3 * t[k] + d];
            if (!moved[f] || !dirty[f]) continue;
            double n0[3], n1[3];
            cross(Xv + 3 * t[0], Xv + 3 * t[1], Xv + 3 * t[2], n0);
            cross(m->X + 3 * t[0], m->X + 3 * t[1], m->X + 3 * t[2], n1);
            double l0 = sqrt(dot(n0, n0)), l1 = sqrt(dot(n1, n1));
            const double *v6[6] = {base + 3 * t[0], base + 3 * t[1], base + 3 * t[2],
                                   m->X + 3 * t[0], m->X + 3 * t[1], m->X + 3 * t[2]};
            /* turned past ~87 degrees or shrunk under 1/20 of its area; or over a point (with O:
             * the points it sweeps over are checked below) */
            bad[f] = dot(n0, n1) < 0.05 * l0 * l1 || l1 < 0.05 * l0;
            if (O) hull_holds_point(G, v6, O->swept);
            else bad[f] = bad[f] || hull_holds_point(G, v6, NULL);
        }
        memcpy(last, alpha, sizeof(double) * nv);
        for (int p = 0; p < npairs; p++) {
            int a = pairs[2 * p], b = pairs[2 * p + 1], apart = 0;
            if (a >= b || !(moved[a] || moved[b]) || !(dirty[a] || dirty[b]) || (bad[a] && bad[b])) continue;
            for (int d = 0; d < 3 && !apart; d++) {
                const int *ta = tris + 3 * a, *tb = tris + 3 * b;
                double alo = fmin(m->X[3 * ta[0] + d], fmin(m->X[3 * ta[1] + d], m->X[3 * ta[2] + d]));
                double ahi = fmax(m->X[3 * ta[0] + d], fmax(m->X[3 * ta[1] + d], m->X[3 * ta[2] + d]));
                double blo = fmin(m->X[3 * tb[0] + d], fmin(m->X[3 * tb[1] + d], m->X[3 * tb[2] + d]));
                double bhi = fmax(m->X[3 * tb[0] + d], fmax(m->X[3 * tb[1] + d], m->X[3 * tb[2] + d]));
                apart = ahi < blo || bhi < alo;
            }
            if (apart) continue;
            if (!same_shift(tris + 3 * a, tris + 3 * b, base, m->X) && rk_proxy_faces_cross(tris + 3 * a, tris + 3 * b, m->X))
                bad[a] = bad[b] = 1;
        }
        if (O) check_outside(O, &F, G, tris, m->X, boxes, dirty, moved, bad);
        for (int f = 0; f < nf; f++) /* (a face that did not move and is crossed: the one that did backs off) */
            if (bad[f] && moved[f]) {
                nbad++;
                for (int k = 0; k < 3; k++) {
                    double *al = &alpha[tris[3 * f + k]];
                    *al = *al > 1.0 / 16 ? 0.5 * *al : 0;
                }
            }
        if (nbad == 0) break;
    }
    /* a point marked swept by a move later backed off, and now far, lies in no face's final
     * sweep (that face would be bad): it is inside, as it was */
    if (O)
        for (int i = 0; i < n; i++) O->loose[i] |= O->swept[i] && !O->far[i];
    free(pairs), free(last), free(dirty);
    rk_proxy_face_grid_free(&F);
    return 0;
}

/* The points within O->t of the surface (x, faces tris): the only ones that may lie outside it (the
 * last stage's bound), so the ones whose distance is checked from the start (loose). */
static int loose_points(outside_bound *O, const point_grid *G, const int *tris, int nf, const double *x, double *boxes,
                        rk_error *err)
{
    rk_proxy_face_grid F;
    rk_proxy_face_boxes(x, tris, nf, boxes);
    if (rk_proxy_face_grid_build(&F, boxes, nf, O->t, G->g, err)) return -1;
    for (int i = 0; i < G->n; i++) {
        const double *p = G->X + 3 * i;
        size_t first, end = rk_proxy_faces_near(&F, p, &first);
        for (size_t k = first; k < end && !O->loose[i]; k++) {
            const int *t = tris + 3 * F.face[k];
            O->loose[i] = near_box(p, boxes + 6 * F.face[k], O->t) &&
                          rk_proxy_face_distance(p, x + 3 * t[0], x + 3 * t[1], x + 3 * t[2]) <= O->t;
        }
    }
    rk_proxy_face_grid_free(&F);
    return 0;
}

/* Colours the surface's vertices (greedily, in order) so that no face has two of one colour (at
 * most 64 colours: a vertex of the voxel surface has at most 14 neighbours); returns the number of
 * colours, or -1 out of memory. */
static int color_vertices(const int *tris, int nf, size_t nv, int *color, rk_error *err)
{
    /* the faces around each vertex: fan[start[v] .. start[v + 1] - 1] */
    size_t *start = rk_calloc(nv + 1, sizeof *start, err);
    int *fan = rk_calloc(3 * (size_t)nf + 1, sizeof *fan, err), ncolor = 0;
    if (!start || !fan) {
        free(start), free(fan);
        return -1;
    }
    for (int k = 0; k < 3 * nf; k++) start[tris[k] + 1]++;
    for (size_t v = 0; v < nv; v++) start[v + 1] += start[v];
    for (int k = 0; k < 3 * nf; k++) fan[start[tris[k]]++] = k / 3;
    for (size_t v = nv; v > 0; v--) start[v] = start[v - 1];
    start[0] = 0;
    for (size_t v = 0; v < nv; v++) {
        uint64_t used = 0;
        color[v] = -1;
        for (size_t k = start[v]; k < start[v + 1]; k++)
            for (int a = 0; a < 3; a++) {
                int u = tris[3 * fan[k] + a];
                if ((size_t)u < v && color[u] >= 0) used |= (uint64_t)1 << color[u];
            }
        if (start[v] == start[v + 1]) continue;
        int c = 0;
        while (c < 63 && ((used >> c) & 1)) c++;
        color[v] = c;
        ncolor = c + 1 > ncolor ? c + 1 : ncolor;
    }
    free(start), free(fan);
    return ncolor;
}

/* rk_proxy_inset (first) and rk_proxy_near (!first), one body: first runs the first two stages,
 * outside > 0 the last; a face's turn and shrink are measured against its voxel face, lattice (the
 * positions m->X had before rk_proxy_inset; NULL: m->X now, the voxel surface itself). */
static int inset(rk_mesh *m, const double *lattice, int n, double g, double tau, double outside, int first, const double lo[3],
                 rk_error *err)
{
    int *tris = NULL, nf = 0, rc = -1;
    point_grid G = {0};
    double *Xv = NULL, *base = NULL, *dir = NULL, *boxes = NULL, *alpha = NULL;
    char *bad = NULL, *moved = NULL, *on = NULL;
    int *color = NULL;
    outside_bound O = {outside, NULL, NULL, NULL};
    double tau1 = fmax(tau, RK_PROXY_INSET * g); /* the first stage's target: about half a voxel */
    if (rk_mesh_boundary(m, &tris, &nf, err) || rk_proxy_grid_build(&G, m->X, n, g, lo, err)) goto done;
    size_t nv = (size_t)m->nv;
    Xv = rk_calloc(3 * nv, sizeof *Xv, err);
    base = rk_calloc(3 * nv, sizeof *base, err);
    dir = rk_calloc(3 * nv, sizeof *dir, err); /* each vertex's whole move */
    alpha = rk_calloc(nv, sizeof *alpha, err);
    boxes = rk_calloc(6 * (size_t)nf, sizeof *boxes, err);
    bad = rk_calloc((size_t)nf, 1, err);
    moved = rk_calloc((size_t)nf, 1, err);
    on = rk_calloc(nv, 1, err); /* on the surface */
    if (!Xv || !base || !dir || !alpha || !boxes || !bad || !moved || !on) goto done;
    for (int k = 0; k < 3 * nf; k++) on[tris[k]] = 1;
    memcpy(Xv, lattice ? lattice : m->X, sizeof(double) * 3 * nv);
    memcpy(base, m->X, sizeof(double) * 3 * nv);
    int rounds = 0, near = outside > 0 ? RK_PROXY_NEAR_ROUNDS : 0;
    if (first) {
        /* first along the area-weighted normals (the cross products are twice the faces' areas) */
        for (int f = 0; f < nf; f++) {
            double nrm[3];
            const int *t = tris + 3 * f;
            cross(Xv + 3 * t[0], Xv + 3 * t[1], Xv + 3 * t[2], nrm);
            for (int k = 0; k < 3; k++)
                for (int d = 0; d < 3; d++) dir[3 * t[k] + d] += nrm[d];
        }
        for (size_t v = (size_t)n; v < nv; v++) {
            double len = sqrt(dot(dir + 3 * v, dir + 3 * v));
            if (!(len > 1e-6 * g * g)) { /* not on the surface, or normals that cancel: stays */
                memset(dir + 3 * v, 0, sizeof(double) * 3);
                continue;
            }
            for (int d = 0; d < 3; d++) dir[3 * v + d] /= len;
            /* no farther than the nearest point is: past that the ray runs between the points */
            double t = fmin(inset_depth(&G, Xv + 3 * v, dir + 3 * v, tau1), nearest(&G, Xv + 3 * v, 2));
            for (int d = 0; d < 3; d++) dir[3 * v + d] *= -t;
            alpha[v] = 1;
        }
        if (settle(m, tris, nf, &G, Xv, base, dir, alpha, boxes, bad, moved, n, NULL, err)) goto done;
        /* then the vertices still farther than the stage's target from the points (a ray between
         * them, a move backed off) straight toward their nearest point, to that target from it:
         * four rounds to tau1, then RK_PROXY_PULL_ROUNDS to tau where that is nearer. A move
         * straight toward the nearest point brings no vertex farther from the points, so the second
         * stage keeps the first's worst distance and moves the rest nearer (going for tau from the
         * start instead let vertices run deep first and then block their neighbours: the donut
         * capture's worst went from 0.97 g to 1.37 g) */
        rounds = tau < tau1 ? 4 + RK_PROXY_PULL_ROUNDS : 4;
    }
    if (near) {
        O.loose = rk_calloc((size_t)n + 1, 1, err), O.swept = rk_calloc((size_t)n + 1, 1, err);
        O.far = rk_calloc((size_t)n + 1, 1, err);
        if (!O.loose || !O.swept || !O.far) goto done;
    }
    /* last (outside > 0), the same pull to tau with the points-inside check relaxed: a point the
     * surface sweeps over may stay outside it by at most outside (settle's O). The vertices held
     * back above are those whose every move would pass over a noisy shell's outer splat */
    /* the last stage moves one colour of vertices a round (no face has two of one colour), each
     * colour RK_PROXY_NEAR_ROUNDS times: a face that fails then backs off only the vertex that
     * moved, not its neighbours (issue 30, the donut capture: moving them all at once held 1,138 of
     * its 3,244 surface vertices farther than s from the points; 708 of those could each go to
     * s / 2 alone under every check) */
    int ncolor = 1;
    if (near) {
        color = rk_calloc(nv, sizeof *color, err);
        if (!color) goto done;
        ncolor = color_vertices(tris, nf, nv, color, err);
        if (ncolor < 0) goto done;
        near *= ncolor;
    }
    /* still: the last stage's rounds in a row that moved nothing; after a whole cycle of colours
     * the next would repeat it exactly */
    for (int round = 0, still = 0; round < rounds + near && still < ncolor; round++) {
        double target = first && round < 4 ? tau1 : tau;
        int any = 0;
        if (round == rounds && loose_points(&O, &G, tris, nf, m->X, boxes, err)) goto done;
        memcpy(base, m->X, sizeof(double) * 3 * nv);
        memset(dir, 0, sizeof(double) * 3 * nv);
        memset(alpha, 0, sizeof(double) * nv);
        for (size_t v = (size_t)n; v < nv; v++) {
            if (!on[v] || (round >= rounds && color[v] != (round - rounds) % ncolor)) continue;
            const double *p = NULL, *x = base + 3 * v;
            double d = rk_proxy_nearest_at(&G, x, 2, &p);
            if (!p || !(d > 1.05 * target)) continue;
            for (int a = 0; a < 3; a++) dir[3 * v + a] = p[a] + target * (x[a] - p[a]) / d - x[a];
            alpha[v] = any = 1;
        }
        if (any && settle(m, tris, nf, &G, Xv, base, dir, alpha, boxes, bad, moved, n, round < rounds ? NULL : &O, err))
            goto done;
        if (round >= rounds) {
            any = 0;
            for (size_t v = (size_t)n; v < nv && !any; v++) any = alpha[v] > 0;
            still = any ? 0 : still + 1;
        }
    }
    rc = 0;
done:
    free(O.loose), free(O.swept), free(O.far), free(color);
    free(tris), free(G.key), free(G.idx), free(Xv), free(base), free(dir), free(alpha), free(boxes), free(bad),
        free(moved), free(on);
    return rc;
}

int rk_proxy_inset(rk_mesh *m, int n, double g, double tau, const double lo[3], rk_error *err)
{
    return inset(m, NULL, n, g, tau, 0, 1, lo, err);
}

int rk_proxy_near(rk_mesh *m, const double *lattice, int n, double g, double tau, double outside, const double lo[3],
                  rk_error *err)
{
    if (!(outside > 0)) return 0;
    return inset(m, lattice, n, g, tau, outside, 0, lo, err);
}
