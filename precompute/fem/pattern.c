/* The one sparsity pattern every fem matrix shares, and the element-to-slot map.
 *
 * Layout (upper triangle, CSC, 3 dofs per vertex): column 3j + c holds, in increasing row order,
 * the three rows 3i, 3i+1, 3i+2 of every vertex i < j that shares a tet with j, then the rows
 * 3j .. 3j + c of j's own diagonal block. So column 3j + c has 3 L_j + c + 1 entries, where L_j
 * counts j's lower neighbours, and vertex i's rows sit at the same offset 3 pos(i) in all
 * three columns of j. Building it: vertex -> tets lists, then each vertex's lower neighbours
 * (deduplicated with a stamp array, sorted); linear in the mesh size apart from tiny sorts. */
#include "fem/element_impl.h"

#include <stdlib.h>

static void sort_ints(int *a, int n)
{
    for (int i = 1; i < n; i++) { /* insertion sort: lists have ~15 entries */
        int key = a[i], j = i - 1;
        while (j >= 0 && a[j] > key) {
            a[j + 1] = a[j];
            j--;
        }
        a[j + 1] = key;
    }
}

/* Position of `key` in the sorted list a[0..n). The key is known to be present. */
static int find_sorted(const int *a, int n, int key)
{
    int lo = 0, hi = n - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (a[mid] < key) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

/* nbr_start/nbr_count: each vertex's sorted lower neighbours, stored in nbr at nbr_start[j]. */
static int lower_neighbours(const rk_fem *f, int *nbr_start, int *nbr_count, int **nbr_out,
                            rk_error *err)
{
    int nv = f->nv, nt = f->nt;
    int *vt_start = rk_calloc((size_t)nv + 1, sizeof(int), err);
    int *vt = rk_calloc(4 * (size_t)nt, sizeof(int), err);
    int *stamp = rk_calloc((size_t)nv, sizeof(int), err);
    /* Each tet adds at most 3 neighbours to each of its vertices. */
    int *nbr = rk_calloc(12 * (size_t)nt, sizeof(int), err);
    if (!vt_start || !vt || !stamp || !nbr) {
        free(vt_start), free(vt), free(stamp), free(nbr);
        return -1;
    }
    for (int k = 0; k < 4 * nt; k++) vt_start[f->tets[k] + 1]++;
    for (int j = 0; j < nv; j++) vt_start[j + 1] += vt_start[j];
    for (int j = 0; j < nv; j++) nbr_count[j] = vt_start[j]; /* fill cursor */
    for (int k = 0; k < 4 * nt; k++) vt[nbr_count[f->tets[k]]++] = k / 4;
    for (int j = 0; j < nv; j++) stamp[j] = -1;
    for (int j = 0; j < nv; j++) {
        nbr_start[j] = 3 * vt_start[j];
        int n = 0;
        for (int e = vt_start[j]; e < vt_start[j + 1]; e++) {
            const int *v = &f->tets[4 * vt[e]];
            for (int a = 0; a < 4; a++)
                if (v[a] < j && stamp[v[a]] != j) {
                    stamp[v[a]] = j;
                    nbr[nbr_start[j] + n++] = v[a];
                }
        }
        sort_ints(&nbr[nbr_start[j]], n);
        nbr_count[j] = n;
    }
    free(vt_start), free(vt), free(stamp);
    *nbr_out = nbr;
    return 0;
}

int rk_fem_build_pattern(rk_fem *f, rk_error *err)
{
    int nv = f->nv, nt = f->nt, n = 3 * nv;
    int *nbr_start = rk_calloc((size_t)nv, sizeof(int), err);
    int *nbr_count = rk_calloc((size_t)nv, sizeof(int), err);
    int *nbr = NULL;
    rk_sparse *S = &f->pattern;
    S->n = n;
    S->colptr = rk_calloc((size_t)n + 1, sizeof(int), err);
    f->slot = rk_calloc((size_t)RK_TET_SLOTS * (size_t)nt, sizeof(int), err);
    if (!nbr_start || !nbr_count || !S->colptr || !f->slot ||
        lower_neighbours(f, nbr_start, nbr_count, &nbr, err)) {
        free(nbr_start), free(nbr_count);
        return -1;
    }
    long nnz = 0;
    for (int j = 0; j < nv; j++)
        for (int c = 0; c < 3; c++) {
            S->colptr[3 * j + c] = (int)nnz;
            nnz += 3L * nbr_count[j] + c + 1;
        }
    if (nnz > 2147483647L) {
        free(nbr_start), free(nbr_count), free(nbr);
        return rk_fail(err, "sparsity pattern has %ld entries, more than 32-bit indices allow", nnz);
    }
    S->colptr[n] = (int)nnz;
    S->nnz = (int)nnz;
    S->rowind = rk_calloc((size_t)nnz, sizeof(int), err);
    if (!S->rowind) {
        free(nbr_start), free(nbr_count), free(nbr);
        return -1;
    }
    for (int j = 0; j < nv; j++)
        for (int c = 0; c < 3; c++) {
            int *r = &S->rowind[S->colptr[3 * j + c]];
            const int *lower = &nbr[nbr_start[j]];
            for (int k = 0; k < nbr_count[j]; k++)
                for (int i = 0; i < 3; i++) *r++ = 3 * lower[k] + i;
            for (int i = 0; i <= c; i++) *r++ = 3 * j + i;
        }

    /* Slot map: block offsets of the 4x4 vertex pairs, then 78 entries by arithmetic. */
    for (int t = 0; t < nt; t++) {
        const int *v = &f->tets[4 * t];
        int off[4][4]; /* off[a][b]: row offset of the lower vertex inside the higher one's columns */
        for (int a = 0; a < 4; a++)
            for (int b = 0; b < 4; b++) {
                int lo = v[a] < v[b] ? v[a] : v[b], hi = v[a] < v[b] ? v[b] : v[a];
                off[a][b] = lo == hi ? 3 * nbr_count[hi]
                                     : 3 * find_sorted(&nbr[nbr_start[hi]], nbr_count[hi], lo);
            }
        int *s = &f->slot[RK_TET_SLOTS * t];
        for (int p = 0; p < 12; p++)
            for (int q = p; q < 12; q++) {
                int a = p / 3, ca = p % 3, b = q / 3, cb = q % 3;
                int row_c, col_v, col_c; /* row component (in the lower vertex) and column dof */
                if (v[a] == v[b]) {
                    col_v = v[a], col_c = ca > cb ? ca : cb, row_c = ca < cb ? ca : cb;
                } else if (v[a] < v[b]) {
                    col_v = v[b], col_c = cb, row_c = ca;
                } else {
                    col_v = v[a], col_c = ca, row_c = cb;
                }
                *s++ = S->colptr[3 * col_v + col_c] + off[a][b] + row_c;
            }
    }
    free(nbr_start), free(nbr_count), free(nbr);
    return 0;
}
