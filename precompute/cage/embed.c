/* rk_cage_embed: points located in a tet mesh (cage.h). A uniform grid over the mesh's bounding
 * box lists the tets whose bounding boxes overlap each cell; a point is tested, exactly, against
 * the tets of its cell. The grid has about one cell per tet, so a cell lists a few tets. */
#include "cage/cage_impl.h"
#include "contact/contact.h"
#include "physics/physics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int rk_point_in_tet(const double *p, const double *a, const double *b, const double *c, const double *d)
{
    /* p is in the closed tet when replacing any one vertex by p never flips the orientation:
     * each sign is the tet's own or zero (p on that face's plane) */
    int s = rk_orient3d_sign(a, b, c, d);
    if (s == 0) return 0; /* a flat tet holds nothing */
    return rk_orient3d_sign(p, b, c, d) != -s && rk_orient3d_sign(a, p, c, d) != -s &&
           rk_orient3d_sign(a, b, p, d) != -s && rk_orient3d_sign(a, b, c, p) != -s;
}

/* Barycentric coordinates of p in tet t (sub-volumes over the volume), clamped to [0, 1] and
 * renormalized when clamp is set. */
static void barycentric(const rk_mesh *m, int t, const double *p, int clamp, double *b)
{
    const double *v[4];
    for (int k = 0; k < 4; k++) v[k] = m->X + 3 * (size_t)m->tets[4 * (size_t)t + k];
    double vol = rk_tet_signed_volume(v[0], v[1], v[2], v[3]), sum = 0;
    for (int k = 0; k < 4; k++) {
        const double *w[4] = {v[0], v[1], v[2], v[3]};
        w[k] = p;
        b[k] = rk_tet_signed_volume(w[0], w[1], w[2], w[3]) / vol;
        if (clamp && !(b[k] > 0)) b[k] = 0;
        sum += b[k];
    }
    if (clamp) /* the coordinates sum to 1, so some are positive and sum > 0 */
        for (int k = 0; k < 4; k++) b[k] /= sum;
}

/* The squared distance of p to triangle abc: the contact stage's closest-feature case and
 * distance (physics/physics.h), the one implementation of it. */
double rk_cage_triangle_distance2(const double *p, const double *a, const double *b, const double *c)
{
    const double *const x[4] = {p, a, b, c};
    return rk_contact_distance2(rk_point_triangle_case(x), x, NULL, NULL);
}

typedef struct {
    double lo[3], cell;
    int dim[3];
    int *first, *list; /* cell c lists list[first[c] .. first[c + 1]) */
} tet_grid;

static int cell_coord(const tet_grid *g, double x, int a)
{
    double f = floor((x - g->lo[a]) / g->cell);
    return f < 0 ? 0 : f >= g->dim[a] ? g->dim[a] - 1 : (int)f;
}

static void tet_cells(const tet_grid *g, const rk_mesh *m, int t, int lo[3], int hi[3])
{
    for (int a = 0; a < 3; a++) {
        double mn = INFINITY, mx = -INFINITY;
        for (int k = 0; k < 4; k++) {
            double x = m->X[3 * (size_t)m->tets[4 * (size_t)t + k] + a];
            mn = fmin(mn, x), mx = fmax(mx, x);
        }
        lo[a] = cell_coord(g, mn, a), hi[a] = cell_coord(g, mx, a);
    }
}

static int grid_build(const rk_mesh *m, tet_grid *g, rk_error *err)
{
    memset(g, 0, sizeof *g);
    double hi[3];
    for (int a = 0; a < 3; a++) g->lo[a] = INFINITY, hi[a] = -INFINITY;
    for (int v = 0; v < m->nv; v++)
        for (int a = 0; a < 3; a++) g->lo[a] = fmin(g->lo[a], m->X[3 * v + a]), hi[a] = fmax(hi[a], m->X[3 * v + a]);
    double vol = 1, ext = 0;
    for (int a = 0; a < 3; a++) ext = fmax(ext, hi[a] - g->lo[a]);
    for (int a = 0; a < 3; a++) vol *= fmax(hi[a] - g->lo[a], 1e-3 * ext);
    g->cell = cbrt(vol / m->nt); /* about one tet per cell */
    if (!(g->cell > 0)) g->cell = 1;
    long cells = 1;
    for (int a = 0; a < 3; a++) {
        g->dim[a] = (int)fmin(1024, floor((hi[a] - g->lo[a]) / g->cell) + 1);
        cells *= g->dim[a];
    }
    g->first = rk_calloc((size_t)cells + 1, sizeof(int), err);
    if (!g->first) return -1;
    for (int pass = 0; pass < 2; pass++) {
        for (int t = 0; t < m->nt; t++) {
            int lo[3], up[3];
            tet_cells(g, m, t, lo, up);
            for (int k = lo[2]; k <= up[2]; k++)
                for (int j = lo[1]; j <= up[1]; j++)
                    for (int i = lo[0]; i <= up[0]; i++) {
                        long c = ((long)k * g->dim[1] + j) * g->dim[0] + i;
                        if (pass == 0) g->first[c + 1]++;
                        else g->list[g->first[c]++] = t;
                    }
        }
        if (pass == 0) {
            for (long c = 0; c < cells; c++) g->first[c + 1] += g->first[c];
            g->list = rk_calloc((size_t)g->first[cells] + 1, sizeof(int), err);
            if (!g->list) return -1;
        } else {
            for (long c = cells; c > 0; c--) g->first[c] = g->first[c - 1]; /* the fill advanced them */
            g->first[0] = 0;
        }
    }
    return 0;
}

/* The tet that has boundary face f (its three vertices), or -1. */
static int face_tet(const rk_mesh *m, const int *f)
{
    for (int t = 0; t < m->nt; t++) {
        int hits = 0;
        for (int k = 0; k < 4; k++) {
            int v = m->tets[4 * (size_t)t + k];
            hits += v == f[0] || v == f[1] || v == f[2];
        }
        if (hits == 3) return t;
    }
    return -1;
}

/* A point in no tet: the tet of the nearest boundary face, clamped barycentrics; its distance. */
static double embed_outside(const rk_mesh *m, const int *tris, int nf, const double *p, int *tet, double *b)
{
    double best = INFINITY;
    int bf = 0;
    for (int f = 0; f < nf; f++) {
        const int *v = tris + 3 * (size_t)f;
        double d2 = rk_cage_triangle_distance2(p, m->X + 3 * (size_t)v[0], m->X + 3 * (size_t)v[1], m->X + 3 * (size_t)v[2]);
        if (d2 < best) best = d2, bf = f;
    }
    *tet = face_tet(m, tris + 3 * (size_t)bf);
    if (*tet < 0) *tet = 0;
    barycentric(m, *tet, p, 1, b);
    return sqrt(best);
}

int rk_cage_embed(const rk_mesh *m, const double *X, int n, rk_embedding *e, rk_error *err)
{
    memset(e, 0, sizeof *e);
    e->worst_point = -1;
    if (m->nt < 1) return rk_fail(err, "embed: the cage has no tets");
    tet_grid g = {0};
    int *tris = NULL, nf = 0, rc = -1;
    e->n = n;
    e->tet = rk_calloc((size_t)n + 1, sizeof(int), err);
    e->bary = rk_calloc(4 * (size_t)n + 1, sizeof(double), err);
    e->distance = rk_calloc((size_t)n + 1, sizeof(double), err);
    if (!e->tet || !e->bary || !e->distance || grid_build(m, &g, err)) goto done;
    for (int i = 0; i < n; i++) {
        const double *p = X + 3 * (size_t)i;
        long c = ((long)cell_coord(&g, p[2], 2) * g.dim[1] + cell_coord(&g, p[1], 1)) * g.dim[0] + cell_coord(&g, p[0], 0);
        int found = -1;
        for (int k = g.first[c]; k < g.first[c + 1] && found < 0; k++) {
            const int *v = m->tets + 4 * (size_t)g.list[k];
            if (rk_point_in_tet(p, m->X + 3 * (size_t)v[0], m->X + 3 * (size_t)v[1], m->X + 3 * (size_t)v[2],
                                m->X + 3 * (size_t)v[3]))
                found = g.list[k];
        }
        if (found >= 0) {
            e->tet[i] = found;
            barycentric(m, found, p, 0, e->bary + 4 * (size_t)i);
            continue;
        }
        if (!tris && rk_mesh_boundary(m, &tris, &nf, err)) goto done;
        double d = embed_outside(m, tris, nf, p, &e->tet[i], e->bary + 4 * (size_t)i);
        e->distance[i] = d;
        e->outside++;
        if (e->worst_point < 0 || d > e->worst_distance) e->worst_distance = d, e->worst_point = i;
    }
    rc = 0;
done:
    free(g.first);
    free(g.list);
    free(tris);
    if (rc) rk_embedding_free(e);
    return rc;
}

void rk_embedding_free(rk_embedding *e)
{
    free(e->tet);
    free(e->bary);
    free(e->distance);
    memset(e, 0, sizeof *e);
    e->worst_point = -1;
}
