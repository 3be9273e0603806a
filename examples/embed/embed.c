/* A host program that embeds the romkit runtime, using only romrt.h: load an asset, ask for the
 * arena, open it in place, push the "tip" group for a while, step, print where the tip is. Then
 * what an engine deforming on the GPU does: the rest positions X and basis rows U of the shown
 * vertices uploaded once, the r reduced coordinates q per frame, x = X + U q in the vertex shader
 * (here a loop standing in for it, checked against romrt_positions).
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
    const romrt_real push[3] = {0, 0, 0.05}; /* newtons, sideways */
    size_t tip, i, n, r, j;
    int steps = argc > 2 ? atoi(argv[2]) : 100, k;
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
    printf("opened: r = %lu, %lu shown vertices, %lu triangles, %lu groups, arena %lu bytes\n",
           (unsigned long)romrt_reduced_size(m), (unsigned long)romrt_shown_count(m),
           (unsigned long)romrt_triangle_count(m), (unsigned long)romrt_group_count(m), (unsigned long)arena_bytes);
    /* an asset without a "tip" group is pushed nowhere (the refusal names the group count) */
    if (romrt_find_group(m, "tip", &tip, &err) == ROMRT_OK && romrt_add_force(m, tip, push, &err) != ROMRT_OK) {
        fprintf(stderr, "embed: push: %s\n", err.message);
        return 1;
    }
    for (k = 0; k < steps; k++) {
        if (k == steps / 2 && romrt_clear_forces(m, &err) != ROMRT_OK) return 1; /* let go half-way */
        if (romrt_step(m, &err) != ROMRT_OK) {
            fprintf(stderr, "embed: step %d: %s: %s\n", k, romrt_status_string(err.status), err.message);
            return 1;
        }
    }
    /* The shown vertex farthest along x stands for the tip. The buffer holds romrt_shown_count
     * vertices and says so: romrt_positions refuses a smaller one rather than overrun it. */
    n = romrt_shown_count(m);
    {
        romrt_real *all = (romrt_real *)malloc(sizeof(romrt_real) * 3 * n);
        size_t best = 0;
        if (!all || romrt_positions(m, all, 3 * n, 3, &err) != ROMRT_OK) return 1;
        for (i = 1; i < n; i++)
            if (all[3 * i] > all[3 * best]) best = i;
        for (i = 0; i < 3; i++) xyz[i] = all[3 * best + i];
        free(all);
    }
    printf("after %d steps (t = %.3f s): tip at %.6f %.6f %.6f\n", steps, romrt_time(m), (double)xyz[0],
           (double)xyz[1], (double)xyz[2]);

    /* On the GPU: an interleaved vertex buffer (position and normal, 6 reals a vertex) takes the
     * rest positions at stride 6; the rows U (3 r reals a vertex: rows[(3 i + k) r + j]) go to a
     * storage buffer once; per frame only q (r reals) is uploaded and the shader computes
     * x_ik = X_ik + sum_j U[(3 i + k) r + j] q_j. */
    r = romrt_reduced_size(m);
    {
        romrt_real *vbo = (romrt_real *)calloc(6 * n, sizeof(romrt_real));
        romrt_real *rows = (romrt_real *)malloc(sizeof(romrt_real) * 3 * n * r);
        romrt_real *q = (romrt_real *)malloc(sizeof(romrt_real) * r);
        romrt_real *x = (romrt_real *)malloc(sizeof(romrt_real) * 3 * n);
        double worst = 0;
        if (!vbo || !rows || !q || !x || romrt_rest_positions(m, vbo, 6 * n, 6, &err) != ROMRT_OK ||
            romrt_basis_rows(m, rows, 3 * n * r, &err) != ROMRT_OK ||
            romrt_reduced_coordinates(m, q, r, &err) != ROMRT_OK || romrt_positions(m, x, 3 * n, 3, &err) != ROMRT_OK)
            return 1;
        for (i = 0; i < 3 * n; i++) { /* the vertex shader's sum: vertex i / 3, axis i % 3 */
            double s = vbo[6 * (i / 3) + i % 3], d;
            for (j = 0; j < r; j++) s += (double)rows[i * r + j] * q[j];
            d = s > x[i] ? s - x[i] : x[i] - s;
            if (d > worst) worst = d;
        }
        printf("on the GPU: X + U q (r = %lu) against romrt_positions: %.1e m at most\n", (unsigned long)r, worst);
        free(vbo);
        free(rows);
        free(q);
        free(x);
    }
    free(arena);
    free(asset);
    return 0;
}
