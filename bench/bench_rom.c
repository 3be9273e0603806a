/* make bench, reduced-model part: per-step speed-up of the reduced model with cubature over the
 * full-order model, on every tet mesh of the bench set, at r = 8, 16, 32, 64 linear modes. The
 * models (scene, fixed group, full-order run, basis, exact model, cubature) are built as
 * bench_rom_model.h says; here:
 *
 *   full order   one untimed warm-up step, then case.steps single steps of one run
 *   exact        5 single steps (after 1 warm-up), each timed
 *   cubature     20 single steps (after 1 warm-up), each timed
 *
 * Spread (bench_cases.h): each X_s_per_step is the median over those steps and X_s_per_step_min,
 * X_s_per_step_max the fastest and slowest; the spread is over the steps of one run, not over
 * repeated runs. training_s: the cubature training, timed once (up to about 10 s a row: three runs
 * would add a minute or more and push the large meshes past the budget); training_s_min and
 * training_s_max equal it, one sample.
 *
 * Error (for the error against time chart): both reduced models start from rest like the
 * full-order run and are compared to its frames over the first error_frames steps (1 + 5, or
 * fewer when the full-order run has fewer frames): exact_error and cubature_error are
 * sqrt(sum |x_rom - x_fom|^2 / sum |x_fom - X|^2) over every vertex of those frames
 * (bench_rom_error). The basis is linear modes, so this is mostly the basis's error on a short
 * sag under gravity; cubature adds its own on top.
 *
 * box_100k and box_200k are skipped when their estimated cost (the last case's seconds scaled by
 * the tet ratio to the power 1.2) would take the run past BUDGET_SECONDS. At the end, for each r:
 * cubature s/step on dinosaur_50k (or, had it not run, the largest 50k+ tet mesh run) over
 * armadillo_4k, the check that the per-step cost does not grow with the tet count (claim: below
 * 2). Writes bench/results/rom.{csv,json}. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_cases.h"
#include "bench_rom_model.h"
#include "util/util.h"

#define NR BENCH_NR
#define ROM_STEPS 20
#define EXACT_STEPS 5
#define BUDGET_SECONDS 360.0

static const int *const R_VALUES = BENCH_R_VALUES;

typedef struct {
    const char *name;
    int nt;
    double cub_s[NR];
} case_result;

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
                           "training_s,training_s_min,training_s_max,fom_s_per_step,fom_s_per_step_min,"
                           "fom_s_per_step_max,exact_s_per_step,exact_s_per_step_min,exact_s_per_step_max,"
                           "cubature_s_per_step,cubature_s_per_step_min,cubature_s_per_step_max,"
                           "speedup_fom_over_cubature,cubature_newton_per_step,error_frames,exact_error,cubature_error",
                           &csv, &json))
        return 1;
    printf("%-14s %7s %3s %6s %9s %9s %11s %11s %11s %9s %9s %9s\n", "case", "tets", "r", "points", "cub err",
           "train s", "fom s/step", "exact s/st", "cub s/step", "speed-up", "exact err", "cub err");
    fflush(stdout);
    case_result res[9];
    int nres = 0, nrows = 0, nfail_tol = 0;
    bench_budget budget = {start, BUDGET_SECONDS, 0, 0, 0};
    for (int c = 0; c < ncases; c++) {
        const char *name = cases[c].name;
        rk_error err;
        bench_rom_case bc;
        int ready = bench_rom_case_open(&cases[c], &budget, &bc, &err);
        if (ready < 0) goto fail;
        if (!ready) continue;
        int nv = bc.nv, nt = bc.nt;
        bench_stat fom_s = bc.fom_s;
        int nf = bc.nframes < 1 + EXACT_STEPS ? bc.nframes : 1 + EXACT_STEPS; /* frames compared */

        res[nres].name = name;
        res[nres].nt = nt;
        for (int k = 0; k < NR; k++) {
            int r = R_VALUES[k];
            rk_rom_model m;
            double *snap, *q_traj = malloc(sizeof(double) * (size_t)r * nf);
            if (!q_traj) {
                rk_fail(&err, "out of memory");
                goto fail;
            }
            if (bench_rom_exact_model(&bc, r, &m, &snap, &err)) goto fail;
            bench_stat exact_s;
            rk_rom_stats st;
            if (bench_time_rom(&m, 1, EXACT_STEPS, 1, &exact_s, &st, NULL, q_traj, nf, &err)) goto fail;
            double exact_error = bench_rom_error(&bc, r, q_traj, nf);
            rk_cubature_set set;
            int poses;
            double train_s;
            if (bench_rom_cubature(&bc, &m, snap, &set, &poses, &train_s, &err)) goto fail;
            bench_stat cub_s, train = {train_s, train_s, train_s};
            if (bench_time_rom(&m, 1, ROM_STEPS, 1, &cub_s, &st, NULL, q_traj, nf, &err)) goto fail;
            double cub_error = bench_rom_error(&bc, r, q_traj, nf);
            double newton = (double)st.newton_iterations / ROM_STEPS, speedup = fom_s.median / cub_s.median;
            if (!set.reached) nfail_tol++;
            res[nres].cub_s[k] = cub_s.median;

            printf("%-14s %7d %3d %6d %9.2e%s %8.3g %11.4g %11.4g %11.4g %9.0f %9.2e %9.2e\n", name, nt, r, set.count,
                   set.relative_error, set.reached ? " " : "!", train_s, fom_s.median, exact_s.median, cub_s.median,
                   speedup, exact_error, cub_error);
            fflush(stdout);
            fprintf(csv,
                    "%s,%d,%d,%d,%d,%.6g,%d,%d,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,"
                    "%.2f,%d,%.4g,%.4g\n",
                    name, nv, nt, r, set.count, set.relative_error, set.reached, poses, BENCH_STAT3(train),
                    BENCH_STAT3(fom_s), BENCH_STAT3(exact_s), BENCH_STAT3(cub_s), speedup, newton, nf, exact_error,
                    cub_error);
            fprintf(json,
                    "%s  {\"case\": \"%s\", \"vertices\": %d, \"tets\": %d, \"r\": %d, \"cubature_points\": %d,"
                    " \"cubature_relative_error\": %.6g, \"cubature_reached\": %s, \"training_poses\": %d,"
                    " \"training_seconds\": %.6g, \"training_seconds_min\": %.6g, \"training_seconds_max\": %.6g,"
                    " \"fom_seconds_per_step\": %.6g, \"fom_seconds_per_step_min\": %.6g,"
                    " \"fom_seconds_per_step_max\": %.6g, \"exact_seconds_per_step\": %.6g,"
                    " \"exact_seconds_per_step_min\": %.6g, \"exact_seconds_per_step_max\": %.6g,"
                    " \"cubature_seconds_per_step\": %.6g, \"cubature_seconds_per_step_min\": %.6g,"
                    " \"cubature_seconds_per_step_max\": %.6g, \"speedup_fom_over_cubature\": %.6g,"
                    " \"cubature_newton_per_step\": %.2f, \"error_frames\": %d, \"exact_error\": %.4g,"
                    " \"cubature_error\": %.4g}\n",
                    nrows ? "," : "", name, nv, nt, r, set.count, set.relative_error, set.reached ? "true" : "false",
                    poses, BENCH_STAT3(train), BENCH_STAT3(fom_s), BENCH_STAT3(exact_s), BENCH_STAT3(cub_s), speedup,
                    newton, nf, exact_error, cub_error);
            nrows++;
            rk_cubature_set_free(&set);
            free(snap);
            free(q_traj);
            rk_rom_model_free(&m);
        }
        nres++;
        bench_rom_case_free(&bc);
        bench_budget_case_done(&budget, nt);
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
