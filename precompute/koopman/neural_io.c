/* The trained neural DMD as a file (koopman.h: rk_koopman_neural_write / _read), so a family is
 * trained once and baked at any shape code or mesh later. Little-endian, native doubles:
 *   "RKNDMD" 0 1 (8 bytes: the magic, then the format version, 1, big-endian)
 *   int32  r, window, g, net layers L, eigenvalue-network layers Le (0 when g = 0)
 *   int32  net sizes (L + 1), eigenvalue-network sizes (Le + 1, when Le > 0), block (r)
 *   double h, vscale, center (3), scale, eig (r), gamma_lo (g), gamma_hi (g),
 *          the training report (pretrained, Adam and final loss, seconds, polish steps),
 *          net params, eigenvalue-network params
 *   uint32 CRC-32 (rombin_crc32, the zlib one) of everything before it
 * Written atomically; read back with every count and value checked, naming what is wrong. */
#include "koopman/koopman.h"

#include "formats/rombin_read.h"
#include "formats/rombin_write.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static const unsigned char MAGIC[8] = {'R', 'K', 'N', 'D', 'M', 'D', 0, 1};

typedef struct {
    unsigned char *data;
    size_t size, cap;
    int failed;
} buffer;

static void put(buffer *b, const void *p, size_t n)
{
    if (b->failed) return;
    if (b->size + n > b->cap) {
        size_t cap = b->cap ? 2 * b->cap : 4096;
        while (cap < b->size + n) cap *= 2;
        unsigned char *d = realloc(b->data, cap);
        if (!d) {
            b->failed = 1;
            return;
        }
        b->data = d;
        b->cap = cap;
    }
    memcpy(b->data + b->size, p, n);
    b->size += n;
}

static void put_ints(buffer *b, const int *v, int n)
{
    for (int i = 0; i < n; i++) {
        int32_t x = v[i];
        put(b, &x, sizeof x);
    }
}

int rk_koopman_neural_write(const rk_koopman_neural *nk, const rk_koopman_neural_report *rep, const char *path,
                            rk_error *err)
{
    buffer b = {0};
    int L = nk->net.nlayers, Le = nk->g ? nk->eignet.nlayers : 0;
    int head[5] = {nk->r, nk->window, nk->g, L, Le};
    put(&b, MAGIC, sizeof MAGIC);
    put_ints(&b, head, 5);
    put_ints(&b, nk->net.sizes, L + 1);
    if (Le) put_ints(&b, nk->eignet.sizes, Le + 1);
    put_ints(&b, nk->block, nk->r);
    double reals[6] = {nk->h, nk->vscale, nk->center[0], nk->center[1], nk->center[2], nk->scale};
    put(&b, reals, sizeof reals);
    put(&b, nk->eig, sizeof(double) * nk->r);
    if (nk->g) {
        put(&b, nk->gamma_lo, sizeof(double) * nk->g);
        put(&b, nk->gamma_hi, sizeof(double) * nk->g);
    }
    rk_koopman_neural_report none = {0};
    if (!rep) rep = &none;
    double report[5] = {rep->pretrained_loss, rep->adam_loss, rep->final_loss, rep->seconds, rep->polish_iterations};
    put(&b, report, sizeof report);
    put(&b, nk->net.params, sizeof(double) * (size_t)rk_mlp_params(&nk->net));
    if (Le) put(&b, nk->eignet.params, sizeof(double) * (size_t)rk_mlp_params(&nk->eignet));
    uint32_t crc = b.failed ? 0 : rombin_crc32(0, b.data, b.size);
    put(&b, &crc, sizeof crc);
    int rc = b.failed ? rk_fail(err, "%s: out of memory serializing the neural DMD", path)
                      : rombin_save(path, b.data, b.size, err);
    free(b.data);
    return rc;
}

/* ---- reading ---- */

typedef struct {
    const unsigned char *data;
    size_t size, at;
    const char *path;
} reader;

static int take(reader *r, void *p, size_t n, const char *what, rk_error *err)
{
    if (r->size - r->at < n)
        return rk_fail(err, "%s: truncated: %s needs %zu bytes at offset %zu, the file has %zu", r->path, what, n, r->at,
                       r->size);
    memcpy(p, r->data + r->at, n);
    r->at += n;
    return 0;
}

static int take_ints(reader *r, int *v, int n, int lo, int hi, const char *what, rk_error *err)
{
    for (int i = 0; i < n; i++) {
        int32_t x = 0;
        if (take(r, &x, sizeof x, what, err)) return -1;
        if (x < lo || x > hi) return rk_fail(err, "%s: %s[%d] is %d; must be %d to %d", r->path, what, i, (int)x, lo, hi);
        v[i] = x;
    }
    return 0;
}

static int take_reals(reader *r, double *v, size_t n, const char *what, rk_error *err)
{
    if (take(r, v, sizeof(double) * n, what, err)) return -1;
    for (size_t i = 0; i < n; i++)
        if (!isfinite(v[i])) return rk_fail(err, "%s: %s value %zu is not finite", r->path, what, i);
    return 0;
}

/* A network of those sizes, made only when the file still holds its parameters (a damaged count
 * must not ask for gigabytes). */
static int network(reader *rd, const int *sizes, int L, rk_mlp *m, const char *what, rk_error *err)
{
    double count = 0;
    for (int l = 0; l < L; l++) count += (double)sizes[l + 1] * (sizes[l] + 1);
    if (count * sizeof(double) > (double)(rd->size - rd->at))
        return rk_fail(err, "%s: the %s's sizes need %.0f parameters; the file holds fewer", rd->path, what, count);
    return rk_mlp_init(m, L + 1, sizes, 1, err);
}

static int read_body(reader *rd, rk_koopman_neural *nk, rk_koopman_neural_report *rep, rk_error *err)
{
    int head[5], sizes[66];
    if (take_ints(rd, head, 5, 0, 1 << 20, "header (rank, window, shape code, layers)", err)) return -1;
    int r = head[0], L = head[3], Le = head[4];
    nk->r = r;
    nk->window = head[1];
    nk->g = head[2];
    if (r < 1 || nk->window < 1 || nk->g > RK_KOOPMAN_SHAPE_MAX || L < 1 || L > 64 || Le > 64 || (nk->g > 0) != (Le > 0))
        return rk_fail(err, "%s: rank %d, window %d, shape code %d, layers %d and %d do not make a neural DMD", rd->path,
                       r, nk->window, nk->g, L, Le);
    if (take_ints(rd, sizes, L + 1, 1, 1 << 24, "network sizes", err)) return -1;
    if (sizes[0] != 3 + nk->g || sizes[L] != 6 * r)
        return rk_fail(err, "%s: the modes' network maps %d to %d values; a rank-%d model with a %d-value shape code "
                       "maps %d to %d", rd->path, sizes[0], sizes[L], r, nk->g, 3 + nk->g, 6 * r);
    if (network(rd, sizes, L, &nk->net, "modes' network", err)) return -1;
    if (Le) {
        if (take_ints(rd, sizes, Le + 1, 1, 1 << 24, "eigenvalue network sizes", err)) return -1;
        if (sizes[0] != nk->g || sizes[Le] != r)
            return rk_fail(err, "%s: the eigenvalue network maps %d to %d values; need %d to %d", rd->path, sizes[0],
                           sizes[Le], nk->g, r);
        if (network(rd, sizes, Le, &nk->eignet, "eigenvalue network", err)) return -1;
    }
    nk->block = rk_calloc((size_t)r, sizeof(int), err);
    nk->eig = rk_calloc((size_t)r, sizeof(double), err);
    if (!nk->block || !nk->eig || take_ints(rd, nk->block, r, 0, 2, "block", err)) return -1;
    for (int j = 0; j < r; j++) /* 1 real, 2 first of a pair, 0 its second (rk_koopman's) */
        if ((nk->block[j] == 2) != (j + 1 < r && nk->block[j + 1] == 0) || (nk->block[j] == 0 && (j == 0 || nk->block[j - 1] != 2)))
            return rk_fail(err, "%s: block %d (%d) does not pair up: 2 must be followed by 0", rd->path, j, nk->block[j]);
    double reals[6];
    if (take_reals(rd, reals, 6, "step, velocity scale, input frame", err) || take_reals(rd, nk->eig, r, "eigenvalue parameters", err))
        return -1;
    nk->h = reals[0];
    nk->vscale = reals[1];
    memcpy(nk->center, reals + 2, sizeof nk->center);
    nk->scale = reals[5];
    if (!(nk->h > 0) || !(nk->vscale > 0) || !(nk->scale > 0))
        return rk_fail(err, "%s: time step %g, velocity scale %g and input scale %g must be positive", rd->path, nk->h,
                       nk->vscale, nk->scale);
    if (nk->g) {
        nk->gamma_lo = rk_calloc((size_t)nk->g, sizeof(double), err);
        nk->gamma_hi = rk_calloc((size_t)nk->g, sizeof(double), err);
        if (!nk->gamma_lo || !nk->gamma_hi || take_reals(rd, nk->gamma_lo, nk->g, "shape code low end", err) ||
            take_reals(rd, nk->gamma_hi, nk->g, "shape code high end", err))
            return -1;
        for (int c = 0; c < nk->g; c++)
            if (!(nk->gamma_lo[c] <= nk->gamma_hi[c]))
                return rk_fail(err, "%s: shape code %d's range [%g, %g] is empty", rd->path, c, nk->gamma_lo[c],
                               nk->gamma_hi[c]);
    }
    double report[5];
    if (take_reals(rd, report, 5, "training report", err) ||
        take_reals(rd, nk->net.params, (size_t)rk_mlp_params(&nk->net), "modes' network parameters", err) ||
        (Le && take_reals(rd, nk->eignet.params, (size_t)rk_mlp_params(&nk->eignet), "eigenvalue network parameters", err)))
        return -1;
    if (rep) *rep = (rk_koopman_neural_report){.pretrained_loss = report[0], .adam_loss = report[1],
                                               .final_loss = report[2], .seconds = report[3],
                                               .polish_iterations = (int)report[4]};
    if (rd->at != rd->size - sizeof(uint32_t))
        return rk_fail(err, "%s: %zu bytes after the model (a different format?)", rd->path, rd->size - sizeof(uint32_t) - rd->at);
    return 0;
}

int rk_koopman_neural_read(const char *path, rk_koopman_neural *nk, rk_koopman_neural_report *rep, rk_error *err)
{
    memset(nk, 0, sizeof *nk);
    unsigned char *data;
    size_t size;
    if (rombin_read_file(path, &data, &size, err)) return -1;
    int rc = -1;
    if (size < sizeof MAGIC + sizeof(uint32_t) || memcmp(data, MAGIC, 6))
        rk_fail(err, "%s: not a neural DMD model (no RKNDMD header)", path);
    else if (data[6] != 0 || data[7] != 1)
        rk_fail(err, "%s: neural DMD model format version %d; this romkit reads version 1", path, data[6] << 8 | data[7]);
    else {
        uint32_t stored;
        memcpy(&stored, data + size - sizeof stored, sizeof stored);
        uint32_t crc = rombin_crc32(0, data, size - sizeof stored);
        if (crc != stored) rk_fail(err, "%s: checksum mismatch (stored %08x, computed %08x): the file is damaged", path, stored, crc);
        else {
            reader rd = {data, size, sizeof MAGIC, path};
            rc = read_body(&rd, nk, rep, err);
        }
    }
    free(data);
    if (rc) rk_koopman_neural_free(nk);
    return rc;
}
