/* Quadratic (P2, 10-node) tetrahedra for static linear elasticity: the converged reference the
 * freeform beam needs where P1 cannot reach it (issue 37: the 122,880-tet P1 run is 9% short of
 * the converged sag at nu = 0.45, since P1 tets lock in bending as the volume stiffens).
 *
 * Shape functions in barycentric coordinates L0..L3 (L1..L3 = Dm^-1 (X - X0), L0 = 1 - L1 - L2 -
 * L3): vertex a, N_a = L_a (2 L_a - 1); edge (a, b), N_ab = 4 L_a L_b. Their gradients are linear,
 * so the stiffness integrand (products of two gradients) and the body-force integrand (one N) are
 * quadratic, and the 4-point rule of degree 2 integrates both exactly on a straight-sided tet. */
#include "fem/fem.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fem/p2_impl.h"

#define EDGE RK_P2_EDGE
const int RK_P2_EDGE[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

typedef struct {
    long long key; /* lo * nv + hi */
    int tet, slot;
} edge_ref;

static int cmp_edge(const void *a, const void *b)
{
    long long x = ((const edge_ref *)a)->key, y = ((const edge_ref *)b)->key;
    return (x > y) - (x < y);
}

int rk_p2_mesh_init(rk_p2_mesh *p, const rk_mesh *m, rk_error *err)
{
    memset(p, 0, sizeof *p);
    size_t ne = (size_t)6 * m->nt;
    edge_ref *e = rk_calloc(1, ne * sizeof *e, err);
    p->elem = rk_calloc(1, (size_t)10 * m->nt * sizeof(int), err);
    if (!e || !p->elem) goto fail;
    for (int t = 0; t < m->nt; t++) {
        const int *v = &m->tets[4 * t];
        for (int a = 0; a < 4; a++) p->elem[10 * t + a] = v[a];
        for (int k = 0; k < 6; k++) {
            int i = v[EDGE[k][0]], j = v[EDGE[k][1]], lo = i < j ? i : j, hi = i < j ? j : i;
            e[6 * (size_t)t + k] = (edge_ref){(long long)lo * m->nv + hi, t, 4 + k};
        }
    }
    qsort(e, ne, sizeof *e, cmp_edge);
    int edges = 0;
    for (size_t k = 0; k < ne; k++) edges += k == 0 || e[k].key != e[k - 1].key;
    if ((long long)m->nv + edges > RK_P2_MAX_NODES) {
        rk_fail(err, "P2 mesh: %d vertices and %d edges are more nodes than %d", m->nv, edges, RK_P2_MAX_NODES);
        goto fail;
    }
    p->nn = m->nv + edges;
    p->nt = m->nt;
    p->nv = m->nv;
    p->X = rk_calloc(1, (size_t)3 * p->nn * sizeof(double), err);
    if (!p->X) goto fail;
    memcpy(p->X, m->X, (size_t)3 * m->nv * sizeof(double));
    int node = m->nv - 1;
    for (size_t k = 0; k < ne; k++) {
        if (k == 0 || e[k].key != e[k - 1].key) {
            int lo = (int)(e[k].key / m->nv), hi = (int)(e[k].key % m->nv);
            node++;
            for (int c = 0; c < 3; c++) p->X[3 * node + c] = 0.5 * (m->X[3 * lo + c] + m->X[3 * hi + c]);
        }
        p->elem[10 * e[k].tet + e[k].slot] = node;
    }
    free(e);
    return 0;
fail:
    free(e);
    rk_p2_mesh_free(p);
    return -1;
}

void rk_p2_mesh_free(rk_p2_mesh *p)
{
    free(p->X);
    free(p->elem);
    memset(p, 0, sizeof *p);
}

void rk_p2_shape_gradients(const double L[4], const double dL[12], double dN[30])
{
    for (int a = 0; a < 4; a++)
        for (int c = 0; c < 3; c++) dN[3 * a + c] = (4 * L[a] - 1) * dL[3 * a + c];
    for (int k = 0; k < 6; k++) {
        int a = EDGE[k][0], b = EDGE[k][1];
        for (int c = 0; c < 3; c++) dN[3 * (4 + k) + c] = 4 * (L[a] * dL[3 * b + c] + L[b] * dL[3 * a + c]);
    }
}

void rk_p2_shape_values(const double L[4], double N[10])
{
    for (int a = 0; a < 4; a++) N[a] = L[a] * (2 * L[a] - 1);
    for (int k = 0; k < 6; k++) N[4 + k] = 4 * L[EDGE[k][0]] * L[EDGE[k][1]];
}

void rk_p2_quadrature_point(int q, double L[4])
{
    const double qa = 0.5854101966249685, qb = 0.1381966011250105; /* degree-2 rule, weights vol/4 */
    for (int k = 0; k < 4; k++) L[k] = k == q ? qa : qb;
}

/* Tet t's 30 x 30 stiffness (row-major, dof 3 node + c) and 30 body-force loads; its volume. */
static double p2_element(const rk_p2_mesh *p, int t, double mu, double lambda, const double b[3], double Ke[900],
                         double fe[30])
{
    const int *n = &p->elem[10 * t];
    double X[12], Dm_inv[9], dL[12];
    for (int a = 0; a < 4; a++)
        for (int c = 0; c < 3; c++) X[3 * a + c] = p->X[3 * n[a] + c];
    double vol = fabs(rk_tet_rest(X, Dm_inv));
    rk_p2_barycentric_gradients(Dm_inv, dL);
    memset(Ke, 0, 900 * sizeof(double));
    memset(fe, 0, 30 * sizeof(double));
    for (int q = 0; q < 4; q++) {
        double L[4], dN[30], N[10], w = vol / 4;
        rk_p2_quadrature_point(q, L);
        rk_p2_shape_gradients(L, dL, dN);
        rk_p2_shape_values(L, N);
        for (int i = 0; i < 10; i++)
            for (int c = 0; c < 3; c++) fe[3 * i + c] += w * N[i] * b[c];
        /* K_{(i,c),(j,d)} = mu (delta_cd gi.gj + gi_d gj_c) + lambda gi_c gj_d */
        for (int i = 0; i < 10; i++) {
            const double *gi = &dN[3 * i];
            for (int j = 0; j < 10; j++) {
                const double *gj = &dN[3 * j];
                double dot = gi[0] * gj[0] + gi[1] * gj[1] + gi[2] * gj[2];
                for (int c = 0; c < 3; c++)
                    for (int d = 0; d < 3; d++)
                        Ke[30 * (3 * i + c) + 3 * j + d] +=
                            w * (mu * ((c == d) * dot + gi[d] * gj[c]) + lambda * gi[c] * gj[d]);
            }
        }
    }
    return vol;
}

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

int rk_p2_pattern(const rk_p2_mesh *p, const int *free_of, int nfree, rk_sparse *S, rk_error *err)
{
    /* node -> tets, then each node's neighbour nodes (sorted, unique) */
    int *count = rk_calloc((size_t)p->nn + 1, sizeof(int), err), *at = NULL, *list = NULL, *nb = NULL, *nbp = NULL;
    int ret = -1;
    if (!count) return -1;
    for (size_t k = 0; k < (size_t)10 * p->nt; k++) count[p->elem[k] + 1]++;
    for (int i = 0; i < p->nn; i++) count[i + 1] += count[i];
    at = rk_calloc(1, (size_t)p->nn * sizeof(int), err);
    list = rk_calloc(1, (size_t)10 * p->nt * sizeof(int), err);
    nbp = rk_calloc((size_t)p->nn + 1, sizeof(int), err);
    if (!at || !list || !nbp) goto out;
    memcpy(at, count, (size_t)p->nn * sizeof(int));
    for (int t = 0; t < p->nt; t++)
        for (int a = 0; a < 10; a++) list[at[p->elem[10 * t + a]]++] = t;
    size_t cap = 0;
    for (int i = 0; i < p->nn; i++) cap += (size_t)10 * (count[i + 1] - count[i]);
    nb = rk_calloc(1, (cap ? cap : 1) * sizeof(int), err);
    if (!nb) goto out;
    size_t used = 0;
    for (int i = 0; i < p->nn; i++) {
        size_t start = used;
        for (int k = count[i]; k < count[i + 1]; k++)
            for (int a = 0; a < 10; a++) nb[used++] = p->elem[10 * list[k] + a];
        qsort(nb + start, used - start, sizeof(int), cmp_int);
        size_t u = start;
        for (size_t k = start; k < used; k++)
            if (k == start || nb[k] != nb[k - 1]) nb[u++] = nb[k];
        used = u;
        nbp[i + 1] = (int)used;
    }
    /* free dofs are numbered node by node, so column (node j, comp d) holds rows (node i <= j) */
    memset(S, 0, sizeof *S);
    S->n = nfree;
    S->colptr = rk_calloc((size_t)nfree + 1, sizeof(int), err);
    if (!S->colptr) goto out;
    long long nnz = 0;
    for (int j = 0; j < p->nn; j++)
        for (int d = 0; d < 3; d++) {
            int col = free_of[3 * j + d];
            if (col < 0) continue;
            for (int k = nbp[j]; k < nbp[j + 1]; k++)
                for (int c = 0; c < 3; c++) {
                    int row = free_of[3 * nb[k] + c];
                    nnz += row >= 0 && row <= col;
                }
            S->colptr[col + 1] = (int)nnz;
        }
    if (nnz > 2147483647LL) {
        rk_fail(err, "P2 stiffness: %lld entries are too many", nnz);
        goto out;
    }
    S->nnz = (int)nnz;
    S->rowind = rk_calloc(1, (size_t)(nnz ? nnz : 1) * sizeof(int), err);
    S->val = rk_calloc((size_t)(nnz ? nnz : 1), sizeof(double), err);
    if (!S->rowind || !S->val) goto out;
    for (int j = 0; j < p->nn; j++)
        for (int d = 0; d < 3; d++) {
            int col = free_of[3 * j + d];
            if (col < 0) continue;
            int k0 = S->colptr[col];
            for (int k = nbp[j]; k < nbp[j + 1]; k++) /* neighbours ascending: rows ascending */
                for (int c = 0; c < 3; c++) {
                    int row = free_of[3 * nb[k] + c];
                    if (row >= 0 && row <= col) S->rowind[k0++] = row;
                }
        }
    ret = 0;
out:
    if (ret) rk_sparse_free(S);
    free(count);
    free(at);
    free(list);
    free(nb);
    free(nbp);
    return ret;
}

int rk_p2_slot(const rk_sparse *S, int row, int col)
{
    int k = S->colptr[col], hi = S->colptr[col + 1] - 1; /* bisect the sorted rows */
    while (k < hi) {
        int mid = (k + hi) / 2;
        if (S->rowind[mid] < row) k = mid + 1;
        else hi = mid;
    }
    return k;
}

void rk_p2_scatter(rk_sparse *S, const int *free_of, const int nodes[10], const double Ke[900], double scale)
{
    for (int a = 0; a < 30; a++) {
        int row = free_of[3 * nodes[a / 3] + a % 3];
        if (row < 0) continue;
        for (int b = 0; b < 30; b++) {
            int col = free_of[3 * nodes[b / 3] + b % 3];
            if (col >= row) S->val[rk_p2_slot(S, row, col)] += scale * Ke[30 * a + b];
        }
    }
}

int rk_p2_static_linear(const rk_p2_mesh *p, double young, double poisson, const double body[3],
                        const unsigned char *fixed, const double *u_fixed, double *u, rk_error *err)
{
    if (!(young > 0) || !isfinite(young) || !(poisson > -1 && poisson < 0.5))
        return rk_fail(err, "P2 static: Young's modulus %g or Poisson's ratio %g out of range", young, poisson);
    double mu, lambda;
    rk_lame(young, poisson, &mu, &lambda);
    int ndof = 3 * p->nn, nfree = 0, ret = -1;
    int *free_of = rk_calloc(1, (size_t)ndof * sizeof(int), err);
    double *f = NULL;
    rk_sparse K = {0};
    rk_chol chol;
    memset(&chol, 0, sizeof chol);
    if (!free_of) return -1;
    for (int i = 0; i < p->nn; i++)
        for (int c = 0; c < 3; c++) free_of[3 * i + c] = fixed[i] ? -1 : nfree++;
    if (nfree == 0) {
        rk_fail(err, "P2 static: every node is fixed");
        goto out;
    }
    if (rk_p2_pattern(p, free_of, nfree, &K, err)) goto out;
    f = rk_calloc((size_t)nfree, sizeof(double), err);
    if (!f) goto out;
    for (int t = 0; t < p->nt; t++) {
        double Ke[900], fe[30];
        p2_element(p, t, mu, lambda, body, Ke, fe);
        const int *n = &p->elem[10 * t];
        for (int a = 0; a < 30; a++) {
            int row = free_of[3 * n[a / 3] + a % 3];
            if (row < 0) continue;
            f[row] += fe[a];
            for (int b = 0; b < 30; b++) {
                int node = n[b / 3], col = free_of[3 * node + b % 3];
                if (col < 0) { /* a prescribed value moves to the right-hand side */
                    if (u_fixed) f[row] -= Ke[30 * a + b] * u_fixed[3 * node + b % 3];
                    continue;
                }
                if (row <= col) K.val[rk_p2_slot(&K, row, col)] += Ke[30 * a + b];
            }
        }
    }
    if (rk_chol_analyze(&chol, &K, err)) goto out;
    int st = rk_chol_factor(&chol, err);
    if (st == RK_CHOL_NOT_POSDEF) {
        rk_error_prefix(err, "P2 static: the stiffness is singular (does the fixed set hold the object?)");
        goto out;
    }
    if (st || rk_chol_solve(&chol, f, f, err)) goto out;
    for (int i = 0; i < p->nn; i++)
        for (int c = 0; c < 3; c++) {
            int k = free_of[3 * i + c];
            u[3 * i + c] = k >= 0 ? f[k] : u_fixed ? u_fixed[3 * i + c] : 0;
        }
    ret = 0;
out:
    rk_chol_free(&chol);
    rk_sparse_free(&K);
    free(free_of);
    free(f);
    return ret;
}
