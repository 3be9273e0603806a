/* rt_push: steps an asset through the float runtime (build/lib/libromrt.a) as an app would, with a
 * force on a group and on a vertex, and writes every step's shown positions as raw float32
 * (steps x shown x 3, this machine's byte order) to OUT. The Python binding's test runs the same
 * pushes through ctypes and compares bit for bit (tests/integration/python_binding.sh).
 * Usage: rt_push ASSET STEPS OUT [GROUP FX FY FZ [VERTEX VX VY VZ [CLEAR_AT]]]
 *   GROUP "-" pushes no group; VERTEX -1 no vertex; CLEAR_AT: romrt_clear_forces before that step. */
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
        data = malloc((size_t)n);
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
    romrt_error err;
    romrt_model *m;
    void *asset, *arena;
    romrt_real *xyz;
    FILE *out;
    int steps, n, k, vertex = -1, clear_at = -1;
    if (sizeof(romrt_real) != 4 || (argc != 4 && argc != 8 && argc != 12 && argc != 13)) {
        fprintf(stderr, "usage: rt_push ASSET STEPS OUT [GROUP FX FY FZ [VERTEX VX VY VZ [CLEAR_AT]]]\n");
        return 2;
    }
    steps = atoi(argv[2]);
    if (!(asset = load(argv[1], &bytes)) || romrt_arena_size(asset, bytes, &arena_bytes, &err) != ROMRT_OK ||
        !(arena = malloc(arena_bytes)) || romrt_open(asset, bytes, arena, arena_bytes, &m, &err) != ROMRT_OK) {
        fprintf(stderr, "rt_push: %s: cannot open\n", argv[1]);
        return 1;
    }
    if (argc >= 8 && argv[4][0] != '-') {
        romrt_real f[3];
        size_t g;
        romrt_error err;
        f[0] = (romrt_real)atof(argv[5]), f[1] = (romrt_real)atof(argv[6]), f[2] = (romrt_real)atof(argv[7]);
        if (romrt_find_group(m, argv[4], &g, &err) || romrt_add_force(m, g, f, &err) != ROMRT_OK)
            return fprintf(stderr, "rt_push: group %s refused: %s\n", argv[4], err.message), 1;
    }
    if (argc >= 12 && (vertex = atoi(argv[8])) >= 0) {
        romrt_real f[3];
        f[0] = (romrt_real)atof(argv[9]), f[1] = (romrt_real)atof(argv[10]), f[2] = (romrt_real)atof(argv[11]);
        if (romrt_add_vertex_force(m, vertex, f, NULL) != ROMRT_OK) return fprintf(stderr, "rt_push: vertex refused\n"), 1;
    }
    if (argc == 13) clear_at = atoi(argv[12]);
    n = romrt_shown_count(m);
    xyz = (romrt_real *)malloc(sizeof(romrt_real) * 3 * (size_t)n + 1);
    if (!xyz || !(out = fopen(argv[3], "wb"))) return 1;
    for (k = 0; k < steps; k++) {
        if (k == clear_at) romrt_clear_forces(m, NULL);
        if (romrt_step(m, &err) != ROMRT_OK) return fprintf(stderr, "rt_push: step %d: %s\n", k, err.message), 1;
        if (romrt_positions(m, xyz, 3 * (size_t)n, 3, NULL) != ROMRT_OK || fwrite(xyz, sizeof(romrt_real), 3 * (size_t)n, out) != 3 * (size_t)n)
            return 1;
    }
    if (fclose(out) != 0) return 1;
    free(xyz);
    free(arena);
    free(asset);
    return 0;
}
