/* STL surfaces, ASCII ("solid ... facet normal ... outer loop vertex x y z ... endsolid") and
 * binary (80-byte header, uint32 count, 50 bytes per triangle, little-endian). STL stores
 * every triangle's corners separately: rk_surface_weld joins the corners with exactly equal
 * coordinates into one vertex so the result has connectivity. */
#include <inttypes.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/binary_reader_impl.h"
#include "mesh/mesh_impl.h"

static int read_binary(rk_reader *r, double **corners, int *nf)
{
    int64_t n;
    r->pos = 80;
    rk_reader_set_binary(r, 1, 0);
    if (rk_read_integer(r, RK_U32, &n, "triangle count") ||
        rk_check_count(r, n, RK_MESH_MAX_COUNT / 3, 0, 50, "triangle"))
        return -1;
    *corners = rk_calloc((size_t)n * 9, sizeof **corners, r->err);
    if (!*corners) return -1;
    for (int64_t t = 0; t < n; t++) {
        double normal;
        for (int k = 0; k < 3; k++)
            if (rk_read_real(r, RK_F32, &normal, "normal")) return -1;
        for (int k = 0; k < 9; k++)
            if (rk_read_real(r, RK_F32, &(*corners)[9 * t + k], "vertex coordinate")) return -1;
        r->pos += 2; /* attribute bytes: the count check above guarantees they are there */
    }
    *nf = (int)n;
    return 0;
}

static int expect(rk_reader *r, const char *word) { return rk_expect_word(r, word, 1); }

static int read_ascii(rk_reader *r, double **corners, int *nf)
{
    size_t cap = 0;
    double p[3], *poly = NULL;
    size_t pcap = 0;
    rk_token tok;
    int rc = 0;
    while (rc == 0 && rk_next_token(r, &tok)) {
        if (rk_token_is_nocase(tok, "solid") || rk_token_is_nocase(tok, "endsolid")) {
            rk_skip_line(r); /* the solid's name */
            continue;
        }
        if (!rk_token_is_nocase(tok, "facet")) {
            char shown[40];
            rc = rk_reader_fail(r, "expected 'facet', got '%s'", rk_token_str(tok, shown, sizeof shown));
            break;
        }
        if (expect(r, "normal") || rk_text_double(r, &p[0], "normal") || rk_text_double(r, &p[1], "normal") ||
            rk_text_double(r, &p[2], "normal") || expect(r, "outer") || expect(r, "loop")) {
            rc = -1;
            break;
        }
        int n = 0;
        while (rc == 0 && rk_next_token(r, &tok) && rk_token_is_nocase(tok, "vertex")) {
            if (rk_grow(&poly, &pcap, 3 * ((size_t)n + 1), sizeof *poly, r->err)) rc = rk_error_prefix(r->err, "%s", r->path);
            for (int k = 0; rc == 0 && k < 3; k++)
                if (rk_text_double(r, &poly[3 * n + k], "vertex coordinate")) rc = -1;
            n++;
        }
        if (rc) break;
        if (!rk_token_is_nocase(tok, "endloop")) {
            rc = rk_reader_fail(r, "expected 'vertex' or 'endloop'");
        } else if (n < 3) {
            rc = rk_reader_fail(r, "a facet needs at least 3 vertices, got %d", n);
        } else if (expect(r, "endfacet")) {
            rc = -1;
        } else if (*nf > RK_MESH_MAX_COUNT / 3 - (n - 2)) {
            rc = rk_reader_fail(r, "too many triangles");
        } else if (rk_grow(corners, &cap, 9 * ((size_t)*nf + (size_t)(n - 2)), sizeof **corners, r->err)) {
            rc = rk_error_prefix(r->err, "%s", r->path);
        } else {
            for (int k = 1; k + 1 < n; k++) { /* fan */
                double *c = *corners + 9 * (size_t)(*nf)++;
                memcpy(c, poly, 3 * sizeof *c);
                memcpy(c + 3, poly + 3 * k, 3 * sizeof *c);
                memcpy(c + 6, poly + 3 * (k + 1), 3 * sizeof *c);
            }
        }
    }
    free(poly);
    return rc;
}

static int is_binary(const rk_reader *r)
{
    if (r->len < 84) return 0;
    const unsigned char *b = (const unsigned char *)r->buf + 80;
    uint64_t n = (uint64_t)b[0] | (uint64_t)b[1] << 8 | (uint64_t)b[2] << 16 | (uint64_t)b[3] << 24;
    if (84 + 50 * n == r->len) return 1;
    /* "solid" starts an ASCII file (a binary header may start with it too: the size decides). */
    size_t i = 0;
    while (i < r->len && (r->buf[i] == ' ' || r->buf[i] == '\t' || r->buf[i] == '\r' || r->buf[i] == '\n')) i++;
    return !(r->len - i >= 5 && strncmp(r->buf + i, "solid", 5) == 0);
}

int rk_read_stl(const char *path, rk_surface *s, rk_error *err)
{
    rk_reader r;
    double *corners = NULL;
    int nf = 0;
    *s = (rk_surface){0};
    if (rk_reader_open(&r, path, 0, err)) return -1;
    int rc = is_binary(&r) ? read_binary(&r, &corners, &nf) : read_ascii(&r, &corners, &nf);
    for (size_t i = 0; rc == 0 && i < 9 * (size_t)nf; i++)
        if (!isfinite(corners[i])) rc = rk_fail(err, "%s: triangle %zu has a non-finite coordinate", path, i / 9);
    if (rc == 0 && nf == 0) rc = rk_fail(err, "%s: no triangles", path);
    if (rc == 0 && rk_surface_weld(corners, nf, s, err)) rc = rk_error_prefix(err, "%s", path);
    free(corners);
    rk_reader_close(&r);
    if (rc) rk_surface_free(s);
    return rc;
}
