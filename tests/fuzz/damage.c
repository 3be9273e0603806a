/* damage VALID.rombin OUTDIR: writes damaged variants of a valid asset, one file each, into
 * OUTDIR/bad/ (the runtime must refuse every one, with a message) and OUTDIR/good/ (it must
 * open and step every one). They seed the fuzzer and drive tests/integration/damaged_assets.sh.
 *
 * Toolchain side (stdio, malloc), but linked against formats/rombin_read.c only: no zlib, CRCs
 * by rombin_crc32. Where a variant must get past the container's checks to reach the model's
 * validation, the payload CRC and the table CRC are recomputed so that only the intended field
 * is wrong. A variant whose chunk the asset lacks is skipped with a note on stderr. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "formats/rombin_read.h"
#include "runtime/romrt_impl.h" /* ROMRT_MAX_R: the build's limit, which the damaged r exceeds */

static unsigned char *orig;     /* the valid asset */
static size_t orig_size;
static rombin_file file;        /* opened on orig */
static const char *outdir;
static int real_bytes;          /* 4 or 8 */

/* Variants written per kind, printed at the end. */
static const char *kind_name[32];
static int kind_count[32], kinds;
static int total_bad, total_good;

static void count(const char *kind)
{
    int k;
    for (k = 0; k < kinds; k++)
        if (strcmp(kind_name[k], kind) == 0) break;
    if (k == kinds) {
        if (kinds == 32) return;
        kind_name[kinds++] = kind;
    }
    kind_count[k]++;
}

static void put_u32(unsigned char *p, uint32_t v)
{
    int b;
    for (b = 0; b < 4; b++) p[b] = (unsigned char)(v >> (8 * b));
}

static void put_u64(unsigned char *p, uint64_t v)
{
    put_u32(p, (uint32_t)v);
    put_u32(p + 4, (uint32_t)(v >> 32));
}

static unsigned char *copy(void)
{
    unsigned char *b = malloc(orig_size + 1);
    if (!b) {
        fprintf(stderr, "damage: out of memory\n");
        exit(1);
    }
    memcpy(b, orig, orig_size);
    return b;
}

static unsigned char *entry(unsigned char *buf, unsigned i)
{
    return buf + ROMBIN_HEADER_BYTES + (size_t)i * ROMBIN_ENTRY_BYTES;
}

/* The table CRC covers header bytes [0, 48) and `count` table entries. */
static void fix_table_crc_n(unsigned char *buf, unsigned count)
{
    uint32_t crc = rombin_crc32(0, buf, ROMBIN_H_TABLE_CRC);
    crc = rombin_crc32(crc, buf + ROMBIN_HEADER_BYTES, (size_t)count * ROMBIN_ENTRY_BYTES);
    put_u32(buf + ROMBIN_H_TABLE_CRC, crc);
}

static void fix_table_crc(unsigned char *buf)
{
    fix_table_crc_n(buf, file.count);
}

/* Recomputes chunk i's payload CRC (over its current offset and stored length), then the table's. */
static void fix_chunk_crc(unsigned char *buf, unsigned i)
{
    unsigned char *e = entry(buf, i);
    uint64_t off = rombin_get_u64(e + ROMBIN_E_OFFSET), stored = rombin_get_u64(e + ROMBIN_E_STORED);
    put_u32(e + ROMBIN_E_CRC, rombin_crc32(0, buf + off, (size_t)stored));
    fix_table_crc(buf);
}

/* Writes OUTDIR/SUB/NAME.rombin and frees buf. */
static void emit(const char *sub, const char *kind, unsigned char *buf, size_t size, const char *fmt, ...)
{
    char name[200], path[4096];
    FILE *fp;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(name, sizeof name, fmt, ap);
    va_end(ap);
    snprintf(path, sizeof path, "%s/%s/%s.rombin", outdir, sub, name);
    fp = fopen(path, "wb");
    if (!fp || (size && fwrite(buf, 1, size, fp) != size) || fclose(fp) != 0) {
        fprintf(stderr, "damage: cannot write %s: %s\n", path, strerror(errno));
        exit(1);
    }
    free(buf);
    count(kind);
    if (strcmp(sub, "bad") == 0) total_bad++;
    else total_good++;
}

#define BAD(kind, buf, size, ...) emit("bad", kind, buf, size, __VA_ARGS__)
#define GOOD(kind, buf, size, ...) emit("good", kind, buf, size, __VA_ARGS__)

static int find(const char *id, rombin_chunk *c, unsigned *index)
{
    unsigned i;
    for (i = 0; i < file.count; i++) {
        rombin_chunk_get(&file, i, c);
        if (memcmp(c->id, id, 4) == 0) {
            if (index) *index = i;
            return 1;
        }
    }
    return 0;
}

static void skip(const char *what, const char *id)
{
    fprintf(stderr, "damage: note: skipping %s (the asset has no usable %s chunk)\n", what, id);
}

/* ---- container damage ---- */

static void truncations(void)
{
    size_t cut[4 * ROMBIN_MAX_CHUNKS + 16], n = 0, i, j;
    const char *why[4 * ROMBIN_MAX_CHUNKS + 16];
    char label[4 * ROMBIN_MAX_CHUNKS + 16][24];
    uint64_t table_end = ROMBIN_HEADER_BYTES + (uint64_t)file.count * ROMBIN_ENTRY_BYTES;
    unsigned k;
#define CUT(at, w) (cut[n] = (size_t)(at), why[n] = (w), label[n][0] = 0, n++)
    CUT(0, "empty");
    CUT(5, "in_signature");
    CUT(8, "after_signature");
    CUT(33, "in_header");
    CUT(ROMBIN_HEADER_BYTES - 1, "header_minus_1");
    CUT(ROMBIN_HEADER_BYTES, "header_only");
    CUT(ROMBIN_HEADER_BYTES + ROMBIN_ENTRY_BYTES / 2, "in_table");
    CUT(table_end - 1, "table_minus_1");
    CUT(table_end, "table_end");
    for (k = 0; k < file.count; k++) {
        rombin_chunk c;
        rombin_chunk_get(&file, k, &c);
        CUT(c.offset, "payload_start");
        memcpy(label[n - 1], c.id, 5);
        if (c.stored > 1) {
            CUT(c.offset + c.stored / 2, "payload_middle");
            memcpy(label[n - 1], c.id, 5);
        }
        CUT(c.offset + c.stored, "payload_end");
        memcpy(label[n - 1], c.id, 5);
    }
    CUT(orig_size - 1, "full_minus_1");
#undef CUT
    for (i = 0; i < n; i++) {
        int seen = 0;
        for (j = 0; j < i; j++) seen |= cut[j] == cut[i];
        if (seen || cut[i] >= orig_size) continue;
        BAD("truncated", copy(), cut[i], "trunc_%06lu_%s%s%s", (unsigned long)cut[i], why[i], label[i][0] ? "_" : "",
            label[i]);
    }
}

static void payload_flips(void)
{
    unsigned k;
    for (k = 0; k < file.count; k++) {
        rombin_chunk c;
        uint64_t at[3];
        const char *where[3] = {"first", "middle", "last"};
        int j;
        rombin_chunk_get(&file, k, &c);
        if (c.stored == 0) continue;
        at[0] = 0, at[1] = c.stored / 2, at[2] = c.stored - 1;
        for (j = 0; j < 3; j++) {
            unsigned char *b;
            if ((j == 1 && (at[1] == at[0])) || (j == 2 && (at[2] == at[1] || at[2] == at[0]))) continue;
            b = copy();
            b[c.offset + at[j]] ^= 0x10; /* CRC left stale */
            BAD("payload_bit_flip", b, orig_size, "flip_payload_%s_%s_byte%lu", c.id, where[j], (unsigned long)at[j]);
        }
    }
}

static void header_and_table_flips(void)
{
    static const struct { int at; const char *field; } h[] = {
        {0, "signature0"}, {3, "signature3"}, {6, "signature6"}, {ROMBIN_H_MAJOR, "major"},
        {ROMBIN_H_MINOR, "minor"}, {ROMBIN_H_ENDIAN, "endian"}, {ROMBIN_H_F32 + 3, "f32_sentinel"},
        {ROMBIN_H_REAL, "real_type"}, {ROMBIN_H_F64 + 7, "f64_sentinel"}, {ROMBIN_H_FILE_BYTES, "file_bytes"},
        {ROMBIN_H_FILE_BYTES + 7, "file_bytes_high"}, {ROMBIN_H_CHUNKS, "chunks"}, {ROMBIN_H_FLAGS, "flags"},
        {ROMBIN_H_TABLE_CRC, "table_crc"}, {ROMBIN_H_RESERVED, "reserved"}, {ROMBIN_HEADER_BYTES - 1, "reserved_last"}};
    static const struct { int at; const char *field; } e[] = {
        {ROMBIN_E_ID, "id"}, {ROMBIN_E_FLAGS, "flags"}, {ROMBIN_E_OFFSET, "offset"}, {ROMBIN_E_STORED, "stored"},
        {ROMBIN_E_RAW, "raw"}, {ROMBIN_E_CRC, "crc"}, {ROMBIN_E_RESERVED, "reserved"}};
    size_t i;
    unsigned k;
    for (i = 0; i < sizeof h / sizeof h[0]; i++) {
        unsigned char *b = copy();
        b[h[i].at] ^= 0x04;
        BAD("header_bit_flip", b, orig_size, "flip_header_%s_byte%d", h[i].field, h[i].at);
    }
    /* One flip per entry, cycling through the entry's fields; the table CRC catches them all. */
    for (k = 0; k < file.count; k++) {
        unsigned char *b = copy();
        size_t f = k % (sizeof e / sizeof e[0]);
        rombin_chunk c;
        rombin_chunk_get(&file, k, &c);
        entry(b, k)[e[f].at] ^= 0x02;
        BAD("table_bit_flip", b, orig_size, "flip_table_%s_%s", c.id, e[f].field);
    }
}

/* Text-mode and 7-bit transfers: what the signature is designed to catch. */
static void transfers(void)
{
    unsigned char *b;
    size_t i, n;
    /* CRLF -> LF everywhere (a Windows-to-Unix text transfer): the file shrinks. */
    b = copy();
    for (i = 0, n = 0; i < orig_size; i++)
        if (!(orig[i] == '\r' && i + 1 < orig_size && orig[i + 1] == '\n')) b[n++] = orig[i];
    BAD("transfer", b, n, "transfer_crlf_to_lf");
    /* Only the signature's CRLF -> LF, the rest intact. */
    b = copy();
    memmove(b + 4, b + 5, orig_size - 5);
    BAD("transfer", b, orig_size - 1, "transfer_signature_crlf_to_lf");
    /* LF -> CRLF everywhere (Unix to Windows). */
    b = malloc(2 * orig_size + 1);
    if (!b) exit(1);
    for (i = 0, n = 0; i < orig_size; i++) {
        if (orig[i] == '\n' && !(i > 0 && orig[i - 1] == '\r')) b[n++] = '\r';
        b[n++] = orig[i];
    }
    BAD("transfer", b, n, "transfer_lf_to_crlf");
    /* A 7-bit channel strips every high bit. */
    b = copy();
    for (i = 0; i < orig_size; i++) b[i] &= 0x7F;
    BAD("transfer", b, orig_size, "transfer_7bit");
    b = copy();
    b[0] &= 0x7F;
    BAD("transfer", b, orig_size, "transfer_7bit_signature_byte");
    /* DOS `type` stops at ^Z (signature byte 6). */
    BAD("transfer", copy(), 6, "transfer_dos_type_stops_at_ctrl_z");
}

static void header_fields(void)
{
    unsigned char *b;
    static const unsigned majors[] = {0, 2, 0xFFFF};
    size_t i;
    for (i = 0; i < sizeof majors / sizeof majors[0]; i++) {
        b = copy();
        b[ROMBIN_H_MAJOR] = (unsigned char)majors[i];
        b[ROMBIN_H_MAJOR + 1] = (unsigned char)(majors[i] >> 8);
        fix_table_crc(b);
        BAD("version", b, orig_size, "version_major_%u", majors[i]);
    }
    /* Chunk counts; the table CRC is recomputed over the entries the count names where they exist. */
    {
        static const uint32_t counts[] = {0, ROMBIN_MAX_CHUNKS + 1, 0xFFFFFFFFu, 0x80000000u};
        for (i = 0; i < sizeof counts / sizeof counts[0]; i++) {
            b = copy();
            put_u32(b + ROMBIN_H_CHUNKS, counts[i]);
            fix_table_crc(b);
            BAD("chunk_count", b, orig_size, "chunk_count_%lu", (unsigned long)counts[i]);
        }
        if (ROMBIN_HEADER_BYTES + (file.count + 1) * ROMBIN_ENTRY_BYTES <= orig_size) {
            b = copy();
            put_u32(b + ROMBIN_H_CHUNKS, file.count + 1); /* the first payload read as an entry */
            fix_table_crc_n(b, file.count + 1);
            BAD("chunk_count", b, orig_size, "chunk_count_plus_1");
        }
        b = copy();
        put_u32(b + ROMBIN_H_CHUNKS, file.count - 1); /* the last chunk becomes trailing bytes */
        fix_table_crc_n(b, file.count - 1);
        BAD("chunk_count", b, orig_size, "chunk_count_minus_1");
    }
    /* file_bytes larger and smaller than the buffer, and trailing data. */
    b = copy();
    put_u64(b + ROMBIN_H_FILE_BYTES, orig_size + 16);
    fix_table_crc(b);
    BAD("file_bytes", b, orig_size, "file_bytes_announces_more");
    b = copy();
    put_u64(b + ROMBIN_H_FILE_BYTES, orig_size - 16);
    fix_table_crc(b);
    BAD("file_bytes", b, orig_size, "file_bytes_announces_less");
    b = calloc(orig_size + 16, 1);
    if (!b) exit(1);
    memcpy(b, orig, orig_size);
    BAD("file_bytes", b, orig_size + 16, "file_bytes_trailing_zeros");
    /* Sentinels and the real type, consistently re-CRC'd. */
    b = copy();
    put_u32(b + ROMBIN_H_ENDIAN, 0x04030201u);
    fix_table_crc(b);
    BAD("platform", b, orig_size, "platform_endian_swapped");
    b = copy();
    b[ROMBIN_H_F32] ^= 1;
    fix_table_crc(b);
    BAD("platform", b, orig_size, "platform_f32_sentinel");
    b = copy();
    b[ROMBIN_H_F64] ^= 1;
    fix_table_crc(b);
    BAD("platform", b, orig_size, "platform_f64_sentinel");
    b = copy();
    put_u32(b + ROMBIN_H_REAL, 3);
    fix_table_crc(b);
    BAD("real_type", b, orig_size, "real_type_3");
    /* The other real type: every real chunk is then read with the wrong width. */
    b = copy();
    put_u32(b + ROMBIN_H_REAL, file.real_type == ROMBIN_REAL_F32 ? ROMBIN_REAL_F64 : ROMBIN_REAL_F32);
    fix_table_crc(b);
    BAD("real_type", b, orig_size, "real_type_swapped");
}

static void reserved_fields(void)
{
    unsigned char *b;
    unsigned k;
    rombin_chunk c;
    b = copy();
    put_u32(b + ROMBIN_H_FLAGS, 1);
    fix_table_crc(b);
    BAD("reserved", b, orig_size, "reserved_header_flags");
    b = copy();
    b[ROMBIN_H_RESERVED] = 1; /* not covered by the CRC */
    BAD("reserved", b, orig_size, "reserved_header_first");
    b = copy();
    b[ROMBIN_HEADER_BYTES - 1] = 0x80;
    BAD("reserved", b, orig_size, "reserved_header_last");
    for (k = 0; k < file.count; k++) {
        rombin_chunk_get(&file, k, &c);
        b = copy();
        put_u32(entry(b, k) + ROMBIN_E_RESERVED, 1);
        fix_table_crc(b);
        BAD("reserved", b, orig_size, "reserved_entry_%s", c.id);
    }
    rombin_chunk_get(&file, 0, &c);
    b = copy();
    put_u32(entry(b, 0) + ROMBIN_E_FLAGS, c.flags | 0x2u);
    fix_table_crc(b);
    BAD("reserved", b, orig_size, "reserved_flag_bit_%s", c.id);
    b = copy();
    put_u32(entry(b, 0) + ROMBIN_E_FLAGS, (c.flags & ~ROMBIN_TYPE_MASK) | 3u << ROMBIN_TYPE_SHIFT);
    fix_table_crc(b);
    BAD("reserved", b, orig_size, "reserved_element_type_3_%s", c.id);
    b = copy();
    put_u32(entry(b, 0) + ROMBIN_E_FLAGS, (c.flags & ~ROMBIN_COMP_MASK) | 2u << ROMBIN_COMP_SHIFT);
    fix_table_crc(b);
    BAD("reserved", b, orig_size, "reserved_compression_2_%s", c.id);
    /* Padding between payloads and after the last one must be zero. */
    for (k = 0; k < file.count; k++) {
        rombin_chunk next;
        uint64_t end, gap_end;
        rombin_chunk_get(&file, k, &c);
        end = c.offset + c.stored;
        if (k + 1 < file.count) {
            rombin_chunk_get(&file, k + 1, &next);
            gap_end = next.offset;
        } else {
            gap_end = orig_size;
        }
        if (gap_end > end) {
            b = copy();
            b[end] = 0x5A;
            BAD("reserved", b, orig_size, "padding_nonzero_after_%s", c.id);
            break; /* one is enough */
        }
    }
}

/* Entries whose bounds are wrong, with the table CRC recomputed so only the bounds are. */
static void bounds(void)
{
    unsigned k;
    for (k = 0; k < file.count; k++) {
        rombin_chunk c;
        unsigned char *b, *e;
        rombin_chunk_get(&file, k, &c);
        b = copy();
        e = entry(b, k);
        put_u64(e + ROMBIN_E_STORED, orig_size - c.offset + 16);
        put_u64(e + ROMBIN_E_RAW, orig_size - c.offset + 16);
        fix_table_crc(b);
        BAD("bounds", b, orig_size, "bounds_length_past_end_%s", c.id);
        b = copy();
        put_u64(entry(b, k) + ROMBIN_E_OFFSET, ((uint64_t)orig_size + 31) / 16 * 16);
        fix_table_crc(b);
        BAD("bounds", b, orig_size, "bounds_offset_past_end_%s", c.id);
        b = copy();
        put_u64(entry(b, k) + ROMBIN_E_OFFSET, c.offset + 8);
        fix_table_crc(b);
        BAD("bounds", b, orig_size, "bounds_offset_misaligned_%s", c.id);
    }
    /* Lengths and offsets near 2^64, which wrap an unchecked offset + length. */
    {
        rombin_chunk c;
        unsigned char *b;
        unsigned last = file.count - 1;
        rombin_chunk_get(&file, last, &c);
        b = copy();
        put_u64(entry(b, last) + ROMBIN_E_STORED, ~(uint64_t)0 - 15);
        put_u64(entry(b, last) + ROMBIN_E_RAW, ~(uint64_t)0 - 15);
        fix_table_crc(b);
        BAD("bounds", b, orig_size, "bounds_length_wraps_%s", c.id);
        b = copy();
        put_u64(entry(b, last) + ROMBIN_E_OFFSET, ~(uint64_t)0 - 15);
        fix_table_crc(b);
        BAD("bounds", b, orig_size, "bounds_offset_wraps_%s", c.id);
        b = copy();
        put_u64(entry(b, last) + ROMBIN_E_RAW, c.raw + 16); /* raw != stored while uncompressed */
        fix_table_crc(b);
        BAD("bounds", b, orig_size, "bounds_raw_differs_%s", c.id);
    }
}

static void overlaps(void)
{
    unsigned k;
    for (k = 1; k < file.count; k++) {
        rombin_chunk prev, c;
        unsigned char *b;
        rombin_chunk_get(&file, k - 1, &prev);
        rombin_chunk_get(&file, k, &c);
        /* Both entries name the same bytes (the payload CRC made to match). */
        b = copy();
        put_u64(entry(b, k) + ROMBIN_E_OFFSET, prev.offset);
        put_u64(entry(b, k) + ROMBIN_E_STORED, prev.stored);
        put_u64(entry(b, k) + ROMBIN_E_RAW, prev.stored);
        put_u32(entry(b, k) + ROMBIN_E_CRC, prev.crc);
        fix_table_crc(b);
        BAD("overlap", b, orig_size, "overlap_%s_same_bytes_as_%s", c.id, prev.id);
        /* The previous chunk runs 16 bytes into this one (its CRC recomputed over the longer range). */
        if (c.offset + 16 <= orig_size && (prev.type != ROMBIN_TYPE_REAL || 16 % real_bytes == 0)) {
            uint64_t grown = c.offset - prev.offset + 16;
            b = copy();
            put_u64(entry(b, k - 1) + ROMBIN_E_STORED, grown);
            put_u64(entry(b, k - 1) + ROMBIN_E_RAW, grown);
            fix_chunk_crc(b, k - 1);
            BAD("overlap", b, orig_size, "overlap_%s_runs_into_%s", prev.id, c.id);
        }
    }
}

/* In an asset holding both a reduced model and a Koopman operator, hiding one's header leaves a
 * valid asset of the other. */
static int other_model_present(const char *id)
{
    rombin_chunk c;
    return (memcmp(id, ROMBIN_HEAD, 4) == 0 && find(ROMBIN_KHED, &c, NULL)) ||
           (memcmp(id, ROMBIN_KHED, 4) == 0 && find(ROMBIN_HEAD, &c, NULL));
}

/* Chunk ids: unknown critical, duplicated, not printable, missing; compression. */
static void ids(void)
{
    unsigned k;
    for (k = 0; k < file.count; k++) {
        rombin_chunk c;
        unsigned char *b;
        rombin_chunk_get(&file, k, &c);
        if (c.critical) {
            b = copy();
            memcpy(entry(b, k) + ROMBIN_E_ID, "XXXX", 4);
            fix_table_crc(b);
            BAD("unknown_critical", b, orig_size, "unknown_critical_%s_renamed_XXXX", c.id);
            /* Renamed and made optional: the runtime sees a required chunk missing. */
            b = copy();
            memcpy(entry(b, k) + ROMBIN_E_ID, "ZZZZ", 4);
            put_u32(entry(b, k) + ROMBIN_E_FLAGS, c.flags & ~ROMBIN_FLAG_CRITICAL);
            fix_table_crc(b);
            if (other_model_present(c.id)) {
                free(b);
                skip("a model header hidden (the other model remains, a valid asset)", c.id);
            } else if (memcmp(c.id, ROMBIN_VEL0, 4) == 0) { /* critical when present; absent, the model starts at rest */
                GOOD("good_without_initial_velocity", b, orig_size, "missing_%s_starts_at_rest", c.id);
            } else if (memcmp(c.id, ROMBIN_VPRS, 4) == 0) { /* critical when present; absent, the volume is pointwise */
                GOOD("good_without_projected_volume", b, orig_size, "missing_%s_steps_pointwise", c.id);
            } else if (memcmp(c.id, ROMBIN_LIFT, 4) == 0) { /* critical when present; absent, the group is free */
                GOOD("good_without_lift", b, orig_size, "missing_%s_group_free", c.id);
            } else {
                BAD("missing_chunk", b, orig_size, "missing_%s", c.id);
            }
        }
        /* Marked deflated (the bytes are not): the runtime reads stored chunks only. INFO, VMAP and
         * SPLY are left out: the runtime never reads them, so ignoring their encoding is right. */
        if (memcmp(c.id, ROMBIN_INFO, 4) != 0 && memcmp(c.id, ROMBIN_VMAP, 4) != 0 && memcmp(c.id, ROMBIN_SPLY, 4) != 0) {
            b = copy();
            put_u32(entry(b, k) + ROMBIN_E_FLAGS,
                    (c.flags & ~ROMBIN_COMP_MASK) | (uint32_t)ROMBIN_COMP_DEFLATE << ROMBIN_COMP_SHIFT);
            fix_table_crc(b);
            BAD("compressed", b, orig_size, "compressed_deflate_%s", c.id);
        }
    }
    if (file.count > 1) {
        rombin_chunk c0, c1;
        unsigned char *b = copy();
        rombin_chunk_get(&file, 0, &c0);
        rombin_chunk_get(&file, 1, &c1);
        memcpy(entry(b, 1) + ROMBIN_E_ID, c0.id, 4);
        fix_table_crc(b);
        BAD("ids", b, orig_size, "id_duplicate_%s_as_%s", c1.id, c0.id);
    }
    {
        unsigned char *b = copy();
        entry(b, 0)[ROMBIN_E_ID + 2] = ' ';
        fix_table_crc(b);
        BAD("ids", b, orig_size, "id_not_printable");
    }
}

/* ---- model damage: the container intact, the content wrong ---- */

/* A copy with u32 element `at` of chunk id set to v; NULL (with a note) if there is none. */
static unsigned char *with_u32(const char *id, uint64_t at, uint32_t v, const char *what)
{
    rombin_chunk c;
    unsigned k;
    unsigned char *b;
    if (!find(id, &c, &k) || c.type != ROMBIN_TYPE_U32 || 4 * at + 4 > c.stored) {
        skip(what, id);
        return NULL;
    }
    b = copy();
    put_u32(b + c.offset + 4 * at, v);
    fix_chunk_crc(b, k);
    return b;
}

static double get_real(const unsigned char *p)
{
    if (real_bytes == 4) {
        float f;
        memcpy(&f, p, 4);
        return f;
    } else {
        double d;
        memcpy(&d, p, 8);
        return d;
    }
}

static void put_real(unsigned char *p, double v)
{
    if (real_bytes == 4) {
        float f = (float)v;
        memcpy(p, &f, 4);
    } else {
        memcpy(p, &v, 8);
    }
}

/* NaN and Inf by bit pattern (no libm, no division by zero). */
static void put_special(unsigned char *p, int nan)
{
    if (real_bytes == 4)
        put_u32(p, nan ? 0x7FC00000u : 0x7F800000u);
    else
        put_u64(p, nan ? 0x7FF8000000000000ull : 0x7FF0000000000000ull);
}

enum { SET_NAN, SET_INF, SET_NEG, SET_ZERO, SET_BIG };

/* A copy with real element `at` of chunk id changed; NULL (with a note) if there is none. */
static unsigned char *with_real(const char *id, uint64_t at, int how, const char *what)
{
    rombin_chunk c;
    unsigned k;
    unsigned char *b, *p;
    double v;
    if (!find(id, &c, &k) || c.type != ROMBIN_TYPE_REAL || (at + 1) * real_bytes > c.stored) {
        skip(what, id);
        return NULL;
    }
    b = copy();
    p = b + c.offset + at * real_bytes;
    v = get_real(p);
    if (how == SET_NAN || how == SET_INF) put_special(p, how == SET_NAN);
    else if (how == SET_ZERO) put_real(p, 0.0);
    else if (how == SET_BIG) put_real(p, 20.0);
    else put_real(p, v > 0 ? -v : -1.0);
    fix_chunk_crc(b, k);
    return b;
}

static uint32_t head(int field)
{
    rombin_chunk c;
    if (!find(ROMBIN_HEAD, &c, NULL) || (uint64_t)(field + 1) * 4 > c.stored) return 0;
    return rombin_get_u32(c.data + 4 * field);
}

static void model(void)
{
    static const char *head_names[ROMBIN_HEAD_COUNT] = {
        "r", "vertices", "shown", "elements", "pins", "planes", "contacts", "groups", "integrator",
        "newton_max_iter", "source_vertices", "source_tets", "points", "reserved13", "reserved14", "reserved15"};
    unsigned char *b;
    unsigned k;
    int f;
    uint32_t vertices = head(ROMBIN_HEAD_VERTICES);
#define MODEL(kind, expr, ...) do { if ((b = (expr)) != NULL) BAD(kind, b, orig_size, __VA_ARGS__); } while (0)
    /* Every HEAD field but the two that are information about the source mesh (nothing to check). */
    for (f = 0; f < ROMBIN_HEAD_COUNT; f++)
        if (f != ROMBIN_HEAD_SOURCE_VERTICES && f != ROMBIN_HEAD_SOURCE_TETS)
            MODEL("head_count", with_u32(ROMBIN_HEAD, f, 0xFFFFFFFFu, "HEAD counts"), "head_%02d_%s_ffffffff", f,
                  head_names[f]);
    MODEL("head_r", with_u32(ROMBIN_HEAD, ROMBIN_HEAD_R, 0, "r = 0"), "head_r_0");
    MODEL("head_r", with_u32(ROMBIN_HEAD, ROMBIN_HEAD_R, ROMRT_MAX_R + 1, "r too large"), "head_r_max_plus_1");
    MODEL("head_r", with_u32(ROMBIN_HEAD, ROMBIN_HEAD_R, head(ROMBIN_HEAD_R) + 1, "r + 1"), "head_r_plus_1");
    MODEL("head_count", with_u32(ROMBIN_HEAD, ROMBIN_HEAD_SHOWN, vertices + 1, "shown"), "head_shown_above_vertices");
    MODEL("head_count", with_u32(ROMBIN_HEAD, ROMBIN_HEAD_INTEGRATOR, 2, "integrator"), "head_integrator_2");
    /* no elements and no integration points: nothing to integrate the energy over */
    if (head(ROMBIN_HEAD_POINTS) == 0)
        MODEL("head_count", with_u32(ROMBIN_HEAD, ROMBIN_HEAD_ELEMENTS, 0, "elements"), "head_elements_0");
    else
        MODEL("head_count", with_u32(ROMBIN_HEAD, ROMBIN_HEAD_POINTS, 0, "points"), "head_points_0");
    /* NaN and Inf in every real chunk: first element; NaN also in the last. */
    for (k = 0; k < file.count; k++) {
        rombin_chunk c;
        rombin_chunk_get(&file, k, &c);
        if (c.type != ROMBIN_TYPE_REAL || c.stored < (uint64_t)real_bytes) continue;
        MODEL("nonfinite", with_real(c.id, 0, SET_NAN, "NaN"), "nan_%s_first", c.id);
        MODEL("nonfinite", with_real(c.id, 0, SET_INF, "Inf"), "inf_%s_first", c.id);
        if (c.stored > (uint64_t)real_bytes)
            MODEL("nonfinite", with_real(c.id, c.stored / real_bytes - 1, SET_NAN, "NaN"), "nan_%s_last", c.id);
    }
    /* Indices out of range: exactly the count (off by one) and 2^32 - 1. */
    MODEL("index", with_u32(ROMBIN_ELEM, 0, vertices, "ELEM vertex"), "index_ELEM_vertex_eq_vertices");
    MODEL("index", with_u32(ROMBIN_ELEM, 3, 0xFFFFFFFFu, "ELEM vertex"), "index_ELEM_vertex_ffffffff");
    MODEL("index", with_u32(ROMBIN_ELEM, 4, 0xFFFFu, "ELEM material"), "index_ELEM_material_ffff");
    MODEL("index", with_u32(ROMBIN_CONT, 0, vertices, "CONT vertex"), "index_CONT_vertex_eq_vertices");
    MODEL("index", with_u32(ROMBIN_CONT, 0, 0xFFFFFFFFu, "CONT vertex"), "index_CONT_vertex_ffffffff");
    MODEL("index", with_u32(ROMBIN_CONT, 1, head(ROMBIN_HEAD_PLANES), "CONT plane"), "index_CONT_plane_eq_planes");
    if (vertices) { /* the HEAD counts (a Koopman asset's are in KHED: koopman()) */
        MODEL("index", with_u32(ROMBIN_GVTX, 0, vertices, "GVTX vertex"), "index_GVTX_vertex_eq_vertices");
        MODEL("index", with_u32(ROMBIN_CVTX, 0, vertices, "CVTX vertex"), "index_CVTX_vertex_eq_vertices");
    }
    MODEL("index", with_u32(ROMBIN_CVTX, 0, 0xFFFFFFFFu, "CVTX vertex"), "index_CVTX_vertex_ffffffff");
    /* Several objects (COBJ): an object index at CVTX's count (more objects than collision
     * vertices) and 2^32 - 1. */
    {
        rombin_chunk c;
        uint32_t ncv = find(ROMBIN_CVTX, &c, NULL) ? (uint32_t)(c.stored / 4) : 0;
        MODEL("index", with_u32(ROMBIN_COBJ, 0, ncv, "COBJ object"), "index_COBJ_object_eq_collision_vertices");
        MODEL("index", with_u32(ROMBIN_COBJ, 0, 0xFFFFFFFFu, "COBJ object"), "index_COBJ_object_ffffffff");
    }
    /* Friction that makes no sense. */
    MODEL("fric", with_real(ROMBIN_FRIC, ROMBIN_FRIC_MU, SET_NEG, "mu"), "fric_mu_negative");
    MODEL("fric", with_real(ROMBIN_FRIC, ROMBIN_FRIC_EPS_V, SET_ZERO, "eps_v"), "fric_eps_v_zero");
    MODEL("fric", with_real(ROMBIN_FRIC, ROMBIN_FRIC_ITERATIONS, SET_ZERO, "iterations"), "fric_iterations_zero");
    MODEL("fric", with_real(ROMBIN_FRIC, ROMBIN_FRIC_COUNT - 1, SET_NEG, "reserved"), "fric_reserved_set");
    /* A lifted group's motion of no kind, and a handle that is none (LIFT, 1.11). */
    MODEL("lift", with_real(ROMBIN_LIFT, 0, SET_BIG, "kind"), "lift_kind_20");
    MODEL("lift", with_real(ROMBIN_LIFT, ROMBIN_PIN_PARAMS, SET_BIG, "handle column"), "lift_column_20");
    MODEL("lift", with_real(ROMBIN_LIFT, ROMBIN_PIN_PARAMS, SET_NEG, "handle column"), "lift_column_negative");
    MODEL("index", with_u32(ROMBIN_GVTX, 0, 0xFFFFFFFFu, "GVTX vertex"), "index_GVTX_vertex_ffffffff");
    MODEL("index", with_u32(ROMBIN_GRPS, 0, 0xFFFFFFFFu, "GRPS first"), "index_GRPS_first_ffffffff");
    MODEL("index", with_u32(ROMBIN_GRPS, 1, 0xFFFFFFFFu, "GRPS count"), "index_GRPS_count_ffffffff");
    if (vertices)
        MODEL("index", with_u32(ROMBIN_SURF, 0, head(ROMBIN_HEAD_SHOWN), "SURF vertex"), "index_SURF_vertex_eq_shown");
    /* Parameters that are finite but meaningless. */
    {
        rombin_chunk c;
        if (find(ROMBIN_VPRS, &c, NULL)) /* the projected volume's pressure functions: finite */
            MODEL("vprs", with_real(ROMBIN_VPRS, 0, SET_NAN, "VPRS"), "vprs_nan");
        else
            skip("projected volume", ROMBIN_VPRS);
    }
    MODEL("parm", with_real(ROMBIN_PARM, ROMBIN_PARM_H, SET_NEG, "h"), "parm_h_negative");
    MODEL("parm", with_real(ROMBIN_PARM, ROMBIN_PARM_H, SET_ZERO, "h"), "parm_h_zero");
    MODEL("parm", with_real(ROMBIN_PARM, ROMBIN_PARM_MASS, SET_NEG, "mass"), "parm_mass_negative");
    MODEL("parm", with_real(ROMBIN_PARM, ROMBIN_PARM_NEWTON_TOL, SET_NEG, "tolerance"), "parm_newton_tol_negative");
    MODEL("parm", with_real(ROMBIN_PARM, ROMBIN_PARM_NEWTON_TOL, SET_NAN, "tolerance"), "parm_newton_tol_nan");
    MODEL("parm", with_real(ROMBIN_PARM, ROMBIN_PARM_MASS, SET_INF, "mass"), "parm_mass_inf");
    if (head(ROMBIN_HEAD_CONTACTS) > 0) {
        MODEL("parm", with_real(ROMBIN_PARM, ROMBIN_PARM_DHAT, SET_NEG, "dhat"), "parm_dhat_negative");
        MODEL("parm", with_real(ROMBIN_PARM, ROMBIN_PARM_KAPPA, SET_NAN, "kappa"), "parm_kappa_nan");
    } else {
        skip("barrier parameters", ROMBIN_CONT);
    }
    /* A group name without its NUL: romrt_group_name must never hand out an unterminated string. */
    {
        rombin_chunk c;
        unsigned gk;
        if (find(ROMBIN_GNAM, &c, &gk) && c.stored >= ROMBIN_GROUP_NAME_BYTES) {
            b = copy();
            memset(b + c.offset, 'g', ROMBIN_GROUP_NAME_BYTES);
            fix_chunk_crc(b, gk);
            BAD("gnam", b, orig_size, "gnam_not_terminated");
        } else {
            skip("unterminated group name", ROMBIN_GNAM);
        }
    }
#undef MODEL
}

/* A Koopman asset's own chunks (ROMBIN.md "Koopman chunks"); skipped for a reduced model. */
static void koopman(void)
{
    static const char *names[ROMBIN_KHED_SOURCE_VERTICES] = {"r", "vertices", "shown", "groups"};
    unsigned char *b;
    int f;
    rombin_chunk c;
    uint32_t r, vertices;
    if (!find(ROMBIN_KHED, &c, NULL)) {
        skip("Koopman fields", ROMBIN_KHED);
        return;
    }
    r = rombin_get_u32(c.data + 4 * ROMBIN_KHED_R);
    vertices = rombin_get_u32(c.data + 4 * ROMBIN_KHED_VERTICES);
#define KOOP(kind, expr, ...) do { if ((b = (expr)) != NULL) BAD(kind, b, orig_size, __VA_ARGS__); } while (0)
    for (f = 0; f < ROMBIN_KHED_SOURCE_VERTICES; f++)
        KOOP("khed_count", with_u32(ROMBIN_KHED, f, 0xFFFFFFFFu, "KHED counts"), "khed_%02d_%s_ffffffff", f, names[f]);
    KOOP("khed_r", with_u32(ROMBIN_KHED, ROMBIN_KHED_R, 0, "r = 0"), "khed_r_0");
    KOOP("khed_r", with_u32(ROMBIN_KHED, ROMBIN_KHED_R, r + 1, "r + 1"), "khed_r_plus_1");
    KOOP("khed_r", with_u32(ROMBIN_KHED, ROMBIN_KHED_R, ROMRT_MAX_R + 1, "r too large"), "khed_r_max_plus_1");
    KOOP("khed_count", with_u32(ROMBIN_KHED, ROMBIN_KHED_SHOWN, vertices + 1, "shown"), "khed_shown_above_vertices");
    KOOP("khed_count", with_u32(ROMBIN_KHED, ROMBIN_KHED_COUNT - 1, 1, "reserved"), "khed_reserved_set");
    KOOP("kprm", with_real(ROMBIN_KPRM, ROMBIN_KPRM_H, SET_NEG, "h"), "kprm_h_negative");
    KOOP("kprm", with_real(ROMBIN_KPRM, ROMBIN_KPRM_H, SET_ZERO, "h"), "kprm_h_zero");
    KOOP("kprm", with_real(ROMBIN_KPRM, ROMBIN_KPRM_COUNT - 1, SET_NEG, "reserved"), "kprm_reserved_set");
    /* eigenvalue 0's imaginary part made negative: a conjugate with no pair before it */
    KOOP("keig", with_real(ROMBIN_KEIG, 1, SET_NEG, "KEIG"), "keig_conjugate_first");
    KOOP("keig", with_real(ROMBIN_KEIG, 2 * (uint64_t)r - 2, SET_BIG, "KEIG"), "keig_last_above_10");
    KOOP("index", with_u32(ROMBIN_GVTX, 0, vertices, "GVTX vertex"), "koopman_GVTX_vertex_eq_vertices");
    KOOP("index", with_u32(ROMBIN_SURF, 0, rombin_get_u32(c.data + 4 * ROMBIN_KHED_SHOWN), "SURF vertex"),
         "koopman_SURF_vertex_eq_shown");
#undef KOOP
}

/* The obstacles' chunks (ROMBIN.md "Obstacle chunks"): counts, ranges, BVH links and items,
 * edge and triangle vertices, thickness, pair capacity; skipped without OBHD. */
static void obstacles(void)
{
    unsigned char *b;
    rombin_chunk c;
    uint32_t nodes, onv, nobs;
    if (!find(ROMBIN_OBHD, &c, NULL) || c.stored < 4 * (ROMBIN_OBHD_COUNT + ROMBIN_OBST_COUNT)) {
        skip("obstacle fields", ROMBIN_OBHD);
        return;
    }
    nobs = rombin_get_u32(c.data + 4 * ROMBIN_OBHD_OBSTACLES);
    onv = rombin_get_u32(c.data + 4 * ROMBIN_OBHD_VERTICES);
    nodes = rombin_get_u32(c.data + 4 * ROMBIN_OBHD_NODES);
#define OBS(kind, expr, ...) do { if ((b = (expr)) != NULL) BAD(kind, b, orig_size, __VA_ARGS__); } while (0)
    OBS("obhd", with_u32(ROMBIN_OBHD, ROMBIN_OBHD_OBSTACLES, 0, "OBHD"), "obhd_obstacles_0");
    OBS("obhd", with_u32(ROMBIN_OBHD, ROMBIN_OBHD_OBSTACLES, nobs + 1, "OBHD"), "obhd_obstacles_plus_1");
    OBS("obhd", with_u32(ROMBIN_OBHD, ROMBIN_OBHD_VERTICES, onv + 1, "OBHD"), "obhd_vertices_plus_1");
    OBS("obhd", with_u32(ROMBIN_OBHD, ROMBIN_OBHD_NODES, nodes - 1, "OBHD"), "obhd_nodes_minus_1");
    OBS("obhd", with_u32(ROMBIN_OBHD, ROMBIN_OBHD_PAIRS, 0, "OBHD"), "obhd_pairs_0");
    OBS("obhd", with_u32(ROMBIN_OBHD, ROMBIN_OBHD_PAIRS, 0xFFFFFFFFu, "OBHD"), "obhd_pairs_ffffffff");
    OBS("obhd", with_u32(ROMBIN_OBHD, ROMBIN_OBHD_FLAGS, 4, "OBHD"), "obhd_unknown_flag");
    OBS("obhd", with_u32(ROMBIN_OBHD, ROMBIN_OBHD_COUNT + ROMBIN_OBST_KIND, 0, "OBHD"), "obhd_kind_plane");
    OBS("obhd", with_u32(ROMBIN_OBHD, ROMBIN_OBHD_COUNT + ROMBIN_OBST_VERTICES, onv + 1, "OBHD"), "obhd_range_past_count");
    OBS("obhd", with_u32(ROMBIN_OBHD, ROMBIN_OBHD_COUNT + ROMBIN_OBST_NODES, 0, "OBHD"), "obhd_no_nodes");
    OBS("index", with_u32(ROMBIN_OBED, 0, onv, "OBED vertex"), "index_OBED_vertex_eq_vertices");
    OBS("index", with_u32(ROMBIN_OBTR, 0, 0xFFFFFFFFu, "OBTR vertex"), "index_OBTR_vertex_ffffffff");
    OBS("index", with_u32(ROMBIN_CEDG, 0, 0xFFFFFFFFu, "CEDG vertex"), "index_CEDG_vertex_ffffffff");
    OBS("index", with_u32(ROMBIN_CTRI, 2, 0xFFFFFFFFu, "CTRI vertex"), "index_CTRI_vertex_ffffffff");
    /* the BVH: node 0 (the first obstacle's root, an inner node or a leaf), and the first inner
     * node linked to itself, to its parent's sibling's range end, to its own sibling twice */
    OBS("bvh", with_u32(ROMBIN_OBVN, 0, 2, "OBVN kind"), "bvh_node_kind_2");
    OBS("bvh", with_u32(ROMBIN_OBVN, 1, nodes, "OBVN link"), "bvh_link_eq_nodes");
    OBS("bvh", with_u32(ROMBIN_OBVN, 2, 0xFFFFFFFFu, "OBVN link"), "bvh_link_ffffffff");
    if (find(ROMBIN_OBVN, &c, NULL)) {
        uint32_t i, inner = 0xFFFFFFFFu;
        for (i = 0; i < nodes && inner == 0xFFFFFFFFu; i++)
            if (rombin_get_u32(c.data + 12 * (uint64_t)i) == 0) inner = i;
        if (inner != 0xFFFFFFFFu) {
            uint32_t left = rombin_get_u32(c.data + 12 * (uint64_t)inner + 4);
            OBS("bvh", with_u32(ROMBIN_OBVN, 3 * (uint64_t)inner + 1, inner, "OBVN link"), "bvh_link_to_itself");
            OBS("bvh", with_u32(ROMBIN_OBVN, 3 * (uint64_t)inner + 2, left, "OBVN link"), "bvh_both_links_one_node");
        } else {
            skip("inner BVH node", ROMBIN_OBVN);
        }
    }
    OBS("bvh", with_u32(ROMBIN_OBIT, 0, 0xFFFFFFFFu, "OBIT item"), "bvh_item_ffffffff");
    OBS("bvh", with_u32(ROMBIN_OBIT, 0, 3, "OBIT item"), "bvh_item_kind_3");
    OBS("obst", with_real(ROMBIN_OBJS, 0, SET_NEG, "thickness"), "objs_thickness_negative");
    OBS("obst", with_real(ROMBIN_OBJS, 1, SET_NEG, "reserved"), "objs_reserved_set");
    OBS("obst", with_real(ROMBIN_OBVB, 0, SET_BIG, "box"), "obvb_box_min_above");
    OBS("obst", with_real(ROMBIN_OBMO, 0, SET_BIG, "motion"), "obmo_kind_unknown");
#undef OBS
}

/* ---- variants the runtime must accept ---- */

static void good(void)
{
    static const char *optional[] = {ROMBIN_INFO, ROMBIN_VMAP};
    unsigned char *b;
    size_t i;
    GOOD("good_original", copy(), orig_size, "original");
    b = copy();
    b[ROMBIN_H_MINOR] = 7;
    b[ROMBIN_H_MINOR + 1] = 0;
    fix_table_crc(b);
    GOOD("good_minor", b, orig_size, "minor_version_7");
    b = copy();
    b[ROMBIN_H_MINOR] = 0xFF;
    b[ROMBIN_H_MINOR + 1] = 0xFF;
    fix_table_crc(b);
    GOOD("good_minor", b, orig_size, "minor_version_65535");
    /* An optional chunk under an id the runtime does not know stands for a newer writer's extra chunk. */
    for (i = 0; i < sizeof optional / sizeof optional[0]; i++) {
        rombin_chunk c;
        unsigned k;
        if (!find(optional[i], &c, &k) || c.critical) {
            skip("renaming an optional chunk", optional[i]);
            continue;
        }
        b = copy();
        memcpy(entry(b, k) + ROMBIN_E_ID, "ZZZZ", 4);
        fix_table_crc(b);
        GOOD("good_unknown_optional", b, orig_size, "unknown_optional_%s_renamed_ZZZZ", optional[i]);
    }
}

/* ---- main ---- */

static void make_dir(const char *path)
{
    if (mkdir(path, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "damage: cannot create %s: %s\n", path, strerror(errno));
        exit(1);
    }
}

int main(int argc, char **argv)
{
    FILE *fp;
    long n;
    rombin_error err;
    char path[4096];
    int k;
    if (argc != 3) {
        fprintf(stderr, "usage: damage VALID.rombin OUTDIR\n  writes OUTDIR/bad/*.rombin (to be refused) and "
                        "OUTDIR/good/*.rombin (to be accepted)\n");
        return 2;
    }
    fp = fopen(argv[1], "rb");
    if (!fp || fseek(fp, 0, SEEK_END) != 0 || (n = ftell(fp)) < 0 || fseek(fp, 0, SEEK_SET) != 0) {
        fprintf(stderr, "damage: cannot read %s\n", argv[1]);
        return 1;
    }
    orig_size = (size_t)n;
    orig = malloc(orig_size + 1);
    if (!orig || fread(orig, 1, orig_size, fp) != orig_size) {
        fprintf(stderr, "damage: cannot read %s\n", argv[1]);
        return 1;
    }
    fclose(fp);
    if (rombin_open(&file, orig, orig_size, NULL, &err) != ROMBIN_OK) {
        fprintf(stderr, "damage: %s is not a valid .rombin: %s\n", argv[1], err.message);
        return 1;
    }
    real_bytes = file.real_type == ROMBIN_REAL_F64 ? 8 : 4;
    outdir = argv[2];
    make_dir(outdir);
    snprintf(path, sizeof path, "%s/bad", outdir);
    make_dir(path);
    snprintf(path, sizeof path, "%s/good", outdir);
    make_dir(path);

    truncations();
    payload_flips();
    header_and_table_flips();
    transfers();
    header_fields();
    reserved_fields();
    bounds();
    overlaps();
    ids();
    model();
    koopman();
    obstacles();
    good();

    for (k = 0; k < kinds; k++) printf("%-22s %d\n", kind_name[k], kind_count[k]);
    printf("bad %d, good %d\n", total_bad, total_good);
    free(orig);
    return 0;
}
