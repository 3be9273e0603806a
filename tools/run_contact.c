/* romkit run --scene (run_contact.h). The collision surface is the scene mesh's boundary: its
 * vertices are the asset's shown vertices (asset.show "surface", the default for meshes) or its
 * collision vertices (CVTX, romrt_collision_positions: a point cloud's contact surface, its proxy's
 * corners, stored but not shown), each placed at its scene vertex (VMAP); the rest of the mesh,
 * which no contact measure reads, stays at rest. */
#include "run_contact.h"

#include <stdlib.h>
#include <string.h>

int run_contact_open(run_contact *o, const run_scene *S, rk_error *err)
{
    memset(o, 0, sizeof *o);
    rk_contact_tally_init(&o->tally);
    o->S = S;
    const rk_fom_options *fo = &S->sim.options;
    if (!run_contact_wanted(S))
        return rk_fail(err, "--scene %s: no obstacles, one object and no self-contact: no contact to measure", S->path);
    int nv = S->sim.mesh.nv;
    o->x = calloc((size_t)3 * nv + 1, sizeof(double));
    int *shown_of = calloc((size_t)nv + 1, sizeof(int));
    if (!o->x || !shown_of) {
        free(shown_of);
        return rk_fail(err, "out of memory");
    }
    memcpy(o->x, S->sim.mesh.X, sizeof(double) * 3 * (size_t)nv);
    o->cxyz = calloc((size_t)3 * S->ncollision + 1, sizeof(romrt_real));
    if (!o->cxyz) {
        free(shown_of);
        return rk_fail(err, "out of memory");
    }
    for (int v = 0; v < nv; v++) shown_of[v] = -1;
    for (int i = 0; i < S->ncollision; i++) shown_of[S->collision_source[i]] = i;
    for (int i = 0; i < S->shown; i++) /* (a caged object's embedded surface is not the contact surface) */
        if (S->source[i] < (uint32_t)nv) shown_of[S->source[i]] = i;
    /* the contact model as the full-order run builds it (fom/init.c): dhat 0 is 1e-3 of the
     * diagonal; kappa and the mass do not enter the measures */
    const rk_fem *fem = &S->sim.fem;
    rk_contact_options co = fo->contact;
    if (co.dhat == 0) co.dhat = 1e-3 * rk_points_diagonal(fem->X, fem->nv);
    rk_mesh view = {.nv = fem->nv, .nt = fem->nt, .X = (double *)fem->X, .tets = (int *)fem->tets,
                    .nghost = fem->nghost, .ghost = (int *)fem->ghost};
    int rc = rk_contact_init(&o->contact, &view, fo->object_first_vertex, fo->nobjects, fo->obstacles, fo->nobstacles,
                             &co, 1.0, err);
    o->have_contact = rc == 0;
    for (int i = 0; !rc && i < o->contact.nv; i++) {
        int v = o->contact.vertex[i], obj = o->contact.object[v];
        if (shown_of[v] >= 0) continue;
        if (S->sim.object_points && S->sim.object_points[obj] > 0)
            rc = rk_fail(err, "--scene %s: object %d is a point cloud, whose contact surface (scene vertex %d on) the "
                              "asset neither shows nor stores as collision vertices (CVTX, VMAP over them): bake "
                              "with the default asset.colliders", S->path, obj, v);
        else
            rc = rk_fail(err, "--scene %s: scene vertex %d is on the collision surface but the asset neither shows it "
                              "nor stores it as a collision vertex (contact is measured on those: bake with asset.show "
                              "\"surface\" or the default asset.colliders)", S->path, v);
    }
    free(shown_of);
    return rc;
}

int run_contact_wanted(const run_scene *S)
{
    const rk_fom_options *fo = &S->sim.options;
    return fo->nobstacles > 0 || fo->nobjects > 1 || fo->contact.self;
}

int run_contact_frame(run_contact *o, const romrt_model *m, double t, const romrt_real *xyz, rk_error *err)
{
    const run_scene *S = o->S;
    romrt_error rerr;
    if (S->ncollision > 0 && romrt_collision_positions(m, o->cxyz, 3 * (size_t)S->ncollision, &rerr) != ROMRT_OK)
        return rk_fail(err, "runtime: %s", rerr.message);
    for (int i = 0; i < S->ncollision; i++)
        for (int a = 0; a < 3; a++) o->x[3 * (size_t)S->collision_source[i] + a] = (double)o->cxyz[3 * i + a];
    for (int i = 0; i < S->shown; i++)
        for (int a = 0; S->source[i] < (uint32_t)S->sim.mesh.nv && a < 3; a++)
            o->x[3 * (size_t)S->source[i] + a] = (double)xyz[3 * i + a];
    rk_contact_set_time(&o->contact, t);
    int crossings;
    double closest;
    if (rk_contact_measure(&o->contact, o->x, &crossings, &closest, err)) return -1;
    rk_contact_tally_add(&o->tally, crossings, closest);
    return 0;
}

void run_contact_close(run_contact *o)
{
    if (o->have_contact) rk_contact_free(&o->contact);
    free(o->x), free(o->cxyz);
    memset(o, 0, sizeof *o);
}
