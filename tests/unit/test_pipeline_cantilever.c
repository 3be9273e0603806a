/* Cantilever under its own weight, linear material, static solve, against Timoshenko beam
 * theory: tip deflection  q L^4 / (8 E I) + q L^2 / (2 kappa G A)  with q = rho g A and the
 * shear coefficient of a rectangle kappa = 10 (1 + nu) / (12 + 11 nu).
 * nu = 0, so the 3D model and beam theory describe the same thing: with nu > 0 the clamped face
 * also stops the lateral contraction, which beam theory ignores (nu = 0.3 measured 2% stiffer at
 * 120k tets, not a discretization error). Linear tets are too stiff in bending on coarse meshes,
 * and what they need is resolution along the length and in the bending direction (y); with
 * nu = 0 nothing varies across z, so two cells there suffice. The error must shrink at every
 * refinement and end within 2%. */
#include "scene_run.h"

#define L 4.0
#define H 0.4
#define E 1e9
#define NU 0.0
#define RHO 1000.0
#define G_ACC 9.81

static double timoshenko_tip(void)
{
    double A = H * H, I = H * H * H * H / 12.0, q = RHO * G_ACC * A;
    double G = E / (2 * (1 + NU)), kappa = 10 * (1 + NU) / (12 + 11 * NU);
    return q * L * L * L * L / (8 * E * I) + q * L * L / (2 * kappa * G * A);
}

/* Mean downward displacement of the free end face. */
static double tip_deflection(int n_long, int n_bend, rk_error *err, int *ok)
{
    char json[1024];
    snprintf(json, sizeof json,
             "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [%g, %g, %g], \"cells\": [%d, %d, %d]}},"
             " \"material\": {\"model\": \"linear\", \"young\": %g, \"poisson\": %g, \"density\": %g},"
             " \"fixed\": [{\"box\": [[-1, -1, -1], [0, 1, 1]]}]}],"
             " \"gravity\": [0, %g, 0], \"time\": {\"static\": true}}",
             L, H, H, n_long, n_bend, 2, E, NU, RHO, -G_ACC);
    scene_run r;
    *ok = 0;
    if (scene_run_open(&r, json, err)) return 0;
    if (rk_fom_static(&r.fom, err)) {
        scene_run_close(&r);
        return 0;
    }
    double sum = 0;
    int count = 0;
    for (int v = 0; v < r.sim.mesh.nv; v++)
        if (r.sim.mesh.X[3 * v] > L - 1e-9) {
            sum += r.sim.mesh.X[3 * v + 1] - r.fom.x[3 * v + 1];
            count++;
        }
    scene_run_close(&r);
    *ok = count > 0;
    return sum / count;
}

TEST(cantilever_converges_to_timoshenko)
{
    rk_error err;
    const int cross[] = {1, 2, 4, 8}; /* cells across y: 2, 4, 8, 16 */
    const int levels = sizeof cross / sizeof cross[0];
    double exact = timoshenko_tip(), prev_err = INFINITY;
    printf("# cantilever %gx%gx%g m, E %g Pa, nu %g: Timoshenko tip deflection %.6e m\n", L, H, H, E, NU, exact);
    printf("# %8s %8s %14s %10s\n", "cells", "tets", "tip (m)", "error");
    for (int k = 0; k < levels; k++) {
        int n = cross[k], ok;
        double tip = tip_deflection(25 * n, 2 * n, &err, &ok);
        CHECK(ok, "static solve failed at %d cells across: %s", n, err.msg);
        double rel = fabs(tip - exact) / exact;
        printf("# %3dx%dx2 %8d %14.6e %9.2f%%\n", 25 * n, 2 * n, 25 * n * 2 * n * 2 * 6, tip, 100 * rel);
        CHECK(rel < prev_err, "error grew from %.3g to %.3g when refining to %d cells across", prev_err, rel, n);
        prev_err = rel;
    }
    CHECK(prev_err < 0.02, "finest mesh is %.2f%% off beam theory (must be within 2%%)", 100 * prev_err);
}

int main(void)
{
    RUN(cantilever_converges_to_timoshenko);
    return test_finish();
}
