/* romkit run --scene (run_contact.h). The runtime gives the shown vertices only; the collision
 * surface is the scene mesh's boundary, so every collision vertex must be shown (asset.show
 * "surface", the default for meshes) and the rest of the mesh, which no contact measure reads,
 * stays at rest. */
#include "run_contact.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "formats/rombin_read.h"

/* The asset's shown vertices rest where the scene's vertices they come from rest, up to the
 * asset's float rounding: otherwise SCENE is not the asset's. */
static int check_rest(const run_contact *o, const romrt_model *m, const char *path, rk_error *err)
{
    romrt_real *X = calloc((size_t)3 * o->shown + 1, sizeof(romrt_real));
    if (!X) return rk_fail(err, "out of memory");
    romrt_error rerr;
    if (romrt_rest_positions(m, X, 3 * (size_t)o->shown, 3, &rerr)) {
        free(X);
        return rk_fail(err, "%s", rerr.message);
    }
    const double *S = o->sim.mesh.X;
    double tol = 1e-5 * (rk_points_diagonal(S, o->sim.mesh.nv) + 1e-300);
    for (int i = 0; i < o->shown; i++) {
        const double *s = &S[3 * (size_t)o->source[i]];
        double d = fabs((double)X[3 * i] - s[0]) + fabs((double)X[3 * i + 1] - s[1]) + fabs((double)X[3 * i + 2] - s[2]);
        if (!(d <= tol)) {
            int bad = rk_fail(err, "--scene %s: the asset's shown vertex %d rests at (%g, %g, %g), its scene vertex %u at "
                                   "(%g, %g, %g): is this the scene the asset was built from?", path, i, (double)X[3 * i],
                              (double)X[3 * i + 1], (double)X[3 * i + 2], o->source[i], s[0], s[1], s[2]);
            free(X);
            return bad;
        }
    }
    free(X);
    return 0;
}

int run_contact_open(run_contact *o, const char *scene_path, const unsigned char *asset, size_t bytes,
                     const romrt_model *m, rk_error *err)
{
    memset(o, 0, sizeof *o);
    rk_contact_tally_init(&o->tally);
    if (rk_scene_load(scene_path, &o->scene, err)) return -1;
    o->have_scene = 1;
    if (rk_scene_build(&o->scene, &o->sim, err)) return -1;
    o->have_sim = 1;
    const rk_fom_options *fo = &o->sim.options;
    if (!(fo->nobstacles > 0 || fo->nobjects > 1 || fo->contact.self))
        return rk_fail(err, "--scene %s: no obstacles, one object and no self-contact: no contact to measure", scene_path);
    int nv = o->sim.mesh.nv;
    if (o->sim.fem.nv != nv)
        return rk_fail(err, "--scene %s: its simulation has %d vertices, its mesh %d", scene_path, o->sim.fem.nv, nv);
    rombin_file f;
    rombin_error e;
    rombin_chunk c;
    o->shown = (int)romrt_shown_count(m);
    if (rombin_open(&f, asset, bytes, NULL, &e) || !rombin_find(&f, ROMBIN_VMAP, &c) || c.raw < 4 * (uint64_t)o->shown)
        return rk_fail(err, "--scene: the asset has no VMAP chunk saying which scene vertex each shown one is");
    o->source = calloc((size_t)o->shown + 1, sizeof(uint32_t));
    o->x = calloc((size_t)3 * nv + 1, sizeof(double));
    int *shown_of = calloc((size_t)nv + 1, sizeof(int));
    if (!o->source || !o->x || !shown_of) {
        free(shown_of);
        return rk_fail(err, "out of memory");
    }
    memcpy(o->source, c.data, 4 * (size_t)o->shown);
    memcpy(o->x, o->sim.mesh.X, sizeof(double) * 3 * (size_t)nv);
    for (int v = 0; v < nv; v++) shown_of[v] = -1;
    for (int i = 0; i < o->shown; i++) {
        if (o->source[i] >= (uint32_t)nv) {
            free(shown_of);
            return rk_fail(err, "--scene %s has %d vertices; the asset's shown vertex %d comes from vertex %u: is this the "
                           "scene the asset was built from?", scene_path, nv, i, o->source[i]);
        }
        shown_of[o->source[i]] = i;
    }
    if (check_rest(o, m, scene_path, err)) {
        free(shown_of);
        return -1;
    }
    /* the contact model as the full-order run builds it (fom/init.c): dhat 0 is 1e-3 of the
     * diagonal; kappa and the mass do not enter the measures */
    const rk_fem *fem = &o->sim.fem;
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
        if (o->sim.object_points && o->sim.object_points[obj] > 0)
            rc = rk_fail(err, "--scene %s: object %d is a point cloud, whose contact proxy (scene vertex %d on) the "
                              "asset stores but does not show: the runtime gives the shown vertices only, so its "
                              "contact is not measured", scene_path, obj, v);
        else
            rc = rk_fail(err, "--scene %s: scene vertex %d is on the collision surface but the asset does not show it "
                              "(contact is measured on the shown vertices: bake with asset.show \"surface\")",
                         scene_path, v);
    }
    free(shown_of);
    return rc;
}

int run_contact_frame(run_contact *o, double t, const romrt_real *xyz, rk_error *err)
{
    for (int i = 0; i < o->shown; i++)
        for (int a = 0; a < 3; a++) o->x[3 * (size_t)o->source[i] + a] = (double)xyz[3 * i + a];
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
    if (o->have_sim) rk_scene_sim_free(&o->sim);
    if (o->have_scene) rk_scene_free(&o->scene);
    free(o->source);
    free(o->x);
    memset(o, 0, sizeof *o);
}
