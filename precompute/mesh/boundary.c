/* rk_mesh_boundary: the faces used by exactly one tet (ghost tets count, but are never emitted),
 * and rk_mesh_face_partners. Faces are matched by sorting their vertex triples; each is emitted as
 * its tet sees it from outside. */
#include <stdlib.h>

#include "mesh/mesh_impl.h"

typedef struct {
    int key[3]; /* sorted vertex indices */
    int tri[3]; /* oriented outward from the tet */
    int tet;    /* its tet: index among the tets, or nt + index among the ghosts */
    int local;  /* the face opposite that tet's local vertex `local` */
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

/* Every face of the tets, and of the ghost tets when `ghosts`, sorted by key (*n of them). */
static tet_face *sorted_faces(const rk_mesh *m, int ghosts, size_t *n, rk_error *err)
{
    /* For a positively oriented tet (a,b,c,d) these faces wind counter-clockwise seen from
     * outside: the face opposite each vertex, ordered so its normal points away from it. */
    static const int local[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    int count = m->nt + (ghosts ? m->nghost : 0);
    *n = 4 * (size_t)count;
    tet_face *f = rk_calloc(*n, sizeof *f, err);
    if (!f) return NULL;
    for (int t = 0; t < count; t++) {
        const int *v = t < m->nt ? m->tets + 4 * (size_t)t : m->ghost + 4 * (size_t)(t - m->nt);
        for (int l = 0; l < 4; l++) {
            tet_face *face = &f[4 * (size_t)t + l];
            for (int k = 0; k < 3; k++) face->tri[k] = face->key[k] = v[local[l][k]];
            sort3(face->key);
            face->tet = t;
            face->local = l;
        }
    }
    qsort(f, *n, sizeof *f, by_key);
    return f;
}

int rk_mesh_boundary(const rk_mesh *m, int **tris, int *nf, rk_error *err)
{
    *tris = NULL;
    *nf = 0;
    size_t n;
    tet_face *f = sorted_faces(m, 1, &n, err);
    if (!f) return -1;
    int *out = rk_calloc(n * 3, sizeof *out, err);
    char *in_tet = rk_calloc((size_t)m->nv + 1, 1, err); /* vertices of a (real) tet */
    if (!out || !in_tet) {
        free(f), free(out), free(in_tet);
        return -1;
    }
    for (size_t k = 0; k < 4 * (size_t)m->nt; k++) in_tet[m->tets[k]] = 1;
    int count = 0;
    for (size_t i = 0; i < n;) {
        size_t j = i + 1;
        while (j < n && by_key(&f[i], &f[j]) == 0) j++;
        if (j - i > 2) {
            int a = f[i].key[0], b = f[i].key[1], c = f[i].key[2];
            free(f), free(out), free(in_tet);
            return rk_fail(err, "face (%d, %d, %d) is shared by %zu tets (a mesh face joins at most 2)", a, b, c, j - i);
        }
        /* a ghost's face is never the body's (a dropped sliver's, among tets), except in a body of
         * ghosts only, no vertex of which a tet holds: a point cloud's contact surface
         * (rk_points_proxy), alone or beside meshes in one scene */
        const int *tri = f[i].tri;
        if (j - i == 1 && (f[i].tet < m->nt || !(in_tet[tri[0]] || in_tet[tri[1]] || in_tet[tri[2]]))) {
            for (int k = 0; k < 3; k++) out[3 * (size_t)count + k] = f[i].tri[k];
            count++;
        }
        i = j;
    }
    free(f), free(in_tet);
    *tris = out;
    *nf = count;
    return 0;
}

int rk_mesh_face_partners(const rk_mesh *m, int *partner, rk_error *err)
{
    size_t n;
    tet_face *f = sorted_faces(m, 0, &n, err);
    if (!f) return -1;
    for (size_t i = 0; i < n;) {
        size_t j = i + 1;
        while (j < n && by_key(&f[i], &f[j]) == 0) j++;
        /* one: a boundary face; two: each other; more (not manifold): each the next, round */
        for (size_t k = i; k < j; k++)
            partner[4 * (size_t)f[k].tet + f[k].local] = j - i == 1 ? -1 : f[k + 1 < j ? k + 1 : i].tet;
        i = j;
    }
    free(f);
    return 0;
}
