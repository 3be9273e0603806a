/* rk_mesh_boundary: the faces used by exactly one tet. Faces are matched by sorting their
 * vertex triples; each is emitted as its tet sees it from outside. */
#include <stdlib.h>

#include "mesh/mesh_impl.h"

typedef struct {
    int key[3]; /* sorted vertex indices */
    int tri[3]; /* oriented outward from the tet */
} tet_face;

static int by_key(const void *a, const void *b)
{
    const int *x = ((const tet_face *)a)->key, *y = ((const tet_face *)b)->key;
    for (int k = 0; k < 3; k++)
        if (x[k] != y[k]) return x[k] < y[k] ? -1 : 1;
    return 0;
}

static void sort3(int *v)
{
    for (int i = 1; i < 3; i++)
        for (int j = i; j > 0 && v[j - 1] > v[j]; j--) {
            int s = v[j];
            v[j] = v[j - 1];
            v[j - 1] = s;
        }
}

int rk_mesh_boundary(const rk_mesh *m, int **tris, int *nf, rk_error *err)
{
    /* For a positively oriented tet (a,b,c,d) these faces wind counter-clockwise seen from
     * outside: the face opposite each vertex, ordered so its normal points away from it. */
    static const int local[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    *tris = NULL;
    *nf = 0;
    size_t n = 4 * (size_t)m->nt;
    tet_face *f = rk_calloc(n, sizeof *f, err);
    if (!f) return -1;
    for (int t = 0; t < m->nt; t++)
        for (int l = 0; l < 4; l++) {
            tet_face *face = &f[4 * (size_t)t + l];
            for (int k = 0; k < 3; k++) face->tri[k] = face->key[k] = m->tets[4 * (size_t)t + local[l][k]];
            sort3(face->key);
        }
    qsort(f, n, sizeof *f, by_key);
    int *out = rk_calloc(n * 3, sizeof *out, err);
    if (!out) {
        free(f);
        return -1;
    }
    int count = 0;
    for (size_t i = 0; i < n;) {
        size_t j = i + 1;
        while (j < n && by_key(&f[i], &f[j]) == 0) j++;
        if (j - i > 2) {
            int a = f[i].key[0], b = f[i].key[1], c = f[i].key[2];
            free(f);
            free(out);
            return rk_fail(err, "face (%d, %d, %d) is shared by %zu tets (a mesh face joins at most 2)", a, b, c, j - i);
        }
        if (j - i == 1) {
            for (int k = 0; k < 3; k++) out[3 * (size_t)count + k] = f[i].tri[k];
            count++;
        }
        i = j;
    }
    free(f);
    *tris = out;
    *nf = count;
    return 0;
}
