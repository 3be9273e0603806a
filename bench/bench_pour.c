/* A baked asset's runtime step split into broad phase, narrow phase and Newton (issue 30's pour,
 * bench/pour.sh). Linked against the runtime's sources compiled with -DROMRT_PROFILE (the
 * Makefile's rt/prof-float and rt/prof-double objects), whose RT_PROF_BEGIN/END hooks call
 * rt_prof_enter/rt_prof_leave below; the shipped library has no hooks. What each phase covers is
 * runtime/romrt_impl.h's comment at RT_PROF_PHASES:
 *   broad   candidates: BVH refit and traversal, the surface's sort and sweep, the Verlet list
 *   narrow  per stencil: distance, barrier, PSD projection, pull into the r x r system, friction, CCD
 *   newton  the rest of the step: elastic energy (cubature), inertia, the r x r Cholesky and solve,
 *           the line search's bookkeeping
 * Each interval is charged to the innermost open phase (a CCD visit inside a broad query is
 * narrow), so the three add up to the step. The hooks cost two clock reads per call (a few
 * percent here): the unprofiled us/step is romkit run's.
 *
 * A step is timed by the process's CPU clock (the machine is shared: its wall clock counts other
 * jobs' time slices), the phases by the monotonic clock, as fractions of the steps' wall time.
 *
 * Usage: [BENCH_HESSIAN_REUSE=N] bench_pour ASSET.rombin STEPS REPEATS [NEWTON]
 *        (NEWTON > 0: romrt_set_newton_iterations; N: romrt_set_hessian_reuse)
 * Prints one line: cpu_median_us cpu_lo_us cpu_hi_us wall_median_us broad narrow newton iters
 * halvings projected (the median over repeats of each repeat's median step, lo/hi the smallest and
 * largest repeat median; broad, narrow and newton the fractions of the step over all repeats;
 * Newton iterations, line-search halvings and projected Hessians per step). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench/bench_read.h"
#include "runtime/romrt.h"

#include "bench/prof_phases.h" /* a pour enters only the first two phases: broad, narrow */

static double clock_s(clockid_t id)
{
    struct timespec t;
    clock_gettime(id, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static double now(void) { return clock_s(CLOCK_MONOTONIC); }

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int main(int argc, char **argv)
{
    size_t size;
    void *asset, *arena;
    size_t arena_bytes;
    romrt_error err;
    int steps, repeats, newton = 0, k, s;
    double *step_s, *cpu_s, *med, *wmed, total = 0, sum[PROF_PHASES] = {0, 0};
    long iters = 0, halvings = 0, projected = 0;
    if ((argc != 4 && argc != 5) || (steps = atoi(argv[2])) < 1 || (repeats = atoi(argv[3])) < 1 ||
        (argc == 5 && (newton = atoi(argv[4])) < 0)) {
        fprintf(stderr, "usage: bench_pour ASSET.rombin STEPS REPEATS [NEWTON]\n");
        return 2;
    }
    if (!(asset = bench_read_file(argv[1], &size))) {
        fprintf(stderr, "bench_pour: cannot read %s\n", argv[1]);
        return 1;
    }
    if (romrt_arena_size(asset, size, &arena_bytes, &err) != ROMRT_OK) {
        fprintf(stderr, "bench_pour: %s: %s\n", argv[1], err.message);
        return 1;
    }
    arena = malloc(arena_bytes);
    step_s = malloc(sizeof(double) * (size_t)steps);
    cpu_s = malloc(sizeof(double) * (size_t)steps);
    med = malloc(sizeof(double) * (size_t)repeats);
    wmed = malloc(sizeof(double) * (size_t)repeats);
    if (!arena || !step_s || !cpu_s || !med || !wmed) return 1;
    for (k = 0; k < repeats; k++) {
        romrt_model *m;
        if (romrt_open(asset, size, arena, arena_bytes, &m, &err) != ROMRT_OK) {
            fprintf(stderr, "bench_pour: %s: %s\n", argv[1], err.message);
            return 1;
        }
        if (newton && romrt_set_newton_iterations(m, newton, &err) != ROMRT_OK) {
            fprintf(stderr, "bench_pour: %s\n", err.message);
            return 1;
        }
        /* BENCH_HESSIAN_REUSE=N: romrt_set_hessian_reuse(N), as bench_assets takes it (1: a fresh
         * Newton matrix every iteration; unset: the runtime's default) */
        if (getenv("BENCH_HESSIAN_REUSE") &&
            romrt_set_hessian_reuse(m, (size_t)atoi(getenv("BENCH_HESSIAN_REUSE")), &err) != ROMRT_OK) {
            fprintf(stderr, "bench_pour: %s\n", err.message);
            return 1;
        }
        memset(prof_s, 0, sizeof prof_s);
        for (s = 0; s < steps; s++) {
            romrt_step_info info;
            double c0 = clock_s(CLOCK_PROCESS_CPUTIME_ID), t0 = now();
            prof_depth = 0, prof_last = t0;
            if (romrt_step(m, &err) != ROMRT_OK) {
                fprintf(stderr, "bench_pour: step %d: %s\n", s, err.message);
                return 1;
            }
            step_s[s] = now() - t0;
            cpu_s[s] = clock_s(CLOCK_PROCESS_CPUTIME_ID) - c0;
            total += step_s[s];
            info.size = sizeof info;
            romrt_last_step(m, &info, NULL);
            iters += info.newton_iterations;
            halvings += info.line_search_halvings;
            projected += info.projected_hessians;
        }
        for (s = 0; s < PROF_PHASES; s++) sum[s] += prof_s[s];
        med[k] = median(cpu_s, steps);
        wmed[k] = median(step_s, steps);
    }
    {
        double lo = med[0], hi = med[0], n = (double)steps * repeats;
        for (k = 1; k < repeats; k++) lo = med[k] < lo ? med[k] : lo, hi = med[k] > hi ? med[k] : hi;
        printf("%.1f %.1f %.1f %.1f %.3f %.3f %.3f %.2f %.2f %.2f\n", 1e6 * median(med, repeats), 1e6 * lo, 1e6 * hi,
               1e6 * median(wmed, repeats), sum[0] / total, sum[1] / total, (total - sum[0] - sum[1]) / total,
               (double)iters / n, (double)halvings / n, (double)projected / n);
    }
    return 0;
}
