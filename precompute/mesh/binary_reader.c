#include "mesh/binary_reader_impl.h"

#include <math.h>
#include <string.h>

size_t rk_scalar_size(rk_scalar t)
{
    switch (t) {
    case RK_I8: case RK_U8: return 1;
    case RK_I16: case RK_U16: return 2;
    case RK_I32: case RK_U32: case RK_F32: return 4;
    case RK_I64: case RK_U64: case RK_F64: return 8;
    }
    return 8;
}

int rk_host_little_endian(void)
{
    const uint16_t one = 1;
    unsigned char b;
    memcpy(&b, &one, 1);
    return b == 1;
}

void rk_reader_set_binary(rk_reader *r, int binary, int big_endian)
{
    r->binary = binary;
    r->big_endian = big_endian;
}

int rk_bin_need(rk_reader *r, size_t n, const char *what)
{
    if (r->pos > r->len || n > r->len - r->pos)
        return rk_reader_fail(r, "truncated: %s needs %zu bytes, %zu remain", what, n,
                              r->pos <= r->len ? r->len - r->pos : 0);
    return 0;
}

int rk_bin_bytes(rk_reader *r, void *out, size_t n, const char *what)
{
    if (rk_bin_need(r, n, what)) return -1;
    memcpy(out, r->buf + r->pos, n);
    r->pos += n;
    return 0;
}

/* The raw value in host byte order, in an 8-byte buffer. */
static int read_raw(rk_reader *r, rk_scalar t, unsigned char raw[8], const char *what)
{
    size_t n = rk_scalar_size(t);
    if (rk_bin_bytes(r, raw, n, what)) return -1;
    if (n > 1 && r->big_endian == rk_host_little_endian()) {
        for (size_t i = 0; i < n / 2; i++) {
            unsigned char c = raw[i];
            raw[i] = raw[n - 1 - i];
            raw[n - 1 - i] = c;
        }
    }
    return 0;
}

/* Binary value as double, and as an exact integer where the type is integral. */
static int read_binary(rk_reader *r, rk_scalar t, double *d, int64_t *i, int *too_big, const char *what)
{
    unsigned char raw[8];
    if (read_raw(r, t, raw, what)) return -1;
    *too_big = 0;
    switch (t) {
    case RK_I8: { int8_t v; memcpy(&v, raw, 1); *i = v; break; }
    case RK_U8: { uint8_t v; memcpy(&v, raw, 1); *i = v; break; }
    case RK_I16: { int16_t v; memcpy(&v, raw, 2); *i = v; break; }
    case RK_U16: { uint16_t v; memcpy(&v, raw, 2); *i = v; break; }
    case RK_I32: { int32_t v; memcpy(&v, raw, 4); *i = v; break; }
    case RK_U32: { uint32_t v; memcpy(&v, raw, 4); *i = v; break; }
    case RK_I64: { int64_t v; memcpy(&v, raw, 8); *i = v; break; }
    case RK_U64: {
        uint64_t v;
        memcpy(&v, raw, 8);
        *too_big = v > (uint64_t)INT64_MAX;
        *i = *too_big ? INT64_MAX : (int64_t)v;
        break;
    }
    case RK_F32: { float v; memcpy(&v, raw, 4); *d = v; return 0; }
    case RK_F64: { double v; memcpy(&v, raw, 8); *d = v; return 0; }
    }
    *d = (double)*i;
    return 0;
}

static int is_float(rk_scalar t) { return t == RK_F32 || t == RK_F64; }

int rk_read_integer(rk_reader *r, rk_scalar t, int64_t *v, const char *what)
{
    double d = 0;
    int64_t i = 0;
    int too_big = 0;
    if (!r->binary) {
        if (!is_float(t)) return rk_text_int64(r, v, what);
        if (rk_text_double(r, &d, what)) return -1;
    } else {
        size_t at = r->pos;
        if (read_binary(r, t, &d, &i, &too_big, what)) return -1;
        if (too_big) {
            r->pos = at;
            return rk_reader_fail(r, "%s is too large", what);
        }
        if (!is_float(t)) {
            *v = i;
            return 0;
        }
    }
    /* A float that must hold an integer (PLY lets any type carry indices). */
    if (!(fabs(d) <= 9007199254740992.0) || d != floor(d))
        return rk_reader_fail(r, "%s %g is not an integer", what, d);
    *v = (int64_t)d;
    return 0;
}

int rk_read_real(rk_reader *r, rk_scalar t, double *v, const char *what)
{
    if (!r->binary) return rk_text_double(r, v, what);
    int64_t i;
    int too_big;
    return read_binary(r, t, v, &i, &too_big, what);
}
