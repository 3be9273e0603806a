/* make bench helper: the runtime's converged Newton mode with a fresh Newton matrix every iteration
 * (romrt_set_hessian_reuse 1) against the same mode with the matrix kept for up to k = 2, 3, 5, 10
 * steps, and against the library's default (whatever romrt_open leaves set), on baked assets, so
 * the default can be chosen from numbers (issue 31). Usage:
 *
 *   bench_newton_modes STEPS ROUNDS A.rombin [B.rombin ...]
 *
 * Per asset and mode: us/step (median over ROUNDS interleaved rounds of STEPS steps from rest, each
 * round's mean; the modes of one asset take turns, so a noisy machine moves them alike), its ratio
 * to the fresh mode, Newton iterations per step, and the kept mode's distance from the fresh one:
 * max over steps and shown vertices of |x_k - x_fresh| in metres and over the largest displacement
 * of the fresh run. Both runs are converged to the asset's tolerance on the RMS Newton step, so
 * that distance is what the tolerance lets two converged solves differ by; the fresh run's own
 * float rounding is of the same order (bench/results/runtime_speed.csv's error columns). Built in
 * float (bench_newton_modes) and double (bench_newton_modes_double, for float64 assets). One CSV
 * line per asset and mode on stdout. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "runtime/romrt.h"
#include "util/util.h"

#define NMODES 6
static const int reuse_of[NMODES] = {1, 2, 3, 5, 10, -1}; /* -1: the default romrt_open leaves */

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static unsigned char *read_all(const char *path, size_t *bytes)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *data = n > 0 ? aligned_alloc(16, ((size_t)n + 15) / 16 * 16) : NULL;
    *bytes = (size_t)n;
    if (data && fread(data, 1, *bytes, f) != *bytes) {
        free(data);
        data = NULL;
    }
    fclose(f);
    return data;
}

/* STEPS steps from rest in mode `mode`; positions into traj (steps x shown x 3) when given; *us its
 * us/step, *its Newton iterations per step. 0, or -1 with the message printed. */
static int run(romrt_model *m, const char *path, int mode, int steps, romrt_real *traj, int n, double *us, double *its)
{
    romrt_error re;
    romrt_step_info info;
    long iterations = 0;
    if (reuse_of[mode] >= 0 && romrt_set_hessian_reuse(m, reuse_of[mode], &re)) {
        fprintf(stderr, "bench_newton_modes: %s: %s\n", path, re.message);
        return -1;
    }
    romrt_reset(m);
    double t0 = rk_now();
    for (int s = 0; s < steps; s++) {
        if (romrt_step(m, &re)) {
            fprintf(stderr, "bench_newton_modes: %s: step %d: %s\n", path, s, re.message);
            return -1;
        }
        romrt_last_step(m, &info);
        iterations += info.newton_iterations;
        if (traj) romrt_positions(m, traj + (size_t)3 * n * s, n, 3);
    }
    *us = (rk_now() - t0) / steps * 1e6;
    *its = (double)iterations / steps;
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 4) {
        fprintf(stderr, "usage: bench_newton_modes STEPS ROUNDS A.rombin [B.rombin ...]\n");
        return 2;
    }
    int steps = atoi(argv[1]), rounds = atoi(argv[2]);
    if (steps < 1 || rounds < 1) {
        fprintf(stderr, "bench_newton_modes: STEPS and ROUNDS must be positive\n");
        return 2;
    }
    printf("asset,mode,us_per_step,us_min,us_max,ratio_to_fresh,newton_per_step,max_diff_m,max_diff_relative\n");
    for (int a = 3; a < argc; a++) {
        const char *path = argv[a], *name = strrchr(path, '/');
        size_t bytes, need;
        romrt_error re;
        romrt_model *m;
        unsigned char *data = read_all(path, &bytes);
        void *arena = NULL;
        if (!data || romrt_arena_size(data, bytes, &need, &re) || !(arena = aligned_alloc(16, (need + 15) / 16 * 16)) ||
            romrt_open(data, bytes, arena, need, &m, &re)) {
            fprintf(stderr, "bench_newton_modes: %s: %s\n", path, data ? re.message : "cannot read");
            return 1;
        }
        name = name ? name + 1 : path;
        int n = romrt_shown_count(m);
        size_t len = (size_t)3 * n * steps;
        romrt_real *rest = malloc(sizeof(romrt_real) * 3 * (size_t)n), *traj[NMODES];
        double *us = calloc((size_t)NMODES * rounds, sizeof(double)), its[NMODES], t;
        romrt_positions(m, rest, n, 3);
        for (int k = 0; k < NMODES; k++) traj[k] = malloc(sizeof(romrt_real) * len);
        /* the default is what a fresh open leaves: measure it before any setter runs */
        if (run(m, path, NMODES - 1, steps, traj[NMODES - 1], n, &t, &its[NMODES - 1])) return 1;
        for (int k = 0; k < NMODES - 1; k++)
            if (run(m, path, k, steps, traj[k], n, &t, &its[k])) return 1;
        for (int round = 0; round < rounds; round++)
            for (int k = 0; k < NMODES; k++) {
                if (k == NMODES - 1) { /* the default again: a fresh open */
                    if (romrt_open(data, bytes, arena, need, &m, &re)) return 1;
                }
                if (run(m, path, k, steps, NULL, n, &us[(size_t)k * rounds + round], &t)) return 1;
            }
        double scale = 0, fresh_med = 0;
        for (size_t i = 0; i < len; i++) scale = fmax(scale, fabs((double)traj[0][i] - (double)rest[i % (3 * (size_t)n)]));
        for (int k = 0; k < NMODES; k++) {
            double *u = us + (size_t)k * rounds, diff = 0;
            qsort(u, (size_t)rounds, sizeof(double), cmp);
            double med = rounds % 2 ? u[rounds / 2] : 0.5 * (u[rounds / 2 - 1] + u[rounds / 2]);
            if (k == 0) fresh_med = med;
            for (size_t i = 0; i < len; i++) diff = fmax(diff, fabs((double)traj[k][i] - (double)traj[0][i]));
            char mode[16];
            if (reuse_of[k] < 0) snprintf(mode, sizeof mode, "default");
            else if (reuse_of[k] == 1) snprintf(mode, sizeof mode, "fresh");
            else snprintf(mode, sizeof mode, "kept-%d", reuse_of[k]);
            printf("%s,%s,%.4g,%.4g,%.4g,%.3f,%.2f,%.3g,%.3g\n", name, mode, med, u[0], u[rounds - 1], med / fresh_med,
                   its[k], diff, scale > 0 ? diff / scale : 0);
            fflush(stdout);
        }
        for (int k = 0; k < NMODES; k++) free(traj[k]);
        free(rest);
        free(us);
        free(arena);
        free(data);
    }
    return 0;
}
