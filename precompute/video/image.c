/* Frames as float luminance: PNG through libpng (its simplified API converts any colour type and
 * bit depth to 8-bit sRGB RGBA; the luma 0.2126 R + 0.7152 G + 0.0722 B of those values is taken,
 * the alpha channel ignored: a camera's frame has no transparency to composite), and binary PGM (P5, maxval up to 65535) read directly since it is a header and raw bytes. */
#include "video/video.h"

#include <math.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>

int rk_image_alloc(rk_image *im, int w, int h, rk_error *err)
{
    im->w = w, im->h = h;
    im->px = rk_calloc((size_t)w * h, sizeof(float), err);
    return im->px ? 0 : -1;
}

void rk_image_free(rk_image *im)
{
    free(im->px);
    memset(im, 0, sizeof *im);
}

static int load_png(const char *path, rk_image *im, rk_error *err)
{
    png_image p;
    memset(&p, 0, sizeof p);
    p.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&p, path)) return rk_fail(err, "%s: not a readable PNG (%s)", path, p.message);
    p.format = PNG_FORMAT_RGBA;
    if (p.width < 2 || p.height < 2 || p.width > 1 << 15 || p.height > 1 << 15) {
        png_image_free(&p);
        return rk_fail(err, "%s: %u x %u pixels; expected 2..32768 each way", path, p.width, p.height);
    }
    unsigned char *buf = rk_calloc(PNG_IMAGE_SIZE(p), 1, err);
    if (!buf) {
        png_image_free(&p);
        return -1;
    }
    if (!png_image_finish_read(&p, NULL, buf, 0, NULL)) {
        free(buf);
        return rk_fail(err, "%s: PNG data unreadable (%s)", path, p.message);
    }
    int rc = rk_image_alloc(im, (int)p.width, (int)p.height, err);
    for (size_t i = 0; !rc && i < (size_t)im->w * im->h; i++)
        im->px[i] = (float)((0.2126 * buf[4 * i] + 0.7152 * buf[4 * i + 1] + 0.0722 * buf[4 * i + 2]) / 255.0);
    free(buf);
    return rc;
}

/* P5: "P5", width, height, maxval (whitespace and # comments between), one whitespace, raw samples. */
static int load_pgm(const char *path, FILE *f, rk_image *im, rk_error *err)
{
    long v[3];
    for (int i = 0; i < 3; i++) {
        int c = fgetc(f);
        while (c == '#' || c == ' ' || c == '\t' || c == '\r' || c == '\n') {
            if (c == '#')
                while (c != '\n' && c != EOF) c = fgetc(f);
            c = fgetc(f);
        }
        if (c < '0' || c > '9') return rk_fail(err, "%s: PGM header field %d is not a number", path, i + 1);
        v[i] = 0;
        while (c >= '0' && c <= '9' && v[i] < 1000000) v[i] = 10 * v[i] + (c - '0'), c = fgetc(f);
    }
    if (v[0] < 2 || v[1] < 2 || v[0] > 1 << 15 || v[1] > 1 << 15 || v[2] < 1 || v[2] > 65535)
        return rk_fail(err, "%s: PGM of %ld x %ld, maxval %ld; expected 2..32768 pixels each way, maxval 1..65535", path,
                       v[0], v[1], v[2]);
    if (rk_image_alloc(im, (int)v[0], (int)v[1], err)) return -1;
    int wide = v[2] > 255;
    for (size_t i = 0; i < (size_t)im->w * im->h; i++) {
        int a = fgetc(f), b = wide ? fgetc(f) : 0;
        if (a == EOF || b == EOF) {
            rk_image_free(im);
            return rk_fail(err, "%s: PGM data ends at pixel %zu of %ld", path, i, v[0] * v[1]);
        }
        im->px[i] = (float)((wide ? a * 256 + b : a) / (double)v[2]);
    }
    return 0;
}

int rk_image_load(const char *path, rk_image *im, rk_error *err)
{
    memset(im, 0, sizeof *im);
    FILE *f = fopen(path, "rb");
    if (!f) return rk_fail(err, "%s: cannot open (missing frame?)", path);
    unsigned char sig[8] = {0};
    size_t got = fread(sig, 1, 8, f);
    if (got >= 2 && sig[0] == 'P' && sig[1] == '5') {
        fseek(f, 2, SEEK_SET);
        int rc = load_pgm(path, f, im, err);
        fclose(f);
        return rc;
    }
    fclose(f);
    if (got < 8 || png_sig_cmp(sig, 0, 8)) return rk_fail(err, "%s: neither a PNG nor a binary PGM (P5) file", path);
    return load_png(path, im, err);
}

int rk_image_save_png(const char *path, const rk_image *im, rk_error *err)
{
    unsigned char *buf = rk_calloc((size_t)im->w * im->h, 1, err);
    if (!buf) return -1;
    for (size_t i = 0; i < (size_t)im->w * im->h; i++) {
        double v = im->px[i];
        buf[i] = (unsigned char)lrint(255 * (v < 0 ? 0 : v > 1 ? 1 : v));
    }
    rk_atomic_file af;
    int rc = rk_atomic_open(&af, path, err);
    if (!rc) {
        png_image p;
        memset(&p, 0, sizeof p);
        p.version = PNG_IMAGE_VERSION;
        p.width = (png_uint_32)im->w, p.height = (png_uint_32)im->h, p.format = PNG_FORMAT_GRAY;
#ifdef PNG_IMAGE_FLAG_FAST
        p.flags |= PNG_IMAGE_FLAG_FAST; /* speed over size: a test renders hundreds of frames */
#endif
        if (!png_image_write_to_stdio(&p, af.fp, 0, buf, 0, NULL)) {
            rk_atomic_abort(&af);
            rc = rk_fail(err, "%s: PNG not written (%s)", path, p.message);
        } else
            rc = rk_atomic_commit(&af, err);
    }
    free(buf);
    return rc;
}

double rk_image_sample(const rk_image *im, double x, double y)
{
    x = x < 0 ? 0 : x > im->w - 1 ? im->w - 1 : x;
    y = y < 0 ? 0 : y > im->h - 1 ? im->h - 1 : y;
    int x0 = (int)x, y0 = (int)y;
    if (x0 > im->w - 2) x0 = im->w - 2;
    if (y0 > im->h - 2) y0 = im->h - 2;
    double ax = x - x0, ay = y - y0;
    const float *r = im->px + (size_t)y0 * im->w + x0;
    return (1 - ay) * ((1 - ax) * r[0] + ax * r[1]) + ay * ((1 - ax) * r[im->w] + ax * r[im->w + 1]);
}
