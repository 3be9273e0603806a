/* make bench, reduced-model part: per-step speed-up of the reduced model with cubature over the
 * full-order model, on every tet mesh of the bench set, at r = 8, 16, 32, 64 linear modes. Every
 * case: the soft neo-Hookean object of bench_scene, bottom 10% (in y) fixed as one prescribed
 * group, gravity, backward Euler at h = 0.01 s.
 *
 *   full order   one untimed warm-up step, then the median of case.steps single steps
 *   basis        64 linear modes once per mesh; r uses the first r columns
 *   exact        the reduced model integrating every element: median of 5 steps (after 1 warm-up)
 *   cubature     trained (An et al. 2008, tolerance 0.01, 40 poses: the projected full-order
 *                frames and random ones) on the exact model; median of 20 steps (after 1 warm-up)
 *
 * box_100k and box_200k are skipped when their estimated cost (the last case's seconds scaled by
 * the tet ratio to the power 1.2) would take the run past BUDGET_SECONDS. At the end, for each r:
 * cubature s/step on dinosaur_50k (or, had it not run, the largest 50k+ tet mesh run) over
 * armadillo_4k, the check that the per-step cost does not grow with the tet count (claim: below
 * 2). Writes bench/results/rom.{csv,json}. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "basis/basis.h"
#include "bench_cases.h"
#include "cubature/cubature.h"
#include "fom/fom.h"
#include "rom/rom.h"
#include "scene/scene.h"
#include "util/timer.h"

#define NR 4
#define MAX_R 64
#define ROM_STEPS 20
#define EXACT_STEPS 5
#define BUDGET_SECONDS 360.0
#define CUBATURE_SAMPLE 1000 /* candidates scored per greedy iteration (the default) */

static const int R_VALUES[NR] = {8, 16, 32, 64};

typedef struct {
    const char *name;
    int nt;
    double cub_s[NR];
} case_result;

/* Median seconds of `steps` single reduced steps after one untimed warm-up step. */
static int time_rom(rk_rom_model *m, int steps, double *median, rk_rom_stats *stats, rk_error *err)
{
    rk_rom rom;
    double t[ROM_STEPS];
    if (rk_rom_init(&rom, m, NULL, NULL, err)) return -1;
    if (rk_rom_step(&rom, err)) {
        rk_rom_free(&rom);
        return -1;
    }
    rk_rom_stats before = rom.stats;
    for (int s = 0; s < steps; s++) {
        double t0 = rk_now();
        if (rk_rom_step(&rom, err)) {
            rk_rom_free(&rom);
            return -1;
        }
        t[s] = rk_now() - t0;
    }
    *stats = rom.stats;
    stats->steps -= before.steps;
    stats->newton_iterations -= before.newton_iterations;
    stats->unconverged_steps -= before.unconverged_steps;
    *median = bench_median(t, steps);
    rk_rom_free(&rom);
    return 0;
}

int main(int argc, char **argv)
{
    const char *data = argc > 1 ? argv[1] : "tests/data/meshes";
    const char *out_dir = argc > 2 ? argv[2] : "bench/results";
    double start = rk_now();
    bench_case cases[9];
    int ncases = bench_cases(data, cases);
    if (getenv("ROMKIT_BENCH_QUICK")) ncases = 4;
    FILE *csv, *json;
    if (bench_open_results(out_dir, "rom",
                           "case,vertices,tets,r,cubature_points,cubature_rel_error,cubature_reached,training_poses,"
                           "training_s,fom_s_per_step,exact_s_per_step,cubature_s_per_step,speedup_fom_over_cubature,"
                           "cubature_newton_per_step",
                           &csv, &json))
        return 1;
    printf("%-14s %7s %3s %6s %9s %9s %11s %11s %11s %9s\n", "case", "tets", "r", "points", "cub err", "train s",
           "fom s/step", "exact s/st", "cub s/step", "speed-up");
    fflush(stdout);
    case_result res[9];
    int nres = 0, nrows = 0, nfail_tol = 0;
    double last_seconds = 0;
    int last_nt = 0;
    for (int c = 0; c < ncases; c++) {
        double case_start = rk_now();
        const char *name = cases[c].name;
        rk_error err;
        rk_scene scene;
        rk_scene_sim sim;
        if (bench_scene(&cases[c], &scene, &sim, &err)) goto fail;
        int nv = sim.mesh.nv, nt = sim.mesh.nt, ndof = 3 * nv;
        if (nv < 1 || nt < 1) {
            rk_fail(&err, "empty mesh (%d vertices, %d tets)", nv, nt);
            goto fail;
        }
        /* Only the two largest boxes may be skipped: their cost estimated from the last case run,
         * a little worse than linear in the tet count. */
        if ((!strcmp(name, "box_100k") || !strcmp(name, "box_200k")) && last_nt > 0) {
            double elapsed = rk_now() - start;
            double estimate = last_seconds * pow((double)nt / last_nt, 1.2);
            if (elapsed + estimate > BUDGET_SECONDS) {
                printf("%-14s %7d  skipped: estimated %.0f s (from %.0f s for %d tets) after %.0f s would exceed %.0f s\n",
                       name, nt, estimate, last_seconds, last_nt, elapsed, BUDGET_SECONDS);
                fflush(stdout);
                rk_scene_sim_free(&sim);
                rk_scene_free(&scene);
                continue;
            }
        }

        /* Bottom 10% in y fixed: the flags for the basis and one prescribed group for both models
         * (in a copy of sim.options: rk_scene_sim_free frees sim.options.prescribed). */
        double lo = INFINITY, hi = -INFINITY;
        for (int v = 0; v < nv; v++) {
            lo = fmin(lo, sim.mesh.X[3 * v + 1]);
            hi = fmax(hi, sim.mesh.X[3 * v + 1]);
        }
        unsigned char *fixed_flags = calloc((size_t)nv, 1);
        rk_prescribed fixed = {.kind = RK_MOTION_FIXED};
        fixed.verts = malloc(sizeof(int) * (size_t)nv);
        for (int v = 0; v < nv; v++)
            if (sim.mesh.X[3 * v + 1] <= lo + 0.1 * (hi - lo)) {
                fixed_flags[v] = 1;
                fixed.verts[fixed.count++] = v;
            }
        rk_fom_options opt = sim.options;
        opt.nprescribed = 1;
        opt.prescribed = &fixed;

        /* 1. Full order: warm-up step, then case.steps timed ones; every frame kept as a snapshot. */
        int steps = cases[c].steps, nframes = steps + 1;
        double *frames = malloc(sizeof(double) * (size_t)ndof * nframes);
        double fom_t[16];
        rk_fom fom;
        if (rk_fom_init(&fom, &sim.fem, &opt, &err)) goto fail;
        if (rk_fom_step(&fom, &err)) goto fail;
        memcpy(frames, fom.x, sizeof(double) * ndof);
        for (int s = 0; s < steps; s++) {
            double t0 = rk_now();
            if (rk_fom_step(&fom, &err)) goto fail;
            fom_t[s] = rk_now() - t0;
            memcpy(frames + (size_t)ndof * (s + 1), fom.x, sizeof(double) * ndof);
        }
        double fom_s = bench_median(fom_t, steps);
        rk_fom_free(&fom);

        /* 2. 64 linear modes; r uses the first r columns. */
        rk_basis b;
        if (rk_basis_modes(&sim.fem, fixed_flags, 0, MAX_R, &b, &err)) goto fail;
        if (b.r < MAX_R) {
            rk_fail(&err, "only %d modes, %d needed", b.r, MAX_R);
            goto fail;
        }
        rk_sparse M = {0};
        if (rk_sparse_alloc_pattern(&sim.fem, &M, &err)) goto fail;
        rk_fem_add_mass(&sim.fem, opt.lumped_mass, 1.0, &M);

        res[nres].name = name;
        res[nres].nt = nt;
        for (int k = 0; k < NR; k++) {
            int r = R_VALUES[k];
            /* 4. The exact quadrature and its model. */
            rk_quadrature Q;
            rk_rom_model m;
            if (rk_quadrature_elements(&sim.fem, b.U, r, nt, NULL, NULL, &Q, &err)) goto fail;
            if (rk_rom_model_init(&m, &sim.fem, &opt, b.U, r, &Q, &err)) goto fail;
            /* 3. The full-order frames in reduced coordinates. */
            double *snap = malloc(sizeof(double) * (size_t)r * nframes);
            for (int f = 0; f < nframes; f++)
                if (rk_rom_project(&m, &M, b.U, ndof, sim.mesh.X, frames + (size_t)ndof * f, snap + (size_t)r * f,
                                   &err))
                    goto fail;
            /* 6 (exact). */
            double exact_s;
            rk_rom_stats st;
            if (time_rom(&m, EXACT_STEPS, &exact_s, &st, &err)) goto fail;
            /* 5. Cubature training on the exact model, then the cubature replaces it. */
            rk_cubature_options co;
            rk_cubature_default_options(&co);
            co.tolerance = 0.01;
            co.poses = 40;
            co.sample = CUBATURE_SAMPLE;
            rk_cubature_set set;
            int poses = 0;
            double t0 = rk_now();
            if (rk_cubature_train(&m.quad, m.M, m.mass, snap, nframes, &co, &set, &poses, &err)) goto fail;
            double train_s = rk_now() - t0;
            rk_quadrature cub;
            if (rk_quadrature_elements(&sim.fem, b.U, r, set.count, set.index, set.weight, &cub, &err)) goto fail;
            rk_quadrature_free(&m.quad);
            m.quad = cub;
            /* 6 (cubature). */
            double cub_s;
            if (time_rom(&m, ROM_STEPS, &cub_s, &st, &err)) goto fail;
            double newton = (double)st.newton_iterations / ROM_STEPS;
            if (!set.reached) nfail_tol++;
            res[nres].cub_s[k] = cub_s;

            printf("%-14s %7d %3d %6d %9.2e%s %8.3g %11.4g %11.4g %11.4g %9.0f\n", name, nt, r, set.count,
                   set.relative_error, set.reached ? " " : "!", train_s, fom_s, exact_s, cub_s, fom_s / cub_s);
            fflush(stdout);
            fprintf(csv, "%s,%d,%d,%d,%d,%.6g,%d,%d,%.6g,%.6g,%.6g,%.6g,%.6g,%.2f\n", name, nv, nt, r, set.count,
                    set.relative_error, set.reached, poses, train_s, fom_s, exact_s, cub_s, fom_s / cub_s, newton);
            fprintf(json,
                    "%s  {\"case\": \"%s\", \"vertices\": %d, \"tets\": %d, \"r\": %d, \"cubature_points\": %d,"
                    " \"cubature_relative_error\": %.6g, \"cubature_reached\": %s, \"training_poses\": %d,"
                    " \"training_seconds\": %.6g, \"fom_seconds_per_step\": %.6g,"
                    " \"exact_seconds_per_step\": %.6g, \"cubature_seconds_per_step\": %.6g,"
                    " \"speedup_fom_over_cubature\": %.6g, \"cubature_newton_per_step\": %.2f}\n",
                    nrows ? "," : "", name, nv, nt, r, set.count, set.relative_error, set.reached ? "true" : "false",
                    poses, train_s, fom_s, exact_s, cub_s, fom_s / cub_s, newton);
            nrows++;
            rk_cubature_set_free(&set);
            free(snap);
            rk_rom_model_free(&m);
        }
        nres++;
        rk_sparse_free(&M);
        rk_basis_free(&b);
        free(frames);
        free(fixed.verts);
        free(fixed_flags);
        rk_scene_sim_free(&sim);
        rk_scene_free(&scene);
        last_seconds = rk_now() - case_start;
        last_nt = nt;
        continue;
    fail:
        fprintf(stderr, "bench_rom: %s: %s\n", name, err.msg);
        return 1;
    }
    fprintf(json, "]\n");
    fclose(csv);
    fclose(json);
    if (nfail_tol) printf("(!: training stopped above the 0.01 tolerance, %d of %d rows)\n", nfail_tol, nrows);

    /* Cubature s/step on dinosaur_50k (otherwise the largest 50k+ tet mesh run) over armadillo_4k. */
    const case_result *small = NULL, *big = NULL;
    for (int i = 0; i < nres; i++) {
        if (!strcmp(res[i].name, "armadillo_4k")) small = &res[i];
        if (!strcmp(res[i].name, "dinosaur_50k")) big = &res[i];
    }
    for (int i = 0; !big && i < nres; i++)
        if (res[i].nt >= 50000 && (!big || res[i].nt > big->nt)) big = &res[i];
    if (small && big) {
        printf("\ncubature s/step, %s (%d tets) over %s (%d tets); claim: below 2\n", big->name, big->nt, small->name,
               small->nt);
        for (int k = 0; k < NR; k++) {
            double ratio = big->cub_s[k] / small->cub_s[k];
            printf("  r = %2d: %.4g / %.4g = %.2f  %s\n", R_VALUES[k], big->cub_s[k], small->cub_s[k], ratio,
                   ratio < 2 ? "below 2" : "NOT below 2");
        }
    }
    printf("total %.1f s\n", rk_now() - start);
    return 0;
}
