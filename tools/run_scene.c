/* romkit run --scene (run_scene.h). */
#include "run_scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "formats/rombin_read.h"

/* The asset's shown vertices rest where the scene's vertices they come from rest, up to the
 * asset's float rounding: otherwise SCENE is not the asset's. */
static int check_rest(const run_scene *o, const romrt_model *m, rk_error *err)
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
        int v = (int)o->source[i], nv = o->sim.mesh.nv;
        const double *s = v < nv ? &S[3 * (size_t)v] : &o->sim.embedded.X[3 * (size_t)(v - nv)];
        double d = fabs((double)X[3 * i] - s[0]) + fabs((double)X[3 * i + 1] - s[1]) + fabs((double)X[3 * i + 2] - s[2]);
        if (!(d <= tol)) {
            int bad = rk_fail(err, "--scene %s: the asset's shown vertex %d rests at (%g, %g, %g), its scene vertex %u at "
                                   "(%g, %g, %g): is this the scene the asset was built from?", o->path, i, (double)X[3 * i],
                              (double)X[3 * i + 1], (double)X[3 * i + 2], o->source[i], s[0], s[1], s[2]);
            free(X);
            return bad;
        }
    }
    free(X);
    return 0;
}

int run_scene_open(run_scene *o, const char *scene_path, const unsigned char *asset, size_t bytes, const romrt_model *m,
                   rk_error *err)
{
    memset(o, 0, sizeof *o);
    o->path = scene_path;
    if (rk_scene_load(scene_path, &o->scene, err)) return -1;
    o->have_scene = 1;
    if (rk_scene_build(&o->scene, &o->sim, err)) return -1;
    o->have_sim = 1;
    int nv = o->sim.mesh.nv;
    if (o->sim.fem.nv != nv)
        return rk_fail(err, "--scene %s: its simulation has %d vertices, its mesh %d", scene_path, o->sim.fem.nv, nv);
    rombin_file f;
    rombin_error e;
    rombin_chunk c;
    o->shown = (int)romrt_shown_count(m);
    if (rombin_open(&f, asset, bytes, NULL, &e) || !rombin_find(&f, ROMBIN_VMAP, &c) || c.raw < 4 * (uint64_t)o->shown)
        return rk_fail(err, "--scene: the asset has no VMAP chunk saying which scene vertex each shown one is");
    if (!(o->source = calloc((size_t)o->shown + 1, sizeof(uint32_t)))) return rk_fail(err, "out of memory");
    memcpy(o->source, c.data, 4 * (size_t)o->shown);
    for (int i = 0; i < o->shown; i++) /* a caged object's surface: the embedded vertices after the mesh's */
        if (o->source[i] >= (uint32_t)nv + (uint32_t)o->sim.embedded.nv)
            return rk_fail(err, "--scene %s has %d vertices%s; the asset's shown vertex %d comes from vertex %u: is this "
                           "the scene the asset was built from?", scene_path, nv,
                           o->sim.embedded.nv ? " and an embedded surface" : "", i, o->source[i]);
    /* the collision vertices' scene vertices: VMAP names every stored vertex, CVTX the stored ones
     * contact acts on (a point cloud's contact surface among them, stored but not shown) */
    size_t ncv = romrt_collision_count(m);
    rombin_chunk cv;
    if (ncv > 0 && rombin_find(&f, ROMBIN_CVTX, &cv) && cv.raw >= 4 * (uint64_t)ncv && cv.stored == cv.raw &&
        c.stored == c.raw) {
        if (!(o->collision_source = calloc(ncv + 1, sizeof(uint32_t)))) return rk_fail(err, "out of memory");
        o->ncollision = (int)ncv;
        for (size_t i = 0; i < ncv; i++) {
            uint32_t id = rombin_get_u32(cv.data + 4 * i), v = 0;
            /* an asset whose VMAP names the shown ones only: measured on those */
            if ((uint64_t)id * 4 + 4 > c.raw || (v = rombin_get_u32(c.data + 4 * (size_t)id)) >= (uint32_t)nv) {
                free(o->collision_source);
                o->collision_source = NULL, o->ncollision = 0;
                break;
            }
            o->collision_source[i] = v;
        }
    }
    return check_rest(o, m, err);
}

void run_scene_shown_at(const run_scene *o, const double *x, int i, double out[3])
{
    int v = (int)o->source[i], nv = o->sim.mesh.nv;
    if (v < nv) {
        for (int a = 0; a < 3; a++) out[a] = x[3 * (size_t)v + a];
        return;
    }
    /* its rest position moved by its tet's displacement there, as the asset's rows carry it (a vertex
     * outside the cage has clamped coordinates, which do not give back its rest position) */
    const rk_embedded_surface *E = &o->sim.embedded;
    const int *t = &o->sim.mesh.tets[4 * (size_t)E->tet[v - nv]];
    const double *b = &E->bary[4 * (size_t)(v - nv)], *X = o->sim.mesh.X;
    for (int a = 0; a < 3; a++) out[a] = E->X[3 * (size_t)(v - nv) + a];
    for (int k = 0; k < 4; k++)
        for (int a = 0; a < 3; a++) out[a] += b[k] * (x[3 * (size_t)t[k] + a] - X[3 * (size_t)t[k] + a]);
}

int run_scene_object_of(const run_scene *o, int v)
{
    int k = 0;
    while (k + 1 < o->scene.nobjects && v >= o->sim.object_first_vertex[k + 1]) k++;
    return k;
}

void run_scene_close(run_scene *o)
{
    if (o->have_sim) rk_scene_sim_free(&o->sim);
    if (o->have_scene) rk_scene_free(&o->scene);
    free(o->source), free(o->collision_source);
    memset(o, 0, sizeof *o);
}
