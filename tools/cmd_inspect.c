/* romkit inspect ASSET.rombin: the container's chunks, sizes and checksums, verified; the
 * model's sizes when the runtime can open it. Exit 1 on any damage. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "commands.h"
#include "formats/rombin_read.h"
#include "formats/rombin_write.h"
#include "runtime/romrt.h"

static void inspect_usage(FILE *f)
{
    fprintf(f, "usage: romkit inspect ASSET.rombin\n"
               "  lists the chunks (id, critical or optional, type, compression, stored and raw bytes,\n"
               "  CRC-32), verifies the container and every checksum, then opens the model with the\n"
               "  runtime's validation. Exit status 1 on any damage.\n\n"
               "example (after romkit build examples/scenes/cantilever_small.json -o cantilever.rombin):\n"
               "  romkit inspect cantilever.rombin\n");
}

int cmd_inspect(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (is_help(argv[i])) {
            inspect_usage(stdout);
            return 0;
        }
    const char *path;
    const cli_option opts[] = {{NULL, NULL, NULL}};
    if (cli_parse("inspect", argc, argv, opts, &path, "asset file")) {
        inspect_usage(stderr);
        return 2;
    }
    rk_error err = {{0}};
    unsigned char *data = NULL;
    size_t size;
    if (rombin_read_file(path, &data, &size, &err)) {
        fprintf(stderr, "romkit inspect: %s\n", err.msg);
        return 1;
    }
    rombin_file f;
    rombin_error e;
    if (rombin_open(&f, data, size, NULL, &e)) {
        fprintf(stderr, "romkit inspect: %s: %s\n", path, e.message);
        free(data);
        return 1;
    }
    static const char *const types[] = {"bytes", "u32", "real"};
    printf("%s: rombin %u.%u, %s reals, %u chunks, %zu bytes\n", path, f.major, f.minor,
           f.real_type == ROMBIN_REAL_F32 ? "float32" : "float64", f.count, size);
    printf("  %-4s  %-8s  %-4s  %-7s  %10s  %10s  %10s  %s\n", "id", "kind", "type", "coding", "offset", "stored", "raw",
           "crc32");
    for (unsigned i = 0; i < f.count; i++) {
        rombin_chunk c;
        rombin_chunk_get(&f, i, &c);
        printf("  %-4s  %-8s  %-4s  %-7s  %10llu  %10llu  %10llu  %08x ok\n", c.id, c.critical ? "critical" : "optional",
               types[c.type], c.compression ? "deflate" : "stored", (unsigned long long)c.offset,
               (unsigned long long)c.stored, (unsigned long long)c.raw, (unsigned)c.crc);
    }
    int inflated;
    if (rombin_inflate_in_place(&data, &size, &inflated, &err)) {
        fprintf(stderr, "romkit inspect: %s: %s\n", path, err.msg);
        free(data);
        return 1;
    }
    /* every model the asset holds: a reduced model, a Koopman operator, or both */
    static const romrt_kind kinds[2] = {ROMRT_KIND_REDUCED, ROMRT_KIND_KOOPMAN};
    static const char *const names[2] = {"reduced model", "Koopman operator"};
    int rc = 0, models = 0;
    for (int k = 0; k < 2; k++) {
        size_t arena;
        romrt_error rerr;
        romrt_status st = romrt_arena_size_kind(data, size, kinds[k], &arena, &rerr);
        if (st == ROMRT_E_UNSUPPORTED && strstr(rerr.message, k ? "has no Koopman operator" : "has no reduced model"))
            continue; /* not in this asset */
        models++;
        if (st != ROMRT_OK) {
            fprintf(stderr, "romkit inspect: %s: %s: %s: %s\n", path, names[k], romrt_status_string(rerr.status), rerr.message);
            rc = 1;
            break; /* a damaged container would say the same for the other model */
        } else {
            romrt_limits limits;
            limits.size = sizeof limits;
            romrt_get_limits(&limits, NULL);
            printf("%s: opens with the runtime (float32, r up to %zu) in a %zu-byte arena%s\n", names[k],
                   limits.max_reduced_size, arena, inflated ? " once inflated" : "");
        }
    }
    if (!models) {
        fprintf(stderr, "romkit inspect: %s: holds no model (neither HEAD nor KHED)\n", path);
        rc = 1;
    }
    free(data);
    return rc;
}
