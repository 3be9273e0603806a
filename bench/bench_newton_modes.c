/* make bench helper: the runtime's converged Newton mode with a fresh Newton matrix every iteration
 * (romrt_set_hessian_reuse 1) against the same mode with the matrix kept for up to k = 2, 3, 5, 10
 * steps, and against the library's default (whatever romrt_open leaves set), on baked assets, so
 * the default can be chosen from numbers (issue 31). Usage:
 *
 *   bench_newton_modes STEPS ROUNDS A.rombin [B.rombin ...]
 *
 * Per asset and mode: us/step of CPU time (median over ROUNDS interleaved rounds of STEPS steps from
 * rest, each round's mean; the modes of one asset take turns, so a noisy machine moves them alike;
 * CPU time, since the runtime is one thread and a shared machine's wall clock counts others), its ratio
 * to the fresh mode, Newton iterations per step, and the kept mode's distance from the fresh one:
 * max over steps and shown vertices of |x_k - x_fresh| in metres and over the largest displacement
 * of the fresh run, and the largest over steps of the RMS over shown vertices of x_k - x_fresh
 * against the asset's Newton tolerance (PARM: on the RMS Newton step, in metres), the most two
 * solves converged to it may differ by in one step; over a run such differences add up, so
 * rms_over_tol is to be read against the step count. Built in
 * float (bench_newton_modes) and double (bench_newton_modes_double, for float64 assets). One CSV
 * line per asset and mode on stdout. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench/bench_read.h"
#include "formats/rombin.h"
#include "formats/rombin_read.h"
#include "runtime/romrt.h"
#include "util/util.h"

#define NMODES 6
static const int reuse_of[NMODES] = {1, 2, 3, 5, 10, -1}; /* -1: the default romrt_open leaves */

/* Seconds of this process's CPU time: the runtime is one thread, and on a shared machine the wall
 * clock also counts the time others ran. */
static double cpu_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
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
    romrt_reset(m, NULL);
    double t0 = cpu_now();
    for (int s = 0; s < steps; s++) {
        if (romrt_step(m, &re)) {
            fprintf(stderr, "bench_newton_modes: %s: step %d: %s\n", path, s, re.message);
            return -1;
        }
        info.size = sizeof info;
        romrt_last_step(m, &info, NULL);
        iterations += info.newton_iterations;
        if (traj) romrt_positions(m, traj + (size_t)3 * n * s, 3 * (size_t)n, 3, NULL);
    }
    *us = (cpu_now() - t0) / steps * 1e6;
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
    printf("asset,mode,us_per_step,us_per_step_min,us_per_step_max,ratio_to_fresh,newton_per_step,max_diff_m,max_diff_relative,tol_m,rms_over_tol\n");
    for (int a = 3; a < argc; a++) {
        const char *path = argv[a], *name = strrchr(path, '/');
        size_t bytes, need;
        romrt_error re;
        romrt_model *m;
        unsigned char *data = bench_read_file(path, &bytes);
        void *arena = NULL;
        if (!data || romrt_arena_size(data, bytes, &need, &re) || !(arena = aligned_alloc(16, (need + 15) / 16 * 16)) ||
            romrt_open(data, bytes, arena, need, &m, &re)) {
            fprintf(stderr, "bench_newton_modes: %s: %s\n", path, data ? re.message : "cannot read");
            return 1;
        }
        name = name ? name + 1 : path;
        double tol = 0;
        {
            rombin_file file;
            rombin_chunk c;
            rombin_error e;
            if (!rombin_open(&file, data, bytes, NULL, &e) && rombin_find(&file, ROMBIN_PARM, &c)) {
                const unsigned char *v = c.data + ROMBIN_PARM_NEWTON_TOL * (file.real_type == ROMBIN_REAL_F64 ? 8 : 4);
                if (file.real_type == ROMBIN_REAL_F64) memcpy(&tol, v, 8);
                else {
                    float f;
                    memcpy(&f, v, 4);
                    tol = f;
                }
            }
        }
        int n = romrt_shown_count(m);
        size_t len = (size_t)3 * n * steps;
        romrt_real *rest = malloc(sizeof(romrt_real) * 3 * (size_t)n), *traj[NMODES];
        double *us = calloc((size_t)NMODES * rounds, sizeof(double)), its[NMODES], t;
        romrt_positions(m, rest, 3 * (size_t)n, 3, NULL);
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
            double rms = 0;
            for (size_t i = 0; i < len; i++) diff = fmax(diff, fabs((double)traj[k][i] - (double)traj[0][i]));
            for (int s = 0; s < steps; s++) {
                double sum = 0;
                for (size_t i = (size_t)3 * n * s; i < (size_t)3 * n * (s + 1); i++)
                    sum += ((double)traj[k][i] - (double)traj[0][i]) * ((double)traj[k][i] - (double)traj[0][i]);
                rms = fmax(rms, sqrt(sum / n));
            }
            char mode[16];
            if (reuse_of[k] < 0) snprintf(mode, sizeof mode, "default");
            else if (reuse_of[k] == 1) snprintf(mode, sizeof mode, "fresh");
            else snprintf(mode, sizeof mode, "kept-%d", reuse_of[k]);
            printf("%s,%s,%.4g,%.4g,%.4g,%.3f,%.2f,%.3g,%.3g,%.3g,%.3g\n", name, mode, med, u[0], u[rounds - 1],
                   med / fresh_med, its[k], diff, scale > 0 ? diff / scale : 0, tol, tol > 0 ? rms / tol : 0);
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
