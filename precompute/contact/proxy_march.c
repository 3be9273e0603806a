/* rk_points_march (contact.h): a point cloud's contact surface that follows the capture, not the
 * voxels (issue 30: "a cloud's contact surface sits within its points' spacing of its points").
 *
 * Why not the voxel surface moved in (points_proxy.c, proxy_inset.c): on a dense capture the voxel
 * is capped at 1/40 of the diagonal (10 s on the donut capture, s the points' spacing), and a
 * staircase's riser on a smooth surface cannot come in without turning over or collapsing, so the
 * donut's 95th percentile vertex stayed 2.39 s off. Here the faces are not axis-aligned:
 *   1. the cloud's reach: the nodes of a lattice of edge h farther than R = RK_MARCH_REACH h from
 *      every point and reachable from the border through such nodes (over the Kuhn lattice's 14
 *      neighbours) are outside, every other node inside (holes narrower than about 2R closed);
 *   2. marching tetrahedra on the lattice's Kuhn tets (the 6 per cube around its 000-111 diagonal,
 *      faces matching between cubes, so the surface is closed and 2-manifold with no ambiguous
 *      case): one vertex on each edge from an outside node a to an inside node b, where the edge
 *      first comes within R of a point (b is within R of one, or flooding would have reached it);
 *      each such vertex is exactly R from its nearest point, the level set R of the distance to the
 *      cloud, and the pieces of a tet lie in the tet, so nothing crosses;
 *   3. each vertex straight toward its nearest point p, to tau = RK_PROXY_SPACING_INSET s from it
 *      (x' = p + tau (x - p) / |x - p|: the offset surface's normal is x - p, so the moves are
 *      nearly parallel where it is smooth); a vertex of a face that would cross another (exact:
 *      rk_proxy_faces_cross) has its move halved, down to none, until none does (at none it is step
 *      2's surface, which passes); then those held back try again, one colour of vertices at a
 *      time (a single halving per failing pair left 5% of the donut's vertices 6.8 s off);
 *   4. the slivers that the pull leaves (vertices pulled to one point end close together) tidied:
 *      short edges collapsed, caps flipped (proxy_march_tidy.c), unless that leaves a point past
 *      RK_PROXY_OUTSIDE s where the untidied surface has none.
 * Then every point is checked: inside (the parity of a ray's exact crossings) or within
 * RK_PROXY_OUTSIDE s of a face; the count of those that are neither goes to the report, and a
 * caller refuses the surface unless it is 0.
 *
 * Measured on the donut capture (45,624 splats, s = 0.77 mm, g = 10 s, h = 1.5 g;
 * docs/cloud_march.md): 5,208 triangles (8,556 before step 4; the voxel surface 6,364), vertices
 * median and 95th percentile 0.50 s from a point, worst 6.81 s, the farthest point outside 0.95 s;
 * 150 triangles of quality under RK_MARCH_SLIVER (2,674 before step 4), the worst 8.1e-4. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "contact/points_proxy_impl.h"

/* Kuhn's tets of the unit cube (points_proxy.c's) and the 7 lattice directions of their edges. */
static const int KUHN[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};
static const int DIR[7][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};

typedef struct {
    long dim[3];
    double lo[3], h;
} lattice;

static long node_of(const lattice *L, long i, long j, long k) { return i + L->dim[0] * (j + L->dim[1] * k); }

static void node_x(const lattice *L, long v, double *x)
{
    long i = v % L->dim[0], j = v / L->dim[0] % L->dim[1], k = v / L->dim[0] / L->dim[1];
    x[0] = L->lo[0] + L->h * (double)i, x[1] = L->lo[1] + L->h * (double)j, x[2] = L->lo[2] + L->h * (double)k;
}

/* The neighbour of v along direction q (0..13: DIR forward, then back), -1 off the lattice; with
 * dir != NULL the edge's id (7 times its lower node plus its direction) into *edge. */
static long neighbour(const lattice *L, long v, int q, long *edge)
{
    long c[3] = {v % L->dim[0], v / L->dim[0] % L->dim[1], v / L->dim[0] / L->dim[1]};
    int sg = q < 7 ? 1 : -1;
    for (int d = 0; d < 3; d++) {
        c[d] += sg * DIR[q % 7][d];
        if (c[d] < 0 || c[d] >= L->dim[d]) return -1;
    }
    long w = node_of(L, c[0], c[1], c[2]);
    if (edge) *edge = 7 * (q < 7 ? v : w) + q % 7;
    return w;
}

/* The first t in [0, 1] at which a + t (b - a) is within r of a point (2 if none), from the points
 * in the cells (edge G->g >= r) that the segment's box grown by r meets. */
static double first_hit(const rk_proxy_grid *G, const double *a, const double *b, double r)
{
    long c0[3], c1[3], q[3];
    double u[3], uu = 0, best = 2;
    for (int d = 0; d < 3; d++) {
        u[d] = b[d] - a[d], uu += u[d] * u[d];
        c0[d] = (long)floor((fmin(a[d], b[d]) - r - G->lo[d]) / G->g);
        c1[d] = (long)floor((fmax(a[d], b[d]) + r - G->lo[d]) / G->g);
        if (c0[d] < 0) c0[d] = 0;
    }
    for (q[2] = c0[2]; q[2] <= c1[2]; q[2]++)
        for (q[1] = c0[1]; q[1] <= c1[1]; q[1]++)
            for (q[0] = c0[0]; q[0] <= c1[0]; q[0]++) {
                int64_t key = q[0] + RK_PROXY_S * (q[1] + RK_PROXY_S * q[2]);
                for (size_t i = rk_proxy_lower_bound(G->key, (size_t)G->n, key); i < (size_t)G->n && G->key[i] == key; i++) {
                    const double *p = G->X + 3 * G->idx[i];
                    double w[3], uw = 0, ww = 0;
                    for (int d = 0; d < 3; d++) w[d] = p[d] - a[d], uw += u[d] * w[d], ww += w[d] * w[d];
                    double disc = uw * uw - uu * (ww - r * r); /* |a + t u - p| = r */
                    if (disc < 0) continue;
                    double t0 = (uw - sqrt(disc)) / uu, t1 = (uw + sqrt(disc)) / uu;
                    if (t1 >= 0 && t0 <= 1) best = fmin(best, fmax(t0, 0));
                }
            }
    return best;
}

void rk_proxy_face_normal(const double *x, const int *t, double *nrm)
{
    double u[3], v[3];
    for (int d = 0; d < 3; d++) u[d] = x[3 * t[1] + d] - x[3 * t[0] + d], v[d] = x[3 * t[2] + d] - x[3 * t[0] + d];
    nrm[0] = u[1] * v[2] - u[2] * v[1], nrm[1] = u[2] * v[0] - u[0] * v[2], nrm[2] = u[0] * v[1] - u[1] * v[0];
}

/* Step 1 and 2: the level set R of the distance to the cloud, as outward triangles. */
static int march(const rk_proxy_grid *G, const lattice *L, double R, rk_surface *out, rk_error *err)
{
    long N = L->dim[0] * L->dim[1] * L->dim[2];
    char *far = rk_calloc((size_t)N, 1, err), *outside = rk_calloc((size_t)N, 1, err);
    long *stack = rk_calloc((size_t)N, sizeof *stack, err);
    int *vert = rk_calloc(7 * (size_t)N, sizeof *vert, err); /* edge -> surface vertex + 1 */
    int rc = -1, capv = 1024, capf = 2048;
    out->X = rk_calloc(3 * (size_t)capv, sizeof *out->X, err);
    out->tris = rk_calloc(3 * (size_t)capf, sizeof *out->tris, err);
    if (!far || !outside || !stack || !vert || !out->X || !out->tris) goto done;
    for (long v = 0; v < N; v++) {
        double x[3];
        node_x(L, v, x);
        far[v] = rk_proxy_nearest_at(G, x, 1, NULL) > R; /* cells of edge h > R: exact */
    }
    long sp = 0;
    stack[sp++] = 0, outside[0] = 1; /* a corner: 2 h off the cloud's box */
    while (sp > 0) {
        long v = stack[--sp];
        for (int q = 0; q < 14; q++) {
            long w = neighbour(L, v, q, NULL);
            if (w >= 0 && far[w] && !outside[w]) outside[w] = 1, stack[sp++] = w;
        }
    }
    for (long k = 0; k + 1 < L->dim[2]; k++)
        for (long j = 0; j + 1 < L->dim[1]; j++)
            for (long i = 0; i + 1 < L->dim[0]; i++) {
                long id[8];
                for (int b = 0; b < 8; b++) id[b] = node_of(L, i + (b & 1), j + ((b >> 1) & 1), k + ((b >> 2) & 1));
                for (int t = 0; t < 6; t++) {
                    int lone, nin = 0, e[4][4];
                    const int *T = KUHN[t];
                    for (int a = 0; a < 4; a++) nin += !outside[id[T[a]]];
                    if (nin == 0 || nin == 4) continue;
                    for (int a = 0; a < 4; a++)
                        for (int b = 0; b < 4; b++) e[a][b] = -1;
                    for (int a = 0; a < 4; a++)
                        for (int b = 0; b < 4; b++) {
                            long A = id[T[a]], B = id[T[b]], edge = -1;
                            if (!outside[A] || outside[B]) continue; /* a outside, b inside */
                            for (int q = 0; q < 14 && edge < 0; q++)
                                if (neighbour(L, A, q, &edge) != B) edge = -1;
                            if (!vert[edge]) {
                                double xa[3], xb[3], s = 0;
                                node_x(L, A, xa), node_x(L, B, xb);
                                s = fmin(first_hit(G, xa, xb, R), 1);
                                if (out->nv == capv) {
                                    double *more = realloc(out->X, sizeof(double) * 6 * (size_t)capv);
                                    if (!more) {
                                        rk_fail(err, "contact surface: out of memory");
                                        goto done;
                                    }
                                    out->X = more, capv *= 2;
                                }
                                for (int d = 0; d < 3; d++) out->X[3 * out->nv + d] = xa[d] + s * (xb[d] - xa[d]);
                                vert[edge] = ++out->nv;
                            }
                            e[a][b] = e[b][a] = vert[edge] - 1;
                        }
                    int tri[2][3], nt = 1, I[4], O[4], ni = 0, no = 0;
                    for (int a = 0; a < 4; a++) {
                        if (!outside[id[T[a]]]) I[ni++] = a;
                        else O[no++] = a;
                    }
                    if (ni == 1 || no == 1) {
                        lone = ni == 1 ? I[0] : O[0];
                        for (int a = 0, q = 0; a < 4; a++)
                            if (a != lone) tri[0][q++] = e[lone][a];
                    } else { /* the quad around I0 O0, I0 O1, I1 O1, I1 O0, cut along I0O0-I1O1 */
                        tri[0][0] = e[I[0]][O[0]], tri[0][1] = e[I[0]][O[1]], tri[0][2] = e[I[1]][O[1]];
                        tri[1][0] = e[I[0]][O[0]], tri[1][1] = e[I[1]][O[1]], tri[1][2] = e[I[1]][O[0]], nt = 2;
                    }
                    double in_c[3] = {0, 0, 0}, out_c[3] = {0, 0, 0}, x[3];
                    for (int a = 0; a < 4; a++) {
                        int in = !outside[id[T[a]]];
                        node_x(L, id[T[a]], x);
                        for (int d = 0; d < 3; d++) (in ? in_c : out_c)[d] += x[d] / (in ? ni : no);
                    }
                    for (int q = 0; q < nt; q++) {
                        double nrm[3];
                        rk_proxy_face_normal(out->X, tri[q], nrm);
                        /* outward: from the inside nodes toward the outside ones */
                        if (nrm[0] * (out_c[0] - in_c[0]) + nrm[1] * (out_c[1] - in_c[1]) + nrm[2] * (out_c[2] - in_c[2]) < 0) {
                            int tmp = tri[q][1];
                            tri[q][1] = tri[q][2], tri[q][2] = tmp;
                        }
                        if (out->nf == capf) {
                            int *more = realloc(out->tris, sizeof(int) * 6 * (size_t)capf);
                            if (!more) {
                                rk_fail(err, "contact surface: out of memory");
                                goto done;
                            }
                            out->tris = more, capf *= 2;
                        }
                        memcpy(out->tris + 3 * out->nf++, tri[q], sizeof tri[q]);
                    }
                }
            }
    rc = 0;
done:
    free(far), free(outside), free(stack), free(vert);
    return rc;
}

/* Places S's vertices at from + alpha (to - from) and marks in bad (nv) the vertices of every pair
 * of faces that cross (exact: rk_proxy_faces_cross); returns how many pairs, -1 on failure. */
static int crossings(rk_surface *S, const double *from, const double *to, const double *alpha, double *boxes, char *bad,
                     rk_error *err)
{
    int *pairs = NULL, npairs = 0, nbad = 0;
    for (int v = 0; v < S->nv; v++)
        for (int d = 0; d < 3; d++) S->X[3 * v + d] = from[3 * v + d] + alpha[v] * (to[3 * v + d] - from[3 * v + d]);
    memset(bad, 0, (size_t)S->nv);
    rk_proxy_face_boxes(S->X, S->tris, S->nf, boxes);
    if (rk_broad_phase(boxes, S->nf, boxes, S->nf, &pairs, &npairs, err)) return -1;
    for (int k = 0; k < npairs; k++) {
        const int *ta = S->tris + 3 * pairs[2 * k], *tb = S->tris + 3 * pairs[2 * k + 1];
        if (pairs[2 * k] < pairs[2 * k + 1] && rk_proxy_faces_cross(ta, tb, S->X))
            nbad++, bad[ta[0]] = bad[ta[1]] = bad[ta[2]] = bad[tb[0]] = bad[tb[1]] = bad[tb[2]] = 1;
    }
    free(pairs);
    return nbad;
}

/* Step 3: each vertex toward its nearest point, to tau, backed off where a face would cross
 * another; then, one colour of vertices at a time (no face with two of a colour: what fails is
 * the one vertex of a face that moved, as in rk_proxy_near), those backed off try again to go
 * all the way, then half of what is left, keeping what passes. rep: the rounds and the vertices
 * still short. */
static int pull_in(const rk_proxy_grid *G, rk_surface *S, double tau, rk_points_march_report *rep, rk_error *err)
{
    size_t nv = (size_t)S->nv, nf = (size_t)S->nf;
    double *from = rk_calloc(3 * nv, sizeof *from, err), *to = rk_calloc(3 * nv, sizeof *to, err);
    double *alpha = rk_calloc(nv, sizeof *alpha, err), *keep = rk_calloc(nv, sizeof *keep, err);
    double *boxes = rk_calloc(6 * nf, sizeof *boxes, err);
    char *bad = rk_calloc(nv, 1, err);
    int *colour = rk_calloc(nv, sizeof *colour, err), rc = -1, ncolour = 0, nbad;
    if (!from || !to || !alpha || !keep || !boxes || !bad || !colour) goto done;
    memcpy(from, S->X, sizeof(double) * 3 * nv);
    for (size_t v = 0; v < nv; v++) {
        const double *p = NULL, *x = from + 3 * v;
        double dist = rk_proxy_nearest_at(G, x, 1, &p);
        alpha[v] = 1;
        for (int d = 0; d < 3; d++) to[3 * v + d] = p && dist > 0 ? p[d] + tau * (x[d] - p[d]) / dist : x[d];
    }
    for (rep->rounds = 1; (nbad = crossings(S, from, to, alpha, boxes, bad, err)) != 0; rep->rounds++) {
        int moved = 0;
        if (nbad < 0) goto done;
        for (size_t v = 0; v < nv; v++)
            if (bad[v] && alpha[v] > 0) alpha[v] = alpha[v] > 1.0 / 64 ? 0.5 * alpha[v] : 0, moved = 1;
        if (!moved) { /* the level set itself failed: rounding in a sliver (not seen) */
            rk_fail(err, "contact surface: %d pairs of faces cross with no move left to undo", nbad);
            goto done;
        }
    }
    /* greedy colours: the smallest not used by a vertex sharing a face with it (64 at most:
     * a vertex with more neighbours takes colour 64, shared, and is retried with others) */
    for (size_t v = 0; v < nv; v++) colour[v] = -1;
    {
        /* vertex -> faces */
        int *start = rk_calloc(nv + 1, sizeof *start, err), *vf = rk_calloc(3 * nf, sizeof *vf, err);
        int *fill = rk_calloc(nv, sizeof *fill, err);
        if (!start || !vf || !fill) {
            free(start), free(vf), free(fill);
            goto done;
        }
        for (size_t k = 0; k < 3 * nf; k++) start[S->tris[k] + 1]++;
        for (size_t v = 0; v < nv; v++) start[v + 1] += start[v];
        for (size_t k = 0; k < 3 * nf; k++) vf[start[S->tris[k]] + fill[S->tris[k]]++] = (int)(k / 3);
        for (size_t v = 0; v < nv; v++) {
            uint64_t used = 0;
            for (int q = start[v]; q < start[v + 1]; q++)
                for (int k = 0; k < 3; k++) {
                    int w = S->tris[3 * vf[q] + k];
                    if (colour[w] >= 0 && colour[w] < 64) used |= (uint64_t)1 << colour[w];
                }
            int c = 0;
            while (c < 64 && ((used >> c) & 1)) c++;
            colour[v] = c;
            if (c + 1 > ncolour) ncolour = c + 1;
        }
        free(start), free(vf), free(fill);
    }
    for (int pass = 0; pass < RK_MARCH_RETRIES; pass++)
        for (int c = 0; c < ncolour; c++) {
            int tried = 0;
            memcpy(keep, alpha, sizeof(double) * nv);
            for (size_t v = 0; v < nv; v++)
                if (colour[v] == c && alpha[v] < 1) alpha[v] = pass == 0 ? 1 : 0.5 * (1 + alpha[v]), tried = 1;
            if (!tried) continue;
            while ((nbad = crossings(S, from, to, alpha, boxes, bad, err)) != 0) {
                if (nbad < 0) goto done;
                for (size_t v = 0; v < nv; v++)
                    if (bad[v] && alpha[v] != keep[v]) alpha[v] = keep[v]; /* only this colour moved */
                rep->rounds++;
            }
        }
    if (crossings(S, from, to, alpha, boxes, bad, err) != 0) goto done; /* places S at alpha */
    rep->backed_off = 0;
    for (size_t v = 0; v < nv; v++) rep->backed_off += alpha[v] < 1;
    rc = 0;
done:
    free(from), free(to), free(alpha), free(keep), free(boxes), free(bad), free(colour);
    return rc;
}

/* Every point inside S (the parity of the exact crossings of a segment from it to past the
 * surface's box, nudged off the axes so it meets no edge by symmetry) or within t of a face: the
 * others counted in rep, with the farthest's distance. */
static int check_points(const double *X, int n, const rk_surface *S, double t, rk_points_march_report *rep, rk_error *err)
{
    size_t nf = (size_t)S->nf;
    double *boxes = rk_calloc(6 * nf, sizeof *boxes, err), lo[3], hi[3];
    int rc = -1;
    rk_proxy_face_grid F;
    memset(&F, 0, sizeof F);
    if (!boxes) goto done;
    rk_proxy_face_boxes(S->X, S->tris, S->nf, boxes);
    for (int d = 0; d < 3; d++) {
        lo[d] = INFINITY, hi[d] = -INFINITY;
        for (size_t f = 0; f < nf; f++) lo[d] = fmin(lo[d], boxes[6 * f + d]), hi[d] = fmax(hi[d], boxes[6 * f + 3 + d]);
    }
    double span = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
    /* cells of a few spacings hold few faces; pad t: a point's cell lists every face within t */
    if (rk_proxy_face_grid_build(&F, boxes, S->nf, t, fmax(span / 64, 4 * t), err)) goto done;
    rep->outside_points = 0, rep->max_outside = 0;
    for (int i = 0; i < n; i++) {
        const double *p = X + 3 * i;
        size_t first, end = rk_proxy_faces_near(&F, p, &first);
        double near = INFINITY;
        for (size_t k = first; k < end; k++) {
            const int *tr = S->tris + 3 * F.face[k];
            near = fmin(near, rk_proxy_face_distance(p, S->X + 3 * tr[0], S->X + 3 * tr[1], S->X + 3 * tr[2]));
        }
        if (near <= t) continue;
        double q[3] = {hi[0] + span, p[1] + 1e-3 * span * 0.7071, p[2] + 1e-3 * span * 0.5257};
        int cross = 0;
        for (size_t f = 0; f < nf; f++) { /* brute force: rare (points deeper than t inside) */
            const double *b = boxes + 6 * f;
            if (b[3] < p[0] || b[4] < fmin(p[1], q[1]) || b[1] > fmax(p[1], q[1]) || b[5] < fmin(p[2], q[2]) || b[2] > fmax(p[2], q[2]))
                continue;
            const int *tr = S->tris + 3 * f;
            cross += rk_segment_triangle_intersect(p, q, S->X + 3 * tr[0], S->X + 3 * tr[1], S->X + 3 * tr[2]);
        }
        if (cross % 2 == 1) continue;
        for (size_t f = 0; f < nf; f++) {
            const int *tr = S->tris + 3 * f;
            near = fmin(near, rk_proxy_face_distance(p, S->X + 3 * tr[0], S->X + 3 * tr[1], S->X + 3 * tr[2]));
        }
        rep->outside_points++, rep->max_outside = fmax(rep->max_outside, near);
    }
    rc = 0;
done:
    rk_proxy_face_grid_free(&F);
    free(boxes);
    return rc;
}

/* Step 4 (proxy_march_tidy.c) and the points' check: the slivers removed, unless that leaves a
 * point past RK_PROXY_OUTSIDE s where the untidied surface has none (then that one is kept; where
 * both do, the caller refuses either, and the tidied one is reported). */
static int tidy_checked(const double *X, int n, double s, rk_surface *S, rk_points_march_report *rep, rk_error *err)
{
    rk_surface keep = {S->nv, S->nf, rk_calloc(3 * (size_t)S->nv, sizeof(double), err), rk_calloc(3 * (size_t)S->nf, sizeof(int), err)};
    int rc = -1;
    if (!keep.X || !keep.tris) goto done;
    memcpy(keep.X, S->X, sizeof(double) * 3 * (size_t)S->nv), memcpy(keep.tris, S->tris, sizeof(int) * 3 * (size_t)S->nf);
    if (rk_march_tidy(S, s, rep, err) || check_points(X, n, S, RK_PROXY_OUTSIDE * s, rep, err)) goto done;
    if (rep->outside_points > 0 && rep->collapsed + rep->flipped > 0) {
        rk_points_march_report tidied = *rep;
        if (check_points(X, n, &keep, RK_PROXY_OUTSIDE * s, rep, err)) goto done;
        if (rep->outside_points == 0) {
            rk_surface t = *S;
            *S = keep, keep = t;
            rep->untidy = 1;
        } else
            *rep = tidied;
    }
    rc = 0;
done:
    free(keep.X), free(keep.tris);
    return rc;
}

int rk_points_march(const double *X, int n, double h, double s, rk_surface *out, rk_points_march_report *rep, rk_error *err)
{
    memset(out, 0, sizeof *out);
    memset(rep, 0, sizeof *rep);
    if (n < 1 || !(h > 0) || !isfinite(h)) return rk_fail(err, "contact surface: %d points, lattice edge %g", n, h);
    if (!(s > 0) || !isfinite(s)) return rk_fail(err, "contact surface: points' spacing %g (expected more than 0)", s);
    lattice L;
    L.h = h;
    double hi[3];
    for (int d = 0; d < 3; d++) L.lo[d] = hi[d] = X[d];
    for (int i = 0; i < n; i++)
        for (int d = 0; d < 3; d++) {
            if (!isfinite(X[3 * i + d]))
                return rk_fail(err, "contact surface: point %d is not finite (%g, %g, %g)", i, X[3 * i], X[3 * i + 1], X[3 * i + 2]);
            L.lo[d] = fmin(L.lo[d], X[3 * i + d]), hi[d] = fmax(hi[d], X[3 * i + d]);
        }
    double nodes = 1;
    for (int d = 0; d < 3; d++) {
        L.lo[d] -= 2 * h; /* the border nodes 2 h off every point: outside */
        double cells = ceil((hi[d] + 2 * h - L.lo[d]) / h) + 1;
        nodes *= cells;
        L.dim[d] = nodes <= (double)(1 << 24) && cells < (double)(RK_PROXY_S - 2) ? (long)cells : 0;
    }
    /* 2^24 nodes: the edge table is 7 ints a node; and the point grid's keys hold 2^20 cells an axis */
    if (!(nodes <= (double)(1 << 24)) || !L.dim[0] || !L.dim[1] || !L.dim[2]) return rk_fail(err, "contact surface: lattice edge %g is too small for the cloud's extent", h);
    rk_proxy_grid G;
    if (rk_proxy_grid_build(&G, X, n, h, L.lo, err)) return -1;
    int rc = march(&G, &L, RK_MARCH_REACH * h, out, err) || pull_in(&G, out, RK_PROXY_SPACING_INSET * s, rep, err) ||
             tidy_checked(X, n, s, out, rep, err);
    rk_proxy_grid_free(&G);
    if (rc) {
        free(out->X), free(out->tris);
        memset(out, 0, sizeof *out);
        return -1;
    }
    return 0;
}
