/* Point clouds at full order (issue 30): a cloud runs on its body (rk_scene_build_full_order: the
 * Kuhn tets of its voxels, the surface sqrt(3)/2 of the points' spacing from them, the points
 * embedded), alone or beside meshes. Lattice clouds at proxy_voxel = their spacing s, whose points
 * are the centres of cells of edge s, so the box they sample is known:
 *  - the body has the box's volume (within 1%) and weighs the cloud's mass (the reduced model's:
 *    rho V / n a point, V the occupancy volume, exact for even point counts) to 1e-9, and the
 *    layout gives back rk_scene_build's vertices at rest (points and contact surface) to 1e-12 m;
 *  - its tets take their nearest point's tag (regions by tag set their material);
 *  - clamped at one end under gravity (static), it sags as the same box meshed (rk_mesh_box) does,
 *    within 2%;
 *  - dropped at 0.5 m/s onto a meshed slab on a plane, no edge ever crosses a triangle (exact test,
 *    every frame), the surfaces stay apart, and it rests with its lowest points within s/2 (its
 *    contact surface under them) + 2 dhat of the slab's top; full order collides through the cloud's
 *    march surface embedded in its body (fom.h, rk_fom_contact_surface), so that surface, measured
 *    on its own as rk_scene_build has it (the reduced model's and the runtime's), never crosses the
 *    slab either (while full order collided through the body's boundary it crossed: 18 crossings
 *    over the 41 frames) and rests within 2 dhat of the slab's top;
 *  - romkit compare's rk_compare_scene on a cloud scene runs and reports a finite error. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "testlib.h"
#include "cloud_inside.h"
#include "compare/compare.h"
#include "pipeline/pipeline.h"

#define S 0.02 /* the lattices' spacing */

/* An nx x ny x nz lattice of spacing S, its first point at o + S / 2 (cells from o), into a scratch PLY. */
static const char *lattice(char *path, size_t cap, const char *name, int nx, int ny, int nz, const double o[3])
{
    const double c[3] = {o[0] + 0.5 * S, o[1] + 0.5 * S, o[2] + 0.5 * S};
    const char *p = tl_scratch(path, cap, name);
    return cloud_write_lattice(p, nx, ny, nz, S, c) == 0 ? p : NULL;
}

/* The cantilever: a 20 x 4 x 4 cloud (0.4 x 0.08 x 0.08 m) or that box meshed, clamped at x = 0 (the
 * box selects the mesh's x = 0 layer, the cloud's first layer of points and its body's x = 0 face). */
static int beam_scene(char *json, size_t n, const char *mesh)
{
    int w = snprintf(json, n,
                     "{\"objects\": [{\"mesh\": %s, \"material\": {\"model\": \"neohookean\", \"young\": 1e7, \"poisson\": 0.3,"
                     " \"density\": 1000}, \"fixed\": [{\"box\": [[-1, -1, -1], [0.011, 1, 1]]}]}],"
                     " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": 0.01, \"duration\": 0.01, \"static\": true},"
                     " \"rom\": {\"basis\": \"rkpm_skinning\", \"size\": 2, \"kernels\": 20, \"mesh_free\": {\"points\": 300}}}",
                     mesh);
    return w > 0 && (size_t)w < n ? 0 : -1;
}

TEST(a_lattice_clouds_body_has_its_mass_and_volume)
{
    char path[512], mesh[1024], json[4096];
    const double o[3] = {0, 0, 0};
    const char *ply = lattice(path, sizeof path, "beam.ply", 20, 4, 4, o);
    CHECK(ply != NULL, "lattice");
    snprintf(mesh, sizeof mesh, "{\"points\": \"%s\", \"proxy_voxel\": %g}", ply, S);
    CHECK(beam_scene(json, sizeof json, mesh) == 0, "scene");
    rk_error err = {{0}};
    rk_scene scene;
    rk_scene_sim sim, full;
    CHECK_OK(rk_scene_parse(json, "beam.json", &scene, &err));
    CHECK_OK(rk_scene_build(&scene, &sim, &err));
    CHECK_OK(rk_scene_build_full_order(&scene, &full, &err));
    double box = 0.4 * 0.08 * 0.08, mass = 0;
    for (int v = 0; v < full.mesh.nv; v++) mass += full.fem.vertex_mass[v];
    CHECK(full.mesh.nt == 6 * 320 && full.body_points == 320 && full.body_outside == 0, "%d tets, %d points, %d outside",
          full.mesh.nt, full.body_points, full.body_outside);
    CHECK(fabs(full.body_volume / box - 1) < 0.01, "the body's volume %g m^3, the box's %g", full.body_volume, box);
    CHECK(fabs(mass / full.body_mass - 1) < 1e-9 && fabs(full.body_mass / (1000 * box) - 1) < 1e-9,
          "the body weighs %.12g kg, the cloud %.12g kg, the box %.12g kg", mass, full.body_mass, 1000 * box);
    CHECK(full.body_min_volume_ratio >= 0.1, "the smallest tet has %g of its lattice volume", full.body_min_volume_ratio);
    CHECK(full.layout.nv == sim.mesh.nv, "the layout has %d vertices, the scene %d", full.layout.nv, sim.mesh.nv);
    double *x = calloc(3 * (size_t)full.layout.nv, sizeof(double)), worst = 0;
    rk_scene_layout_apply(&full.layout, full.mesh.X, x);
    for (int i = 0; i < 3 * sim.mesh.nv; i++) worst = fmax(worst, fabs(x[i] - sim.mesh.X[i]));
    CHECK(worst < 1e-12, "the layout at rest is %g m off the scene's vertices", worst);
    free(x);
    rk_scene_sim_free(&full);
    rk_scene_sim_free(&sim);
    rk_scene_free(&scene);
}

/* Per-point tags become the body's tets' (their nearest point's): a 12 x 4 x 4 lattice whose
 * points at x > 0.11 are tagged 2, that tag 10 times as dense: every tet of the body's far half is
 * 10 times as dense as every tet of its near half, and the body weighs the cloud (5.5 x uniform). */
TEST(a_clouds_point_tags_set_its_bodys_tets)
{
    char path[512], json[2048];
    const char *ply = tl_scratch(path, sizeof path, "tagged.ply");
    FILE *fp = fopen(ply, "w");
    CHECK(fp != NULL, "%s", ply);
    if (!fp) return;
    fprintf(fp, "ply\nformat ascii 1.0\nelement vertex 192\nproperty float x\nproperty float y\nproperty float z\n"
                "property int tag\nend_header\n");
    for (int i = 0; i < 12; i++)
        for (int j = 0; j < 4; j++)
            for (int k = 0; k < 4; k++) fprintf(fp, "%g %g %g %d\n", S * (i + 0.5), S * (j + 0.5), S * (k + 0.5), i < 6 ? 1 : 2);
    fclose(fp);
    snprintf(json, sizeof json,
             "{\"objects\": [{\"mesh\": {\"points\": \"%s\", \"proxy_voxel\": %g}, \"regions\": [{\"tag\": 2,"
             " \"material\": {\"density\": 10000}}], \"material\": {\"model\": \"neohookean\", \"young\": 1e5,"
             " \"poisson\": 0.3, \"density\": 1000}}], \"time\": {\"step\": 0.01, \"duration\": 0.01}}", ply, S);
    rk_error err = {{0}};
    rk_scene scene;
    rk_scene_sim sim;
    CHECK_OK(rk_scene_parse(json, "tagged.json", &scene, &err));
    CHECK_OK(rk_scene_build_full_order(&scene, &sim, &err));
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {0, 0};
    for (int t = 0; t < sim.mesh.nt; t++) {
        double cx = 0;
        for (int a = 0; a < 4; a++) cx += 0.25 * sim.mesh.X[3 * sim.mesh.tets[4 * t + a]];
        int far = cx > 0.12;
        lo[far] = fmin(lo[far], sim.materials[t].density), hi[far] = fmax(hi[far], sim.materials[t].density);
    }
    CHECK(lo[0] == hi[0] && lo[1] == hi[1] && fabs(lo[1] / lo[0] - 10) < 1e-12,
          "near half's densities %g..%g, far half's %g..%g", lo[0], hi[0], lo[1], hi[1]);
    double box = 12 * 4 * 4 * S * S * S;
    CHECK(fabs(sim.body_mass / (5500 * box) - 1) < 1e-9, "the cloud weighs %g kg, 5.5 x uniform is %g", sim.body_mass,
          5500 * box);
    rk_scene_sim_free(&sim);
    rk_scene_free(&scene);
}

typedef struct {
    const rk_scene_sim *sim;
    double sag;
} sag_ctx;

static int keep_sag(void *ctx, int step, rk_fom *fom, double seconds, rk_error *err)
{
    sag_ctx *c = ctx;
    for (int v = 0; v < c->sim->mesh.nv; v++) c->sag = fmax(c->sag, c->sim->mesh.X[3 * v + 1] - fom->x[3 * v + 1]);
    return 0;
}

static double static_sag(const char *json, rk_error *err, int *rc)
{
    rk_scene scene;
    rk_scene_sim sim;
    sag_ctx c = {&sim, 0};
    *rc = rk_scene_parse(json, "beam.json", &scene, err);
    if (*rc) return NAN;
    *rc = rk_scene_build_full_order(&scene, &sim, err);
    if (!*rc) {
        *rc = rk_scene_fom_run(&sim, NULL, "sag", keep_sag, &c, NULL, err);
        rk_scene_sim_free(&sim);
    }
    rk_scene_free(&scene);
    return c.sag;
}

TEST(a_clamped_cloud_sags_as_the_box_meshed)
{
    char path[512], mesh[1024], json[4096];
    const double o[3] = {0, 0, 0};
    const char *ply = lattice(path, sizeof path, "beam.ply", 20, 4, 4, o);
    rk_error err = {{0}};
    int rc;
    snprintf(mesh, sizeof mesh, "{\"points\": \"%s\", \"proxy_voxel\": %g}", ply, S);
    CHECK(ply && beam_scene(json, sizeof json, mesh) == 0, "scene");
    double cloud = static_sag(json, &err, &rc);
    CHECK(rc == 0, "cloud: %s", err.msg);
    CHECK(beam_scene(json, sizeof json, "{\"box\": {\"size\": [0.4, 0.08, 0.08], \"cells\": [20, 4, 4]}}") == 0, "scene");
    double box = static_sag(json, &err, &rc);
    CHECK(rc == 0, "box: %s", err.msg);
    printf("  sag: cloud %.6g m, box meshed %.6g m (%+.2f%%)\n", cloud, box, 100 * (cloud / box - 1));
    CHECK(box > 1e-3 && fabs(cloud / box - 1) < 0.02, "the cloud sags %g m, the box %g m", cloud, box);
}

typedef struct {
    const rk_scene_sim *sim;
    double *shown;
    int crossings, frames;
    double closest;
    rk_contact *scene;         /* the scene's own contact model (rk_scene_build's: the march surface) */
    int scene_crossings;
    double scene_closest;
} drop_ctx;

static int measure_drop(void *ctx, int step, rk_fom *fom, double seconds, rk_error *err)
{
    drop_ctx *c = ctx;
    int crossings;
    double d;
    if (rk_fom_contact_measure(fom, &crossings, &d, err)) return -1;
    c->crossings += crossings;
    c->closest = fmin(c->closest, d);
    c->frames++;
    rk_scene_layout_apply(&c->sim->layout, fom->x, c->shown);
    /* independently of full order's contact model: the scene's vertices where the run has them, on
     * the contact surface the reduced model and the runtime collide through */
    if (rk_contact_measure(c->scene, c->shown, &crossings, &d, err)) return -1;
    c->scene_crossings += crossings;
    c->scene_closest = fmin(c->scene_closest, d);
    return 0;
}

TEST(a_cloud_dropped_on_a_meshed_slab_never_crosses_and_rests_on_it)
{
    char path[512], json[4096];
    const double o[3] = {-0.05, 0.05, -0.05};
    const char *ply = lattice(path, sizeof path, "cube.ply", 5, 5, 5, o);
    CHECK(ply != NULL, "lattice");
    snprintf(json, sizeof json,
             "{\"objects\": ["
             "  {\"mesh\": {\"box\": {\"size\": [0.3, 0.04, 0.3], \"cells\": [3, 1, 3]}, \"translate\": [-0.15, 0.001, -0.15]},"
             "   \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000}},"
             "  {\"mesh\": {\"points\": \"%s\", \"proxy_voxel\": %g},"
             "   \"material\": {\"model\": \"neohookean\", \"young\": 5e4, \"poisson\": 0.4, \"density\": 1000},"
             "   \"velocity\": [0, -0.5, 0]}],"
             " \"gravity\": [0, -9.81, 0], \"damping\": {\"mass\": 5},"
             " \"obstacles\": [{\"plane\": {\"point\": [0, 0, 0], \"normal\": [0, 1, 0]}}],"
             " \"contact\": {\"dhat\": 0.002}, \"time\": {\"step\": 0.01, \"duration\": 0.4}}",
             ply, S);
    rk_error err = {{0}};
    rk_scene scene;
    rk_scene_sim sim;
    CHECK_OK(rk_scene_parse(json, "drop.json", &scene, &err));
    CHECK_OK(rk_scene_build_full_order(&scene, &sim, &err));
    CHECK(sim.options.contact_surface != NULL, "full order does not collide through the march surface");
    rk_scene_sim reduced;
    rk_contact own;
    CHECK_OK(rk_scene_build(&scene, &reduced, &err));
    CHECK(reduced.mesh.nv == sim.layout.nv, "the scene has %d vertices, the layout %d", reduced.mesh.nv, sim.layout.nv);
    const rk_fom_options *ro = &reduced.options;
    CHECK_OK(rk_contact_init(&own, &reduced.mesh, ro->object_first_vertex, ro->nobjects, ro->obstacles, ro->nobstacles,
                             &ro->contact, 1.0, &err));
    drop_ctx c = {&sim, calloc(3 * (size_t)sim.layout.nv, sizeof(double)), 0, 0, INFINITY, &own, 0, INFINITY};
    CHECK_OK(rk_scene_fom_run(&sim, NULL, "drop", measure_drop, &c, NULL, &err));
    /* the scene's vertices: the slab's 32, then the cloud's 125 points, then its contact surface;
     * the slab's top under the cloud: its top vertices at x, z = +-0.05, under the cube's edges */
    double top = -INFINITY, low = INFINITY;
    for (int v = 0; v < 32; v++)
        if (fabs(sim.mesh.X[3 * v]) < 0.06 && fabs(sim.mesh.X[3 * v + 2]) < 0.06 && sim.mesh.X[3 * v + 1] > 0.02)
            top = fmax(top, c.shown[3 * v + 1]);
    for (int v = 32; v < 32 + 125; v++) low = fmin(low, c.shown[3 * v + 1]);
    double surface = INFINITY; /* the contact surface: the march's vertices, after the points */
    for (int v = 32 + 125; v < sim.layout.nv; v++) surface = fmin(surface, c.shown[3 * v + 1]);
    printf("  %d frames: %d crossings, closest %.3g m; the lowest points %.4g m over the slab, the contact surface %.4g m\n",
           c.frames, c.crossings, c.closest, low - top, surface - top);
    CHECK(c.frames == 41 && c.crossings == 0 && c.closest > 0, "%d frames: %d crossings, closest %g m", c.frames,
          c.crossings, c.closest);
    printf("  the scene's own contact surface: %d crossings, closest %.3g m\n", c.scene_crossings, c.scene_closest);
    CHECK(c.scene_crossings == 0 && c.scene_closest > 0, "the march surface: %d crossings, closest %g m",
          c.scene_crossings, c.scene_closest);
    CHECK(surface - top > -2 * 0.002 && surface - top < 2 * 0.002, "the contact surface rests %g m over the slab's top",
          surface - top);
    CHECK(low - top > 0 && low - top < 0.5 * S + 2 * 0.002, "the lowest points are %g m over the slab's top",
          low - top);
    free(c.shown);
    rk_contact_free(&own);
    rk_scene_sim_free(&reduced);
    rk_scene_sim_free(&sim);
    rk_scene_free(&scene);
}

TEST(compare_measures_a_clouds_reduced_model_against_full_order)
{
    char path[512], mesh[1024], json[4096];
    const double o[3] = {0, 0, 0};
    const char *ply = lattice(path, sizeof path, "small.ply", 10, 4, 4, o);
    snprintf(mesh, sizeof mesh, "{\"points\": \"%s\", \"proxy_voxel\": %g}", ply, S);
    CHECK(ply && beam_scene(json, sizeof json, mesh) == 0, "scene");
    /* dynamic, 10 steps, softer: it swings */
    char *t = strstr(json, "\"time\"");
    CHECK(t != NULL, "time");
    snprintf(t, sizeof json - (size_t)(t - json), "\"time\": {\"step\": 0.01, \"duration\": 0.1},"
             " \"rom\": {\"basis\": \"rkpm_skinning\", \"size\": 2, \"kernels\": 20, \"mesh_free\": {\"points\": 300}}}");
    rk_error err = {{0}};
    rk_scene scene;
    rk_compare_result r;
    CHECK_OK(rk_scene_parse(json, "small.json", &scene, &err));
    CHECK_OK(rk_compare_scene(&scene, &r, &err));
    CHECK(r.nmethods == 1 && r.methods[0].failure[0] == 0, "the method failed: %s", r.nmethods ? r.methods[0].failure : "");
    CHECK(r.tets == 6 * 160 && r.steps == 10, "%d tets, %d steps", r.tets, r.steps);
    CHECK(isfinite(r.methods[0].normalized_mse) && r.methods[0].normalized_mse > 0 && r.methods[0].max_error_m < 0.05,
          "nMSE %g, max error %g m", r.methods[0].normalized_mse, r.methods[0].max_error_m);
    printf("  compare: nMSE %.3g, max error %.3g m\n", r.methods[0].normalized_mse, r.methods[0].max_error_m);
    rk_compare_result_free(&r);
    rk_scene_free(&scene);
}

int main(void)
{
    RUN(a_lattice_clouds_body_has_its_mass_and_volume);
    RUN(a_clouds_point_tags_set_its_bodys_tets);
    RUN(a_clamped_cloud_sags_as_the_box_meshed);
    RUN(a_cloud_dropped_on_a_meshed_slab_never_crosses_and_rests_on_it);
    RUN(compare_measures_a_clouds_reduced_model_against_full_order);
    return test_finish();
}
