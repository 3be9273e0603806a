/* Full order's contact on a surface embedded in its elements (fom_impl.h, rk_fom_embedding): a
 * point cloud's march surface in its full-order body (docs/cloud_march.md). The contact positions
 * are y = W x + o, W a fixed sparse matrix (each contact vertex at its embedding tet's barycentric
 * weights, a mesh vertex at weight 1 on itself) and o the rest offsets of vertices embedded
 * outside their tet. The contact stage (precompute/contact) is evaluated on y and pulled back:
 * the gradient W^T g_y, each pair's Hessian block W_p^T B W_p (PSD when B is: the stencil's
 * projected blocks stay PSD), CCD on y with dy = W dx (y is affine in x, so a straight step of x
 * is a straight path of y and CCD stays exact), friction's lagged quantities on y. Every full-order
 * call into the contact stage goes through here; without an embedding each wrapper hands x on
 * as it is (mesh-only scenes run bit for bit as before). */
#include "fom/fom_impl.h"

#include <math.h>
#include <string.h>

#include "util/util.h"

int rk_fom_embedding_init(rk_fom_embedding *e, const rk_fom_contact_surface *cs, int nv_mesh, rk_error *err)
{
    memset(e, 0, sizeof *e);
    if (!cs) return 0;
    int nv = cs->mesh.nv;
    if (nv < 1 || !cs->vertex || !cs->weight || !cs->offset || !cs->mesh.X)
        return rk_fail(err, "contact surface: %d vertices given without their embedding", nv);
    for (int j = 0; j < nv; j++) {
        for (int a = 0; a < 4; a++) {
            int v = cs->vertex[4 * (size_t)j + a];
            double w = cs->weight[4 * (size_t)j + a];
            if (v < 0 || v >= nv_mesh || !isfinite(w))
                return rk_fail(err, "contact surface: vertex %d's embedding names mesh vertex %d (of %d) at weight %g", j,
                               v, nv_mesh, w);
        }
        for (int d = 0; d < 3; d++)
            if (!isfinite(cs->offset[3 * (size_t)j + d]))
                return rk_fail(err, "contact surface: vertex %d's offset is not finite", j);
    }
    e->on = 1;
    e->nv = nv;
    size_t n = (size_t)nv;
    e->vertex = rk_calloc(4 * n, sizeof(int), err);
    e->weight = rk_calloc(4 * n, sizeof(double), err);
    e->offset = rk_calloc(3 * n, sizeof(double), err);
    e->y = rk_calloc(3 * n, sizeof(double), err);
    e->dy = rk_calloc(3 * n, sizeof(double), err);
    e->g = rk_calloc(3 * n, sizeof(double), err);
    e->gb = rk_calloc(3 * n, sizeof(double), err);
    if (!e->vertex || !e->weight || !e->offset || !e->y || !e->dy || !e->g || !e->gb) return -1;
    memcpy(e->vertex, cs->vertex, sizeof(int) * 4 * n);
    memcpy(e->weight, cs->weight, sizeof(double) * 4 * n);
    memcpy(e->offset, cs->offset, sizeof(double) * 3 * n);
    return 0;
}

void rk_fom_embedding_free(rk_fom_embedding *e)
{
    free(e->vertex), free(e->weight), free(e->offset);
    free(e->y), free(e->dy), free(e->g), free(e->gb);
    memset(e, 0, sizeof *e);
}

void rk_fom_embed(int nv, const int *vertex, const double *weight, const double *offset, const double *x, double *y)
{
    for (int j = 0; j < nv; j++) {
        double *p = y + 3 * (size_t)j;
        for (int d = 0; d < 3; d++) p[d] = offset ? offset[3 * (size_t)j + d] : 0;
        for (int a = 0; a < 4; a++) {
            double w = weight[4 * (size_t)j + a];
            if (w == 0) continue;
            const double *q = x + 3 * (size_t)vertex[4 * (size_t)j + a];
            for (int d = 0; d < 3; d++) p[d] += w * q[d];
        }
    }
}

const double *rk_fom_contact_x(rk_fom_impl *im, const double *x)
{
    if (!im->emb.on) return x;
    rk_fom_embed(im->emb.nv, im->emb.vertex, im->emb.weight, im->emb.offset, x, im->emb.y);
    return im->emb.y;
}

const double *rk_fom_contact_dx(rk_fom_impl *im, const double *dx)
{
    if (!im->emb.on) return dx;
    rk_fom_embed(im->emb.nv, im->emb.vertex, im->emb.weight, NULL, dx, im->emb.dy);
    return im->emb.dy;
}

double *rk_fom_contact_gradient(rk_fom_impl *im, double *g)
{
    if (!im->emb.on || !g) return g;
    memset(im->emb.g, 0, sizeof(double) * 3 * (size_t)im->emb.nv);
    return im->emb.g;
}

void rk_fom_contact_pull(rk_fom_impl *im, const double *gy, double *g)
{
    const rk_fom_embedding *e = &im->emb;
    if (!e->on || !g || gy == g) return;
    for (int j = 0; j < e->nv; j++)
        for (int a = 0; a < 4; a++) {
            double w = e->weight[4 * (size_t)j + a];
            if (w == 0) continue;
            double *q = g + 3 * (size_t)e->vertex[4 * (size_t)j + a];
            for (int d = 0; d < 3; d++) q[d] += w * gy[3 * (size_t)j + d];
        }
}

/* A stencil's nodes: each contact point's mesh vertices (up to 4 each) or an obstacle's point
 * (id < 0, itself), 16 at most. */
#define MAX_NODES 16

/* Block B (3 np square) of contact points id as W_p^T B W_p over their nodes, recorded into the
 * Newton matrix as blocks of at most 4 nodes (rk_contact_block's size): the nodes in pairs, each
 * pair's own 6 x 6 block, and for two pairs a 4-node block holding only their coupling (its
 * diagonal parts zero), so that the recorded blocks sum to W_p^T B W_p. */
static void record_embedded(void *ctx, const int *id, int np, const double *B)
{
    rk_fom_impl *im = ctx;
    const rk_fom_embedding *e = &im->emb;
    int node[MAX_NODES], nn = 0;
    double w[4][MAX_NODES] = {{0}};
    for (int i = 0; i < np; i++) {
        for (int a = 0; a < (id[i] >= 0 ? 4 : 1); a++) {
            int v = id[i] >= 0 ? e->vertex[4 * (size_t)id[i] + a] : id[i];
            double wt = id[i] >= 0 ? e->weight[4 * (size_t)id[i] + a] : 1;
            if (wt == 0) continue;
            int k = 0;
            while (k < nn && node[k] != v) k++;
            if (k == nn) node[nn++] = v;
            w[i][k] += wt;
        }
    }
    int m = 3 * np, dim = 3 * nn;
    double H[3 * MAX_NODES * 3 * MAX_NODES], BW[12 * 3 * MAX_NODES];
    /* BW = B W_p (m x dim), then H = W_p^T BW (dim x dim) */
    for (int r = 0; r < m; r++)
        for (int k = 0; k < nn; k++)
            for (int d = 0; d < 3; d++) {
                double s = 0;
                for (int j = 0; j < np; j++) s += B[m * r + 3 * j + d] * w[j][k];
                BW[dim * r + 3 * k + d] = s;
            }
    for (int k = 0; k < nn; k++)
        for (int c = 0; c < 3; c++)
            for (int col = 0; col < dim; col++) {
                double s = 0;
                for (int i = 0; i < np; i++) s += w[i][k] * BW[dim * (3 * i + c) + col];
                H[dim * (3 * k + c) + col] = s;
            }
    if (nn <= 4) {
        rk_newton_matrix_record(&im->N, node, nn, H);
        return;
    }
    int groups = (nn + 1) / 2;
    for (int p = 0; p < groups; p++)
        for (int q = p; q < groups; q++) {
            int ids[4], at[4], nb = 0;
            for (int k = 2 * p; k < 2 * p + 2 && k < nn; k++) ids[nb] = node[k], at[nb++] = k;
            int split = nb;
            if (q != p)
                for (int k = 2 * q; k < 2 * q + 2 && k < nn; k++) ids[nb] = node[k], at[nb++] = k;
            double Hb[144];
            int db = 3 * nb;
            for (int r = 0; r < nb; r++)
                for (int c = 0; c < nb; c++) {
                    int keep = q == p || (r < split) != (c < split); /* two pairs: their coupling only */
                    for (int a = 0; a < 3; a++)
                        for (int b = 0; b < 3; b++)
                            Hb[db * (3 * r + a) + 3 * c + b] = keep ? H[dim * (3 * at[r] + a) + 3 * at[c] + b] : 0;
                }
            rk_newton_matrix_record(&im->N, ids, nb, Hb);
        }
}

rk_hessian_sink rk_fom_contact_sink(rk_fom_impl *im, void **ctx)
{
    if (!im->emb.on) {
        *ctx = &im->N;
        return rk_newton_matrix_record;
    }
    *ctx = im;
    return record_embedded;
}

double rk_fom_contact_ccd(rk_fom_impl *im, const double *x, const double *dx, const double *odx, rk_error *err)
{
    return rk_contact_max_step(&im->contact, rk_fom_contact_x(im, x), rk_fom_contact_dx(im, dx), odx, err);
}

int rk_fom_friction_start(rk_fom_impl *im, const double *x, rk_error *err)
{
    return rk_contact_friction_start(&im->contact, rk_fom_contact_x(im, x), err);
}

int rk_fom_friction_lag(rk_fom_impl *im, const double *x, rk_error *err)
{
    return rk_contact_friction_lag(&im->contact, rk_fom_contact_x(im, x), err);
}

int rk_fom_intersections(rk_fom_impl *im, const double *x, rk_error *err)
{
    return rk_contact_intersections(&im->contact, rk_fom_contact_x(im, x), err);
}

double rk_fom_min_distance(rk_fom_impl *im, const double *x, rk_error *err)
{
    return rk_contact_min_distance(&im->contact, rk_fom_contact_x(im, x), err);
}
