/* Full order's contact surface for a scene with a cloud colliding through its march surface
 * (build_impl.h, rk_cloud_contact_surface; fom.h, rk_fom_contact_surface): the surface the
 * reduced model and the runtime collide through, embedded in the full-order bodies, so that full
 * order lands a cloud where they do (docs/cloud_march.md, "The rest gap").
 *
 * Layout of the contact mesh, object by object (so object k owns a contiguous range, as
 * rk_contact_init needs):
 *  - a tet mesh, or a cloud on its voxel surface ("proxy": "voxels", which keeps the body's own
 *    boundary as before): all its simulated vertices, each at weight 1 on itself, with its tets
 *    and ghost tets (their boundary is its surface, as without the map);
 *  - a cloud on its march surface: its apex (point 0, embedded as the layout embeds it), then the
 *    march surface's vertices (the layout's entries after the points: their body tet's barycentric
 *    weights, and the rest offset of one outside the body), with the surface's ghost cones
 *    (rk_points_march_mesh), whose boundary is the march surface; the apex is on no triangle, so
 *    the contact model never sees it. */
#include "pipeline/build_impl.h"

#include <stdlib.h>
#include <string.h>

#include "util/util.h"

typedef struct {
    int *vertex, *tets, *ghost;
    double *weight, *offset;
} contact_arrays;

/* Contact vertex c as layout entry j (its weights, its offset). */
static void from_layout(const rk_scene_layout *L, int j, contact_arrays *a, int c)
{
    memcpy(a->vertex + 4 * (size_t)c, L->vertex + 4 * (size_t)j, 4 * sizeof(int));
    memcpy(a->weight + 4 * (size_t)c, L->weight + 4 * (size_t)j, 4 * sizeof(double));
    memcpy(a->offset + 3 * (size_t)c, L->offset + 3 * (size_t)j, 3 * sizeof(double));
}

int rk_cloud_contact_surface(const rk_scene *s, const rk_cloud_body *bodies, rk_scene_sim *out, rk_error *err)
{
    const rk_mesh *m = &out->mesh;
    int march = 0, nv = 0, nt = 0, ng = 0;
    for (int k = 0; k < s->nobjects; k++) {
        const rk_cloud_body *b = &bodies[k];
        march += b->march;
        if (b->n && b->march) {
            nv += 1 + b->surface_nv;
            ng += b->nghost;
        } else {
            nv += out->object_first_vertex[k + 1] - out->object_first_vertex[k];
            nt += out->object_first_tet[k + 1] - out->object_first_tet[k];
        }
    }
    ng += m->nghost; /* the meshes' own ghosts (an upper bound) */
    if (!march) return 0;
    rk_fom_contact_surface *cs = &out->contact;
    contact_arrays a = {rk_calloc(4 * (size_t)nv, sizeof(int), err), rk_calloc(4 * (size_t)nt + 1, sizeof(int), err),
                        rk_calloc(4 * (size_t)ng + 1, sizeof(int), err), rk_calloc(4 * (size_t)nv, sizeof(double), err),
                        rk_calloc(3 * (size_t)nv, sizeof(double), err)};
    double *X = rk_calloc(3 * (size_t)nv, sizeof(double), err);
    int *first = rk_calloc((size_t)s->nobjects + 1, sizeof(int), err);
    cs->mesh = (rk_mesh){.nv = nv, .X = X, .tets = a.tets, .ghost = a.ghost};
    cs->vertex = a.vertex, cs->weight = a.weight, cs->offset = a.offset, cs->object_first_vertex = first;
    if (!a.vertex || !a.tets || !a.ghost || !a.weight || !a.offset || !X || !first) return -1;
    const rk_scene_layout *L = &out->layout;
    int c = 0, j = 0, t = 0, g = 0; /* contact vertex, layout entry, tet, ghost */
    for (int k = 0; k < s->nobjects; k++) {
        const rk_cloud_body *b = &bodies[k];
        int v0 = out->object_first_vertex[k], v1 = out->object_first_vertex[k + 1], c0 = c;
        if (b->n && b->march) {
            from_layout(L, j, &a, c++); /* the apex: point 0 */
            for (int i = 0; i < b->surface_nv; i++) from_layout(L, j + b->n + i, &a, c++);
            for (int i = 0; i < 4 * b->nghost; i++) a.ghost[4 * (size_t)g + i] = c0 + b->ghost[i];
            g += b->nghost;
            j += b->n + b->surface_nv;
        } else {
            for (int v = v0; v < v1; v++, c++) {
                for (int q = 0; q < 4; q++) a.vertex[4 * (size_t)c + q] = v;
                a.weight[4 * (size_t)c] = 1;
            }
            for (int e = out->object_first_tet[k]; e < out->object_first_tet[k + 1]; e++, t++)
                for (int q = 0; q < 4; q++) a.tets[4 * (size_t)t + q] = m->tets[4 * (size_t)e + q] - v0 + c0;
            for (int e = 0; e < m->nghost; e++)
                if (m->ghost[4 * (size_t)e] >= v0 && m->ghost[4 * (size_t)e] < v1) {
                    for (int q = 0; q < 4; q++) a.ghost[4 * (size_t)g + q] = m->ghost[4 * (size_t)e + q] - v0 + c0;
                    g++;
                }
            j += b->n ? b->n + b->surface_nv : v1 - v0;
        }
        first[k + 1] = c;
    }
    cs->mesh.nt = t;
    cs->mesh.nghost = g;
    /* its rest positions: the map at the bodies' rest (a march vertex exactly where the march put it) */
    rk_fom_embed(nv, a.vertex, a.weight, a.offset, m->X, X);
    return 0;
}
