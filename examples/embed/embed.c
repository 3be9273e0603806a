/* A host program that embeds the romkit runtime, using only romrt.h: load an asset, ask for the
 * arena, open it in place, push the "tip" group for a while, step, print where the tip is.
 * Build from the tree: the Makefile's $(BUILD)/embed (-Iruntime); against an installed runtime
 * (make install): cc embed.c $(pkg-config --cflags --libs romrt). Run: embed ASSET.rombin [STEPS]. */
#include <stdio.h>
#include <stdlib.h>

#include "romrt.h"

static void *load(const char *path, size_t *bytes)
{
    FILE *f = fopen(path, "rb");
    void *data = NULL;
    long n;
    if (!f) return NULL;
    if (fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) > 0 && fseek(f, 0, SEEK_SET) == 0) {
        data = malloc((size_t)n); /* malloc's alignment (>= 8) is what romrt_open needs */
        if (data && fread(data, 1, (size_t)n, f) != (size_t)n) {
            free(data);
            data = NULL;
        }
        *bytes = (size_t)n;
    }
    fclose(f);
    return data;
}

int main(int argc, char **argv)
{
    size_t bytes = 0, arena_bytes = 0;
    void *asset, *arena;
    romrt_model *m;
    romrt_error err;
    romrt_real xyz[3];
    int steps = argc > 2 ? atoi(argv[2]) : 100, tip, k, i, n;
    if (argc < 2) {
        fprintf(stderr, "usage: embed ASSET.rombin [STEPS]\n");
        return 2;
    }
    asset = load(argv[1], &bytes);
    if (!asset) {
        fprintf(stderr, "embed: cannot read %s\n", argv[1]);
        return 1;
    }
    if (romrt_arena_size(asset, bytes, &arena_bytes, &err) != ROMRT_OK ||
        !(arena = malloc(arena_bytes)) ||
        romrt_open(asset, bytes, arena, arena_bytes, &m, &err) != ROMRT_OK) {
        fprintf(stderr, "embed: %s: %s\n", romrt_status_string(err.status), err.message);
        return 1;
    }
    printf("opened: r = %d, %d shown vertices, %d triangles, %d groups, arena %lu bytes\n", romrt_reduced_size(m),
           romrt_shown_count(m), romrt_triangle_count(m), romrt_group_count(m), (unsigned long)arena_bytes);
    tip = romrt_find_group(m, "tip");
    if (tip >= 0) {
        const romrt_real push[3] = {0, 0, 0.05}; /* newtons, sideways */
        romrt_add_force(m, tip, push);
    }
    for (k = 0; k < steps; k++) {
        if (k == steps / 2) romrt_clear_forces(m); /* let go half-way */
        if (romrt_step(m, &err) != ROMRT_OK) {
            fprintf(stderr, "embed: step %d: %s: %s\n", k, romrt_status_string(err.status), err.message);
            return 1;
        }
    }
    /* The shown vertex farthest along x stands for the tip. */
    n = romrt_shown_count(m);
    {
        romrt_real *all = (romrt_real *)malloc(sizeof(romrt_real) * 3 * (size_t)n);
        int best = 0;
        if (!all || romrt_positions(m, all, n, 3) != ROMRT_OK) return 1;
        for (i = 1; i < n; i++)
            if (all[3 * i] > all[3 * best]) best = i;
        for (i = 0; i < 3; i++) xyz[i] = all[3 * best + i];
        free(all);
    }
    printf("after %d steps (t = %.3f s): tip at %.6f %.6f %.6f\n", steps, (double)romrt_time(m), (double)xyz[0],
           (double)xyz[1], (double)xyz[2]);
    free(arena);
    free(asset);
    return 0;
}
