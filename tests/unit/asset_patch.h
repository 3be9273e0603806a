/* Shared by the runtime tests that damage an asset on purpose: bytes of one chunk's payload
 * overwritten, the chunk's CRC and the table's recomputed (formats/ROMBIN.md), so that the damage
 * gets past the container's checks and reaches the model's. */
#ifndef RK_TEST_ASSET_PATCH_H
#define RK_TEST_ASSET_PATCH_H

#include <stdint.h>
#include <string.h>

#include "formats/rombin.h"
#include "formats/rombin_read.h"

/* Overwrites n bytes of chunk `id`'s payload at `offset` (little-endian machine, as the format). */
static inline void asset_patch_chunk(unsigned char *asset, const char *id, size_t offset, const void *bytes, size_t n)
{
    uint32_t count, crc;
    memcpy(&count, asset + ROMBIN_H_CHUNKS, 4);
    for (uint32_t i = 0; i < count; i++) {
        unsigned char *e = asset + ROMBIN_HEADER_BYTES + (size_t)i * ROMBIN_ENTRY_BYTES;
        uint64_t off, stored;
        if (memcmp(e + ROMBIN_E_ID, id, 4) != 0) continue;
        memcpy(&off, e + ROMBIN_E_OFFSET, 8);
        memcpy(&stored, e + ROMBIN_E_STORED, 8);
        memcpy(asset + off + offset, bytes, n);
        crc = rombin_crc32(0, asset + off, (size_t)stored);
        memcpy(e + ROMBIN_E_CRC, &crc, 4);
    }
    crc = rombin_crc32(0, asset, ROMBIN_H_TABLE_CRC);
    crc = rombin_crc32(crc, asset + ROMBIN_HEADER_BYTES, (size_t)count * ROMBIN_ENTRY_BYTES);
    memcpy(asset + ROMBIN_H_TABLE_CRC, &crc, 4);
}

#endif
