/* rk_points_body (contact.h): a point cloud's full-order body, the tets that fill its contact
 * surface.
 *
 * The contact proxy is already a tet mesh: the well-composed voxel set Kuhn-split into 6 tets per
 * voxel (ghost tets, points_proxy.c), its surface vertices moved in toward the points
 * (proxy_inset.c). Taking those tets as elements gives a conforming body whose boundary is the
 * cloud's contact surface, with no second mesher and no new vertices: the reduced simulator's
 * proxy vertices are the body's own, so a full-order run and a reduced one are compared vertex for
 * vertex on the surface. TetGen on the inset surface would give better-shaped tets but new interior
 * vertices, and a run per cloud (the Kuhn tets of a cube are within a factor 3 of the regular
 * tet's radius ratio already).
 *
 * The inset checks faces, not tets: a surface vertex moved in by up to about a voxel can flatten
 * or turn over a tet whose other vertices stay (an interior corner under it). Every tet is
 * therefore checked for at least RK_BODY_MIN_VOLUME of its lattice volume g^3 / 6 (its vertices'
 * moves are bounded by ~g, so its edges are at most ~3 g: a tet with a tenth of the volume keeps a
 * shape the FEM tolerates), and where one is not, its vertices' moves are halved, toward their
 * lattice corners, until it is; the lattice itself passes (every tet has g^3 / 6), so this ends. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "contact/points_proxy_impl.h"

/* The smallest tet volume kept, as a fraction of the lattice tet's g^3 / 6. */
#define RK_BODY_MIN_VOLUME 0.1
/* Halvings of a move before it is dropped (2^-12 of a voxel is below any contact thickness). */
#define RK_BODY_HALVINGS 12

static double tet_volume(const double *x, const int *t)
{
    return rk_tet_signed_volume(x + 3 * (size_t)t[0], x + 3 * (size_t)t[1], x + 3 * (size_t)t[2], x + 3 * (size_t)t[3]);
}

/* Cuts back the moves (from L to x) of the vertices of every tet under the volume bound, round by
 * round, until none is; returns how many vertices were cut back. */
static int back_off(double *x, const double *L, const int *tets, int nt, int nv, double vmin, double *ratio, char *cut)
{
    int *halved = calloc((size_t)nv + 1, sizeof(int));
    char *mark = calloc((size_t)nv + 1, 1);
    int count = 0;
    if (!halved || !mark) {
        free(halved), free(mark);
        return -1;
    }
    for (;;) {
        int bad = 0;
        memset(mark, 0, (size_t)nv);
        for (int t = 0; t < nt; t++)
            if (!(tet_volume(x, tets + 4 * (size_t)t) >= vmin)) {
                bad++;
                for (int a = 0; a < 4; a++) mark[tets[4 * (size_t)t + a]] = 1;
            }
        if (!bad) break;
        int changed = 0;
        for (int v = 0; v < nv; v++) {
            if (!mark[v] || memcmp(x + 3 * (size_t)v, L + 3 * (size_t)v, 3 * sizeof(double)) == 0) continue;
            if (!cut[v]) cut[v] = 1, count++;
            changed = 1;
            if (++halved[v] >= RK_BODY_HALVINGS) memcpy(x + 3 * (size_t)v, L + 3 * (size_t)v, 3 * sizeof(double));
            else
                for (int d = 0; d < 3; d++) x[3 * v + d] = L[3 * v + d] + 0.5 * (x[3 * v + d] - L[3 * v + d]);
        }
        if (!changed) break; /* only lattice tets left under the bound: cannot happen (each has g^3 / 6) */
    }
    double worst = INFINITY;
    for (int t = 0; t < nt; t++) worst = fmin(worst, tet_volume(x, tets + 4 * (size_t)t));
    *ratio = worst / vmin * RK_BODY_MIN_VOLUME;
    free(halved), free(mark);
    return count;
}

/* The point nearest each tet's centroid (within two lattice cells; else four: a voxel the
 * well-composing added touches one that holds a point). */
static int nearest_points(const rk_mesh *b, const double *X, int n, double g, const double lo[3], int *tet_point,
                          rk_error *err)
{
    rk_proxy_grid G = {0};
    if (rk_proxy_grid_build(&G, X, n, g, lo, err)) return -1;
    for (int t = 0; t < b->nt; t++) {
        double c[3] = {0, 0, 0};
        for (int a = 0; a < 4; a++)
            for (int d = 0; d < 3; d++) c[d] += 0.25 * b->X[3 * (size_t)b->tets[4 * (size_t)t + a] + d];
        const double *p = NULL;
        if (!isfinite(rk_proxy_nearest_at(&G, c, 2, &p))) rk_proxy_nearest_at(&G, c, 4, &p);
        tet_point[t] = p ? (int)((p - X) / 3) : 0;
    }
    rk_proxy_grid_free(&G);
    return 0;
}

int rk_points_body(const double *X, int n, double g, double s, double tau, rk_mesh *body, int **tet_point, double **proxy_X,
                   rk_points_body_report *rep, rk_error *err)
{
    memset(body, 0, sizeof *body);
    memset(rep, 0, sizeof *rep);
    *tet_point = NULL;
    *proxy_X = NULL;
    rk_mesh p, contact = {0};
    double lo[3], *L = NULL;
    char *cut = NULL;
    if (rk_proxy_lattice(X, n, g, &p, lo, err)) return -1;
    int nc = p.nv - n, rc = -1;
    L = rk_calloc(3 * (size_t)p.nv, sizeof(double), err);
    if (!L) goto done;
    memcpy(L, p.X, sizeof(double) * 3 * (size_t)p.nv);
    if (rk_points_proxy(X, n, g, s, &contact, err)) goto done; /* where the contact surface is (proxy_X) */
    if (rk_proxy_inset(&p, n, g, tau, lo, err)) goto done;
    body->nv = nc;
    body->nt = p.nghost;
    body->X = rk_calloc(3 * (size_t)nc + 1, sizeof(double), err);
    body->tets = rk_calloc(4 * (size_t)p.nghost + 1, sizeof(int), err);
    *tet_point = rk_calloc((size_t)p.nghost + 1, sizeof(int), err);
    *proxy_X = rk_calloc(3 * (size_t)nc + 1, sizeof(double), err);
    cut = rk_calloc((size_t)nc + 1, 1, err);
    if (!body->X || !body->tets || !*tet_point || !*proxy_X || !cut) goto done;
    memcpy(body->X, p.X + 3 * (size_t)n, sizeof(double) * 3 * (size_t)nc);
    memcpy(*proxy_X, contact.X + 3 * (size_t)n, sizeof(double) * 3 * (size_t)nc);
    for (size_t i = 0; i < 4 * (size_t)p.nghost; i++) body->tets[i] = p.ghost[i] - n;
    rep->points = n;
    rep->backed_off = back_off(body->X, L + 3 * (size_t)n, body->tets, body->nt, nc,
                               RK_BODY_MIN_VOLUME * g * g * g / 6, &rep->min_volume_ratio, cut);
    if (rep->backed_off < 0) {
        rk_fail(err, "cloud body: out of memory");
        goto done;
    }
    if (nearest_points(body, X, n, g, lo, *tet_point, err)) goto done;
    rc = 0;
done:
    rk_mesh_free(&p);
    rk_mesh_free(&contact);
    free(L), free(cut);
    if (rc) {
        rk_mesh_free(body);
        free(*tet_point), free(*proxy_X);
        *tet_point = NULL, *proxy_X = NULL;
    }
    return rc;
}
