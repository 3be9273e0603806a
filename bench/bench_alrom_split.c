/* An adaptive linear ROM's runtime step split into its parts (issue 33, bench_alrom_runtime.sh):
 * the encoder, the basis (history and Grassmann), the rows (the step basis at the used vertices
 * and the elements' G_e), the terms (reference, M_r, f_r, prediction, commit) and Newton (the rest
 * of the step: the reduced solve over the cubature elements). Linked against the runtime's sources
 * compiled with -DROMRT_PROFILE (the Makefile's rt/prof-float objects), whose RT_PROF_BEGIN/END
 * hooks call rt_prof_enter/rt_prof_leave below; what each phase covers is runtime/romrt_impl.h's
 * comment at RT_PROF_PHASES. Each interval is charged to the innermost open phase, so the parts
 * add up to the step; the hooks cost a clock read each (a dozen a step). A fixed basis's step
 * is all Newton.
 *
 * Usage: bench_alrom_split ASSET.rombin STEPS REPEATS
 * Prints one line: the fractions of the steps' time (the thread's CPU clock: the machine is shared,
 * and its wall clock counts other jobs' time slices; over every repeat of STEPS steps from rest)
 * spent in encode, basis, rows, terms and newton. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench/bench_read.h"
#include "runtime/romrt.h"

#include "bench/prof_phases.h"

/* romrt_impl.h's RT_PROF_* order: broad, narrow, then the adaptive ROM's four */
enum { BROAD, NARROW, ENCODE, BASIS, ROWS, TERMS };

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(int argc, char **argv)
{
    size_t size;
    void *asset, *arena;
    size_t arena_bytes;
    romrt_error err;
    romrt_model *m;
    int steps, repeats, k, s;
    double total = 0, parts = 0;
    if (argc != 4 || (steps = atoi(argv[2])) < 1 || (repeats = atoi(argv[3])) < 1) {
        fprintf(stderr, "usage: bench_alrom_split ASSET.rombin STEPS REPEATS\n");
        return 2;
    }
    if (!(asset = bench_read_file(argv[1], &size))) {
        fprintf(stderr, "bench_alrom_split: cannot read %s\n", argv[1]);
        return 1;
    }
    if (romrt_arena_size(asset, size, &arena_bytes, &err) != ROMRT_OK || !(arena = malloc(arena_bytes)) ||
        romrt_open(asset, size, arena, arena_bytes, &m, &err) != ROMRT_OK) {
        fprintf(stderr, "bench_alrom_split: %s: %s\n", argv[1], err.message);
        return 1;
    }
    for (k = 0; k < repeats; k++) {
        romrt_reset(m, NULL);
        for (s = 0; s < steps; s++) {
            double t0 = now();
            prof_depth = 0, prof_last = t0;
            if (romrt_step(m, &err) != ROMRT_OK) {
                fprintf(stderr, "bench_alrom_split: step %d: %s\n", s, err.message);
                return 1;
            }
            total += now() - t0;
        }
    }
    for (k = ENCODE; k <= TERMS; k++) parts += prof_s[k];
    printf("%.5f %.5f %.5f %.5f %.5f\n", prof_s[ENCODE] / total, prof_s[BASIS] / total, prof_s[ROWS] / total,
           prof_s[TERMS] / total, (total - parts) / total);
    free(arena);
    free(asset);
    return 0;
}
