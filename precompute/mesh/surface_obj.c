/* Wavefront OBJ surfaces: "v x y z [w | r g b]" and "f a b c ..." with a, a/t, a//n or a/t/n
 * references (1-based; negative counts back from the last vertex). Polygons become triangle
 * fans; every other statement (vt, vn, g, o, s, usemtl, l, ...) is ignored. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/mesh_impl.h"
#include "mesh/text_reader_impl.h"

/* The vertex index of one face reference ("12", "12/3", "-1//7"), 0-based. */
static int face_reference(rk_reader *r, rk_token tok, int nv, int *out)
{
    char buf[64], shown[40], *end;
    size_t n = 0;
    while (n < tok.len && tok.s[n] != '/') n++;
    if (n == 0 || n >= sizeof buf) return rk_reader_fail(r, "bad face reference '%s'", rk_token_str(tok, shown, sizeof shown));
    memcpy(buf, tok.s, n);
    buf[n] = '\0';
    errno = 0;
    long i = strtol(buf, &end, 10);
    if (*end != '\0' || errno == ERANGE)
        return rk_reader_fail(r, "bad face reference '%s'", rk_token_str(tok, shown, sizeof shown));
    if (i == 0) return rk_reader_fail(r, "face reference 0 (OBJ indices start at 1)");
    long idx = i > 0 ? i - 1 : nv + i;
    if (idx < 0 || idx >= nv)
        return rk_reader_fail(r, "face references vertex %ld, but %d vertices are defined before it", i, nv);
    *out = (int)idx;
    return 0;
}

static int read_face(rk_reader *r, rk_surface_builder *b, int **poly, size_t *cap)
{
    rk_token tok;
    int n = 0;
    while (rk_next_token_on_line(r, &tok)) {
        if (rk_grow(poly, cap, (size_t)n + 1, sizeof **poly, r->err)) return rk_error_prefix(r->err, "%s", r->path);
        if (face_reference(r, tok, b->s.nv, &(*poly)[n])) return -1;
        n++;
    }
    if (n < 3) return rk_reader_fail(r, "a face needs at least 3 vertices, got %d", n);
    if (rk_sb_polygon(b, *poly, n, r->err)) return rk_error_prefix(r->err, "%s", r->path);
    return 0;
}

int rk_read_obj(const char *path, rk_surface *s, rk_error *err)
{
    rk_reader r;
    rk_surface_builder b = {0};
    int *poly = NULL;
    size_t cap = 0;
    int rc = 0;
    *s = (rk_surface){0};
    if (rk_reader_open(&r, path, '#', err)) return -1;
    rk_token tok;
    while (rc == 0 && rk_next_token(&r, &tok)) {
        if (rk_token_is(tok, "v")) {
            double p[3];
            rc = rk_text_double(&r, &p[0], "vertex x") || rk_text_double(&r, &p[1], "vertex y") ||
                 rk_text_double(&r, &p[2], "vertex z");
            if (rc == 0 && rk_sb_vertex(&b, p, err)) rc = rk_error_prefix(err, "%s", path);
        } else if (rk_token_is(tok, "f")) {
            rc = read_face(&r, &b, &poly, &cap);
        }
        rk_skip_line(&r);
    }
    if (rc) rc = -1;
    free(poly);
    rk_reader_close(&r);
    if (rc) rk_surface_free(&b.s);
    else *s = b.s;
    return rc;
}
