/* rt_capacity: the buffer writers of romrt.h on heap buffers of exactly the size they are given,
 * so that a write past a buffer is an AddressSanitizer report (tests/integration/runtime_abi.sh
 * builds this and the runtime's sources with -fsanitize=address,undefined). Prints "ok NAME" or
 * "FAIL NAME: why" per check. Usage: rt_capacity ASSET.rombin */
#include <stdio.h>
#include <stdlib.h>

#include "romrt.h"

static int failures;

static void check(int cond, const char *name)
{
    printf("%s %s\n", cond ? "ok" : "FAIL", name);
    failures += !cond;
}

/* An exact-size heap buffer of n reals (at least one byte, so malloc(0) is not a special case). */
static romrt_real *reals(size_t n) { return (romrt_real *)malloc(n ? n * sizeof(romrt_real) : 1); }

int main(int argc, char **argv)
{
    FILE *f;
    long len;
    size_t bytes, arena_bytes, nr;
    void *asset, *arena;
    romrt_model *m;
    romrt_error err;
    romrt_real *b;
    int n, r, k;
    const romrt_real push[3] = {0, 0, 1};
    if (argc != 2 || !(f = fopen(argv[1], "rb"))) return 2;
    fseek(f, 0, SEEK_END);
    len = ftell(f);
    fseek(f, 0, SEEK_SET);
    bytes = (size_t)len;
    asset = malloc(bytes);
    if (!asset || fread(asset, 1, bytes, f) != bytes) return 2;
    fclose(f);
    if (romrt_arena_size(asset, bytes, &arena_bytes, &err) != ROMRT_OK || !(arena = malloc(arena_bytes)) ||
        romrt_open(asset, bytes, arena, arena_bytes, &m, &err) != ROMRT_OK) {
        printf("FAIL open: %s\n", err.message);
        return 1;
    }
    romrt_add_vertex_force(m, romrt_shown_count(m) - 1, push, NULL);
    for (k = 0; k < 5; k++) romrt_step(m, &err);
    n = romrt_shown_count(m);
    r = romrt_reduced_size(m);
    nr = (size_t)3 * (size_t)n * (size_t)r;

    /* one vertex short: refused (an overrun would write 3 reals past the buffer's end) */
    b = reals(3 * (size_t)(n - 1));
    check(romrt_positions(m, b, 3 * (size_t)(n - 1), 3, NULL) == ROMRT_E_ARGUMENT, "asan_positions_one_vertex_short_refused");
    check(romrt_rest_positions(m, b, 3 * (size_t)(n - 1), 3, NULL) == ROMRT_E_ARGUMENT, "asan_rest_positions_one_vertex_short_refused");
    free(b);
    /* exactly n vertices, packed and interleaved (the last vertex needs only its 3 reals) */
    b = reals(3 * (size_t)n);
    check(romrt_positions(m, b, 3 * (size_t)n, 3, NULL) == ROMRT_OK && romrt_rest_positions(m, b, 3 * (size_t)n, 3, NULL) == ROMRT_OK,
          "asan_positions_exact_packed_buffer");
    free(b);
    b = reals(7 * (size_t)(n - 1) + 3);
    check(romrt_positions(m, b, 7 * (size_t)n, 7, NULL) == ROMRT_OK && romrt_rest_positions(m, b, 7 * (size_t)n, 7, NULL) == ROMRT_OK,
          "asan_positions_exact_interleaved_buffer");
    free(b);
    /* basis rows: one real short refused, exact accepted */
    b = reals(nr - 1);
    check(romrt_basis_rows(m, b, nr - 1, NULL) == ROMRT_E_ARGUMENT, "asan_basis_rows_one_short_refused");
    free(b);
    b = reals(nr);
    check(romrt_basis_rows(m, b, nr, NULL) == ROMRT_OK, "asan_basis_rows_exact_buffer");
    free(b);
    b = reals((size_t)r - 1);
    check(romrt_reduced_coordinates(m, b, r - 1, NULL) == ROMRT_E_ARGUMENT, "asan_reduced_coordinates_one_short_refused");
    free(b);
    b = reals((size_t)r);
    check(romrt_reduced_coordinates(m, b, r, NULL) == ROMRT_OK, "asan_reduced_coordinates_exact_buffer");
    free(b);
    free(arena);
    free(asset);
    return failures != 0;
}
