/* main.c: steps the embedded asset (asset_data.h) with the romkit runtime and prints what
 * tests/mcu/compare.sh compares. Portable C99: built for the Cortex-M4F under qemu (with
 * ROMKIT_MCU defined, each step timed in instructions) and for the host (no timing), so the
 * two runs of the same float runtime can be checked against each other. */
#include <stdio.h>
#include <stdlib.h>

#include "runtime/romrt.h"
#include "asset_data.h"
#ifdef ROMKIT_MCU
#include "cycles.h"
#endif

#ifndef STEPS
#define STEPS 100
#endif
#ifndef ARENA_BYTES
#define ARENA_BYTES (512u * 1024u)
#endif
#ifndef MAX_SHOWN
#define MAX_SHOWN 4096
#endif

/* Static, so the harness needs no heap; 16-byte alignment is more than romrt_open asks (8). */
#ifdef __GNUC__
#define ALIGN16 __attribute__((aligned(16)))
#else
#define ALIGN16
#endif
static unsigned char arena[ARENA_BYTES] ALIGN16;
static romrt_real xyz[3 * MAX_SHOWN];
static long long step_cost[STEPS];

static int failed(romrt_status s, const romrt_error *err)
{
    printf("error %s %s\n", romrt_status_string(s), err->message);
    return 1;
}

/* Prints the shown vertices as "<tag> <i> <x> <y> <z>"; 0 on failure. */
static int positions(const char *tag, const romrt_model *m, int shown)
{
    int i;
    romrt_status s = romrt_positions(m, xyz, 3 * (size_t)MAX_SHOWN, 3, NULL); /* the buffer's capacity: too small is refused */
    if (s != ROMRT_OK) {
        printf("error %s romrt_positions\n", romrt_status_string(s));
        return 0;
    }
    for (i = 0; i < shown; i++)
        printf("%s %d %.8e %.8e %.8e\n", tag, i, (double)xyz[3 * i], (double)xyz[3 * i + 1],
               (double)xyz[3 * i + 2]);
    return 1;
}

static int by_value(const void *a, const void *b)
{
    long long x = *(const long long *)a, y = *(const long long *)b;
    return (x > y) - (x < y);
}

int main(void)
{
    romrt_error err;
    romrt_model *m;
    size_t need;
    romrt_status s;
    int i, shown;

    s = romrt_arena_size(romkit_asset, romkit_asset_len, &need, &err);
    if (s != ROMRT_OK)
        return failed(s, &err);
    printf("arena_bytes %lu\n", (unsigned long)need);
    if (need > sizeof arena) {
        printf("error arena too small: the model needs %lu bytes, the harness has %lu "
               "(raise ARENA_BYTES)\n", (unsigned long)need, (unsigned long)sizeof arena);
        return 1;
    }
    s = romrt_open(romkit_asset, romkit_asset_len, arena, sizeof arena, &m, &err);
    if (s != ROMRT_OK)
        return failed(s, &err);
#ifdef HESSIAN_REUSE /* make mcu MCU_REUSE=k: Newton's matrix kept for up to k steps */
    s = romrt_set_hessian_reuse(m, HESSIAN_REUSE, &err);
    if (s != ROMRT_OK)
        return failed(s, &err);
#endif
    shown = romrt_shown_count(m);
    printf("r %d\nshown %d\nsteps %d\n", (int)romrt_reduced_size(m), shown, STEPS);
    if (shown > MAX_SHOWN) {
        printf("error too many shown vertices: %d > MAX_SHOWN %d\n", shown, MAX_SHOWN);
        return 1;
    }

    /* The rest shape, so compare.sh can measure displacements. */
    if (!positions("rest", m, shown))
        return 1;
#ifdef ROMKIT_MCU
    cycles_init();
#endif
    for (i = 0; i < STEPS; i++) {
#ifdef ROMKIT_MCU
        uint64_t t0 = cycles_now();
        s = romrt_step(m, &err);
        step_cost[i] = (long long)(cycles_now() - t0);
#else
        s = romrt_step(m, &err);
        step_cost[i] = -1;
#endif
        if (s != ROMRT_OK)
            return failed(s, &err);
    }
#ifndef ROMKIT_MCU
    printf("step_instructions -1\n");
#endif
    qsort(step_cost, STEPS, sizeof step_cost[0], by_value);
    printf("step_instructions_median %lld\n", step_cost[STEPS / 2]);
    printf("step_instructions_max %lld\n", step_cost[STEPS - 1]);

    if (!positions("x", m, shown))
        return 1;
    return 0;
}
