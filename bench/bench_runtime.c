/* make bench, runtime part: the C99 runtime (float32, build/lib/libromrt.a) stepping a baked
 * .rombin asset, against the precompute's double-precision reduced simulator (rk_rom_step) and
 * the full-order step, on the models bench_rom.c times: every bench mesh, r = 8, 16, 32, 64
 * linear modes, cubature trained as bench_rom_model.h says. Per case and r:
 *
 *   asset       the model baked with the default asset options (float32, the boundary surface
 *               shown) into memory, uncompressed and deflated; the uncompressed one's bytes per
 *               chunk (stored bytes), its stored vertices (shown ones and the rest) against the
 *               mesh's, and the arena the runtime asks for it (romrt_arena_size)
 *   runtime     romrt_open on the uncompressed asset, then from rest: 1 untimed warm-up step,
 *               then RT_REPEATS samples of rt_steps(r) steps (50 up to r = 16, 20 above: the
 *               step's cost grows like r^2 to r^3 and not with the mesh); the median of the
 *               samples' us/step
 *   rom         rk_rom_step on the same model, timed the same way (same steps from rest), so
 *               both time the same stretch of the same motion; runtime/rom is their ratio
 *   full order  as bench_rom.c (bench_rom_model.h: median of case.steps steps after a warm-up);
 *               fom/runtime is the speed-up of the runtime over it
 *   |dq|        |q_runtime - q_rom| / |q_rom| after the last timed step: float32 against double
 *
 * Spread (bench_cases.h): runtime_us_per_step and rom_us_per_step are medians over their
 * RT_REPEATS samples (each the mean us/step of its rt_steps(r) steps), with _min and _max the
 * fastest and slowest sample; fom_s_per_step's spread is over the steps of its one run (as in
 * bench_rom.c). The ratios are of the medians.
 *
 * box_100k and box_200k are skipped when their estimated cost would take the run past
 * BUDGET_SECONDS (bench_over_budget). Writes bench/results/runtime.{csv,json}. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "asset/asset.h"
#include "bench_cases.h"
#include "bench_rom_model.h"
#include "formats/rombin_read.h"
#include "formats/rombin_write.h"
#include "runtime/romrt.h"
#include "util/util.h"

#define RT_REPEATS 5
#define BUDGET_SECONDS 150.0
#define MAX_ROWS (9 * BENCH_NR)

typedef struct {
    const char *name;
    int r;
    int count;
    char id[ROMBIN_MAX_CHUNKS][5];
    uint64_t stored[ROMBIN_MAX_CHUNKS];
} chunk_row;

/* Steps per timed sample. */
static int rt_steps(int r) { return r <= 16 ? 50 : 20; }

/* Bakes R into an in-memory asset (float32, compressed or not): *out (malloc'd), *bytes. */
static int bake(const rk_scene_sim *sim, const rk_scene_rom *R, int compress, unsigned char **out, size_t *bytes,
                rk_asset_summary *summary, rk_error *err)
{
    rk_asset_options ao;
    rk_asset_default_options(&ao);
    ao.real_type = ROMBIN_REAL_F32;
    ao.compress = compress;
    rombin_writer w;
    rombin_writer_init(&w, ROMBIN_REAL_F32, compress);
    rk_asset_rom source = rk_scene_asset_rom(sim, R);
    int rc = rk_asset_bake(&source, NULL, NULL, &ao, NULL, &w, summary, err) || rombin_serialize(&w, out, bytes, err);
    rombin_writer_free(&w);
    return rc ? -1 : 0;
}

/* Times romrt_step from rest as bench_time_rom times rk_rom_step: 1 warm-up step, then
 * RT_REPEATS samples of `steps` steps. *sec: s/step (median, min, max over the samples); *newton: Newton iterations per timed
 * step; *unconverged: timed steps that ended unconverged; q: r reals after the last step. */
static int time_runtime(romrt_model *m, int steps, bench_stat *sec, double *newton, int *unconverged, float *q,
                        rk_error *err)
{
    romrt_error re;
    romrt_step_info info;
    double t[RT_REPEATS];
    long iters = 0;
    *unconverged = 0;
    romrt_reset(m, NULL);
    if (romrt_step(m, &re) != ROMRT_OK) return rk_fail(err, "romrt_step (warm-up): %s", re.message);
    for (int s = 0; s < RT_REPEATS; s++) {
        double t0 = rk_now();
        for (int k = 0; k < steps; k++) {
            if (romrt_step(m, &re) != ROMRT_OK)
                return rk_fail(err, "romrt_step %d: %s", 1 + s * steps + k, re.message);
            info.size = sizeof info;
            romrt_last_step(m, &info, NULL);
            iters += info.newton_iterations;
            *unconverged += !info.converged;
        }
        t[s] = (rk_now() - t0) / steps;
    }
    *sec = bench_stat_of(t, RT_REPEATS);
    *newton = (double)iters / (RT_REPEATS * steps);
    if (romrt_reduced_coordinates(m, q, romrt_reduced_size(m), NULL) != ROMRT_OK)
        return rk_fail(err, "romrt_reduced_coordinates");
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
    if (bench_open_results(out_dir, "runtime",
                           "case,vertices,tets,r,cubature_points,stored_vertices,shown_vertices,asset_bytes,"
                           "asset_bytes_compressed,arena_bytes,runtime_us_per_step,runtime_us_per_step_min,"
                           "runtime_us_per_step_max,rom_us_per_step,rom_us_per_step_min,rom_us_per_step_max,"
                           "fom_s_per_step,fom_s_per_step_min,fom_s_per_step_max,"
                           "runtime_over_rom,fom_over_runtime,runtime_newton_per_step,rom_newton_per_step,"
                           "runtime_unconverged_steps,q_relative_difference,chunk_bytes",
                           &csv, &json))
        return 1;
    printf("runtime (float32) and rk_rom_step (double): median of %d samples of %d (r <= 16) or %d steps from rest,"
           " after 1 warm-up step\n", RT_REPEATS, rt_steps(16), rt_steps(32));
    printf("%-13s %6s %2s %4s %13s %9s %9s %9s %9s %9s %7s %9s %9s %9s %8s\n", "case", "tets", "r", "pts",
           "stored/verts", "asset KiB", "zip KiB", "arena KiB", "rt us/st", "rom us/st", "rt/rom", "fom s/st",
           "fom/rt", "newton rt", "|dq|");
    fflush(stdout);
    static chunk_row chunks[MAX_ROWS];
    int nrows = 0;
    double max_ratio = 0;
    int total_unconverged = 0;
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
        for (int k = 0; k < BENCH_NR; k++) {
            int r = BENCH_R_VALUES[k];
            rk_rom_model m;
            double *snap;
            rk_cubature_set set;
            int poses;
            double train_s;
            if (bench_rom_exact_model(&bc, r, &m, &snap, &err) ||
                bench_rom_cubature(&bc, &m, snap, &set, &poses, &train_s, &err))
                goto fail;
            free(snap);

            /* The assets: the scene's reduced model is the bench's basis and cubature model
             * (borrowed, not freed through R). */
            rk_scene_rom R;
            memset(&R, 0, sizeof R);
            R.basis = bc.b;
            R.model = m;
            unsigned char *asset = NULL, *zipped = NULL;
            size_t bytes = 0, zbytes = 0;
            rk_asset_summary sum;
            if (bake(&bc.sim, &R, 0, &asset, &bytes, &sum, &err) || bake(&bc.sim, &R, 1, &zipped, &zbytes, NULL, &err))
                goto fail;
            free(zipped);
            rombin_file file;
            rombin_error fe;
            if (rombin_open(&file, asset, bytes, NULL, &fe)) {
                rk_fail(&err, "baked asset: %s", fe.message);
                goto fail;
            }
            chunk_row *cr = &chunks[nrows];
            cr->name = name;
            cr->r = r;
            cr->count = (int)file.count;
            for (unsigned i = 0; i < file.count && i < ROMBIN_MAX_CHUNKS; i++) {
                rombin_chunk ch;
                rombin_chunk_get(&file, i, &ch);
                memcpy(cr->id[i], ch.id, 5);
                cr->stored[i] = ch.stored;
            }

            /* The runtime on the uncompressed asset. */
            romrt_error re;
            size_t arena_bytes;
            if (romrt_arena_size(asset, bytes, &arena_bytes, &re) != ROMRT_OK) {
                rk_fail(&err, "romrt_arena_size: %s", re.message);
                goto fail;
            }
            void *arena = aligned_alloc(16, (arena_bytes + 15) / 16 * 16);
            romrt_model *rt;
            if (!arena || romrt_open(asset, bytes, arena, arena_bytes, &rt, &re) != ROMRT_OK) {
                rk_fail(&err, "romrt_open: %s", arena ? re.message : "out of memory");
                goto fail;
            }
            bench_stat rt_s = {0, 0, 0};
            double rt_newton = 0;
            int rt_unconverged = 0;
            float q_rt[BENCH_MAX_R] = {0};
            if (time_runtime(rt, rt_steps(r), &rt_s, &rt_newton, &rt_unconverged, q_rt, &err)) goto fail;
            free(arena);
            free(asset);

            /* The double reduced simulator on the same model and the same steps. */
            bench_stat rom_s;
            double q_rom[BENCH_MAX_R];
            rk_rom_stats st;
            if (bench_time_rom(&m, 1, RT_REPEATS, rt_steps(r), &rom_s, &st, q_rom, NULL, 0, &err)) goto fail;
            double rom_newton = (double)st.newton_iterations / (RT_REPEATS * rt_steps(r));
            double dq = 0, qn = 0;
            for (int j = 0; j < r; j++) {
                dq += (q_rt[j] - q_rom[j]) * (q_rt[j] - q_rom[j]);
                qn += q_rom[j] * q_rom[j];
            }
            double qdiff = qn > 0 ? sqrt(dq / qn) : sqrt(dq);
            double ratio = rt_s.median / rom_s.median, speedup = fom_s.median / rt_s.median;
            bench_stat rt_us = bench_stat_scale(rt_s, 1e6), rom_us = bench_stat_scale(rom_s, 1e6);
            if (ratio > max_ratio) max_ratio = ratio;
            total_unconverged += rt_unconverged;

            char stored[32];
            snprintf(stored, sizeof stored, "%d/%d", sum.vertices, nv);
            printf("%-13s %6d %2d %4d %13s %9.1f %9.1f %9.1f %9.1f %9.1f %7.2f %9.3g %9.0f %4.2f/%4.2f %8.1e\n", name, nt,
                   r, set.count, stored, bytes / 1024.0, zbytes / 1024.0, arena_bytes / 1024.0, rt_us.median,
                   rom_us.median, ratio, fom_s.median, speedup, rt_newton, rom_newton, qdiff);
            fflush(stdout);
            fprintf(csv,
                    "%s,%d,%d,%d,%d,%d,%d,%zu,%zu,%zu,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.2f,%.2f,"
                    "%d,%.3g,",
                    name, nv, nt, r, set.count, sum.vertices, sum.shown, bytes, zbytes, arena_bytes, BENCH_STAT3(rt_us),
                    BENCH_STAT3(rom_us), BENCH_STAT3(fom_s), ratio, speedup, rt_newton, rom_newton, rt_unconverged,
                    qdiff);
            for (int i = 0; i < cr->count; i++)
                fprintf(csv, "%s%s:%llu", i ? " " : "", cr->id[i], (unsigned long long)cr->stored[i]);
            fprintf(csv, "\n");
            fprintf(json,
                    "%s  {\"case\": \"%s\", \"vertices\": %d, \"tets\": %d, \"r\": %d, \"cubature_points\": %d,"
                    " \"stored_vertices\": %d, \"shown_vertices\": %d, \"asset_bytes\": %zu,"
                    " \"asset_bytes_compressed\": %zu, \"arena_bytes\": %zu, \"runtime_us_per_step\": %.6g,"
                    " \"runtime_us_per_step_min\": %.6g, \"runtime_us_per_step_max\": %.6g,"
                    " \"rom_us_per_step\": %.6g, \"rom_us_per_step_min\": %.6g, \"rom_us_per_step_max\": %.6g,"
                    " \"fom_seconds_per_step\": %.6g, \"fom_seconds_per_step_min\": %.6g,"
                    " \"fom_seconds_per_step_max\": %.6g, \"runtime_over_rom\": %.6g,"
                    " \"fom_over_runtime\": %.6g, \"runtime_newton_per_step\": %.2f, \"rom_newton_per_step\": %.2f,"
                    " \"runtime_unconverged_steps\": %d, \"q_relative_difference\": %.3g, \"chunk_bytes\": {",
                    nrows ? "," : "", name, nv, nt, r, set.count, sum.vertices, sum.shown, bytes, zbytes, arena_bytes,
                    BENCH_STAT3(rt_us), BENCH_STAT3(rom_us), BENCH_STAT3(fom_s), ratio, speedup, rt_newton, rom_newton,
                    rt_unconverged, qdiff);
            for (int i = 0; i < cr->count; i++)
                fprintf(json, "%s\"%s\": %llu", i ? ", " : "", cr->id[i], (unsigned long long)cr->stored[i]);
            fprintf(json, "}}\n");
            nrows++;
            rk_cubature_set_free(&set);
            rk_rom_model_free(&m);
        }
        bench_rom_case_free(&bc);
        bench_budget_case_done(&budget, nt);
        continue;
    fail:
        fprintf(stderr, "bench_runtime: %s: %s\n", name, err.msg);
        return 1;
    }
    fprintf(json, "]\n");
    fclose(csv);
    fclose(json);

    /* The uncompressed float32 assets' chunks: one column per id, in the order first met. */
    char ids[ROMBIN_MAX_CHUNKS][5];
    int nids = 0;
    for (int i = 0; i < nrows; i++)
        for (int j = 0; j < chunks[i].count; j++) {
            int seen = 0;
            for (int k = 0; k < nids && !seen; k++) seen = !strcmp(ids[k], chunks[i].id[j]);
            if (!seen && nids < ROMBIN_MAX_CHUNKS) memcpy(ids[nids++], chunks[i].id[j], 5);
        }
    printf("\nuncompressed float32 asset, stored bytes per chunk (-: absent)\n%-13s %2s", "case", "r");
    for (int k = 0; k < nids; k++) printf(" %8s", ids[k]);
    printf("\n");
    for (int i = 0; i < nrows; i++) {
        printf("%-13s %2d", chunks[i].name, chunks[i].r);
        for (int k = 0; k < nids; k++) {
            int j = 0;
            while (j < chunks[i].count && strcmp(chunks[i].id[j], ids[k])) j++;
            if (j < chunks[i].count)
                printf(" %8llu", (unsigned long long)chunks[i].stored[j]);
            else
                printf(" %8s", "-");
        }
        printf("\n");
    }
    if (total_unconverged) printf("runtime: %d timed steps ended unconverged\n", total_unconverged);
    printf("largest runtime/rom ratio %.2f\ntotal %.1f s\n", max_ratio, rk_now() - start);
    return 0;
}
