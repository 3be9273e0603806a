/* Several point-cloud objects in the reduced simulator: each gets its own RKPM skinning basis (the
 * scene is not one body: there is no single constant weight), and they collide through the contact
 * stage on their voxel proxies. A slab of points lies on a plane and a smaller block of points falls
 * onto it. On every frame: no exact crossing between the proxies (rk_rom_contact_measure) and no
 * point of either cloud inside the other's proxy (ray parity against its deformed triangles,
 * cloud_inside.h); and the block does come to rest on the slab, not short of it. */
#include <math.h>
#include <stdio.h>

#include "testlib.h"
#include "cloud_inside.h"
#include "pipeline/pipeline.h"
#include "pipeline/method_fixed.h"

TEST(a_block_of_points_lands_on_a_slab_of_points)
{
    char slab_path[512], block_path[512];
    const char *slab = tl_scratch(slab_path, sizeof slab_path, "slab.ply"),
               *block = tl_scratch(block_path, sizeof block_path, "block.ply");
    char json[2048];
    CHECK(cloud_slab_block_scene(json, sizeof json, slab, block, 0.2, "") == 0, "the clouds' scene");
    rk_error err = {{0}};
    rk_scene scene;
    rk_scene_sim sim;
    rk_scene_rom R;
    rk_rom s;
    CHECK_OK(rk_scene_parse(json, "clouds.json", &scene, &err));
    CHECK_OK(rk_scene_build(&scene, &sim, &err));
    CHECK_OK(rk_scene_rom_build(&scene, &sim, &scene.entries[0], NULL, 0, &R, &err));
    CHECK(R.basis.nparts == 2 && R.basis.m == 6 && R.model.r == 72, "%d parts, %d weights, r = %d", R.basis.nparts,
          R.basis.m, R.model.r);
    CHECK(R.model.has_contact && sim.cloud_points == 363 + 125, "contact %d, %d points", R.model.has_contact, sim.cloud_points);
    /* each object's weights vanish on the other */
    double leak = 0;
    for (int j = 0; j < R.basis.m; j++)
        for (int v = 0; v < sim.mesh.nv; v++) {
            int obj = v >= sim.object_first_vertex[1], part = j >= R.basis.part_handle[1];
            if (obj != part) leak = fmax(leak, fabs(R.basis.W[(size_t)v + (size_t)sim.mesh.nv * j]));
        }
    CHECK(leak == 0, "a weight of one object is %g on the other", leak);
    int *tris = NULL, nf = 0;
    CHECK_OK(rk_mesh_boundary(&sim.mesh, &tris, &nf, &err));
    cloud_surface surf[2];
    CHECK(cloud_surface_init(&surf[0], tris, nf, 0, sim.object_first_vertex[1]) == 0 &&
          cloud_surface_init(&surf[1], tris, nf, sim.object_first_vertex[1], sim.mesh.nv) == 0, "surfaces");
    CHECK_OK(rk_rom_init(&s, &R.model, NULL, NULL, &err));
    int ndof = 3 * sim.mesh.nv, worst_inter = 0, inside = 0, frames = 50;
    double *x = calloc((size_t)ndof, sizeof(double)), min_d = INFINITY, block_low = INFINITY, slab_top = -INFINITY;
    for (int f = 1; f <= frames; f++) {
        CHECK_OK(rk_rom_step(&s, &err));
        int inter;
        double d;
        CHECK_OK(rk_rom_contact_measure(&s, &inter, &d, &err));
        worst_inter = inter > worst_inter ? inter : worst_inter;
        min_d = fmin(min_d, d);
        rk_rom_positions(R.basis.U, ndof, R.model.r, sim.mesh.X, s.q, x);
        /* every cloud point against the other object's proxy */
        for (int k = 0; k < 2; k++) cloud_surface_box(&surf[k], x);
        for (int k = 0; k < 2; k++) {
            int v0 = sim.object_first_vertex[k], n = sim.object_points[k];
            for (int v = v0; v < v0 + n; v++) inside += cloud_surface_inside(&surf[1 - k], x, x + 3 * v);
        }
        if (f == frames) {
            for (int v = sim.object_first_vertex[1]; v < sim.object_first_vertex[1] + sim.object_points[1]; v++)
                block_low = fmin(block_low, x[3 * v + 1]);
            for (int v = 0; v < sim.object_points[0]; v++) slab_top = fmax(slab_top, x[3 * v + 1]);
        }
    }
    printf("# %d frames: %d exact crossings at most, smallest distance %.3g m, %d point-in-other events; at the end the "
           "block's lowest point %.4f m over the slab's highest %.4f m\n",
           frames, worst_inter, min_d, inside, block_low, slab_top);
    CHECK(worst_inter == 0, "%d crossings", worst_inter);
    CHECK(min_d > 0, "smallest distance %g", min_d);
    CHECK(inside == 0, "%d times a point was inside the other object", inside);
    CHECK(block_low > slab_top && block_low < slab_top + 0.1, "the block rests at %g over the slab's %g", block_low, slab_top);
    free(x);
    free(tris);
    cloud_surface_free(&surf[0]);
    cloud_surface_free(&surf[1]);
    rk_rom_free(&s);
    rk_scene_rom_free(&R);
    rk_scene_sim_free(&sim);
    rk_scene_free(&scene);
    remove(slab);
    remove(block);
}

int main(void)
{
    RUN(a_block_of_points_lands_on_a_slab_of_points);
    return test_finish();
}
