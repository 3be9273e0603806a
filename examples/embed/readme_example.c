/* The README's example, the same text as its code block (tests/integration/readme_example.sh). */
#include <stdio.h>
#include <stdlib.h>
#include "romrt.h"

int main(int argc, char **argv)
{
    static double asset[1 << 21];                 /* 16 MB, 8-byte aligned as romrt_open wants */
    FILE *f = argc == 2 ? fopen(argv[1], "rb") : NULL;
    size_t bytes = f ? fread(asset, 1, sizeof asset, f) : 0, need = 0, n, tip, k;
    const romrt_real push[3] = {0, 0, 0.05};      /* newtons, held until cleared */
    romrt_real *xyz;
    void *arena = NULL;
    romrt_model *m;
    romrt_error err;                              /* every call's status, with what and where */
    if (!f || fclose(f)) return fprintf(stderr, "usage: readme_example ASSET.rombin\n"), 2;
    if (romrt_arena_size(asset, bytes, &need, &err) ||
        romrt_open(asset, bytes, arena = malloc(need), need, &m, &err))      /* NULL is refused */
        return fprintf(stderr, "open: %s\n", err.message), 1;             /* names the chunk and index */
    n = romrt_shown_count(m);                                              /* the vertices to draw */
    if (!(xyz = malloc(sizeof *xyz * 3 * n))) return fprintf(stderr, "out of memory\n"), 1;
    if (romrt_find_group(m, "tip", &tip, &err) || romrt_add_force(m, tip, push, &err))
        return fprintf(stderr, "push: %s\n", err.message), 1;             /* no group "tip" */
    for (k = 0; k < 100; k++)
        if (romrt_step(m, &err) || romrt_positions(m, xyz, 3 * n, 3, &err)) /* 3 n reals, packed */
            return fprintf(stderr, "step %zu: %s\n", k, err.message), 1;
    printf("t = %g s, vertex %zu at %g %g %g\n", romrt_time(m), n - 1,
           (double)xyz[3 * n - 3], (double)xyz[3 * n - 2], (double)xyz[3 * n - 1]);
    free(xyz);
    free(arena);                                  /* the model lives in it: nothing to close */
    return 0;
}
