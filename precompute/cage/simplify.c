/* rk_cage_simplify: meshoptimizer's edge-collapse simplifier (Debian's libmeshoptimizer 0.18,
 * meshopt_simplify: quadric error metrics, Garland and Heckbert 1997) on the surface, in float as
 * its API takes it; the vertices it keeps are copied from the double input, so the simplified
 * surface's vertices are original vertices, bit for bit. */
#include "cage/cage_impl.h"

#include <meshoptimizer.h>
#include <stdlib.h>
#include <string.h>

/* The three vertices of a triangle in ascending order, for comparing triangles as vertex sets. */
static void sorted3(const unsigned *t, unsigned *k)
{
    unsigned a = t[0], b = t[1], c = t[2], x;
    if (a > b) x = a, a = b, b = x;
    if (b > c) x = b, b = c, c = x;
    if (a > b) x = a, a = b, b = x;
    k[0] = a, k[1] = b, k[2] = c;
}

static int compare_keys(const void *pa, const void *pb)
{
    const unsigned *a = pa, *b = pb;
    for (int i = 0; i < 3; i++)
        if (a[i] != b[i]) return a[i] < b[i] ? -1 : 1;
    return 0;
}

/* Triangles over the same three vertices, removed in pairs: meshopt_simplify 0.18 can collapse a
 * thin part into a zero-volume fin, a triangle and its reverse, which leaves each of their edges
 * with four faces (on decimated-knight.off at every target from 132 to 402 triangles); dropping
 * both closes the surface again. A key seen an odd number of times keeps one triangle. */
static size_t drop_fins(unsigned *idx, size_t n)
{
    size_t nt = n / 3;
    unsigned *keys = malloc(sizeof(unsigned) * 4 * (nt ? nt : 1));
    if (!keys) return n; /* nothing dropped: TetGen's check names the fin */
    for (size_t t = 0; t < nt; t++) {
        sorted3(idx + 3 * t, keys + 4 * t);
        keys[4 * t + 3] = (unsigned)t;
    }
    qsort(keys, nt, 4 * sizeof(unsigned), compare_keys);
    unsigned char *drop = calloc(nt ? nt : 1, 1);
    if (!drop) {
        free(keys);
        return n;
    }
    for (size_t i = 0; i < nt;) {
        size_t j = i;
        while (j < nt && compare_keys(keys + 4 * i, keys + 4 * j) == 0) j++;
        for (size_t k = i; k < i + ((j - i) & ~(size_t)1); k++) drop[keys[4 * k + 3]] = 1;
        i = j;
    }
    size_t out = 0;
    for (size_t t = 0; t < nt; t++)
        if (!drop[t]) memmove(idx + 3 * out++, idx + 3 * t, 3 * sizeof(unsigned));
    free(keys);
    free(drop);
    return 3 * out;
}

int rk_cage_simplify(const rk_surface *s, int target, rk_surface *out, double *error, rk_error *err)
{
    memset(out, 0, sizeof *out);
    size_t ni = 3 * (size_t)s->nf;
    float *pos = rk_calloc(3 * (size_t)s->nv, sizeof(float), err);
    unsigned *idx = rk_calloc(ni, sizeof(unsigned), err), *dst = rk_calloc(ni, sizeof(unsigned), err);
    int *map = rk_calloc((size_t)s->nv, sizeof(int), err), rc = -1;
    if (!pos || !idx || !dst || !map) goto done;
    for (size_t i = 0; i < 3 * (size_t)s->nv; i++) pos[i] = (float)s->X[i];
    for (size_t i = 0; i < ni; i++) idx[i] = (unsigned)s->tris[i];
    float rel = 0;
    /* target_error 1 (the whole extent): the triangle count is what stops it */
    size_t kept = meshopt_simplify(dst, idx, ni, pos, (size_t)s->nv, 3 * sizeof(float), 3 * (size_t)target, 1.0f, 0, &rel);
    *error = (double)rel * (double)meshopt_simplifyScale(pos, (size_t)s->nv, 3 * sizeof(float));
    if (kept < 12) {
        rk_fail(err, "cage: meshopt_simplify left %zu triangles of %d (target %d)", kept / 3, s->nf, target);
        goto done;
    }
    kept = drop_fins(dst, kept);
    for (int v = 0; v < s->nv; v++) map[v] = -1;
    for (size_t i = 0; i < kept; i++)
        if (map[dst[i]] < 0) map[dst[i]] = out->nv++;
    out->nf = (int)(kept / 3);
    out->X = rk_calloc(3 * (size_t)out->nv, sizeof(double), err);
    out->tris = rk_calloc(kept, sizeof(int), err);
    if (!out->X || !out->tris) goto done;
    for (int v = 0; v < s->nv; v++)
        if (map[v] >= 0) memcpy(out->X + 3 * (size_t)map[v], s->X + 3 * (size_t)v, 3 * sizeof(double));
    for (size_t i = 0; i < kept; i++) out->tris[i] = map[dst[i]];
    rc = 0;
done:
    free(pos);
    free(idx);
    free(dst);
    free(map);
    if (rc) rk_surface_free(out);
    return rc;
}
