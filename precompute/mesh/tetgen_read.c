/* TetGen .node/.ele reader. Either file name may be given; the other has the same stem.
 * .node: "count 3 attributes markers" then "index x y z [attributes] [marker]".
 * .ele:  "count 4|10 region" then "index n1..n4 [n5..n10] [region attribute]" (region -> tet_tag).
 * Numbering is 0- or 1-based, as the first index in .node says; every index must follow it. */
#include <inttypes.h>
#include <math.h>
#include <stdlib.h>

#include "mesh/mesh_impl.h"
#include "mesh/text_reader_impl.h"

/* Reads the next token as an index that must equal `expected`. */
static int expect_index(rk_reader *r, int64_t expected, const char *what)
{
    int64_t i;
    if (rk_text_int64(r, &i, what)) return -1;
    if (i != expected)
        return rk_reader_fail(r, "%s is %" PRId64 ", expected %" PRId64 " (TetGen numbers consecutively)", what, i,
                              expected);
    return 0;
}

static int read_node(rk_reader *r, rk_mesh *m, int *base)
{
    int64_t n, dim, nattr, nmark, first;
    double skip;
    if (rk_text_int64(r, &n, "number of points") || rk_text_int64(r, &dim, "dimension") ||
        rk_text_int64(r, &nattr, "number of attributes") || rk_text_int64(r, &nmark, "boundary marker flag"))
        return -1;
    if (n == 0) return rk_reader_fail(r, "no points (points stored in a .poly file are not supported)");
    if (dim != 3) return rk_reader_fail(r, "dimension %" PRId64 ": only 3D is supported", dim);
    if (nattr < 0 || nattr > 1000) return rk_reader_fail(r, "bad attribute count %" PRId64, nattr);
    if (nmark != 0 && nmark != 1) return rk_reader_fail(r, "boundary marker flag %" PRId64 " is not 0 or 1", nmark);
    int per_point = 4 + (int)nattr + (int)nmark;
    if (rk_check_count(r, n, RK_MESH_MAX_COUNT, per_point, 0, "point")) return -1;
    m->X = rk_calloc((size_t)n * 3, sizeof *m->X, r->err);
    if (!m->X) return -1;
    m->nv = (int)n;
    for (int i = 0; i < m->nv; i++) {
        if (i == 0) {
            if (rk_text_int64(r, &first, "point index")) return -1;
            if (first != 0 && first != 1)
                return rk_reader_fail(r, "first point index is %" PRId64 ", expected 0 or 1", first);
            *base = (int)first;
        } else if (expect_index(r, *base + (int64_t)i, "point index")) {
            return -1;
        }
        for (int k = 0; k < 3; k++)
            if (rk_text_double(r, &m->X[3 * (size_t)i + (size_t)k], "point coordinate")) return -1;
        for (int k = 0; k < per_point - 4; k++)
            if (rk_text_double(r, &skip, "point attribute or marker")) return -1;
    }
    return 0;
}

static int read_ele(rk_reader *r, rk_mesh *m, int base)
{
    int64_t n, per_tet, region, v;
    if (rk_text_int64(r, &n, "number of tetrahedra") || rk_text_int64(r, &per_tet, "nodes per tetrahedron") ||
        rk_text_int64(r, &region, "region attribute flag"))
        return -1;
    if (per_tet != 4 && per_tet != 10) return rk_reader_fail(r, "%" PRId64 " nodes per tetrahedron (expected 4 or 10)", per_tet);
    if (region < 0 || region > 1000) return rk_reader_fail(r, "bad attribute count %" PRId64, region);
    if (rk_check_count(r, n, RK_MESH_MAX_COUNT, 1 + (int)per_tet + (int)region, 0, "tetrahedron")) return -1;
    m->tets = rk_calloc((size_t)n * 4, sizeof *m->tets, r->err);
    if (!m->tets) return -1;
    if (region) {
        m->tet_tag = rk_calloc((size_t)n, sizeof *m->tet_tag, r->err);
        if (!m->tet_tag) return -1;
    }
    m->nt = (int)n;
    for (int t = 0; t < m->nt; t++) {
        if (expect_index(r, base + (int64_t)t, "tetrahedron index")) return -1;
        for (int k = 0; k < per_tet; k++) {
            if (rk_text_int64(r, &v, "vertex index")) return -1;
            if (v < base || v - base >= m->nv)
                return rk_reader_fail(r, "tet %d references point %" PRId64 ", outside %d..%d", t + base, v, base,
                                      m->nv - 1 + base);
            if (k < 4) m->tets[4 * (size_t)t + (size_t)k] = (int)(v - base); /* corners; 5..10 are mid-edge */
        }
        for (int64_t a = 0; a < region; a++) {
            double attr;
            if (rk_text_double(r, &attr, "region attribute")) return -1;
            if (a > 0) continue;
            if (!(fabs(attr) <= INT32_MAX) || attr != floor(attr))
                return rk_reader_fail(r, "region attribute %g of tet %d is not an integer", attr, t + base);
            m->tet_tag[t] = (int)attr;
        }
    }
    return 0;
}

int rk_read_tetgen(const char *path, rk_mesh *m, rk_error *err)
{
    char node_path[4096], ele_path[4096];
    *m = (rk_mesh){0};
    if (rk_path_with_ext(path, ".node", node_path, sizeof node_path, err) ||
        rk_path_with_ext(path, ".ele", ele_path, sizeof ele_path, err))
        return -1;
    rk_reader r;
    int base = 0;
    if (rk_reader_open(&r, node_path, '#', err)) return -1;
    int rc = read_node(&r, m, &base);
    rk_reader_close(&r);
    if (rc == 0) {
        if (rk_reader_open(&r, ele_path, '#', err)) {
            rc = -1;
        } else {
            rc = read_ele(&r, m, base);
            rk_reader_close(&r);
        }
    }
    if (rc) rk_mesh_free(m);
    return rc;
}
