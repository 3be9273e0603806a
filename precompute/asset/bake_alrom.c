/* An adaptive linear ROM's chunks (bake_impl.h, rk_bake_alrom_chunks; ROMBIN.md "Adaptive linear
 * ROM chunks"). The runtime steps it over the stored vertices only, so the mesh's lumped mass and
 * loads are gathered onto them: each unstored free vertex gives its mass and load to the stored
 * vertex nearest along the mesh's edges (a multi-source Dijkstra), which keeps the total mass, the
 * total load and, to the spacing of the stored vertices, where they act. Prescribed vertices give
 * nothing: they are not unknowns, their mass never enters a step. */
#include "asset/bake_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    double d;
    int v;
} heap_item;

static void heap_push(heap_item *h, int *n, heap_item it)
{
    int i = (*n)++;
    while (i > 0 && h[(i - 1) / 2].d > it.d) {
        h[i] = h[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    h[i] = it;
}

static heap_item heap_pop(heap_item *h, int *n)
{
    heap_item top = h[0], last = h[--*n];
    int i = 0;
    for (;;) {
        int c = 2 * i + 1;
        if (c >= *n) break;
        if (c + 1 < *n && h[c + 1].d < h[c].d) c++;
        if (h[c].d >= last.d) break;
        h[i] = h[c];
        i = c;
    }
    h[i] = last;
    return top;
}

/* owner[v]: the stored index nearest to source vertex v along the tets' edges (every vertex of a
 * checked mesh is in a tet, and the stored ones reach every connected piece they are on). */
static int nearest_stored(const rk_fem *f, const rk_bake_state *s, int *owner, rk_error *err)
{
    int nv = f->nv, rc = -1, nheap = 0;
    int *start = rk_calloc((size_t)nv + 1, sizeof(int), err), *adj = NULL;
    double *dist = rk_calloc((size_t)nv, sizeof(double), err);
    heap_item *heap = NULL;
    if (!start || !dist) goto out;
    for (int t = 0; t < f->nt; t++)
        for (int a = 0; a < 4; a++) start[f->tets[4 * t + a] + 1] += 3;
    for (int v = 0; v < nv; v++) start[v + 1] += start[v];
    adj = rk_calloc((size_t)start[nv] + 1, sizeof(int), err);
    heap = rk_calloc((size_t)start[nv] + (size_t)nv + 1, sizeof(heap_item), err);
    int *fill = rk_calloc((size_t)nv + 1, sizeof(int), err);
    if (!adj || !heap || !fill) {
        free(fill);
        goto out;
    }
    for (int t = 0; t < f->nt; t++) /* each tet edge, both ways (repeats are harmless) */
        for (int a = 0; a < 4; a++)
            for (int b = 0; b < 4; b++)
                if (a != b) {
                    int v = f->tets[4 * t + a];
                    adj[start[v] + fill[v]++] = f->tets[4 * t + b];
                }
    free(fill);
    for (int v = 0; v < nv; v++) {
        owner[v] = s->stored[v];
        dist[v] = owner[v] >= 0 ? 0 : INFINITY;
        if (owner[v] >= 0) heap_push(heap, &nheap, (heap_item){0, v});
    }
    while (nheap) {
        heap_item it = heap_pop(heap, &nheap);
        if (it.d > dist[it.v]) continue;
        const double *x = f->X + 3 * (size_t)it.v;
        for (int k = start[it.v]; k < start[it.v + 1]; k++) {
            int w = adj[k];
            const double *y = f->X + 3 * (size_t)w;
            double d = it.d + sqrt((x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) + (x[2] - y[2]) * (x[2] - y[2]));
            if (d < dist[w]) {
                dist[w] = d;
                owner[w] = owner[it.v];
                heap_push(heap, &nheap, (heap_item){d, w});
            }
        }
    }
    rc = 0;
out:
    free(start);
    free(adj);
    free(dist);
    free(heap);
    return rc;
}

/* The prescribed group of each source vertex (the first that lists it), or -1. */
static int *motion_of_vertices(const rk_fom_options *o, int nv, rk_error *err)
{
    int *g = rk_calloc((size_t)nv + 1, sizeof(int), err);
    if (!g) return NULL;
    for (int v = 0; v < nv; v++) g[v] = -1;
    for (int k = o->nprescribed - 1; k >= 0; k--)
        for (int i = 0; i < o->prescribed[k].count; i++) g[o->prescribed[k].verts[i]] = k;
    return g;
}

/* A CROM decoder's chunks: CRMS (L_e, L_d, the encoder's sizes, the decoder's), CRMX (the
 * normalised rest positions of the stored vertices), CRMW (the encoder's parameters with its
 * first layer's columns in the stored vertices' order, the decoder's, then the displacement
 * scale). */
static int crom_chunks(const rk_crom_parts *c, const rk_bake_state *s, int nv, rombin_writer *w, rk_error *err)
{
    int ns = 2 + c->enc_layers + 1 + c->dec_layers + 1, n = 3 * nv, n1 = c->enc_sizes[1];
    if (s->count != nv || c->enc_sizes[0] != n)
        return rk_fail(err, "a CROM encoder reads all %d vertices; %d are stored", nv, s->count);
    int *sizes = rk_calloc((size_t)ns, sizeof(int), err);
    double *X = rk_calloc(3 * (size_t)nv, sizeof(double), err);
    double *W = rk_calloc((size_t)(c->enc_count + c->dec_count + 1), sizeof(double), err);
    int rc = -1;
    if (sizes && X && W) {
        sizes[0] = c->enc_layers;
        sizes[1] = c->dec_layers;
        memcpy(sizes + 2, c->enc_sizes, sizeof(int) * (size_t)(c->enc_layers + 1));
        memcpy(sizes + 3 + c->enc_layers, c->dec_sizes, sizeof(int) * (size_t)(c->dec_layers + 1));
        for (int i = 0; i < nv; i++)
            for (int a = 0; a < 3; a++) X[3 * i + a] = c->Xn[3 * s->source[i] + a];
        memcpy(W, c->enc_params, sizeof(double) * (size_t)c->enc_count);
        for (int o = 0; o < n1; o++) /* W_0 (n1 x 3 nv, row-major): its columns in stored order */
            for (int i = 0; i < nv; i++)
                for (int a = 0; a < 3; a++)
                    W[(size_t)o * n + 3 * i + a] = c->enc_params[(size_t)o * n + 3 * s->source[i] + a];
        memcpy(W + c->enc_count, c->dec_params, sizeof(double) * (size_t)c->dec_count);
        W[c->enc_count + c->dec_count] = c->u_scale;
        rc = rk_bake_add_u32s(w, ROMBIN_CRMS, 1, sizes, (size_t)ns, err) ||
             rombin_add_reals(w, ROMBIN_CRMX, 1, X, 3 * (size_t)nv, err) ||
             rombin_add_reals(w, ROMBIN_CRMW, 1, W, (size_t)(c->enc_count + c->dec_count + 1), err)
                 ? -1 : 0;
    }
    free(sizes);
    free(X);
    free(W);
    return rc;
}

int rk_bake_alrom_chunks(const rk_asset_rom *R, const rk_bake_state *s, rombin_writer *w, rk_error *err)
{
    const rk_asset_alrom *A = R->alrom;
    const rk_fom_options *o = A->options;
    const rk_fem *f = R->fem;
    int r = R->model->r, nv = f->nv, n = 3 * nv, count = s->count, pairs = r * (r + 1) / 2;
    if (o->nprescribed > (int)ROMBIN_MAX_MOTIONS)
        return rk_fail(err, "an adaptive linear ROM holds up to %d prescribed groups, the scene has %d",
                       (int)ROMBIN_MAX_MOTIONS, o->nprescribed);
    if (o->rayleigh_stiffness != 0)
        return rk_fail(err, "an adaptive linear ROM's runtime damps in proportion to mass only (its basis moves, the "
                       "rest stiffness K0 is not stored); set damping.stiffness to 0");
    int *owner = rk_calloc((size_t)nv + 1, sizeof(int), err), *motion = motion_of_vertices(o, nv, err);
    int *amov = rk_calloc((size_t)count + 1, sizeof(int), err);
    double *mass = rk_calloc((size_t)count + 1, sizeof(double), err), *load = rk_calloc(3 * (size_t)count + 1, sizeof(double), err);
    double *psi = rk_calloc(3 * (size_t)count * pairs + 1, sizeof(double), err);
    double *mot = rk_calloc((size_t)ROMBIN_PIN_PARAMS * (o->nprescribed + 1), sizeof(double), err);
    int rc = -1;
    if (!owner || !motion || !amov || !mass || !load || !psi || !mot || nearest_stored(f, s, owner, err)) goto out;
    for (int v = 0; v < nv; v++) {
        int to = s->stored[v] >= 0 ? s->stored[v] : motion[v] >= 0 ? -1 : owner[v];
        if (to < 0) continue;
        mass[to] += f->vertex_mass[v];
        for (int a = 0; a < 3; a++)
            load[3 * to + a] += f->vertex_mass[v] * o->gravity[a] + (o->force ? o->force[3 * v + a] : 0);
    }
    for (int i = 0; i < count; i++) {
        int v = s->source[i];
        amov[i] = motion[v] >= 0 ? motion[v] : (int)ROMBIN_NO_MOTION;
        for (int a = 0; a < 3 && A->Psi; a++)
            for (int p = 0; p < pairs; p++) psi[(size_t)(3 * i + a) * pairs + p] = A->Psi[(size_t)p * n + 3 * v + a];
    }
    for (int k = 0; k < o->nprescribed; k++) rk_bake_motion_params(&o->prescribed[k], mot + (size_t)ROMBIN_PIN_PARAMS * k);
    uint32_t head[ROMBIN_ALRH_COUNT] = {0};
    head[ROMBIN_ALRH_HISTORY] = (uint32_t)A->history;
    head[ROMBIN_ALRH_PAIRS] = (uint32_t)pairs;
    head[ROMBIN_ALRH_MOTIONS] = (uint32_t)o->nprescribed;
    head[ROMBIN_ALRH_DECODER] = A->crom ? 1 : 0;
    head[ROMBIN_ALRH_CADENCE] = A->cadence > 1 ? (uint32_t)A->cadence : 0; /* (1: 0, as before it) */
    head[ROMBIN_ALRH_ENCODER] = A->encoder_iterations > 0 && A->encoder_iterations < 20 ? (uint32_t)A->encoder_iterations : 0;
    double parm[ROMBIN_ALRP_COUNT] = {0};
    parm[ROMBIN_ALRP_LAMBDA] = A->lambda;
    parm[ROMBIN_ALRP_REG] = A->reg;
    parm[ROMBIN_ALRP_DAMPING] = o->rayleigh_mass;
    parm[ROMBIN_ALRP_RIDGE] = A->ridge;
    parm[ROMBIN_ALRP_BUDGET] = A->budget;
    rc = rombin_add_u32(w, ROMBIN_ALRH, 1, head, ROMBIN_ALRH_COUNT, err) ||
         rombin_add_reals(w, ROMBIN_ALRP, 1, parm, ROMBIN_ALRP_COUNT, err) ||
         (A->crom ? crom_chunks(A->crom, s, nv, w, err) : rombin_add_reals(w, ROMBIN_QDRV, 1, psi, 3 * (size_t)count * pairs, err)) ||
         rombin_add_reals(w, ROMBIN_VMSS, 1, mass, (size_t)count, err) ||
         rombin_add_reals(w, ROMBIN_VLOD, 1, load, 3 * (size_t)count, err) ||
         rk_bake_add_u32s(w, ROMBIN_AMOV, 1, amov, (size_t)count, err) ||
         (o->nprescribed && rombin_add_reals(w, ROMBIN_AMOT, 1, mot, (size_t)ROMBIN_PIN_PARAMS * o->nprescribed, err))
             ? -1 : 0;
out:
    free(owner);
    free(motion);
    free(amov);
    free(mass);
    free(load);
    free(psi);
    free(mot);
    return rc;
}
