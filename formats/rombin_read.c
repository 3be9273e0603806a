/* The validating .rombin reader (rombin_read.h). Every length read from the file is checked
 * against the buffer with subtraction, never with an addition that could wrap. */
#include "formats/rombin_read.h"

#include <string.h>

uint32_t rombin_get_u32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

uint64_t rombin_get_u64(const unsigned char *p)
{
    return (uint64_t)rombin_get_u32(p) | (uint64_t)rombin_get_u32(p + 4) << 32;
}

/* Nibble-table CRC-32 (reflected polynomial 0xEDB88320): 64 bytes of table, small enough for
 * flash, two lookups per byte. */
uint32_t rombin_crc32(uint32_t crc, const void *data, size_t n)
{
    static const uint32_t table[16] = {
        0x00000000u, 0x1DB71064u, 0x3B6E20C8u, 0x26D930ACu, 0x76DC4190u, 0x6B6B51F4u,
        0x4DB26158u, 0x5005713Cu, 0xEDB88320u, 0xF00F9344u, 0xD6D6A3E8u, 0xCB61B38Cu,
        0x9B64C2B0u, 0x86D3D2D4u, 0xA00AE278u, 0xBDBDF21Cu};
    const unsigned char *p = (const unsigned char *)data;
    size_t i;
    crc = ~crc;
    for (i = 0; i < n; i++) {
        crc ^= p[i];
        crc = (crc >> 4) ^ table[crc & 15];
        crc = (crc >> 4) ^ table[crc & 15];
    }
    return ~crc;
}

/* ---- messages ---- */

#ifndef ROMBIN_NO_MESSAGES
static size_t append(char *buf, size_t at, const char *s)
{
    while (s && *s && at + 1 < ROMBIN_MESSAGE_BYTES) buf[at++] = *s++;
    buf[at] = 0;
    return at;
}

static size_t append_number(char *buf, size_t at, uint64_t n)
{
    char digits[21];
    int k = 0;
    do {
        digits[k++] = (char)('0' + (int)(n % 10));
        n /= 10;
    } while (n);
    while (k > 0 && at + 1 < ROMBIN_MESSAGE_BYTES) buf[at++] = digits[--k];
    buf[at] = 0;
    return at;
}
#endif

static int fail_with(rombin_error *e, int status, const char *chunk, const char *t1, int numbers, uint64_t n,
                     const char *t2, uint64_t n2, const char *t3)
{
    if (!e) return status;
    e->status = status;
    memset(e->chunk, 0, sizeof e->chunk);
    if (chunk) memcpy(e->chunk, chunk, strlen(chunk) < 4 ? strlen(chunk) : 4);
    e->message[0] = 0;
#ifndef ROMBIN_NO_MESSAGES
    {
        size_t at = 0;
        if (chunk && *chunk) {
            at = append(e->message, at, "chunk '");
            at = append(e->message, at, e->chunk);
            at = append(e->message, at, "': ");
        }
        at = append(e->message, at, t1);
        if (numbers > 0) {
            at = append_number(e->message, at, n);
            at = append(e->message, at, t2);
        }
        if (numbers > 1) {
            at = append_number(e->message, at, n2);
            at = append(e->message, at, t3);
        }
    }
#else
    (void)t1; (void)numbers; (void)n; (void)t2; (void)n2; (void)t3;
#endif
    return status;
}

int rombin_fail(rombin_error *e, int status, const char *chunk, const char *text1)
{
    return fail_with(e, status, chunk, text1, 0, 0, 0, 0, 0);
}

int rombin_fail_n(rombin_error *e, int status, const char *chunk, const char *text1, uint64_t n, const char *text2)
{
    return fail_with(e, status, chunk, text1, 1, n, text2, 0, 0);
}

int rombin_fail_nn(rombin_error *e, int status, const char *chunk, const char *text1, uint64_t n,
                   const char *text2, uint64_t n2, const char *text3)
{
    return fail_with(e, status, chunk, text1, 2, n, text2, n2, text3);
}

/* ---- the container ---- */

static int check_signature(const unsigned char *p, rombin_error *e)
{
    static const char expected[] = ROMBIN_SIGNATURE;
    if (memcmp(p, expected, ROMBIN_SIGNATURE_BYTES) == 0) return ROMBIN_OK;
    if (p[0] == 0x09 && memcmp(p + 1, "ROM", 3) == 0)
        return rombin_fail(e, ROMBIN_E_DAMAGED, 0, "signature: the first byte lost its high bit (a 7-bit transfer)");
    if (memcmp(p, "\x89ROM", 4) == 0)
        return rombin_fail(e, ROMBIN_E_DAMAGED, 0, "signature: line endings were converted (a text-mode transfer)");
    return rombin_fail(e, ROMBIN_E_DAMAGED, 0, "not a .rombin file (no signature)");
}

static int check_platform(const unsigned char *p, rombin_error *e)
{
    uint32_t endian;
    float f32;
    double f64;
    static const float want32 = ROMBIN_F32_SENTINEL;
    static const double want64 = ROMBIN_F64_SENTINEL;
    memcpy(&endian, p + ROMBIN_H_ENDIAN, 4);
    if (endian != ROMBIN_ENDIAN_SENTINEL) {
        if (rombin_get_u32(p + ROMBIN_H_ENDIAN) == ROMBIN_ENDIAN_SENTINEL)
            return rombin_fail(e, ROMBIN_E_PLATFORM, 0, "the asset is little-endian and this machine is not");
        return rombin_fail(e, ROMBIN_E_DAMAGED, 0, "header: byte-order sentinel damaged");
    }
    memcpy(&f32, p + ROMBIN_H_F32, 4);
    memcpy(&f64, p + ROMBIN_H_F64, 8);
    if (memcmp(&f32, &want32, 4) != 0 || memcmp(&f64, &want64, 8) != 0)
        return rombin_fail(e, ROMBIN_E_PLATFORM, 0,
                           "header: float sentinels differ (damaged, or this machine's floats are not IEEE 754)");
    return ROMBIN_OK;
}

static int all_zero(const unsigned char *p, uint64_t n)
{
    uint64_t i;
    for (i = 0; i < n; i++)
        if (p[i]) return 0;
    return 1;
}

static int id_is_printable(const unsigned char *id)
{
    int k;
    for (k = 0; k < 4; k++) {
        unsigned char c = id[k];
        if (!((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_')) return 0;
    }
    return 1;
}

static int is_known(const char *const *known, const char *id)
{
    if (!known) return 1;
    for (; *known; known++)
        if (memcmp(*known, id, 4) == 0) return 1;
    return 0;
}

void rombin_chunk_get(const rombin_file *f, unsigned index, rombin_chunk *c)
{
    const unsigned char *p = f->base + ROMBIN_HEADER_BYTES + (size_t)index * ROMBIN_ENTRY_BYTES;
    memcpy(c->id, p + ROMBIN_E_ID, 4);
    c->id[4] = 0;
    c->flags = rombin_get_u32(p + ROMBIN_E_FLAGS);
    c->critical = (c->flags & ROMBIN_FLAG_CRITICAL) != 0;
    c->type = (int)((c->flags & ROMBIN_TYPE_MASK) >> ROMBIN_TYPE_SHIFT);
    c->compression = (int)((c->flags & ROMBIN_COMP_MASK) >> ROMBIN_COMP_SHIFT);
    c->offset = rombin_get_u64(p + ROMBIN_E_OFFSET);
    c->stored = rombin_get_u64(p + ROMBIN_E_STORED);
    c->raw = rombin_get_u64(p + ROMBIN_E_RAW);
    c->crc = rombin_get_u32(p + ROMBIN_E_CRC);
    /* Only a pointer inside the buffer is formed; rombin_open rejects an entry that points outside. */
    c->data = c->offset <= f->size ? f->base + (size_t)c->offset : 0;
}

int rombin_find(const rombin_file *f, const char *id, rombin_chunk *c)
{
    unsigned i;
    for (i = 0; i < f->count; i++) {
        rombin_chunk_get(f, i, c);
        if (memcmp(c->id, id, 4) == 0) return 1;
    }
    return 0;
}

/* One table entry on its own: id, flags, bounds, sizes. `end` is where the previous payload
 * ended (payloads are in table order, ascending, not overlapping). */
static int check_entry(const rombin_file *f, const rombin_chunk *c, const unsigned char *raw_entry, uint64_t end,
                       unsigned real_bytes, rombin_error *e)
{
    uint64_t element;
    if (!id_is_printable((const unsigned char *)c->id))
        return rombin_fail(e, ROMBIN_E_DAMAGED, 0, "chunk table: an id is not 4 letters or digits");
    if (c->flags & ~(uint32_t)ROMBIN_FLAGS_KNOWN)
        return rombin_fail(e, ROMBIN_E_DAMAGED, c->id, "reserved flag bits are set");
    if (rombin_get_u32(raw_entry + ROMBIN_E_RESERVED) != 0)
        return rombin_fail(e, ROMBIN_E_DAMAGED, c->id, "reserved table field is not zero");
    if (c->type > ROMBIN_TYPE_REAL)
        return rombin_fail_n(e, ROMBIN_E_DAMAGED, c->id, "unknown element type ", (uint64_t)c->type, "");
    if (c->compression > ROMBIN_COMP_DEFLATE)
        return rombin_fail_n(e, ROMBIN_E_DAMAGED, c->id, "unknown compression ", (uint64_t)c->compression, "");
    if (c->offset % ROMBIN_ALIGN != 0)
        return rombin_fail_n(e, ROMBIN_E_DAMAGED, c->id, "offset ", c->offset, " is not 16-byte aligned");
    if (c->offset < end)
        return rombin_fail_n(e, ROMBIN_E_DAMAGED, c->id, "offset ", c->offset,
                             " overlaps the table or the previous chunk");
    if (c->offset > f->size || c->stored > f->size - c->offset)
        return rombin_fail_nn(e, ROMBIN_E_DAMAGED, c->id, "ends past the end of the file (offset ", c->offset,
                              ", stored bytes ", c->stored, ")");
    if (c->compression == ROMBIN_COMP_NONE && c->raw != c->stored)
        return rombin_fail_nn(e, ROMBIN_E_DAMAGED, c->id, "raw length ", c->raw, " differs from stored length ",
                              c->stored, " of an uncompressed chunk");
    element = c->type == ROMBIN_TYPE_U32 ? 4 : c->type == ROMBIN_TYPE_REAL ? real_bytes : 1;
    if (c->raw % element != 0)
        return rombin_fail_nn(e, ROMBIN_E_DAMAGED, c->id, "raw length ", c->raw, " is not a multiple of ", element,
                              " (its element size)");
    return ROMBIN_OK;
}

int rombin_open(rombin_file *f, const void *data, size_t size, const char *const *known, rombin_error *e)
{
    const unsigned char *p = (const unsigned char *)data;
    uint64_t file_bytes, table_end, end;
    unsigned i, j, real_bytes;
    if (e) {
        e->status = 0;
        e->chunk[0] = 0;
        e->message[0] = 0;
    }
    if (!f || !data) return rombin_fail(e, ROMBIN_E_ARGUMENT, 0, "no asset (NULL)");
    memset(f, 0, sizeof *f);
    if (size < ROMBIN_SIGNATURE_BYTES)
        return rombin_fail_n(e, ROMBIN_E_DAMAGED, 0, "truncated: ", (uint64_t)size, " bytes, not even a signature");
    if (check_signature(p, e)) return ROMBIN_E_DAMAGED;
    if (size < ROMBIN_HEADER_BYTES)
        return rombin_fail_n(e, ROMBIN_E_DAMAGED, 0, "truncated: ", (uint64_t)size, " bytes, the header needs 64");
    f->major = (unsigned)p[ROMBIN_H_MAJOR] | (unsigned)p[ROMBIN_H_MAJOR + 1] << 8;
    f->minor = (unsigned)p[ROMBIN_H_MINOR] | (unsigned)p[ROMBIN_H_MINOR + 1] << 8;
    if (f->major != ROMBIN_VERSION_MAJOR)
        return rombin_fail_nn(e, ROMBIN_E_VERSION, 0, "format version ", f->major, ".", f->minor,
                              ": this reader reads version 1.x");
    {
        int st = check_platform(p, e);
        if (st) return st;
    }
    file_bytes = rombin_get_u64(p + ROMBIN_H_FILE_BYTES);
    if (file_bytes > size)
        return rombin_fail_nn(e, ROMBIN_E_DAMAGED, 0, "truncated: ", (uint64_t)size, " bytes of the ", file_bytes,
                              " the header announces");
    if (file_bytes < size)
        return rombin_fail_nn(e, ROMBIN_E_DAMAGED, 0, "the buffer holds ", (uint64_t)size,
                              " bytes but the header announces ", file_bytes, " (trailing data)");
    f->base = p;
    f->size = file_bytes;
    f->real_type = rombin_get_u32(p + ROMBIN_H_REAL);
    if (f->real_type != ROMBIN_REAL_F32 && f->real_type != ROMBIN_REAL_F64)
        return rombin_fail_n(e, ROMBIN_E_DAMAGED, 0, "header: unknown real type ", f->real_type, "");
    real_bytes = f->real_type == ROMBIN_REAL_F32 ? 4 : 8;
    f->count = rombin_get_u32(p + ROMBIN_H_CHUNKS);
    if (f->count == 0 || f->count > ROMBIN_MAX_CHUNKS)
        return rombin_fail_n(e, ROMBIN_E_DAMAGED, 0, "header: chunk count ", f->count, " is not in 1..64");
    if (rombin_get_u32(p + ROMBIN_H_FLAGS) != 0 || !all_zero(p + ROMBIN_H_RESERVED, ROMBIN_HEADER_BYTES - ROMBIN_H_RESERVED))
        return rombin_fail(e, ROMBIN_E_DAMAGED, 0, "header: reserved fields are not zero");
    table_end = ROMBIN_HEADER_BYTES + (uint64_t)f->count * ROMBIN_ENTRY_BYTES;
    if (table_end > f->size)
        return rombin_fail_nn(e, ROMBIN_E_DAMAGED, 0, "truncated: the chunk table needs ", table_end,
                              " bytes, the file has ", f->size, "");
    {
        uint32_t crc = rombin_crc32(0, p, ROMBIN_H_TABLE_CRC);
        crc = rombin_crc32(crc, p + ROMBIN_HEADER_BYTES, (size_t)(table_end - ROMBIN_HEADER_BYTES));
        if (crc != rombin_get_u32(p + ROMBIN_H_TABLE_CRC))
            return rombin_fail(e, ROMBIN_E_DAMAGED, 0, "header or chunk table CRC mismatch");
    }
    end = table_end;
    for (i = 0; i < f->count; i++) {
        rombin_chunk c;
        int st;
        rombin_chunk_get(f, i, &c);
        st = check_entry(f, &c, p + ROMBIN_HEADER_BYTES + (size_t)i * ROMBIN_ENTRY_BYTES, end, real_bytes, e);
        if (st) return st;
        if (!all_zero(p + end, c.offset - end))
            return rombin_fail(e, ROMBIN_E_DAMAGED, c.id, "the padding before it is not zero");
        for (j = 0; j < i; j++) {
            rombin_chunk other;
            rombin_chunk_get(f, j, &other);
            if (memcmp(other.id, c.id, 4) == 0) return rombin_fail(e, ROMBIN_E_DAMAGED, c.id, "appears twice");
        }
        if (c.critical && !is_known(known, c.id))
            return rombin_fail(e, ROMBIN_E_UNSUPPORTED, c.id, "unknown critical chunk (a newer writer?)");
        if (rombin_crc32(0, c.data, (size_t)c.stored) != c.crc)
            return rombin_fail(e, ROMBIN_E_DAMAGED, c.id, "CRC mismatch (the payload is damaged)");
        end = c.offset + c.stored;
    }
    if (!all_zero(p + end, f->size - end))
        return rombin_fail(e, ROMBIN_E_DAMAGED, 0, "the padding after the last chunk is not zero");
    return ROMBIN_OK;
}
