/* rk_march_tidy (points_proxy_impl.h): the march surface's slivers removed after the pull
 * (proxy_march.c's step 3), by the two standard moves of mesh cleanup, each one kept only where
 * the surface stays what rk_points_march promises:
 *   - a short edge (at most RK_MARCH_TIDY_EDGE s, s the points' spacing) of a sliver is collapsed
 *     onto one of its ends (a half-edge collapse: the surviving vertex does not move, so every
 *     vertex keeps its distance to the points) where the link condition holds (the ends share
 *     exactly the two neighbours opposite the edge, each of valence 4 or more: the surface stays a
 *     closed 2-manifold);
 *   - the longest edge of a sliver with no short edge (a cap: one vertex near the opposite edge)
 *     is flipped where the new edge is not there yet, its ends keep valence 3 or more, and the two
 *     diagonals pass within RK_MARCH_TIDY_EDGE s of each other (the surface moves no more);
 * and either only where the worst quality among the faces it changes gets better, no changed
 * face turns over against a well-shaped one it replaces (quality at least RK_MARCH_SLIVER: a
 * sliver's own normal is round-off), and no changed face crosses any face of the surface (exact:
 * rk_proxy_faces_cross, which also catches neighbours folded onto each other). A sliver is a face
 * of quality 4 sqrt(3) A / sum l^2 under RK_MARCH_SLIVER.
 *
 * Why: the pull to s / 2 takes vertices that go to one point to nearly one place, leaving faces
 * of quality down to 2.6e-5 on the donut capture (shortest edge s/33 on a lattice cube). Their
 * barrier pairs are near-degenerate (a point-triangle distance's second derivatives grow as one
 * over the triangle's height), and a lattice cube's impact on a slab ran projected Newton's 50
 * iterations unconverged in double on them, 16 once tidied (docs/cloud_march.md). A tetrahedral
 * mesher chases them too (TetGen split the untidied donut surface into 5 million tets).
 *
 * The moves scan every face for the ones around a vertex (no adjacency kept up to date): on the
 * donut (2,674 slivers of 8,556 faces) rk_points_march takes 2.6-3.1 s of CPU against 2.2-2.3 s
 * untidied (3 runs each, load 2-3; docs/cloud_march.md). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "contact/points_proxy_impl.h"
#include "physics/physics.h"

typedef struct {
    double *X;
    int *tris; /* a removed face has -1 first */
    int nf;
    double s;
    int *list; /* scratch: face ids */
} tidy;

static double quality(const double *X, const int *t)
{
    double n[3], l2 = 0;
    rk_proxy_face_normal(X, t, n);
    for (int k = 0; k < 3; k++)
        for (int d = 0; d < 3; d++) {
            double e = X[3 * t[(k + 1) % 3] + d] - X[3 * t[k] + d];
            l2 += e * e;
        }
    return l2 > 0 ? 2 * sqrt(3.0) * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) / l2 : 0;
}

static double dist2(const double *a, const double *b)
{
    return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
}

static int has(const int *t, int v) { return t[0] == v || t[1] == v || t[2] == v; }

/* The live faces around v into T->list (from *at on); returns how many. */
static int faces_of(tidy *T, int v, int at)
{
    int k = at;
    for (int f = 0; f < T->nf; f++)
        if (T->tris[3 * f] >= 0 && has(T->tris + 3 * f, v)) T->list[k++] = f;
    return k - at;
}

/* Whether face t (not yet in the surface, or face skip itself) crosses a live face other than
 * those in ignore[0 .. nignore - 1]. */
static int crosses(const tidy *T, const int *t, const int *ignore, int nignore)
{
    double lo[3], hi[3];
    for (int d = 0; d < 3; d++) {
        lo[d] = fmin(T->X[3 * t[0] + d], fmin(T->X[3 * t[1] + d], T->X[3 * t[2] + d]));
        hi[d] = fmax(T->X[3 * t[0] + d], fmax(T->X[3 * t[1] + d], T->X[3 * t[2] + d]));
    }
    for (int f = 0; f < T->nf; f++) {
        const int *u = T->tris + 3 * f;
        int skip = u[0] < 0;
        for (int k = 0; k < nignore && !skip; k++) skip = ignore[k] == f;
        if (skip) continue;
        int apart = 0;
        for (int d = 0; d < 3 && !apart; d++)
            apart = fmax(T->X[3 * u[0] + d], fmax(T->X[3 * u[1] + d], T->X[3 * u[2] + d])) < lo[d] ||
                    fmin(T->X[3 * u[0] + d], fmin(T->X[3 * u[1] + d], T->X[3 * u[2] + d])) > hi[d];
        if (!apart && rk_proxy_faces_cross(t, u, T->X)) return 1;
    }
    return 0;
}

/* Whether the new faces nt[0 .. n - 1] (replacing the faces old[0 .. nold - 1]) pass: worst
 * quality above worse_than, no turn against a well-shaped face they replace (new face k replaces
 * the face whose shape is oldt[k], for k < nmatch), no crossing with any face but the replaced
 * ones, nor with each other. */
static int passes(const tidy *T, const int (*nt)[3], int n, const int (*oldt)[3], int nold, int nmatch, const int *old,
                  double worse_than)
{
    double qmin = INFINITY;
    for (int k = 0; k < n; k++) qmin = fmin(qmin, quality(T->X, nt[k]));
    if (!(qmin > worse_than)) return 0;
    for (int k = 0; k < nmatch; k++) {
        double a[3], b[3];
        if (quality(T->X, oldt[k]) < RK_MARCH_SLIVER) continue;
        rk_proxy_face_normal(T->X, oldt[k], a), rk_proxy_face_normal(T->X, nt[k], b);
        if (a[0] * b[0] + a[1] * b[1] + a[2] * b[2] <= 0) return 0;
    }
    for (int k = 0; k < n; k++) {
        if (crosses(T, nt[k], old, nold)) return 0;
        for (int j = 0; j < k; j++)
            if (rk_proxy_faces_cross(nt[k], nt[j], T->X)) return 0;
    }
    return 1;
}

/* Collapses b onto a (a stays where it is); 1 if done. */
static int collapse(tidy *T, int a, int b)
{
    int na = faces_of(T, a, 0), nb = faces_of(T, b, na), *F = T->list, shared = 0, opp[2] = {-1, -1};
    for (int k = na; k < na + nb; k++)
        if (has(T->tris + 3 * F[k], a)) {
            const int *t = T->tris + 3 * F[k];
            if (shared < 2) opp[shared] = t[0] != a && t[0] != b ? t[0] : t[1] != a && t[1] != b ? t[1] : t[2];
            shared++;
        }
    if (shared != 2 || opp[0] == opp[1] || na + nb > 128) return 0; /* (old[]'s room) */
    /* the link condition: a's and b's neighbours in common are the two opposite vertices */
    for (int k = 0; k < na; k++)
        for (int i = 0; i < 3; i++) {
            int w = T->tris[3 * F[k] + i];
            if (w == a || w == b || w == opp[0] || w == opp[1]) continue;
            for (int j = na; j < na + nb; j++)
                if (has(T->tris + 3 * F[j], w)) return 0;
        }
    int nc = faces_of(T, opp[0], na + nb), nd = faces_of(T, opp[1], na + nb);
    if (nc < 4 || nd < 4 || na + nb - 4 < 3) return 0; /* a tetrahedron, or a valence-3 vertex losing a face */
    int nt[64][3], oldt[64][3], old[128], n = 0, nold = 0;
    double worst = INFINITY;
    for (int k = 0; k < na + nb; k++) {
        worst = fmin(worst, quality(T->X, T->tris + 3 * F[k]));
        old[nold++] = F[k];
    }
    for (int k = na; k < na + nb; k++) {
        const int *t = T->tris + 3 * F[k];
        if (has(t, a)) continue;
        if (n == 64) return 0;
        memcpy(oldt[n], t, sizeof oldt[n]);
        for (int i = 0; i < 3; i++) nt[n][i] = t[i] == b ? a : t[i];
        n++;
    }
    /* against every face but b's (removed or replaced): a's others stay */
    if (!passes(T, (const int (*)[3])nt, n, (const int (*)[3])oldt, nb, n, old + na, worst)) return 0;
    for (int k = 0, j = 0; k < na + nb; k++) {
        int *t = T->tris + 3 * F[k];
        if (k < na) continue;
        if (has(t, a)) t[0] = t[1] = t[2] = -1;
        else memcpy(t, nt[j++], sizeof nt[0]);
    }
    return 1;
}

/* Flips edge (a, b) of face f (a -> b in it); 1 if done. */
static int flip(tidy *T, int f, int a, int b)
{
    int g = -1, *F = T->list;
    int nb = faces_of(T, a, 0);
    for (int k = 0; k < nb; k++) {
        const int *t = T->tris + 3 * F[k];
        for (int i = 0; i < 3; i++)
            if (F[k] != f && t[i] == b && t[(i + 1) % 3] == a) g = F[k];
    }
    if (g < 0) return 0;
    const int *tf = T->tris + 3 * f, *tg = T->tris + 3 * g;
    int c = tf[0] != a && tf[0] != b ? tf[0] : tf[1] != a && tf[1] != b ? tf[1] : tf[2];
    int d = tg[0] != a && tg[0] != b ? tg[0] : tg[1] != a && tg[1] != b ? tg[1] : tg[2];
    if (c == d || nb < 4 || faces_of(T, b, 0) < 4) return 0;
    int nc = faces_of(T, c, 0);
    for (int k = 0; k < nc; k++)
        if (has(T->tris + 3 * F[k], d)) return 0; /* edge c-d is there already */
    /* how far the surface moves: the distance between the two diagonals (physics' edge-edge case) */
    const double *x4[4] = {T->X + 3 * a, T->X + 3 * b, T->X + 3 * c, T->X + 3 * d};
    double gap = rk_contact_distance2(rk_edge_edge_case(x4), x4, NULL, NULL);
    if (!(sqrt(gap) <= RK_MARCH_TIDY_EDGE * T->s)) return 0;
    /* (a, b, c), (b, a, d) -> (c, a, d), (d, b, c): the quad's boundary b c a d kept */
    int nt[2][3] = {{c, a, d}, {d, b, c}}, oldt[2][3], old[2] = {f, g};
    memcpy(oldt[0], tf, sizeof oldt[0]), memcpy(oldt[1], tg, sizeof oldt[1]);
    double worst = fmin(quality(T->X, tf), quality(T->X, tg)), n0[3], n1[3];
    rk_proxy_face_normal(T->X, nt[0], n0), rk_proxy_face_normal(T->X, nt[1], n1);
    if (n0[0] * n1[0] + n0[1] * n1[1] + n0[2] * n1[2] <= 0) return 0; /* the quad folds */
    if (!passes(T, (const int (*)[3])nt, 2, (const int (*)[3])oldt, 2, 0, old, worst)) return 0;
    memcpy(T->tris + 3 * f, nt[0], sizeof nt[0]), memcpy(T->tris + 3 * g, nt[1], sizeof nt[1]);
    return 1;
}

int rk_march_tidy(rk_surface *S, double s, rk_points_march_report *rep, rk_error *err)
{
    tidy T = {S->X, S->tris, S->nf, s, rk_calloc(4 * (size_t)S->nf + 64, sizeof(int), err)};
    int *map = rk_calloc((size_t)S->nv + 1, sizeof *map, err);
    if (!T.list || !map) {
        free(T.list), free(map);
        return -1;
    }
    for (int pass = 0, changed = 1; pass < RK_MARCH_TIDY_PASSES && changed; pass++) {
        changed = 0;
        for (int f = 0; f < T.nf; f++) {
            int *t = T.tris + 3 * f;
            if (t[0] < 0 || quality(T.X, t) >= RK_MARCH_SLIVER) continue;
            int k0 = 0, k1 = 0; /* the shortest and the longest edge: (t[k], t[k + 1]) */
            double l[3];
            for (int k = 0; k < 3; k++) {
                l[k] = dist2(T.X + 3 * t[k], T.X + 3 * t[(k + 1) % 3]);
                if (l[k] < l[k0]) k0 = k;
                if (l[k] > l[k1]) k1 = k;
            }
            int a = t[k0], b = t[(k0 + 1) % 3];
            if (sqrt(l[k0]) <= RK_MARCH_TIDY_EDGE * s && (collapse(&T, a, b) || collapse(&T, b, a))) {
                rep->collapsed++, changed = 1;
                continue;
            }
            if (flip(&T, f, t[k1], t[(k1 + 1) % 3])) rep->flipped++, changed = 1;
        }
    }
    /* drop the removed faces and the vertices no face uses, keeping the order of the rest */
    int nf = 0, nv = 0;
    for (int f = 0; f < T.nf; f++)
        if (T.tris[3 * f] >= 0) memmove(T.tris + 3 * nf++, T.tris + 3 * f, 3 * sizeof(int));
    for (int k = 0; k < 3 * nf; k++) map[T.tris[k]] = 1;
    for (int v = 0; v < S->nv; v++)
        if (map[v]) {
            memmove(S->X + 3 * nv, S->X + 3 * v, 3 * sizeof(double));
            map[v] = nv++;
        }
    for (int k = 0; k < 3 * nf; k++) T.tris[k] = map[T.tris[k]];
    S->nf = nf, S->nv = nv;
    free(T.list), free(map);
    return 0;
}
