/* The .rombin writer (rombin_write.h). */
#include "formats/rombin_write.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "formats/rombin_read.h"
#include "util/util.h"

void rombin_writer_init(rombin_writer *w, int real_type, int compress)
{
    memset(w, 0, sizeof *w);
    w->real_type = real_type;
    w->compress = compress;
}

void rombin_writer_free(rombin_writer *w)
{
    for (int i = 0; i < w->count; i++) free(w->chunk[i].data);
    w->count = 0;
}

static int valid_id(const char *id)
{
    if (strlen(id) != 4) return 0;
    for (int k = 0; k < 4; k++) {
        char c = id[k];
        if (!((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_')) return 0;
    }
    return 1;
}

/* Takes ownership of data (freed on failure too). */
static int add_owned(rombin_writer *w, const char *id, uint32_t flags, unsigned char *data, size_t n, rk_error *err)
{
    if (!valid_id(id)) {
        free(data);
        return rk_fail(err, "rombin: chunk id '%s' is not 4 letters or digits", id);
    }
    for (int i = 0; i < w->count; i++)
        if (memcmp(w->chunk[i].id, id, 4) == 0) {
            free(data);
            return rk_fail(err, "rombin: chunk '%s' added twice", id);
        }
    if (w->count >= ROMBIN_MAX_CHUNKS) {
        free(data);
        return rk_fail(err, "rombin: more than %d chunks", ROMBIN_MAX_CHUNKS);
    }
    rombin_out_chunk *c = &w->chunk[w->count++];
    memcpy(c->id, id, 5);
    c->flags = flags;
    c->data = data;
    c->bytes = n;
    return 0;
}

static uint32_t flags_of(int critical, int type)
{
    return (critical ? ROMBIN_FLAG_CRITICAL : 0) | (uint32_t)type << ROMBIN_TYPE_SHIFT;
}

int rombin_add_bytes(rombin_writer *w, const char *id, int critical, const void *data, size_t n, rk_error *err)
{
    unsigned char *copy = rk_calloc(n ? n : 1, 1, err);
    if (!copy) return -1;
    if (n) memcpy(copy, data, n);
    return add_owned(w, id, flags_of(critical, ROMBIN_TYPE_BYTES), copy, n, err);
}

int rombin_add_u32(rombin_writer *w, const char *id, int critical, const uint32_t *v, size_t n, rk_error *err)
{
    unsigned char *copy = rk_calloc(n ? 4 * n : 1, 1, err);
    if (!copy) return -1;
    for (size_t i = 0; i < n; i++) /* little-endian whatever the host */
        for (int b = 0; b < 4; b++) copy[4 * i + b] = (unsigned char)(v[i] >> (8 * b));
    return add_owned(w, id, flags_of(critical, ROMBIN_TYPE_U32), copy, 4 * n, err);
}

int rombin_add_reals(rombin_writer *w, const char *id, int critical, const double *v, size_t n, rk_error *err)
{
    size_t size = w->real_type == ROMBIN_REAL_F32 ? 4 : 8;
    unsigned char *copy = rk_calloc(n ? size * n : 1, 1, err);
    if (!copy) return -1;
    for (size_t i = 0; i < n; i++) {
        if (!isfinite(v[i]) || (size == 4 && fabs(v[i]) > 3.4e38)) {
            free(copy);
            return rk_fail(err, "rombin: chunk '%s' value %zu (%g) is not a finite %s", id, i, v[i],
                           size == 4 ? "float32" : "float64");
        }
        if (size == 4) {
            float f = (float)v[i];
            memcpy(copy + 4 * i, &f, 4);
        } else {
            memcpy(copy + 8 * i, &v[i], 8);
        }
    }
    return add_owned(w, id, flags_of(critical, ROMBIN_TYPE_REAL), copy, size * n, err);
}

static void put_u32(unsigned char *p, uint32_t v)
{
    for (int b = 0; b < 4; b++) p[b] = (unsigned char)(v >> (8 * b));
}

static void put_u64(unsigned char *p, uint64_t v)
{
    put_u32(p, (uint32_t)v);
    put_u32(p + 4, (uint32_t)(v >> 32));
}

static size_t align_up(size_t n) { return (n + ROMBIN_ALIGN - 1) / ROMBIN_ALIGN * ROMBIN_ALIGN; }

int rombin_serialize(const rombin_writer *w, unsigned char **out, size_t *bytes, rk_error *err)
{
    *out = NULL;
    if (w->count < 1) return rk_fail(err, "rombin: no chunks to write");
    unsigned char *stored[ROMBIN_MAX_CHUNKS] = {0};
    size_t stored_bytes[ROMBIN_MAX_CHUNKS];
    uint32_t comp[ROMBIN_MAX_CHUNKS];
    size_t table_end = ROMBIN_HEADER_BYTES + (size_t)w->count * ROMBIN_ENTRY_BYTES, total = align_up(table_end);
    int rc = 0;
    for (int i = 0; i < w->count && !rc; i++) {
        const rombin_out_chunk *c = &w->chunk[i];
        stored[i] = c->data;
        stored_bytes[i] = c->bytes;
        comp[i] = ROMBIN_COMP_NONE;
        if (w->compress && c->bytes > 0) {
            uLongf n = compressBound((uLong)c->bytes);
            unsigned char *z = malloc(n);
            if (!z) rc = rk_fail(err, "rombin: out of memory compressing '%s'", c->id);
            else if (compress2(z, &n, c->data, (uLong)c->bytes, 9) != Z_OK) {
                free(z);
                rc = rk_fail(err, "rombin: zlib failed on chunk '%s'", c->id);
            } else if (n < c->bytes) {
                stored[i] = z;
                stored_bytes[i] = n;
                comp[i] = ROMBIN_COMP_DEFLATE;
            } else {
                free(z);
            }
        }
        total += align_up(stored_bytes[i]);
    }
    unsigned char *buf = rc ? NULL : rk_calloc(total, 1, err);
    if (buf) {
        memcpy(buf, ROMBIN_SIGNATURE, ROMBIN_SIGNATURE_BYTES);
        buf[ROMBIN_H_MAJOR] = ROMBIN_VERSION_MAJOR;
        buf[ROMBIN_H_MINOR] = ROMBIN_VERSION_MINOR;
        put_u32(buf + ROMBIN_H_ENDIAN, ROMBIN_ENDIAN_SENTINEL);
        float f32 = ROMBIN_F32_SENTINEL;
        double f64 = ROMBIN_F64_SENTINEL;
        memcpy(buf + ROMBIN_H_F32, &f32, 4);
        memcpy(buf + ROMBIN_H_F64, &f64, 8);
        put_u32(buf + ROMBIN_H_REAL, (uint32_t)w->real_type);
        put_u64(buf + ROMBIN_H_FILE_BYTES, total);
        put_u32(buf + ROMBIN_H_CHUNKS, (uint32_t)w->count);
        size_t at = align_up(table_end);
        for (int i = 0; i < w->count; i++) {
            unsigned char *e = buf + ROMBIN_HEADER_BYTES + (size_t)i * ROMBIN_ENTRY_BYTES;
            memcpy(e + ROMBIN_E_ID, w->chunk[i].id, 4);
            put_u32(e + ROMBIN_E_FLAGS, w->chunk[i].flags | comp[i] << ROMBIN_COMP_SHIFT);
            put_u64(e + ROMBIN_E_OFFSET, at);
            put_u64(e + ROMBIN_E_STORED, stored_bytes[i]);
            put_u64(e + ROMBIN_E_RAW, w->chunk[i].bytes);
            put_u32(e + ROMBIN_E_CRC, rombin_crc32(0, stored[i], stored_bytes[i]));
            if (stored_bytes[i]) memcpy(buf + at, stored[i], stored_bytes[i]);
            at += align_up(stored_bytes[i]);
        }
        uint32_t crc = rombin_crc32(0, buf, ROMBIN_H_TABLE_CRC);
        crc = rombin_crc32(crc, buf + ROMBIN_HEADER_BYTES, table_end - ROMBIN_HEADER_BYTES);
        put_u32(buf + ROMBIN_H_TABLE_CRC, crc);
        *out = buf;
        *bytes = total;
    } else {
        rc = -1;
    }
    for (int i = 0; i < w->count; i++)
        if (stored[i] && stored[i] != w->chunk[i].data) free(stored[i]);
    return rc;
}

int rombin_save(const char *path, const unsigned char *data, size_t bytes, rk_error *err)
{
    rk_atomic_file f;
    if (rk_atomic_open(&f, path, err)) return -1;
    if (fwrite(data, 1, bytes, f.fp) != bytes) {
        rk_atomic_abort(&f);
        return rk_fail(err, "%s: write failed", path);
    }
    return rk_atomic_commit(&f, err);
}

int rombin_inflate_all(const void *data, size_t size, unsigned char **out, size_t *bytes, rk_error *err)
{
    rombin_file f;
    rombin_error e;
    if (rombin_open(&f, data, size, NULL, &e)) return rk_fail(err, "%s", e.message);
    rombin_writer w;
    rombin_writer_init(&w, (int)f.real_type, 0);
    int rc = 0;
    for (unsigned i = 0; i < f.count && !rc; i++) {
        rombin_chunk c;
        rombin_chunk_get(&f, i, &c);
        uLongf n = (uLongf)c.raw;
        unsigned char *raw = rk_calloc(c.raw ? (size_t)c.raw : 1, 1, err);
        if (!raw) {
            rc = -1;
            break;
        }
        if (c.compression == ROMBIN_COMP_NONE) {
            memcpy(raw, c.data, (size_t)c.raw);
        } else if (uncompress(raw, &n, c.data, (uLong)c.stored) != Z_OK || n != c.raw) {
            free(raw);
            rc = rk_fail(err, "chunk '%s': deflate stream is damaged or does not inflate to its raw length %llu",
                         c.id, (unsigned long long)c.raw);
            break;
        }
        rc = add_owned(&w, c.id, c.flags & ~ROMBIN_COMP_MASK, raw, (size_t)c.raw, err);
    }
    if (!rc) rc = rombin_serialize(&w, out, bytes, err);
    rombin_writer_free(&w);
    return rc;
}

int rombin_inflate_in_place(unsigned char **data, size_t *size, int *inflated, rk_error *err)
{
    rombin_file f;
    rombin_error e;
    *inflated = 0;
    if (rombin_open(&f, *data, *size, NULL, &e)) return 0;
    for (unsigned i = 0; i < f.count && !*inflated; i++) {
        rombin_chunk c;
        rombin_chunk_get(&f, i, &c);
        *inflated = c.compression != ROMBIN_COMP_NONE;
    }
    if (!*inflated) return 0;
    unsigned char *plain;
    size_t n;
    if (rombin_inflate_all(*data, *size, &plain, &n, err)) return -1;
    free(*data);
    *data = plain;
    *size = n;
    return 0;
}

int rombin_read_file(const char *path, unsigned char **data, size_t *size, rk_error *err)
{
    *data = NULL;
    FILE *fp = fopen(path, "rb");
    if (!fp) return rk_fail(err, "%s: cannot open", path);
    if (fseek(fp, 0, SEEK_END) != 0) {
        fclose(fp);
        return rk_fail(err, "%s: cannot seek", path);
    }
    long n = ftell(fp);
    rewind(fp);
    if (n < 0) {
        fclose(fp);
        return rk_fail(err, "%s: cannot tell its size", path);
    }
    size_t alloc = ((size_t)n + 15) / 16 * 16;
    unsigned char *buf = aligned_alloc(16, alloc ? alloc : 16);
    if (!buf) {
        fclose(fp);
        return rk_fail(err, "%s: out of memory for %ld bytes", path, n);
    }
    if (fread(buf, 1, (size_t)n, fp) != (size_t)n) {
        free(buf);
        fclose(fp);
        return rk_fail(err, "%s: read failed", path);
    }
    fclose(fp);
    *data = buf;
    *size = (size_t)n;
    return 0;
}
