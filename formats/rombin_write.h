/* formats/rombin_write.h: the toolchain's .rombin writer (C11, zlib for deflate). Deterministic:
 * the bytes depend only on the chunks added, in the order added (no timestamps, fixed zlib
 * level). Written atomically through util/atomic_file (a temporary file, then rename). */
#ifndef ROMBIN_WRITE_H
#define ROMBIN_WRITE_H

#include <stddef.h>
#include <stdint.h>

#include "formats/rombin.h"
#include "util/util.h"

typedef struct {
    char id[5];
    uint32_t flags;            /* critical and type; compression is decided when serializing */
    unsigned char *data;       /* raw payload (owned) */
    size_t bytes;
} rombin_out_chunk;

typedef struct {
    int real_type;             /* ROMBIN_REAL_F32 or ROMBIN_REAL_F64 */
    int compress;              /* deflate each chunk that shrinks by it */
    int count;
    rombin_out_chunk chunk[ROMBIN_MAX_CHUNKS];
} rombin_writer;

void rombin_writer_init(rombin_writer *w, int real_type, int compress);
void rombin_writer_free(rombin_writer *w);

/* Each copies its payload. The id must be 4 letters or digits and new to the writer. Reals
 * are converted to the file's type and must be finite (and representable in float32). */
int rombin_add_bytes(rombin_writer *w, const char *id, int critical, const void *data, size_t n, rk_error *err);
int rombin_add_u32(rombin_writer *w, const char *id, int critical, const uint32_t *v, size_t n, rk_error *err);
int rombin_add_reals(rombin_writer *w, const char *id, int critical, const double *v, size_t n, rk_error *err);

/* The whole file in memory (malloc'd). */
int rombin_serialize(const rombin_writer *w, unsigned char **out, size_t *bytes, rk_error *err);
/* Writes a serialized file to PATH atomically. */
int rombin_save(const char *path, const unsigned char *data, size_t bytes, rk_error *err);

/* A validated file with every deflated chunk inflated (stored), for consumers that open assets
 * in place: the runtime reads stored chunks only. Same chunks, same order, same CRC rules. */
int rombin_inflate_all(const void *data, size_t size, unsigned char **out, size_t *bytes, rk_error *err);

/* When *data (malloc'd, *size bytes) is a valid file with deflated chunks, replaces it by its
 * rombin_inflate_all copy and sets *inflated; otherwise leaves it (a file the container reader
 * refuses is left for the caller's own reader to report). */
int rombin_inflate_in_place(unsigned char **data, size_t *size, int *inflated, rk_error *err);

/* Reads a whole file into memory (malloc'd, 16-byte aligned so its payloads can be used in place). */
int rombin_read_file(const char *path, unsigned char **data, size_t *size, rk_error *err);

#endif
