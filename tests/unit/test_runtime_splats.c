/* The FreeForm paper's Gaussian splats end to end: the donut capture (45,624 splats) simulated
 * mesh-free, dropped onto a plane by the runtime, its splats written at every frame as 3DGS PLY
 * (what romkit run --splats writes: romrt_deformation_gradients and rk_splats_write) and read back
 * as a viewer would: unit quaternions, finite scales and values, every attribute but the moved ones
 * unchanged, and no splat centre, nor any vertex of the contact proxy, on or behind the plane on
 * any frame. */
#include <math.h>

#include "runtime_fixture.h"

#define PLANE_Y (-0.15)
#define ASSET_REAL ROMBIN_REAL_F32

static const char *donut_drop =
    "{\"objects\": [{\"mesh\": {\"points\": \"tests/data/meshes/donut_3dgs.ply\"},"
    " \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000}}],"
    " \"gravity\": [0, -9.81, 0], \"obstacles\": [{\"plane\": {\"point\": [0, -0.15, 0], \"normal\": [0, 1, 0]}}],"
    " \"contact\": {\"dhat\": 0.005}, \"time\": {\"step\": 0.01, \"duration\": 0.3},"
    " \"rom\": {\"basis\": \"rkpm_skinning\", \"size\": 4, \"kernels\": 300, \"integration_points\": 10000,"
    "  \"mesh_free\": {\"points\": 2000}}}";

TEST(donut_splats_drop_onto_a_plane_and_read_back)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture f;
    CHECK_OK(rt_fixture_open(&f, donut_drop, ASSET_REAL, &err, &rerr));
    rk_splats src;
    CHECK_OK(rk_splats_read("tests/data/meshes/donut_3dgs.ply", &src, &err));
    int n = romrt_shown_count(f.m), steps = 30, lowest_frame = -1;
    CHECK(n == src.n, "shown %d, splats %d", n, src.n);
    romrt_real *xyz = calloc(3 * (size_t)n, sizeof *xyz), *Fr = calloc(9 * (size_t)n, sizeof *Fr);
    double *x = calloc(3 * (size_t)n, sizeof *x), *F = calloc(9 * (size_t)n, sizeof *F), lowest = INFINITY;
    double worst_q = 0, proxy_lowest = INFINITY;
    int bad_values = 0, moved_other = 0;
    char path_buf[512];
    const char *path = tl_scratch(path_buf, sizeof path_buf, "splats_frame.ply");
    for (int k = 0; k <= steps; k++) {
        if (k) CHECK(romrt_step(f.m, &rerr) == ROMRT_OK, "step %d: %s", k, rerr.message);
        CHECK(romrt_positions(f.m, xyz, 3 * (size_t)n, 3, NULL) == ROMRT_OK && romrt_deformation_gradients(f.m, Fr, 9 * (size_t)n, NULL) == ROMRT_OK, "F");
        for (int i = 0; i < 3 * n; i++) x[i] = (double)xyz[i];
        for (int i = 0; i < 9 * n; i++) F[i] = (double)Fr[i];
        CHECK_OK(rk_splats_write(path, &src, x, F, &err));
        rk_splats back;
        CHECK_OK(rk_splats_read(path, &back, &err));
        CHECK(back.n == n && back.nprop == src.nprop, "frame %d: %d splats, %d properties", k, back.n, back.nprop);
        for (int i = 0; i < n; i++) {
            const double *v = back.values + (size_t)i * back.nprop, *v0 = src.values + (size_t)i * src.nprop;
            double q2 = 0;
            for (int c = 0; c < 4; c++) q2 += v[back.rot[c]] * v[back.rot[c]];
            worst_q = fmax(worst_q, fabs(sqrt(q2) - 1));
            for (int p = 0; p < back.nprop; p++) bad_values += !isfinite(v[p]);
            /* opacity and colour have no reason to change */
            moved_other += v[back.opacity] != v0[src.opacity] || v[back.f_dc[0]] != v0[src.f_dc[0]];
            double y = v[back.xyz[1]];
            if (y < lowest) lowest = y, lowest_frame = k;
        }
        /* the contact proxy's boundary (the collision vertices) stays in front of the plane, in double */
        int ndof = 3 * f.sim.mesh.nv, r = f.R.basis.r;
        romrt_real q[256];
        CHECK(r <= 256 && romrt_reduced_coordinates(f.m, q, r, NULL) == ROMRT_OK, "q");
        for (int c = 0; c < f.R.model.ncv; c++) {
            int v = f.R.model.cv[c];
            double y = f.sim.mesh.X[3 * v + 1];
            for (int j = 0; j < r; j++) y += f.R.basis.U[(size_t)ndof * j + 3 * v + 1] * (double)q[j];
            proxy_lowest = fmin(proxy_lowest, y);
        }
        rk_splats_free(&back);
    }
    remove(path);
    printf("# %d splats, %d frames: lowest centre %.4f m (frame %d), lowest proxy vertex %.4f m, plane at %.2f;"
           " |q| - 1 at most %.2g\n", n, steps + 1, lowest, lowest_frame, proxy_lowest, PLANE_Y, worst_q);
    CHECK(bad_values == 0, "%d non-finite values", bad_values);
    CHECK(worst_q < 1e-5, "quaternion norm off by %g", worst_q);
    CHECK(moved_other == 0, "%d splats changed opacity or colour", moved_other);
    CHECK(lowest > PLANE_Y, "a splat centre reached %g, behind the plane at %g", lowest, PLANE_Y);
    CHECK(proxy_lowest > PLANE_Y, "a proxy vertex reached %g, behind the plane at %g", proxy_lowest, PLANE_Y);
    CHECK(proxy_lowest < PLANE_Y + 0.02, "the donut never reached the plane (lowest proxy vertex %g)", proxy_lowest);
    free(xyz), free(Fr), free(x), free(F);
    rk_splats_free(&src);
    rt_fixture_close(&f);
}

int main(void)
{
    RUN(donut_splats_drop_onto_a_plane_and_read_back);
    return test_finish();
}
