/* MEDIT .mesh reader (ASCII). Keywords are case-insensitive and '#' starts a comment.
 * Vertices ("x y z ref") and Tetrahedra ("a b c d ref", 1-based; ref -> tet_tag) are read;
 * every other section (Triangles, Edges, Corners, Normals, ...) is skipped by passing over
 * numbers up to the next keyword, so sections we do not know need no size table. */
#include <inttypes.h>
#include <stdlib.h>

#include "mesh/mesh_impl.h"
#include "mesh/text_reader_impl.h"

static int is_keyword(rk_token tok)
{
    char c = tok.s[0];
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z');
}

static int read_vertices(rk_reader *r, rk_mesh *m)
{
    int64_t n, ref;
    if (m->X) return rk_reader_fail(r, "a second Vertices section");
    if (rk_text_int64(r, &n, "number of vertices") || rk_check_count(r, n, RK_MESH_MAX_COUNT, 4, 0, "vertex"))
        return -1;
    m->X = rk_calloc((size_t)n * 3, sizeof *m->X, r->err);
    if (!m->X) return -1;
    m->nv = (int)n;
    for (size_t i = 0; i < 3 * (size_t)n; i += 3) {
        if (rk_text_double(r, &m->X[i], "vertex x") || rk_text_double(r, &m->X[i + 1], "vertex y") ||
            rk_text_double(r, &m->X[i + 2], "vertex z") || rk_text_int64(r, &ref, "vertex reference"))
            return -1;
    }
    return 0;
}

static int read_tetrahedra(rk_reader *r, rk_mesh *m)
{
    int64_t n, v, ref;
    if (m->tets) return rk_reader_fail(r, "a second Tetrahedra section");
    if (!m->X) return rk_reader_fail(r, "Tetrahedra before Vertices");
    if (rk_text_int64(r, &n, "number of tetrahedra") || rk_check_count(r, n, RK_MESH_MAX_COUNT, 5, 0, "tetrahedron"))
        return -1;
    m->tets = rk_calloc((size_t)n * 4, sizeof *m->tets, r->err);
    m->tet_tag = rk_calloc((size_t)n, sizeof *m->tet_tag, r->err);
    if (!m->tets || !m->tet_tag) return -1;
    m->nt = (int)n;
    for (int t = 0; t < m->nt; t++) {
        for (int k = 0; k < 4; k++) {
            if (rk_text_int64(r, &v, "vertex index")) return -1;
            if (v < 1 || v > m->nv)
                return rk_reader_fail(r, "tet %d references vertex %" PRId64 ", but there are %d vertices "
                                         "(MEDIT indices are 1-based)", t + 1, v, m->nv);
            m->tets[4 * (size_t)t + (size_t)k] = (int)(v - 1);
        }
        if (rk_text_int64(r, &ref, "tet reference")) return -1;
        if (ref < INT32_MIN || ref > INT32_MAX) return rk_reader_fail(r, "tet reference %" PRId64 " does not fit an int", ref);
        m->tet_tag[t] = (int)ref;
    }
    return 0;
}

static int read_sections(rk_reader *r, rk_mesh *m)
{
    rk_token tok;
    int64_t v;
    if (!rk_next_token(r, &tok) || !rk_token_is_nocase(tok, "MeshVersionFormatted"))
        return rk_reader_fail(r, "not a MEDIT file (expected MeshVersionFormatted)");
    if (rk_text_int64(r, &v, "mesh version")) return -1;
    if (v < 1 || v > 4) return rk_reader_fail(r, "unsupported MeshVersionFormatted %" PRId64, v);
    while (rk_next_token(r, &tok)) {
        if (!is_keyword(tok)) {
            char shown[40];
            return rk_reader_fail(r, "expected a keyword, got '%s'", rk_token_str(tok, shown, sizeof shown));
        }
        int rc = 0;
        if (rk_token_is_nocase(tok, "End")) break;
        if (rk_token_is_nocase(tok, "Dimension")) {
            if (rk_text_int64(r, &v, "dimension")) return -1;
            if (v != 3) return rk_reader_fail(r, "dimension %" PRId64 ": only 3D meshes are supported", v);
        } else if (rk_token_is_nocase(tok, "Vertices")) {
            rc = read_vertices(r, m);
        } else if (rk_token_is_nocase(tok, "Tetrahedra")) {
            rc = read_tetrahedra(r, m);
        } else {
            rk_token next;
            while (rk_peek_token(r, &next) && !is_keyword(next)) rk_next_token(r, &next);
        }
        if (rc) return -1;
    }
    if (!m->X) return rk_reader_fail(r, "no Vertices section");
    if (!m->tets) return rk_reader_fail(r, "no Tetrahedra section");
    return 0;
}

int rk_read_medit(const char *path, rk_mesh *m, rk_error *err)
{
    rk_reader r;
    *m = (rk_mesh){0};
    if (rk_reader_open(&r, path, '#', err)) return -1;
    int rc = read_sections(&r, m);
    rk_reader_close(&r);
    if (rc) rk_mesh_free(m);
    return rc;
}
