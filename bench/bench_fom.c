/* make bench, full-order part: seconds per full-order step against tet count, with the share
 * spent in CHOLMOD's numeric factorization. Every case: a soft neo-Hookean object, bottom 10%
 * fixed, gravity, backward Euler at h = 0.01 s; one warm-up step, then case.steps (3 to 10)
 * single steps of one run, each timed.
 *
 * Spread (bench_cases.h): s_per_step is the median over those steps, s_per_step_min and
 * s_per_step_max the fastest and slowest step: the spread is over the steps of one run, not over
 * repeated runs (one run of the largest mesh already takes about a minute).
 * Writes bench/results/fom_scaling.{csv,json}. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_cases.h"
#include "fom/fom.h"
#include "pipeline/pipeline.h"
#include "util/timer.h"

int main(int argc, char **argv)
{
    const char *data = argc > 1 ? argv[1] : "tests/data/meshes";
    const char *out_dir = argc > 2 ? argv[2] : "bench/results";
    int quick = getenv("ROMKIT_BENCH_QUICK") != NULL;
    bench_case cases[9];
    int ncases = bench_cases(data, cases);
    if (quick) ncases = 4;
    FILE *csv, *json;
    if (bench_open_results(out_dir, "fom_scaling", "case,vertices,tets,steps,s_per_step,s_per_step_min,s_per_step_max,factor_share,newton_per_step", &csv, &json)) return 1;
    printf("%-14s %8s %8s %12s %20s %8s %8s\n", "case", "verts", "tets", "s/step", "(min..max)", "factor", "newton");
    for (int c = 0; c < ncases; c++) {
        rk_error err;
        rk_scene scene;
        rk_scene_sim sim;
        if (bench_scene(&cases[c], &scene, &sim, &err)) {
            fprintf(stderr, "bench_fom: %s: %s\n", cases[c].name, err.msg);
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
        printf("%-14s %8d %8d %12.4g %9.4g..%-9.4g %7.0f%% %8.1f\n", cases[c].name, sim.mesh.nv, sim.mesh.nt,
               BENCH_STAT3(t), 100 * factor, newton);
        fflush(stdout);
        fprintf(csv, "%s,%d,%d,%d,%.6g,%.6g,%.6g,%.4f,%.2f\n", cases[c].name, sim.mesh.nv, sim.mesh.nt, steps,
                BENCH_STAT3(t), factor, newton);
        fprintf(json,
                "%s  {\"case\": \"%s\", \"vertices\": %d, \"tets\": %d, \"steps\": %d, \"seconds_per_step\": %.6g,"
                " \"seconds_per_step_min\": %.6g, \"seconds_per_step_max\": %.6g, \"factorization_share\": %.4f,"
                " \"newton_per_step\": %.2f}\n",
                c ? "," : "", cases[c].name, sim.mesh.nv, sim.mesh.nt, steps, BENCH_STAT3(t), factor, newton);
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
