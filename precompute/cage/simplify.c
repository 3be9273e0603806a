/* rk_cage_simplify: meshoptimizer's edge-collapse simplifier (Debian's libmeshoptimizer 0.18,
 * meshopt_simplify: quadric error metrics, Garland and Heckbert 1997) on the surface, in float as
 * its API takes it; the vertices it keeps are copied from the double input, so the simplified
 * surface's vertices are original vertices, bit for bit. */
#include "cage/cage_impl.h"

#include <meshoptimizer.h>
#include <stdlib.h>
#include <string.h>

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
