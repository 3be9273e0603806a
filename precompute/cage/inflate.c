/* rk_cage_inflate (cage_impl.h): the boundary vertices of a tetrahedralized simplification moved
 * outward until the original surface's vertices are inside. Offsetting the surface and
 * tetrahedralizing that was tried first: the offset surface folded into itself in spot.obj's
 * narrow grooves (between ear and head) at every simplification, and TetGen aborted. Moving the
 * tet mesh's boundary instead never inverts a tet: a move that would crush one is cut back (halved
 * until every tet keeps RK_CAGE_KEEP of its volume and radius ratio). Two parts of the boundary
 * across a gap narrower than their moves may still overlap (no tet spans the gap): elements that
 * overlap at rest are no matter to the simulation, but would be to self-contact. */
#include "cage/cage_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define RK_CAGE_KEEP 0.25
#define SWEEPS 30
#define RK_CAGE_GOOD 0.2 /* radius ratio */
#define MAX_ROUNDS 6
#define HALVINGS 10

typedef struct {
    rk_surface b;        /* the boundary over its own vertices */
    int *mesh_vertex;    /* b's vertex -> m's */
    int *first, *list;   /* m's vertex -> its tets */
    double *rest_volume; /* m's tets */
    double *rest_ratio;  /* m's tets: radius ratio */
    char *halve;         /* m's vertices: scratch */
} inflate_state;

static void state_free(inflate_state *st)
{
    rk_surface_free(&st->b);
    free(st->mesh_vertex);
    free(st->first);
    free(st->list);
    free(st->rest_volume);
    free(st->rest_ratio);
    free(st->halve);
}

static double tet_volume(const rk_mesh *m, int t)
{
    const int *v = m->tets + 4 * (size_t)t;
    return rk_tet_signed_volume(m->X + 3 * (size_t)v[0], m->X + 3 * (size_t)v[1], m->X + 3 * (size_t)v[2],
                                m->X + 3 * (size_t)v[3]);
}

static int state_init(const rk_mesh *m, inflate_state *st, rk_error *err)
{
    memset(st, 0, sizeof *st);
    int *tris = NULL, nf = 0;
    int *local = rk_calloc((size_t)m->nv, sizeof(int), err);
    if (!local || rk_mesh_boundary(m, &tris, &nf, err)) {
        free(local);
        return -1;
    }
    for (int v = 0; v < m->nv; v++) local[v] = -1;
    for (int k = 0; k < 3 * nf; k++)
        if (local[tris[k]] < 0) local[tris[k]] = st->b.nv++;
    st->b.nf = nf;
    st->b.X = rk_calloc(3 * (size_t)st->b.nv, sizeof(double), err);
    st->b.tris = tris;
    st->mesh_vertex = rk_calloc((size_t)st->b.nv, sizeof(int), err);
    st->first = rk_calloc((size_t)m->nv + 1, sizeof(int), err);
    st->list = rk_calloc(4 * (size_t)m->nt, sizeof(int), err);
    st->rest_volume = rk_calloc((size_t)m->nt, sizeof(double), err);
    st->rest_ratio = rk_calloc((size_t)m->nt, sizeof(double), err);
    st->halve = rk_calloc((size_t)m->nv, 1, err);
    if (!st->b.X || !st->mesh_vertex || !st->first || !st->list || !st->rest_volume || !st->rest_ratio || !st->halve) {
        free(local);
        state_free(st);
        return -1;
    }
    for (int v = 0; v < m->nv; v++)
        if (local[v] >= 0) {
            st->mesh_vertex[local[v]] = v;
            memcpy(st->b.X + 3 * (size_t)local[v], m->X + 3 * (size_t)v, 3 * sizeof(double));
        }
    for (int k = 0; k < 3 * nf; k++) tris[k] = local[tris[k]];
    free(local);
    for (int k = 0; k < 4 * m->nt; k++) st->first[m->tets[k] + 1]++;
    for (int v = 0; v < m->nv; v++) st->first[v + 1] += st->first[v];
    for (int t = 0; t < m->nt; t++)
        for (int k = 0; k < 4; k++) st->list[st->first[m->tets[4 * t + k]]++] = t;
    for (int v = m->nv; v > 0; v--) st->first[v] = st->first[v - 1];
    st->first[0] = 0;
    for (int t = 0; t < m->nt; t++) {
        const int *v = m->tets + 4 * (size_t)t;
        st->rest_volume[t] = tet_volume(m, t);
        st->rest_ratio[t] = rk_tet_radius_ratio(m->X + 3 * (size_t)v[0], m->X + 3 * (size_t)v[1], m->X + 3 * (size_t)v[2],
                                                m->X + 3 * (size_t)v[3]);
    }
    return 0;
}

/* The tet keeps its shape well enough: a share of its rest volume and of its radius ratio (of
 * RK_CAGE_GOOD at most). */
static int tet_kept(const rk_mesh *m, const inflate_state *st, int t)
{
    const int *v = m->tets + 4 * (size_t)t;
    const double *a = m->X + 3 * (size_t)v[0], *b = m->X + 3 * (size_t)v[1], *c = m->X + 3 * (size_t)v[2],
                 *d = m->X + 3 * (size_t)v[3];
    /* a tet that starts as a sliver may stay one (its ratio swings with any move: holding it to a
     * share of its own blocked the moves of 48 of spot.obj's vertices); a good one may not become one */
    return rk_tet_signed_volume(a, b, c, d) >= RK_CAGE_KEEP * st->rest_volume[t] &&
           rk_tet_radius_ratio(a, b, c, d) >= RK_CAGE_KEEP * fmin(st->rest_ratio[t], RK_CAGE_GOOD);
}

/* m's vertices moved from rest by disp: the boundary's as given, the interior's the average of
 * their neighbours' (Gauss-Seidel sweeps: a discrete harmonic extension, so the boundary layer is
 * not crushed), each vertex of a tet that would lose its shape then moving half as far, again,
 * until every tet keeps it. */
static void move_vertices(rk_mesh *m, const inflate_state *st, const double *rest, double *disp, const char *on_boundary)
{
    for (int sweep = 0; sweep < SWEEPS; sweep++)
        for (int v = 0; v < m->nv; v++) {
            if (on_boundary[v]) continue;
            double sum[3] = {0, 0, 0};
            int n = 0;
            for (int k = st->first[v]; k < st->first[v + 1]; k++)
                for (int j = 0; j < 4; j++) {
                    int u = m->tets[4 * (size_t)st->list[k] + j];
                    if (u == v) continue;
                    for (int i = 0; i < 3; i++) sum[i] += disp[3 * (size_t)u + i];
                    n++;
                }
            for (int i = 0; n && i < 3; i++) disp[3 * (size_t)v + i] = sum[i] / n;
        }
    for (int h = 0;; h++) {
        for (size_t i = 0; i < 3 * (size_t)m->nv; i++) m->X[i] = rest[i] + disp[i];
        int bad = 0;
        for (int t = 0; t < m->nt; t++) {
            if (tet_kept(m, st, t)) continue;
            bad++;
            for (int j = 0; j < 4; j++) st->halve[m->tets[4 * (size_t)t + j]] = 1;
        }
        if (!bad) return; /* at the latest when every bad tet's vertices are back at rest */
        for (int v = 0; v < m->nv; v++)
            if (st->halve[v]) {
                for (int i = 0; i < 3; i++) disp[3 * (size_t)v + i] *= h >= HALVINGS ? 0 : 0.5;
                st->halve[v] = 0;
            }
    }
}

int rk_cage_inflate(rk_mesh *m, const rk_surface *orig, double margin, rk_cage_report *rep, rk_error *err)
{
    inflate_state st;
    rk_cage_heights h = {0};
    rk_surface off = {0};
    if (state_init(m, &st, err)) return -1;
    double *extra = rk_calloc((size_t)st.b.nv, sizeof(double), err), *bump = rk_calloc((size_t)st.b.nv, sizeof(double), err);
    double *rest = rk_calloc(3 * (size_t)m->nv, sizeof(double), err), *disp = rk_calloc(3 * (size_t)m->nv, sizeof(double), err);
    double *best = rk_calloc(3 * (size_t)m->nv, sizeof(double), err);
    char *on_boundary = rk_calloc((size_t)m->nv, 1, err);
    int rc = !extra || !bump || !best || !rest || !disp || !on_boundary || rk_cage_heights_measure(&st.b, orig, &h, err) ? -1 : 0;
    if (rc == 0) memcpy(rest, m->X, sizeof(double) * 3 * (size_t)m->nv);
    for (int i = 0; rc == 0 && i < st.b.nv; i++) on_boundary[st.mesh_vertex[i]] = 1;
    for (int round = 0; rc == 0 && round < MAX_ROUNDS; round++) {
        rk_surface_free(&off);
        double max_offset;
        if (rk_cage_offset(&st.b, &h, margin, extra, &off, &max_offset, err)) {
            rc = -1;
            break;
        }
        /* from the rest positions each round, so that every round's moves are checked whole */
        memset(disp, 0, sizeof(double) * 3 * (size_t)m->nv);
        for (int i = 0; i < st.b.nv; i++)
            for (int a = 0; a < 3; a++)
                disp[3 * (size_t)st.mesh_vertex[i] + a] = off.X[3 * (size_t)i + a] - st.b.X[3 * (size_t)i + a];
        move_vertices(m, &st, rest, disp, on_boundary);
        rk_embedding e;
        if (rk_cage_embed(m, orig->X, orig->nv, &e, err)) {
            rc = -1;
            break;
        }
        rep->inflate_rounds = round + 1;
        /* a round is not always better than the last (a vertex moved further can crush a tet that
         * then holds its neighbours back): the best round's cage is kept */
        if (round == 0 || e.outside < rep->outside) {
            rep->outside = e.outside;
            rep->worst_distance = e.worst_distance;
            rep->max_offset = max_offset;
            memcpy(best, m->X, sizeof(double) * 3 * (size_t)m->nv);
        }
        /* enlarge where needed: the vertices of the face each outside vertex was measured against
         * move out further, by twice the distance of the farthest of those beyond the cage */
        memset(bump, 0, sizeof(double) * (size_t)st.b.nv);
        for (int i = 0; i < orig->nv; i++)
            if (e.distance[i] > 0)
                for (int k = 0; k < 3; k++) {
                    double *b = &bump[st.b.tris[3 * h.tri[i] + k]];
                    *b = fmax(*b, 2 * e.distance[i] + margin);
                }
        for (int i = 0; i < st.b.nv; i++) extra[i] += bump[i];
        rk_embedding_free(&e);
        if (rep->outside == 0) break;
    }
    if (rc == 0) memcpy(m->X, best, sizeof(double) * 3 * (size_t)m->nv);
    free(extra);
    free(bump);
    free(best);
    free(rest);
    free(disp);
    free(on_boundary);
    rk_surface_free(&off);
    rk_cage_heights_free(&h);
    state_free(&st);
    return rc;
}
