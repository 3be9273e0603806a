/* A point cloud simulated at full order (rk_scene_build_full_order): its body is the tets that
 * fill its contact surface (rk_points_body: the voxel set's Kuhn tets, surface inset), with the
 * cloud's mass, the material of each tet's nearest point, and the points embedded in the tets
 * (barycentric, rk_cage_embed: mesh.cage's embedding, the one implementation) so that what a
 * full-order run writes is the scene's vertices as the reduced simulator numbers them: the cloud's
 * points, then its contact surface's vertices (rk_scene_layout). */
#include "pipeline/build_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/util.h"

int rk_cloud_proxy_spacing(const rk_scene_object *o, const double *X, int n, double *g, double *s, rk_error *err)
{
    /* the points' median spacing s (the occupancy voxel is 2 s: rk_rkpm_sample_cloud), which the
     * contact surface comes in to s / 2 of; g defaults to the cloud's RKPM sampling spacing 2 s, so
     * that neighbouring points' balls of radius g / 2 overlap and the surface around them has no
     * holes, no finer than 1/RK_PROXY_VOXELS of the cloud's diagonal, which bounds the surface's
     * triangles (a dense capture's spacing is tiny). Under 4 points (no spacing): s = 0, and the
     * surface stays at g / 2 */
    *g = o->proxy_voxel / o->scale;
    *s = 0;
    if (n < 4 && *g > 0) return 0;
    rk_rkpm_points occupancy;
    if (rk_rkpm_sample_cloud(X, n, n, &occupancy, err)) return -1;
    *s = 0.5 * occupancy.spacing;
    if (!(*g > 0)) *g = fmax(rk_points_diagonal(X, n) / RK_PROXY_VOXELS, occupancy.spacing);
    rk_rkpm_points_free(&occupancy);
    return 0;
}

int rk_cloud_surface(const rk_scene_object *o, const double *X, int n, rk_mesh *m, rk_error *err)
{
    double g, s;
    if (rk_cloud_proxy_spacing(o, X, n, &g, &s, err)) return -1;
    if (o->proxy_voxels || !(s > 0)) return rk_points_proxy(X, n, g, s, m, err);
    /* the march surface follows the capture where the voxel surface's staircase cannot come in
     * (docs/cloud_march.md: the donut's 95th percentile vertex 0.50 s from a point, not 2.39 s) */
    rk_points_march_report rep;
    if (rk_points_march_mesh(X, n, RK_MARCH_LATTICE * g, s, m, &rep, err)) return -1;
    if (rep.outside_points == 0) return 0;
    /* a lattice cell's alignment can leave a point past s (the pour's turned, thinned donut: 1 of
     * 2,852 at 1.3 s); the finer lattice g kept every point of the donut within s
     * (docs/cloud_march.md) at about twice the triangles, so it is tried before refusing */
    rk_warn("%s: %d of %d points lie more than their spacing outside the contact surface on the lattice %g (the "
            "farthest %g, in the file's units): trying the lattice %g", o->file, rep.outside_points, n,
            RK_MARCH_LATTICE * g, rep.max_outside, g);
    rk_mesh_free(m);
    if (rk_points_march_mesh(X, n, g, s, m, &rep, err)) return -1;
    if (rep.outside_points == 0) return 0;
    rk_mesh_free(m);
    return rk_fail(err, "%s: %d of %d points lie more than their spacing (%g in the file's units) outside the cloud's "
                   "contact surface, the farthest %g, even on the lattice %g: give a smaller proxy_voxel, or proxy "
                   "\"voxels\"", o->file, rep.outside_points, n, s, rep.max_outside, g);
}

int rk_cloud_body_load(const rk_scene_object *o, rk_mesh *m, rk_cloud_body *b, rk_error *err)
{
    memset(b, 0, sizeof *b);
    double g, spacing, tau;
    if (rk_points_load_tagged(o->file, &b->X, &b->n, &b->tag, err) ||
        rk_cloud_proxy_spacing(o, b->X, b->n, &g, &spacing, err))
        goto fail;
    if (!(spacing > 0)) {
        rk_fail(err, "point cloud: %d points, at least 4 are needed", b->n);
        goto fail;
    }
    /* the body's surface vertices no farther than sqrt(3) / 2 s from the points, s the points'
     * median spacing: a point stands for the cube of edge s around it,
     * whose corners are that far from it, so the union of those cubes is what a surface vertex
     * nearer than that already bounds (a lattice cloud at proxy_voxel s keeps its cells' union, the
     * box it samples, exactly). The contact surface comes in to s / 2 (RK_PROXY_SPACING_INSET),
     * nearer (the body at s / 2 would lose a third of a lattice's cells' volume) */
    tau = 0.5 * sqrt(3.0) * spacing;
    if (rk_points_body(b->X, b->n, g, spacing, tau, m, &b->tet_point, &b->proxy_X, &b->rep, err)) goto fail;
    b->corners = b->surface_nv = m->nv;
    if (!o->proxy_voxels) { /* the march surface's vertices, embedded in the body (embed_cloud) */
        rk_mesh surface;
        if (rk_cloud_surface(o, b->X, b->n, &surface, err)) goto fail;
        free(b->proxy_X);
        b->surface_nv = surface.nv - b->n;
        b->proxy_X = rk_calloc(3 * (size_t)b->surface_nv + 1, sizeof(double), err);
        b->ghost = rk_calloc(4 * (size_t)surface.nghost + 1, sizeof(int), err);
        if (b->proxy_X) memcpy(b->proxy_X, surface.X + 3 * (size_t)b->n, sizeof(double) * 3 * (size_t)b->surface_nv);
        /* its ghost cones (rk_points_march_mesh: coned to point 0) over the apex, then the vertices */
        for (int i = 0; b->ghost && i < 4 * surface.nghost; i++)
            b->ghost[i] = surface.ghost[i] < b->n ? 0 : 1 + surface.ghost[i] - b->n;
        b->nghost = surface.nghost;
        rk_mesh_free(&surface);
        if (!b->proxy_X || !b->ghost) goto fail;
        b->march = 1;
    }
    m->tet_tag = rk_calloc((size_t)m->nt + 1, sizeof(int), err);
    if (!m->tet_tag) goto fail;
    for (int t = 0; t < m->nt; t++) m->tet_tag[t] = b->tag ? b->tag[b->tet_point[t]] : 0;
    return 0;
fail:
    rk_mesh_free(m);
    rk_cloud_body_free(b);
    return rk_error_prefix(err, "full-order body");
}

void rk_cloud_body_place(rk_cloud_body *b, double scale, const double translate[3])
{
    for (int i = 0; i < b->n; i++)
        for (int d = 0; d < 3; d++) b->X[3 * i + d] = scale * b->X[3 * i + d] + translate[d];
    for (int c = 0; c < b->surface_nv; c++)
        for (int d = 0; d < 3; d++) b->proxy_X[3 * c + d] = scale * b->proxy_X[3 * c + d] + translate[d];
}

void rk_cloud_body_free(rk_cloud_body *b)
{
    free(b->X), free(b->tag), free(b->tet_point), free(b->proxy_X), free(b->ghost);
    memset(b, 0, sizeof *b);
}

/* Cloud k's tets made to weigh the cloud's mass: sum over its points of rho(point) V / n, V its
 * occupancy volume (rk_rkpm_sample_cloud), as the reduced model weighs it (build.c, cloud_fem). */
static int match_mass(const rk_scene *s, const rk_cloud_body *b, int k, rk_scene_sim *out, rk_error *err)
{
    const rk_scene_object *o = &s->objects[k];
    rk_rkpm_points pts;
    if (rk_rkpm_sample_cloud(b->X, b->n, b->n, &pts, err)) return -1;
    double cloud = 0, body = 0, volume = 0;
    for (int i = 0; i < b->n; i++)
        cloud += rk_scene_region_material(o, b->X + 3 * (size_t)i, b->tag != NULL, b->tag ? b->tag[i] : 0).density *
                 pts.volume / b->n;
    rk_rkpm_points_free(&pts);
    const rk_mesh *m = &out->mesh;
    for (int t = out->object_first_tet[k]; t < out->object_first_tet[k + 1]; t++) {
        const int *v = m->tets + 4 * (size_t)t;
        double vt = rk_tet_signed_volume(m->X + 3 * (size_t)v[0], m->X + 3 * (size_t)v[1], m->X + 3 * (size_t)v[2],
                                         m->X + 3 * (size_t)v[3]);
        body += out->materials[t].density * vt;
        volume += vt;
    }
    if (!(body > 0) || !(cloud > 0))
        return rk_fail(err, "%s: objects[%d]: the cloud weighs %g kg, its full-order body %g kg", s->path, k, cloud, body);
    for (int t = out->object_first_tet[k]; t < out->object_first_tet[k + 1]; t++)
        out->materials[t].density *= cloud / body;
    out->body_volume += volume;
    out->body_mass += cloud;
    out->body_mass_scale = out->body_mass_scale > 0 ? fmax(out->body_mass_scale, cloud / body) : cloud / body;
    return 0;
}

static void direct(rk_scene_layout *L, int i, int v)
{
    L->vertex[4 * (size_t)i] = L->vertex[4 * (size_t)i + 1] = L->vertex[4 * (size_t)i + 2] = L->vertex[4 * (size_t)i + 3] = v;
    L->weight[4 * (size_t)i] = 1;
}

/* The layout's entries *i on for the n places P (3n) embedded in cloud k's body tets (ov), by
 * rk_cage_embed (one warning for those outside, carried by their nearest tet); with `offset`, each
 * entry's rest offset puts it exactly where it is (an outside place's barycentrics are clamped). */
static int embed_places(const rk_scene *s, int k, const rk_object_view *ov, const double *P, int n, const char *what,
                        int offset, int *i, rk_scene_sim *out, int *outside, double *worst, rk_error *err)
{
    rk_scene_layout *L = &out->layout;
    rk_embedding e;
    if (rk_cage_embed(&ov->mesh, P, n, &e, err))
        return rk_error_prefix(err, "%s: objects[%d]: embedding the %s in the full-order body", s->path, k, what);
    if (e.outside)
        rk_warn("%s: objects[%d]: %d of %d %s are outside the cloud's full-order body (the farthest, %d, %.3g m "
                "away): each is carried by its nearest tet", s->path, k, e.outside, n, what, e.worst_point, e.worst_distance);
    *outside += e.outside;
    *worst = fmax(*worst, e.worst_distance);
    for (int p = 0; p < n; p++, ++*i) {
        const int *tet = out->mesh.tets + 4 * (size_t)(ov->t0 + e.tet[p]);
        for (int a = 0; a < 4; a++) {
            L->vertex[4 * (size_t)*i + a] = tet[a];
            L->weight[4 * (size_t)*i + a] = e.bary[4 * (size_t)p + a];
        }
        if (!offset) continue;
        double at[3];
        rk_scene_layout_at(L, out->mesh.X, *i, at);
        for (int d = 0; d < 3; d++) L->offset[3 * (size_t)*i + d] = P[3 * p + d] - at[d];
    }
    rk_embedding_free(&e);
    return 0;
}

/* The layout's entries for cloud k: its points embedded in its body's tets, then its contact
 * surface's vertices: the march surface's embedded likewise (full order's contact stays the body's
 * own boundary), or the voxel surface's, the body's vertices each with the offset from the body's
 * rest positions to where rk_scene_build has it. */
static int embed_cloud(const rk_scene *s, const rk_cloud_body *b, int k, int *i, rk_scene_sim *out, rk_error *err)
{
    rk_object_view ov;
    rk_scene_layout *L = &out->layout;
    if (rk_scene_object_view(out, k, &ov, err)) return -1;
    double far = 0;
    int rc = embed_places(s, k, &ov, b->X, b->n, "points", 0, i, out, &out->body_outside, &out->body_worst_distance, err);
    if (!rc && b->march)
        rc = embed_places(s, k, &ov, b->proxy_X, b->surface_nv, "contact surface vertices", 1, i, out,
                          &out->body_surface_outside, &far, err);
    free(ov.mesh.tets);
    if (rc || b->march) return rc;
    for (int c = 0; c < ov.mesh.nv; c++, ++*i) {
        direct(L, *i, ov.v0 + c);
        for (int d = 0; d < 3; d++) L->offset[3 * (size_t)*i + d] = b->proxy_X[3 * c + d] - ov.mesh.X[3 * c + d];
    }
    return 0;
}

int rk_cloud_bodies_finish(const rk_scene *s, rk_cloud_body *bodies, rk_scene_sim *out, rk_error *err)
{
    rk_scene_layout *L = &out->layout;
    int nv = out->mesh.nv;
    for (int k = 0; k < s->nobjects; k++) nv += bodies[k].n + bodies[k].surface_nv - bodies[k].corners;
    L->vertex = rk_calloc(4 * (size_t)nv, sizeof(int), err);
    L->weight = rk_calloc(4 * (size_t)nv, sizeof(double), err);
    L->offset = rk_calloc(3 * (size_t)nv, sizeof(double), err);
    if (!L->vertex || !L->weight || !L->offset) return -1;
    L->nv = nv;
    int i = 0;
    for (int k = 0; k < s->nobjects; k++) {
        const rk_cloud_body *b = &bodies[k];
        if (b->n == 0) {
            for (int v = out->object_first_vertex[k]; v < out->object_first_vertex[k + 1]; v++) direct(L, i++, v);
            continue;
        }
        if (match_mass(s, b, k, out, err) || embed_cloud(s, b, k, &i, out, err)) return -1;
        out->body_points += b->n;
        out->body_backed_off += b->rep.backed_off;
        out->body_min_volume_ratio = out->body_min_volume_ratio > 0 ? fmin(out->body_min_volume_ratio, b->rep.min_volume_ratio)
                                                                    : b->rep.min_volume_ratio;
    }
    return 0; /* (a point's offset stays 0: its barycentric coordinates give it back to rounding) */
}

void rk_scene_layout_at(const rk_scene_layout *L, const double *x, int j, double out[3])
{
    for (int d = 0; d < 3; d++) out[d] = L->offset[3 * (size_t)j + d];
    for (int a = 0; a < 4; a++) {
        double w = L->weight[4 * (size_t)j + a];
        if (w == 0) continue;
        const double *p = x + 3 * (size_t)L->vertex[4 * (size_t)j + a];
        for (int d = 0; d < 3; d++) out[d] += w * p[d];
    }
}

void rk_scene_layout_apply(const rk_scene_layout *L, const double *x, double *out)
{
    for (int j = 0; j < L->nv; j++) rk_scene_layout_at(L, x, j, out + 3 * (size_t)j);
}
