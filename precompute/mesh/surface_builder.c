#include "mesh/mesh_impl.h"

int rk_sb_vertex(rk_surface_builder *b, const double p[3], rk_error *err)
{
    if (b->s.nv >= RK_MESH_MAX_COUNT) return rk_fail(err, "too many vertices (more than %d)", RK_MESH_MAX_COUNT);
    if (rk_grow(&b->s.X, &b->vcap, 3 * ((size_t)b->s.nv + 1), sizeof(double), err)) return -1;
    for (int k = 0; k < 3; k++) b->s.X[3 * (size_t)b->s.nv + k] = p[k];
    b->s.nv++;
    return 0;
}

int rk_sb_polygon(rk_surface_builder *b, const int *idx, int n, rk_error *err)
{
    if (n < 3) return rk_fail(err, "a face needs at least 3 vertices, got %d", n);
    if (b->s.nf > RK_MESH_MAX_COUNT - (n - 2)) return rk_fail(err, "too many faces (more than %d)", RK_MESH_MAX_COUNT);
    if (rk_grow(&b->s.tris, &b->fcap, 3 * ((size_t)b->s.nf + (size_t)(n - 2)), sizeof(int), err)) return -1;
    /* Fan around the first vertex: exact for convex polygons, which is what exporters write. */
    for (int k = 1; k + 1 < n; k++) {
        int *t = b->s.tris + 3 * (size_t)b->s.nf;
        t[0] = idx[0];
        t[1] = idx[k];
        t[2] = idx[k + 1];
        b->s.nf++;
    }
    return 0;
}
