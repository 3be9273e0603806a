/* The fixed decomposition (adaptive-subspace paper, footnote 5, Sec. 3.6 and 3.9): METIS parts of
 * the mesh's vertex graph, for grouping nodal enrichment and for the subdomains whose elastic
 * subspace Hessians BFGS keeps; and the full symmetric pattern the enriched rows are read from. */
#include "adaptive/adaptive_impl.h"

#include <metis.h>
#include <stdlib.h>
#include <string.h>

/* The vertex graph (no self loops, each edge both ways) from the fem pattern's upper columns. */
static int vertex_graph(const rk_fem *f, idx_t **xadj_out, idx_t **adj_out, rk_error *err)
{
    int nv = f->nv;
    const rk_sparse *S = &f->pattern;
    idx_t *xadj = rk_calloc((size_t)nv + 1, sizeof *xadj, err);
    if (!xadj) return -1;
    for (int j = 0; j < nv; j++)
        for (int k = S->colptr[3 * j]; k < S->colptr[3 * j + 1]; k++) {
            int r = S->rowind[k];
            if (r % 3 || r / 3 == j) continue;
            xadj[r / 3 + 1]++;
            xadj[j + 1]++;
        }
    for (int i = 0; i < nv; i++) xadj[i + 1] += xadj[i];
    idx_t *adj = rk_calloc((size_t)xadj[nv] + 1, sizeof *adj, err);
    idx_t *fill = rk_calloc((size_t)nv, sizeof *fill, err);
    if (!adj || !fill) {
        free(xadj);
        free(adj);
        free(fill);
        return -1;
    }
    for (int j = 0; j < nv; j++)
        for (int k = S->colptr[3 * j]; k < S->colptr[3 * j + 1]; k++) {
            int r = S->rowind[k], i = r / 3;
            if (r % 3 || i == j) continue;
            adj[xadj[i] + fill[i]++] = j;
            adj[xadj[j] + fill[j]++] = i;
        }
    free(fill);
    *xadj_out = xadj;
    *adj_out = adj;
    return 0;
}

static int metis_parts(const rk_fem *f, int parts, int *part, rk_error *err)
{
    if (parts <= 1) {
        memset(part, 0, sizeof(int) * (size_t)f->nv);
        return 0;
    }
    idx_t *xadj, *adj;
    if (vertex_graph(f, &xadj, &adj, err)) return -1;
    idx_t nvtx = f->nv, ncon = 1, np = parts, cut = 0, options[METIS_NOPTIONS];
    idx_t *out = rk_calloc((size_t)f->nv, sizeof *out, err);
    if (!out) {
        free(xadj);
        free(adj);
        return -1;
    }
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_SEED] = 1; /* the same parts on every run */
    options[METIS_OPTION_CONTIG] = 0;
    int rc = METIS_PartGraphKway(&nvtx, &ncon, xadj, adj, NULL, NULL, NULL, &np, NULL, NULL, options, &cut, out);
    for (int i = 0; i < f->nv; i++) part[i] = (int)out[i];
    free(xadj);
    free(adj);
    free(out);
    if (rc != METIS_OK) return rk_fail(err, "METIS could not partition the mesh into %d subdomains (status %d)", parts, rc);
    return 0;
}

int rk_adaptive_partition(rk_adaptive_impl *im, int parts, rk_error *err)
{
    const rk_fem *f = im->f;
    im->L = parts;
    im->part = rk_calloc((size_t)f->nv, sizeof(int), err);
    im->sub = rk_calloc((size_t)parts, sizeof *im->sub, err);
    im->part_first = rk_calloc((size_t)parts + 1, sizeof(int), err);
    im->part_vert = rk_calloc((size_t)f->nv, sizeof(int), err);
    int *mark = rk_calloc((size_t)f->nv, sizeof(int), err);
    if (!im->part || !im->sub || !im->part_first || !im->part_vert || !mark || metis_parts(f, parts, im->part, err)) {
        free(mark);
        return -1;
    }
    for (int i = 0; i < f->nv; i++) im->part_first[im->part[i] + 1]++;
    for (int l = 0; l < parts; l++) im->part_first[l + 1] += im->part_first[l];
    for (int i = 0, *fill = mark; i < f->nv; i++) im->part_vert[im->part_first[im->part[i]] + fill[im->part[i]]++] = i;
    memset(mark, 0, sizeof(int) * (size_t)f->nv);
    /* elements by the part of their first vertex */
    for (int t = 0; t < f->nt; t++) im->sub[im->part[f->tets[4 * t]]].ne++;
    for (int l = 0; l < parts; l++) {
        rk_subdomain *s = &im->sub[l];
        s->elem = rk_calloc((size_t)s->ne + 1, sizeof(int), err);
        s->local = rk_calloc(4 * (size_t)s->ne + 1, sizeof(int), err);
        if (!s->elem || !s->local) {
            free(mark);
            return -1;
        }
        s->ne = 0;
    }
    for (int t = 0; t < f->nt; t++) {
        rk_subdomain *s = &im->sub[im->part[f->tets[4 * t]]];
        s->elem[s->ne++] = t;
    }
    /* local vertices: mark[v] = 1 + local index within the subdomain being built */
    for (int l = 0; l < parts; l++) {
        rk_subdomain *s = &im->sub[l];
        s->vert = rk_calloc(4 * (size_t)s->ne + 1, sizeof(int), err);
        if (!s->vert) {
            free(mark);
            return -1;
        }
        for (int e = 0; e < s->ne; e++)
            for (int k = 0; k < 4; k++) {
                int v = f->tets[4 * s->elem[e] + k];
                if (!mark[v]) {
                    s->vert[s->nv] = v;
                    mark[v] = ++s->nv;
                }
                s->local[4 * e + k] = mark[v] - 1;
            }
        for (int i = 0; i < s->nv; i++) mark[s->vert[i]] = 0;
    }
    free(mark);
    return 0;
}

void rk_adaptive_partition_free(rk_adaptive_impl *im)
{
    for (int l = 0; im->sub && l < im->L; l++) {
        rk_subdomain *s = &im->sub[l];
        free(s->elem);
        free(s->vert);
        free(s->local);
        free(s->B);
        free(s->Bu);
        free(s->proj);
    }
    free(im->sub);
    free(im->part);
    free(im->part_first);
    free(im->part_vert);
}

int rk_full_pattern_init(rk_full_pattern *P, const rk_sparse *S, rk_error *err)
{
    memset(P, 0, sizeof *P);
    int n = S->n;
    P->n = n;
    P->rowptr = rk_calloc((size_t)n + 1, sizeof(int), err);
    int *fill = rk_calloc((size_t)n, sizeof(int), err);
    if (!P->rowptr || !fill) {
        free(fill);
        return -1;
    }
    for (int c = 0; c < n; c++)
        for (int k = S->colptr[c]; k < S->colptr[c + 1]; k++) {
            int r = S->rowind[k];
            P->rowptr[r + 1]++;
            if (r != c) P->rowptr[c + 1]++;
        }
    for (int i = 0; i < n; i++) P->rowptr[i + 1] += P->rowptr[i];
    P->nnz = P->rowptr[n];
    P->col = rk_calloc((size_t)P->nnz, sizeof(int), err);
    P->up = rk_calloc((size_t)S->nnz, sizeof(int), err);
    P->lo = rk_calloc((size_t)S->nnz, sizeof(int), err);
    if (!P->col || !P->up || !P->lo) {
        free(fill);
        return -1;
    }
    /* columns ascending, rows ascending within each: every row fills in ascending column order */
    for (int c = 0; c < n; c++)
        for (int k = S->colptr[c]; k < S->colptr[c + 1]; k++) {
            int r = S->rowind[k];
            int pu = P->rowptr[r] + fill[r]++;
            P->col[pu] = c;
            P->up[k] = pu;
            if (r == c) {
                P->lo[k] = pu;
            } else {
                int pl = P->rowptr[c] + fill[c]++;
                P->col[pl] = r;
                P->lo[k] = pl;
            }
        }
    free(fill);
    return 0;
}

void rk_full_pattern_free(rk_full_pattern *P)
{
    free(P->rowptr);
    free(P->col);
    free(P->up);
    free(P->lo);
    memset(P, 0, sizeof *P);
}

void rk_full_mul(const rk_full_pattern *P, const double *val, const double *x, double *y)
{
    for (int i = 0; i < P->n; i++) {
        double s = 0;
        for (int k = P->rowptr[i]; k < P->rowptr[i + 1]; k++) s += val[k] * x[P->col[k]];
        y[i] = s;
    }
}
