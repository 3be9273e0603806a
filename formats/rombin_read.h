/* formats/rombin_read.h: the validating .rombin reader. C99, no dependencies, no allocation,
 * no global state; compiled into the runtime and into the toolchain (romkit inspect).
 *
 * rombin_open checks the whole container once (ROMBIN.md, "What a reader checks"): signature,
 * version, platform sentinels, the table's CRC and layout, every reserved field, every
 * chunk's bounds and CRC. After it succeeds, rombin_chunk_get / rombin_find hand out chunks
 * whose bytes are known to lie inside the buffer and to be intact. What the chunks mean is
 * the consumer's business (runtime/open.c for the reduced model). */
#ifndef ROMBIN_READ_H
#define ROMBIN_READ_H

#include <stddef.h>
#include <stdint.h>

#include "formats/rombin.h"

typedef enum {
    ROMBIN_OK = 0,
    ROMBIN_E_ARGUMENT,     /* NULL buffer or pointer */
    ROMBIN_E_DAMAGED,      /* truncated, bad signature, bad CRC, overlapping or out-of-bounds chunks */
    ROMBIN_E_VERSION,      /* another major version */
    ROMBIN_E_PLATFORM,     /* the machine's byte order or float format differs from the file's */
    ROMBIN_E_UNSUPPORTED   /* an unknown critical chunk, or a feature this reader lacks */
} rombin_status;

/* Messages name what failed and where; define ROMBIN_NO_MESSAGES to compile the texts out
 * (status and chunk id remain). */
#define ROMBIN_MESSAGE_BYTES 160
typedef struct {
    int status;
    char chunk[5];                    /* the chunk involved, or "" */
    char message[ROMBIN_MESSAGE_BYTES];
} rombin_error;

typedef struct {
    char id[5];
    uint32_t flags;
    int critical, type, compression;  /* ROMBIN_TYPE_*, ROMBIN_COMP_* */
    uint64_t offset, stored, raw;
    uint32_t crc;
    const unsigned char *data;        /* the stored bytes (aligned like the buffer + offset) */
} rombin_chunk;

typedef struct {
    const unsigned char *base;
    uint64_t size;
    unsigned major, minor;
    unsigned real_type;               /* ROMBIN_REAL_* */
    unsigned count;                   /* chunks */
} rombin_file;

/* Validates a whole file held in memory. known: NULL-terminated ids the caller understands;
 * a critical chunk outside it is ROMBIN_E_UNSUPPORTED (NULL: accept every id). */
int rombin_open(rombin_file *f, const void *data, size_t size, const char *const *known, rombin_error *e);
/* Chunk `index` of an opened file (0 <= index < count). */
void rombin_chunk_get(const rombin_file *f, unsigned index, rombin_chunk *c);
/* 1 and *c when the file has chunk `id`, else 0. */
int rombin_find(const rombin_file *f, const char *id, rombin_chunk *c);

/* CRC-32 (IEEE 802.3, the zlib one): crc = rombin_crc32(0, data, n), chainable. */
uint32_t rombin_crc32(uint32_t crc, const void *data, size_t n);

/* Little-endian field access (byte-wise, any alignment). */
uint32_t rombin_get_u32(const unsigned char *p);
uint64_t rombin_get_u64(const unsigned char *p);

/* Message building without stdio: e->status = status, e->chunk = chunk (or NULL), and
 * e->message = text1 [number text2 [number2 text3]]. Returns status. */
int rombin_fail(rombin_error *e, int status, const char *chunk, const char *text1);
int rombin_fail_n(rombin_error *e, int status, const char *chunk, const char *text1, uint64_t n,
                  const char *text2);
int rombin_fail_nn(rombin_error *e, int status, const char *chunk, const char *text1, uint64_t n,
                   const char *text2, uint64_t n2, const char *text3);

#endif
