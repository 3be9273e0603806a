/* rk_points_march_mesh (contact.h): rk_points_march's surface in the form every user of a cloud's
 * contact surface already reads, an rk_mesh whose rk_mesh_boundary is the surface (the n points,
 * then the surface's vertices, ghost tets and no tets, as rk_points_proxy gives the voxel surface).
 *
 * Why ghost tets coned to one apex rather than an explicit boundary: the reduced model, the bake,
 * the runtime's surface and full order's layout all take a cloud's surface from rk_mesh_boundary of
 * the scene's mesh (boundary.c), so a cone keeps every one of them unchanged. Triangle (a, b, c),
 * outward, becomes ghost (a, c, b, apex): boundary.c emits a tet's face opposite its fourth vertex
 * as (v0, v2, v1), by vertex order, never by geometry, so that face comes out (a, b, c). Each cone
 * face (a, b, apex) belongs to the two triangles on edge (a, b) of a closed 2-manifold surface
 * (rk_points_march's guarantee), so it is matched and never emitted. The apex is point 0: a vertex
 * of the object already (no vertex added to the model), in no tet and on no triangle. The ghosts'
 * geometry (inverted or flat cones) is read by nothing: rk_mesh_check and rk_mesh_refine, which
 * would, are not run on a cloud (parse.c refuses refine on points). */
#include <stdlib.h>
#include <string.h>

#include "contact/contact.h"

int rk_points_march_mesh(const double *X, int n, double h, double s, rk_mesh *out, rk_points_march_report *rep, rk_error *err)
{
    memset(out, 0, sizeof *out);
    rk_surface S;
    if (rk_points_march(X, n, h, s, &S, rep, err)) return -1;
    out->nv = n + S.nv;
    out->nghost = S.nf;
    out->X = malloc(sizeof(double) * 3 * (size_t)out->nv);
    out->ghost = malloc(sizeof(int) * 4 * ((size_t)S.nf + 1));
    out->tets = malloc(sizeof(int)); /* none, as rk_points_proxy's */
    if (!out->X || !out->ghost || !out->tets) {
        rk_surface_free(&S);
        rk_mesh_free(out);
        return rk_fail(err, "contact surface: out of memory");
    }
    memcpy(out->X, X, sizeof(double) * 3 * (size_t)n);
    memcpy(out->X + 3 * (size_t)n, S.X, sizeof(double) * 3 * (size_t)S.nv);
    for (int f = 0; f < S.nf; f++) {
        const int *t = S.tris + 3 * (size_t)f;
        int *G = out->ghost + 4 * (size_t)f;
        G[0] = n + t[0], G[1] = n + t[2], G[2] = n + t[1], G[3] = 0;
    }
    rk_surface_free(&S);
    return 0;
}
