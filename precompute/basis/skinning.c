/* Skinning eigenmodes on a tetrahedral mesh (Benchekroun et al. 2023, as restated in the
 * freeform paper Sec. 3.2). H_w = K_xx + K_yy + K_zz: the sum of the diagonal blocks of the
 * rest stiffness, which for linear elasticity is the integral of (lambda + 4 mu) grad w . grad w
 * (Prop. 1) with P1 weights, so each element's own Lame parameters come in. M_w is the
 * volume mass (no density), as in the paper's Eq. 14, so mesh and RKPM weights compare. A clamp
 * (fixed vertices) is a Dirichlet boundary: the pencil restricted to the free vertices. */
#include "basis/basis.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The scalar (vertex x vertex) matrix sum_a S[3i+a, 3j+a] on the vertex-pair pattern of S. */
static int scalar_trace_blocks(const rk_sparse *S, int nv, rk_sparse *out, rk_error *err)
{
    out->n = nv;
    out->nnz = 0;
    out->colptr = rk_calloc((size_t)nv + 1, sizeof(int), err);
    out->rowind = rk_calloc((size_t)S->nnz / 3 + 1, sizeof(int), err);
    out->val = rk_calloc((size_t)S->nnz / 3 + 1, sizeof(double), err);
    if (!out->colptr || !out->rowind || !out->val) { rk_sparse_free(out); return -1; }
    for (int j = 0; j < nv; j++) {
        /* Column 3j holds rows 3i (i <= j): one entry per coupled vertex i, in order. */
        for (int k = S->colptr[3 * j]; k < S->colptr[3 * j + 1]; k++) {
            int row = S->rowind[k];
            if (row % 3) continue;
            int i = row / 3;
            double v = 0;
            for (int a = 0; a < 3; a++) {
                int s = rk_sparse_find(S, 3 * i + a, 3 * j + a);
                if (s >= 0) v += S->val[s];
            }
            out->rowind[out->nnz] = i;
            out->val[out->nnz++] = v;
        }
        out->colptr[j + 1] = out->nnz;
    }
    return 0;
}

/* M_w = the x-block of the vector volume mass (all three blocks are equal). */
static int mass_scalar(const rk_sparse *S, int nv, rk_sparse *out, rk_error *err)
{
    if (scalar_trace_blocks(S, nv, out, err)) return -1;
    for (int k = 0; k < out->nnz; k++) out->val[k] /= 3.0;
    return 0;
}

/* H_w and M_w over the whole mesh. */
static int pencil(const rk_fem *f, int lumped, rk_sparse *Hw, rk_sparse *Mw, rk_error *err)
{
    rk_sparse K = {0}, M = {0};
    int rc = -1;
    if (!rk_sparse_alloc_pattern(f, &K, err) && !rk_sparse_alloc_pattern(f, &M, err)) {
        rk_fem_add_rest_stiffness(f, 1.0, &K);
        rk_fem_add_volume_mass(f, lumped, 1.0, &M);
        rc = scalar_trace_blocks(&K, f->nv, Hw, err) || mass_scalar(&M, f->nv, Mw, err) ? -1 : 0;
    }
    rk_sparse_free(&K);
    rk_sparse_free(&M);
    return rc;
}

/* The m + 1 weights of the vertices v0 to v1 - 1 (one object, or the whole mesh) into b, a basis
 * over those vertices: the pencil restricted to them, clamped where some are fixed. */
static int object_weights(const rk_fem *f, const rk_sparse *Hw, const rk_sparse *Mw, const unsigned char *fixed,
                          int v0, int v1, int m, rk_basis *b, rk_error *err)
{
    int rc = -1, nfree = 0, nv = v1 - v0;
    int *keep = rk_calloc((size_t)f->nv, sizeof(int), err);
    double *C = NULL;
    if (!keep) return -1;
    for (int v = 0; v < f->nv; v++) keep[v] = v < v0 || v >= v1 || (fixed && fixed[v]) ? -1 : nfree++;
    if (nfree == 0) {
        rk_fail(err, "skinning eigenmodes: every vertex is fixed, nothing is left to move");
        goto out;
    }
    b->type = RK_BASIS_SKINNING;
    b->n = nv;
    b->m = b->nvalues = m + 1;
    b->r = 12 * (m + 1);
    b->values = rk_calloc((size_t)m + 1, sizeof(double), err);
    b->W = rk_calloc((size_t)nv * (m + 1), sizeof(double), err);
    C = nv == f->nv ? b->W : rk_calloc((size_t)f->nv * (m + 1), sizeof(double), err);
    if (!b->values || !b->W || !C) goto out;
    if (nfree < f->nv ? rk_weight_eigs_restricted(Hw, Mw, keep, nfree, m, nfree < nv, b->values, C, &b->nzero, err)
                      : rk_weight_eigs(Hw, Mw, m, 0, b->values, C, &b->nzero, err))
        goto out;
    if (C != b->W)
        for (int j = 0; j <= m; j++)
            memcpy(b->W + (size_t)nv * j, C + (size_t)f->nv * j + v0, sizeof(double) * (size_t)nv);
    rc = 0;
out:
    if (C != b->W) free(C);
    free(keep);
    return rc;
}

int rk_basis_skinning(const rk_fem *f, const unsigned char *fixed, int lumped, int m, rk_basis *b, rk_error *err)
{
    memset(b, 0, sizeof *b);
    rk_sparse Hw = {0}, Mw = {0};
    int rc = -1;
    if (pencil(f, lumped, &Hw, &Mw, err) || object_weights(f, &Hw, &Mw, fixed, 0, f->nv, m, b, err)) goto out;
    b->U = rk_calloc((size_t)3 * f->nv * b->r, sizeof(double), err);
    if (!b->U) goto out;
    rk_skinning_to_U(b->W, f->nv, m + 1, f->X, b->U);
    rc = 0;
out:
    rk_sparse_free(&Hw);
    rk_sparse_free(&Mw);
    if (rc) rk_basis_free(b);
    return rc;
}

int rk_basis_skinning_objects(const rk_fem *f, const unsigned char *fixed, int lumped, int m, const int *first_vertex,
                              int nparts, rk_basis *b, rk_error *err)
{
    memset(b, 0, sizeof *b);
    rk_sparse Hw = {0}, Mw = {0};
    rk_basis *parts = rk_calloc((size_t)nparts, sizeof *parts, err);
    int rc = -1, k = 0;
    if (!parts || pencil(f, lumped, &Hw, &Mw, err)) goto out;
    for (; k < nparts; k++)
        if (object_weights(f, &Hw, &Mw, fixed, first_vertex[k], first_vertex[k + 1], m, &parts[k], err)) {
            rk_basis_free(&parts[k]);
            rk_error_prefix(err, "objects[%d]", k);
            goto out;
        }
    rc = rk_basis_join(parts, nparts, first_vertex, f->X, f->nv, b, err); /* (b owns the parts now) */
    parts = NULL;
out:
    for (int i = 0; parts && i < k; i++) rk_basis_free(&parts[i]);
    free(parts);
    rk_sparse_free(&Hw);
    rk_sparse_free(&Mw);
    return rc;
}
