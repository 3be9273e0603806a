/* OFF surfaces: "OFF" (or COFF, NOFF, ...), "nv nf ne", nv lines "x y z [extra]",
 * nf lines "n i1 .. in [color]" (0-based). Polygons become triangle fans. */
#include <inttypes.h>
#include <stdlib.h>

#include "mesh/mesh_impl.h"
#include "mesh/text_reader_impl.h"

static int is_off_keyword(rk_token tok)
{
    /* Optional prefixes ST (texture), C (colour), N (normals) before OFF; not nOFF/4OFF. */
    if (tok.len < 3 || tok.len > 8) return 0;
    for (size_t i = 0; i + 3 < tok.len; i++)
        if (tok.s[i] != 'S' && tok.s[i] != 'T' && tok.s[i] != 'C' && tok.s[i] != 'N') return 0;
    rk_token tail = {tok.s + tok.len - 3, 3};
    return rk_token_is(tail, "OFF");
}

static int read_faces(rk_reader *r, rk_surface_builder *b, int64_t nf)
{
    int *poly = NULL;
    size_t cap = 0;
    int rc = 0;
    for (int64_t f = 0; rc == 0 && f < nf; f++) {
        int n;
        if (rk_text_int(r, 3, 1 << 20, &n, "face vertex count") ||
            rk_check_count(r, n, 1 << 20, 1, 0, "face vertex")) {
            rc = -1;
            break;
        }
        if (rk_grow(&poly, &cap, (size_t)n, sizeof *poly, r->err)) {
            rc = rk_error_prefix(r->err, "%s", r->path);
            break;
        }
        for (int k = 0; rc == 0 && k < n; k++) {
            int64_t i;
            if (rk_text_int64(r, &i, "face vertex index")) rc = -1;
            else if (i < 0 || i >= b->s.nv)
                rc = rk_reader_fail(r, "face %" PRId64 " references vertex %" PRId64 ", but there are %d vertices", f, i, b->s.nv);
            else poly[k] = (int)i;
        }
        if (rc == 0 && rk_sb_polygon(b, poly, n, r->err)) rc = rk_error_prefix(r->err, "%s", r->path);
        rk_skip_line(r); /* per-face colour */
    }
    free(poly);
    return rc;
}

int rk_read_off(const char *path, rk_surface *s, rk_error *err)
{
    rk_reader r;
    rk_surface_builder b = {0};
    rk_token tok;
    int64_t nv, nf, ne;
    int rc = -1;
    *s = (rk_surface){0};
    if (rk_reader_open(&r, path, '#', err)) return -1;
    int on_line = 0;
    if (!rk_next_token(&r, &tok) || !is_off_keyword(tok)) {
        rk_reader_fail(&r, "not an OFF file (expected OFF on the first line)");
    } else if ((on_line = rk_next_token_on_line(&r, &tok)) && rk_token_is_nocase(tok, "BINARY")) {
        rk_reader_fail(&r, "binary OFF is not supported");
    } else {
        if (on_line) r.pos = (size_t)(tok.s - r.buf); /* counts on the OFF line: read them below */
        if (rk_text_int64(&r, &nv, "vertex count") || rk_text_int64(&r, &nf, "face count") ||
            rk_text_int64(&r, &ne, "edge count") || rk_check_count(&r, nv, RK_MESH_MAX_COUNT, 3, 0, "vertex") ||
            rk_check_count(&r, nf, RK_MESH_MAX_COUNT, 4, 0, "face"))
            goto done;
        rk_skip_line(&r);
        for (int64_t i = 0; i < nv; i++) {
            double p[3];
            if (rk_text_double(&r, &p[0], "vertex x") || rk_text_double(&r, &p[1], "vertex y") ||
                rk_text_double(&r, &p[2], "vertex z"))
                goto done;
            if (rk_sb_vertex(&b, p, err)) {
                rk_error_prefix(err, "%s", path);
                goto done;
            }
            rk_skip_line(&r); /* colour, normal, texture coordinates */
        }
        rc = read_faces(&r, &b, nf);
    }
done:
    rk_reader_close(&r);
    if (rc) rk_surface_free(&b.s);
    else *s = b.s;
    return rc;
}
