/* A baked asset's bytes for the benches that open it with the runtime (bench_pour.c,
 * bench_alrom_split.c, bench_assets.c, bench_newton_modes.c): the whole file, 16-byte aligned as
 * romrt_open reads it in place. */
#ifndef BENCH_READ_H
#define BENCH_READ_H

#include <stdio.h>
#include <stdlib.h>

/* The file's bytes (free() them) and their count in *bytes; NULL when it cannot be opened or read,
 * or is empty. */
static unsigned char *bench_read_file(const char *path, size_t *bytes)
{
    FILE *f = fopen(path, "rb");
    long n;
    unsigned char *data = NULL;
    *bytes = 0;
    if (!f) return NULL;
    if (!fseek(f, 0, SEEK_END) && (n = ftell(f)) > 0 && !fseek(f, 0, SEEK_SET)) {
        *bytes = (size_t)n;
        data = aligned_alloc(16, ((size_t)n + 15) / 16 * 16);
        if (data && fread(data, 1, *bytes, f) != *bytes) {
            free(data);
            data = NULL;
        }
    }
    fclose(f);
    return data;
}

#endif
