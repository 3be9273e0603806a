/* make bench helper: the float32 runtime's step cost on several baked assets in one process, the
 * samples interleaved (a round steps every asset once for `steps` steps from rest), so that the
 * ratios against the first asset hold on a noisy machine. Usage:
 *
 *   bench_assets STEPS ROUNDS A.rombin B.rombin ...
 *
 * Prints one CSV line per asset: asset, us_per_step (median over the rounds of each round's mean
 * us/step), us_min, us_max (fastest and slowest round), ratio (median over the first asset's
 * median), newton_iterations (per step, last round); BENCH_HESSIAN_REUSE=N in the environment sets
 * romrt_set_hessian_reuse(N) where an asset takes it. A round is timed by the thread's CPU clock:
 * the machine is shared, and its wall clock counts other jobs' time slices (a PCA round of 115 us a
 * step read 2 ms by the wall clock beside two builds). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench/bench_read.h"
#include "runtime/romrt.h"
#include "util/util.h"

#define MAX_ASSETS 16

static double cpu_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

typedef struct {
    const char *path;
    unsigned char *data;
    size_t bytes;
    void *arena;
    romrt_model *m;
    double *us;
    long iterations;
} asset;

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int load(asset *a, rk_error *err)
{
    a->data = bench_read_file(a->path, &a->bytes);
    if (!a->data) return rk_fail(err, "%s: cannot read", a->path);
    size_t need;
    romrt_error re;
    if (romrt_arena_size(a->data, a->bytes, &need, &re)) return rk_fail(err, "%s: %s", a->path, re.message);
    a->arena = aligned_alloc(16, (need + 15) / 16 * 16);
    if (!a->arena || romrt_open(a->data, a->bytes, a->arena, need, &a->m, &re))
        return rk_fail(err, "%s: %s", a->path, re.message);
    /* BENCH_HESSIAN_REUSE=N: romrt_set_hessian_reuse(N) on the assets that take it (0: a fresh Newton
     * matrix every iteration, as an adaptive basis needs; a fixed one keeps it by default) */
    const char *reuse = getenv("BENCH_HESSIAN_REUSE");
    if (reuse && romrt_set_hessian_reuse(a->m, (size_t)atoi(reuse), &re))
        fprintf(stderr, "bench_assets: %s: %s (left as it is)\n", a->path, re.message);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 4 || argc - 3 > MAX_ASSETS) {
        fprintf(stderr, "usage: bench_assets STEPS ROUNDS A.rombin [B.rombin ...] (up to %d)\n", MAX_ASSETS);
        return 2;
    }
    int steps = atoi(argv[1]), rounds = atoi(argv[2]), n = argc - 3;
    if (steps < 1 || rounds < 1) {
        fprintf(stderr, "bench_assets: STEPS and ROUNDS must be positive\n");
        return 2;
    }
    asset as[MAX_ASSETS];
    memset(as, 0, sizeof as);
    rk_error err;
    for (int k = 0; k < n; k++) {
        as[k].path = argv[3 + k];
        as[k].us = calloc((size_t)rounds, sizeof(double));
        if (!as[k].us || load(&as[k], &err)) {
            fprintf(stderr, "bench_assets: %s\n", err.msg);
            return 1;
        }
    }
    for (int round = 0; round < rounds; round++)
        for (int k = 0; k < n; k++) {
            romrt_error re;
            romrt_step_info info;
            romrt_reset(as[k].m, NULL);
            as[k].iterations = 0;
            double t0 = cpu_now();
            for (int s = 0; s < steps; s++) {
                if (romrt_step(as[k].m, &re)) {
                    fprintf(stderr, "bench_assets: %s: step %d: %s\n", as[k].path, s, re.message);
                    return 1;
                }
                info.size = sizeof info;
                romrt_last_step(as[k].m, &info, NULL);
                as[k].iterations += info.newton_iterations;
            }
            as[k].us[round] = (cpu_now() - t0) / steps * 1e6;
        }
    double first = 0;
    printf("asset,us_per_step,us_min,us_max,ratio,newton_iterations\n");
    for (int k = 0; k < n; k++) {
        qsort(as[k].us, (size_t)rounds, sizeof(double), cmp);
        double med = rounds % 2 ? as[k].us[rounds / 2] : 0.5 * (as[k].us[rounds / 2 - 1] + as[k].us[rounds / 2]);
        if (k == 0) first = med;
        const char *name = strrchr(as[k].path, '/');
        printf("%s,%.4g,%.4g,%.4g,%.3g,%.2f\n", name ? name + 1 : as[k].path, med, as[k].us[0], as[k].us[rounds - 1],
               med / first, (double)as[k].iterations / steps);
        free(as[k].data);
        free(as[k].arena);
        free(as[k].us);
    }
    return 0;
}
