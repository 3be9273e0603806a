/* make bench, full-order part: seconds per full-order step against tet count, with the share
 * spent in CHOLMOD's numeric factorization, and the seconds of rk_fem_init (rest shapes, masses,
 * the sparsity pattern and slot map) on the same mesh. Every case: a soft neo-Hookean object,
 * bottom 10% fixed, gravity, backward Euler at h = 0.01 s; one warm-up step, then case.steps
 * (3 to 10) single steps of one run, each timed.
 *
 * Spread (bench_cases.h): s_per_step is the median over those steps, s_per_step_min and
 * s_per_step_max the fastest and slowest step: the spread is over the steps of one run, not over
 * repeated runs (one run of the largest mesh already takes about a minute). fem_init_s is the
 * median of INIT_REPEATS runs of rk_fem_init (after the scene's own, which warms the caches),
 * fem_init_s_min and fem_init_s_max the fastest and slowest: the spread is over repeated runs.
 * Writes bench/results/fom_scaling.{csv,json}. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_cases.h"
#include "fom/fom.h"
#include "pipeline/pipeline.h"
#include "util/util.h"

#define INIT_REPEATS 5

/* rk_fem_init on the case's mesh and materials, INIT_REPEATS times. */
static int time_fem_init(const rk_scene_sim *sim, bench_stat *sec, rk_error *err)
{
    double t[INIT_REPEATS];
    for (int k = 0; k < INIT_REPEATS; k++) {
        rk_fem f;
        double t0 = rk_now();
        if (rk_fem_init(&f, &sim->mesh, sim->materials, err)) return -1;
        t[k] = rk_now() - t0;
        rk_fem_free(&f);
    }
    *sec = bench_stat_of(t, INIT_REPEATS);
    return 0;
}

int main(int argc, char **argv)
{
    const char *data = argc > 1 ? argv[1] : "tests/data/meshes";
    const char *out_dir = argc > 2 ? argv[2] : "bench/results";
    int quick = getenv("ROMKIT_BENCH_QUICK") != NULL;
    bench_case cases[9];
    int ncases = bench_cases(data, cases);
    if (quick) ncases = 4;
    FILE *csv, *json;
    if (bench_open_results(out_dir, "fom_scaling", "case,vertices,tets,steps,s_per_step,s_per_step_min,s_per_step_max,factor_share,newton_per_step,"
                           "fem_init_s,fem_init_s_min,fem_init_s_max", &csv, &json)) return 1;
    printf("%-14s %8s %8s %12s %20s %8s %8s %12s %20s\n", "case", "verts", "tets", "s/step", "(min..max)", "factor",
           "newton", "fem_init s", "(min..max)");
    for (int c = 0; c < ncases; c++) {
        rk_error err;
        rk_scene scene;
        rk_scene_sim sim;
        if (bench_scene(&cases[c], &scene, &sim, &err)) {
            fprintf(stderr, "bench_fom: %s: %s\n", cases[c].name, err.msg);
            return 1;
        }
        bench_stat init;
        if (time_fem_init(&sim, &init, &err)) {
            fprintf(stderr, "bench_fom: %s: rk_fem_init: %s\n", cases[c].name, err.msg);
            return 1;
        }
        /* Fix the lowest 10% (in y) as one prescribed group. */
        double lo = INFINITY, hi = -INFINITY;
        for (int v = 0; v < sim.mesh.nv; v++) {
            lo = fmin(lo, sim.mesh.X[3 * v + 1]);
            hi = fmax(hi, sim.mesh.X[3 * v + 1]);
        }
        rk_prescribed fixed = {.kind = RK_MOTION_FIXED};
        fixed.verts = malloc(sizeof(int) * (size_t)sim.mesh.nv);
        for (int v = 0; v < sim.mesh.nv; v++)
            if (sim.mesh.X[3 * v + 1] <= lo + 0.1 * (hi - lo)) fixed.verts[fixed.count++] = v;
        rk_fom_options opt = sim.options;
        opt.nprescribed = 1;
        opt.prescribed = &fixed;
        rk_fom fom;
        if (rk_fom_init(&fom, &sim.fem, &opt, &err) || rk_fom_step(&fom, &err)) {
            fprintf(stderr, "bench_fom: %s: %s\n", cases[c].name, err.msg);
            return 1;
        }
        int steps = cases[c].steps;
        double times[16];
        rk_fom_stats before = fom.stats;
        for (int s = 0; s < steps; s++) {
            double t0 = rk_now();
            if (rk_fom_step(&fom, &err)) {
                fprintf(stderr, "bench_fom: %s: %s\n", cases[c].name, err.msg);
                return 1;
            }
            times[s] = rk_now() - t0;
        }
        double factor = (fom.stats.seconds_factor - before.seconds_factor) /
                        (fom.stats.seconds_total - before.seconds_total);
        double newton = (double)(fom.stats.newton_iterations - before.newton_iterations) / steps;
        bench_stat t = bench_stat_of(times, steps);
        printf("%-14s %8d %8d %12.4g %9.4g..%-9.4g %7.0f%% %8.1f %12.4g %9.4g..%-9.4g\n", cases[c].name, sim.mesh.nv,
               sim.mesh.nt, BENCH_STAT3(t), 100 * factor, newton, BENCH_STAT3(init));
        fflush(stdout);
        fprintf(csv, "%s,%d,%d,%d,%.6g,%.6g,%.6g,%.4f,%.2f,%.6g,%.6g,%.6g\n", cases[c].name, sim.mesh.nv, sim.mesh.nt,
                steps, BENCH_STAT3(t), factor, newton, BENCH_STAT3(init));
        fprintf(json,
                "%s  {\"case\": \"%s\", \"vertices\": %d, \"tets\": %d, \"steps\": %d, \"seconds_per_step\": %.6g,"
                " \"seconds_per_step_min\": %.6g, \"seconds_per_step_max\": %.6g, \"factorization_share\": %.4f,"
                " \"newton_per_step\": %.2f, \"fem_init_seconds\": %.6g, \"fem_init_seconds_min\": %.6g,"
                " \"fem_init_seconds_max\": %.6g}\n",
                c ? "," : "", cases[c].name, sim.mesh.nv, sim.mesh.nt, steps, BENCH_STAT3(t), factor, newton,
                BENCH_STAT3(init));
        rk_fom_free(&fom);
        free(fixed.verts);
        rk_scene_sim_free(&sim);
        rk_scene_free(&scene);
    }
    fprintf(json, "]\n");
    fclose(csv);
    fclose(json);
    return 0;
}
