#include "util/util.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


int rk_npy_stream_open(rk_npy_stream *st, const char *path, int ndim, const long *shape, rk_error *err)
{
    memset(st, 0, sizeof *st);
    if (ndim < 1 || ndim > 4) return rk_fail(err, "%s: npy arrays must have 1 to 4 dimensions", path);
    char dims[160] = "";
    size_t count = 1;
    for (int i = 0; i < ndim; i++) {
        char one[40];
        snprintf(one, sizeof one, "%ld, ", shape[i]);
        strcat(dims, one);
        count *= (size_t)shape[i];
    }
    if (ndim > 1) dims[strlen(dims) - 2] = '\0'; /* "(3,)" needs its comma; "(2, 3)" does not */
    char header[256];
    int len = snprintf(header, sizeof header,
                       "{'descr': '<f8', 'fortran_order': False, 'shape': (%s), }", dims);
    /* Magic (6) + version (2) + header length (2) + header, padded with spaces to a multiple of 64
     * and ended by a newline, as the format asks. */
    int total = 10 + len + 1;
    int pad = (64 - total % 64) % 64;
    if (rk_atomic_open(&st->file, path, err)) return -1;
    uint16_t hlen = (uint16_t)(len + pad + 1);
    unsigned char pre[10] = {0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0,
                             (unsigned char)(hlen & 0xff), (unsigned char)(hlen >> 8)};
    fwrite(pre, 1, 10, st->file.fp);
    fwrite(header, 1, (size_t)len, st->file.fp);
    for (int i = 0; i < pad; i++) fputc(' ', st->file.fp);
    fputc('\n', st->file.fp);
    st->expected = count;
    return 0;
}

void rk_npy_stream_append(rk_npy_stream *st, const double *data, size_t count)
{
    fwrite(data, sizeof(double), count, st->file.fp); /* x86 and ARM hosts are little-endian */
    st->written += count;
}

int rk_npy_stream_commit(rk_npy_stream *st, rk_error *err)
{
    if (st->written != st->expected) {
        rk_atomic_abort(&st->file);
        return rk_fail(err, "%s: %zu values written, the shape promised %zu", st->file.final_path,
                       st->written, st->expected);
    }
    return rk_atomic_commit(&st->file, err);
}

void rk_npy_stream_abort(rk_npy_stream *st) { rk_atomic_abort(&st->file); }

int rk_npy_write(const char *path, const double *data, int ndim, const long *shape, rk_error *err)
{
    rk_npy_stream st;
    if (rk_npy_stream_open(&st, path, ndim, shape, err)) return -1;
    rk_npy_stream_append(&st, data, st.expected);
    return rk_npy_stream_commit(&st, err);
}

int rk_npy_read(const char *path, double **data, int *ndim, long shape[4], rk_error *err)
{
    *data = NULL;
    FILE *fp = fopen(path, "rb");
    if (!fp) return rk_fail(err, "%s: cannot open: %s", path, strerror(errno));
    unsigned char pre[10];
    char header[4096];
    if (fread(pre, 1, 10, fp) != 10 || memcmp(pre, "\x93NUMPY", 6) != 0) {
        fclose(fp);
        return rk_fail(err, "%s: not a .npy file (bad magic at byte 0)", path);
    }
    size_t hlen = (size_t)pre[8] | ((size_t)pre[9] << 8);
    if (pre[6] != 1) {
        fclose(fp);
        return rk_fail(err, "%s: .npy version %d not supported (only 1.0)", path, pre[6]);
    }
    if (hlen >= sizeof header || fread(header, 1, hlen, fp) != hlen) {
        fclose(fp);
        return rk_fail(err, "%s: truncated .npy header", path);
    }
    header[hlen] = '\0';
    int is_f4 = strstr(header, "'<f4'") != NULL;
    if (!is_f4 && !strstr(header, "'<f8'")) {
        fclose(fp);
        return rk_fail(err, "%s: .npy dtype must be little-endian float64 or float32", path);
    }
    if (strstr(header, "'fortran_order': True")) {
        fclose(fp);
        return rk_fail(err, "%s: Fortran-ordered .npy not supported", path);
    }
    const char *s = strstr(header, "'shape':");
    s = s ? strchr(s, '(') : NULL;
    if (!s) {
        fclose(fp);
        return rk_fail(err, "%s: .npy header has no shape", path);
    }
    s++;
    *ndim = 0;
    size_t count = 1;
    while (*s && *s != ')') {
        char *end;
        long v = strtol(s, &end, 10);
        if (end == s) { s++; continue; }
        if (*ndim >= 4 || v < 0 || (v > 0 && count > ((size_t)1 << 40) / (size_t)v)) {
            fclose(fp);
            return rk_fail(err, "%s: .npy shape too large or has more than 4 dimensions", path);
        }
        shape[(*ndim)++] = v;
        count *= (size_t)v;
        s = end;
    }
    if (*ndim == 0) {
        fclose(fp);
        return rk_fail(err, "%s: .npy scalar arrays not supported", path);
    }
    double *out = malloc(count * sizeof(double) + 1);
    if (!out) {
        fclose(fp);
        return rk_fail(err, "%s: out of memory", path);
    }
    size_t got;
    if (is_f4) {
        got = 0;
        float v;
        while (got < count && fread(&v, 4, 1, fp) == 1) out[got++] = v;
    } else {
        got = fread(out, sizeof(double), count, fp);
    }
    fclose(fp);
    if (got != count) {
        free(out);
        return rk_fail(err, "%s: truncated .npy data (%zu of %zu values)", path, got, count);
    }
    *data = out;
    return 0;
}
