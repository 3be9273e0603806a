/* Gmsh .msh reader: versions 2.x and 4.1, ASCII and binary.
 *
 * ASCII and binary carry the same fields in the same order, so each section is parsed once
 * with the dual-mode number reads of binary_reader_impl.h; only element records differ (ASCII
 * elements are read a line at a time so a short record is reported on its own line).
 * Tetrahedra are element type 4; second-order tets (type 11) contribute their 4 corner
 * nodes; every other element type is skipped. tet_tag is the element's physical tag (2.x:
 * first tag; 4.1: the physical tag of its volume in $Entities, or the entity tag when the
 * file has no $Entities). */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/binary_reader_impl.h"
#include "mesh/mesh_impl.h"

#define MAX_LINE_INTS 256

typedef struct {
    rk_reader r;
    int major;            /* 2 or 4 */
    int binary, big_endian;
    rk_scalar size_type;  /* 4.1 binary size_t */
    int have_nodes, have_elements;
    double *X;
    int64_t *node_tag;
    size_t nv;
    rk_tag_map nodes;
    int *tets, *tet_tag;
    size_t nt, tet_cap, tag_cap;
    int have_entities;
    int64_t *vol_tag, *vol_phys; /* $Entities volumes and their first physical tag (0: none) */
    size_t nvol;
} gmsh;

/* Nodes per element for Gmsh element types 1..31 (0: unknown). */
static int nodes_per_element(int64_t type)
{
    static const int n[32] = {0, 2, 3, 4, 4, 8, 6, 5, 3, 6, 9, 10, 27, 18, 14, 1,
                              8, 20, 15, 13, 9, 10, 12, 15, 15, 21, 4, 5, 6, 20, 35, 56};
    return type >= 1 && type <= 31 ? n[type] : 0;
}

static int is_tet(int64_t type) { return type == 4 || type == 11; }

/* Binary blocks start after the rest of the keyword line. */
static void enter_binary(gmsh *g)
{
    if (!g->binary) return;
    rk_skip_line(&g->r);
    rk_reader_set_binary(&g->r, 1, g->big_endian);
}

static int end_section(gmsh *g, const char *end)
{
    rk_reader_set_binary(&g->r, 0, 0);
    return rk_expect_word(&g->r, end, 0);
}

static int read_format(gmsh *g)
{
    rk_reader *r = &g->r;
    double version;
    int64_t file_type, data_size;
    if (rk_expect_word(r, "$MeshFormat", 0) || rk_text_double(r, &version, "format version") ||
        rk_text_int64(r, &file_type, "file type") || rk_text_int64(r, &data_size, "data size"))
        return -1;
    if (version >= 2.0 && version < 3.0) g->major = 2;
    else if (version > 4.05 && version < 5.0) g->major = 4;
    else if (version >= 4.0 && version < 5.0)
        return rk_reader_fail(r, "Gmsh format 4.0 is not supported; re-export as 4.1 or 2.2");
    else return rk_reader_fail(r, "unsupported Gmsh format version %g (expected 2.2 or 4.1)", version);
    if (file_type != 0 && file_type != 1) return rk_reader_fail(r, "file type %" PRId64 " is neither 0 (ASCII) nor 1 (binary)", file_type);
    if (data_size != 4 && data_size != 8) return rk_reader_fail(r, "data size %" PRId64 " is neither 4 nor 8", data_size);
    g->binary = (int)file_type;
    g->size_type = data_size == 4 ? RK_U32 : RK_U64;
    if (g->binary) {
        /* The integer 1, written in the writer's byte order. */
        unsigned char one[4];
        enter_binary(g);
        if (rk_bin_bytes(r, one, 4, "byte-order mark")) return -1;
        if (one[0] == 1 && !one[1] && !one[2] && !one[3]) g->big_endian = 0;
        else if (one[3] == 1 && !one[0] && !one[1] && !one[2]) g->big_endian = 1;
        else {
            r->pos -= 4;
            return rk_reader_fail(r, "bad byte-order mark (expected the integer 1)");
        }
    }
    return end_section(g, "$EndMeshFormat");
}

static int read_count(gmsh *g, int64_t *v, const char *what)
{
    return rk_read_integer(&g->r, g->size_type, v, what);
}

static int alloc_nodes(gmsh *g, int64_t n)
{
    g->X = rk_calloc((size_t)n * 3, sizeof *g->X, g->r.err);
    g->node_tag = rk_calloc((size_t)n, sizeof *g->node_tag, g->r.err);
    return g->X && g->node_tag ? 0 : -1;
}

static int read_xyz(gmsh *g, size_t i)
{
    for (int k = 0; k < 3; k++)
        if (rk_read_real(&g->r, RK_F64, &g->X[3 * i + k], "node coordinate")) return -1;
    return 0;
}

static int read_nodes_v2(gmsh *g)
{
    rk_reader *r = &g->r;
    int64_t n;
    if (rk_text_int64(r, &n, "number of nodes")) return -1;
    enter_binary(g);
    if (rk_check_count(r, n, RK_MESH_MAX_COUNT, 4, 28, "node") || alloc_nodes(g, n)) return -1;
    for (size_t i = 0; i < (size_t)n; i++) {
        if (rk_read_integer(r, RK_I32, &g->node_tag[i], "node number") || read_xyz(g, i)) return -1;
        g->nv++;
    }
    return end_section(g, "$EndNodes");
}

static int read_nodes_v4(gmsh *g)
{
    rk_reader *r = &g->r;
    int64_t blocks, n, min_tag, max_tag;
    enter_binary(g);
    size_t sz = rk_scalar_size(g->size_type);
    if (read_count(g, &blocks, "number of node blocks") || read_count(g, &n, "number of nodes") ||
        read_count(g, &min_tag, "minimum node tag") || read_count(g, &max_tag, "maximum node tag") ||
        rk_check_count(r, blocks, RK_MESH_MAX_COUNT, 4, 12 + sz, "node block") ||
        rk_check_count(r, n, RK_MESH_MAX_COUNT, 4, sz + 24, "node") || alloc_nodes(g, n))
        return -1;
    for (int64_t b = 0; b < blocks; b++) {
        int64_t dim, entity, parametric, count;
        if (rk_read_integer(r, RK_I32, &dim, "entity dimension") ||
            rk_read_integer(r, RK_I32, &entity, "entity tag") ||
            rk_read_integer(r, RK_I32, &parametric, "parametric flag") ||
            read_count(g, &count, "number of nodes in block"))
            return -1;
        if (dim < 0 || dim > 3) return rk_reader_fail(r, "entity dimension %" PRId64 " is not 0..3", dim);
        if (count < 0 || count > n - (int64_t)g->nv)
            return rk_reader_fail(r, "node block %" PRId64 " holds %" PRId64 " nodes, more than the %" PRId64
                                     " declared in all", b + 1, count, n);
        for (int64_t i = 0; i < count; i++)
            if (read_count(g, &g->node_tag[g->nv + (size_t)i], "node tag")) return -1;
        for (int64_t i = 0; i < count; i++) {
            if (read_xyz(g, g->nv + (size_t)i)) return -1;
            for (int64_t k = 0; parametric && k < dim; k++) { /* u, v, w: not needed */
                double uvw;
                if (rk_read_real(r, RK_F64, &uvw, "parametric coordinate")) return -1;
            }
        }
        g->nv += (size_t)count;
    }
    if ((int64_t)g->nv != n)
        return rk_reader_fail(r, "%" PRId64 " nodes declared, the blocks hold %zu", n, g->nv);
    return end_section(g, "$EndNodes");
}

static int read_nodes(gmsh *g)
{
    if (g->have_nodes) return rk_reader_fail(&g->r, "a second $Nodes section");
    g->have_nodes = 1;
    if (g->major == 2 ? read_nodes_v2(g) : read_nodes_v4(g)) return -1;
    if (rk_tag_map_build(&g->nodes, g->node_tag, g->nv, g->r.err))
        return rk_error_prefix(g->r.err, "%s: $Nodes", g->r.path);
    return 0;
}

/* Stores one tet given its first four node tags. */
static int add_tet(gmsh *g, int64_t element, const int64_t *node_tags, int64_t tag)
{
    rk_reader *r = &g->r;
    if (g->nt >= RK_MESH_MAX_COUNT) return rk_reader_fail(r, "too many tetrahedra");
    if (tag < INT32_MIN || tag > INT32_MAX)
        return rk_reader_fail(r, "tag %" PRId64 " of element %" PRId64 " does not fit an int", tag, element);
    if (rk_grow(&g->tets, &g->tet_cap, 4 * (g->nt + 1), sizeof(int), r->err) ||
        rk_grow(&g->tet_tag, &g->tag_cap, g->nt + 1, sizeof(int), r->err))
        return rk_error_prefix(r->err, "%s", r->path);
    for (int k = 0; k < 4; k++) {
        int idx = rk_tag_map_find(&g->nodes, node_tags[k]);
        if (idx < 0)
            return rk_reader_fail(r, "tet element %" PRId64 " references node %" PRId64 ", which is not in $Nodes",
                                  element, node_tags[k]);
        g->tets[4 * g->nt + (size_t)k] = idx;
    }
    g->tet_tag[g->nt++] = (int)tag;
    return 0;
}

/* 2.x ASCII: "number type ntags tag... node..." per line. */
static int read_elements_v2_ascii(gmsh *g, int64_t n)
{
    rk_reader *r = &g->r;
    int64_t v[MAX_LINE_INTS];
    for (int64_t e = 0; e < n; e++) {
        int count;
        if (rk_line_int64s(r, v, MAX_LINE_INTS, &count, "element record")) return -1;
        if (count < 3 || v[2] < 0 || v[2] > count - 3)
            return rk_reader_fail(r, "element %" PRId64 ": malformed record (number, type, tag count, tags, nodes)", e + 1);
        if (!is_tet(v[1])) continue;
        int ntags = (int)v[2], nodes = count - 3 - ntags, want = nodes_per_element(v[1]);
        if (nodes != want)
            return rk_reader_fail(r, "expected %d node indices for tet element %" PRId64 ", got %d", want, v[0], nodes);
        if (add_tet(g, v[0], v + 3 + ntags, ntags > 0 ? v[3] : 0)) return -1;
    }
    return 0;
}

/* 2.x binary: blocks of "type count ntags" then count records of 1 + ntags + nodes ints. */
static int read_elements_v2_binary(gmsh *g, int64_t n)
{
    rk_reader *r = &g->r;
    int64_t done = 0, v[MAX_LINE_INTS];
    while (done < n) {
        int64_t type, count, ntags;
        if (rk_read_integer(r, RK_I32, &type, "element type") ||
            rk_read_integer(r, RK_I32, &count, "element count") ||
            rk_read_integer(r, RK_I32, &ntags, "tag count"))
            return -1;
        int nodes = nodes_per_element(type);
        if (!nodes) return rk_reader_fail(r, "unknown element type %" PRId64 " (cannot skip it in a binary file)", type);
        if (count <= 0 || count > n - done)
            return rk_reader_fail(r, "element block of %" PRId64 " elements exceeds the %" PRId64 " declared", count, n);
        if (ntags < 0 || ntags > MAX_LINE_INTS - 1 - nodes)
            return rk_reader_fail(r, "bad tag count %" PRId64, ntags);
        int len = 1 + (int)ntags + nodes;
        if (rk_check_count(r, count, n, len, 4 * (size_t)len, "element")) return -1;
        for (int64_t e = 0; e < count; e++) {
            for (int k = 0; k < len; k++)
                if (rk_read_integer(r, RK_I32, &v[k], "element record")) return -1;
            if (is_tet(type) && add_tet(g, v[0], v + 1 + ntags, ntags > 0 ? v[1] : 0)) return -1;
        }
        done += count;
    }
    return 0;
}

/* With $Entities the region is the volume's physical tag (0 when it has none); without,
 * the entity tag is all there is. */
static int64_t volume_tag(const gmsh *g, int64_t entity)
{
    if (!g->have_entities) return entity;
    for (size_t i = 0; i < g->nvol; i++)
        if (g->vol_tag[i] == entity) return g->vol_phys[i];
    return 0;
}

static int read_elements_v4(gmsh *g)
{
    rk_reader *r = &g->r;
    int64_t blocks, n, min_tag, max_tag, done = 0, v[MAX_LINE_INTS];
    size_t sz = rk_scalar_size(g->size_type);
    if (read_count(g, &blocks, "number of element blocks") || read_count(g, &n, "number of elements") ||
        read_count(g, &min_tag, "minimum element tag") || read_count(g, &max_tag, "maximum element tag") ||
        rk_check_count(r, blocks, RK_MESH_MAX_COUNT, 4, 12 + sz, "element block") ||
        rk_check_count(r, n, INT64_MAX, 2, 2 * sz, "element"))
        return -1;
    for (int64_t b = 0; b < blocks; b++) {
        int64_t dim, entity, type, count;
        if (rk_read_integer(r, RK_I32, &dim, "entity dimension") ||
            rk_read_integer(r, RK_I32, &entity, "entity tag") ||
            rk_read_integer(r, RK_I32, &type, "element type") || read_count(g, &count, "number of elements in block"))
            return -1;
        if (count < 0 || count > n - done)
            return rk_reader_fail(r, "element block %" PRId64 " holds %" PRId64 " elements, more than the %" PRId64
                                     " declared in all", b + 1, count, n);
        int nodes = nodes_per_element(type);
        int64_t tag = volume_tag(g, entity);
        if (g->binary) {
            if (!nodes) return rk_reader_fail(r, "unknown element type %" PRId64 " (cannot skip it in a binary file)", type);
            if (rk_check_count(r, count, n, 0, (size_t)(1 + nodes) * sz, "element")) return -1;
        }
        for (int64_t e = 0; e < count; e++) {
            int got = 1 + nodes;
            if (g->binary) {
                for (int k = 0; k < got; k++)
                    if (read_count(g, &v[k], "element record")) return -1;
            } else if (rk_line_int64s(r, v, MAX_LINE_INTS, &got, "element record")) {
                return -1;
            }
            if (!is_tet(type)) continue;
            if (got != 1 + nodes)
                return rk_reader_fail(r, "expected %d node indices for tet element %" PRId64 ", got %d", nodes, v[0], got - 1);
            if (add_tet(g, v[0], v + 1, tag)) return -1;
        }
        done += count;
    }
    if (done != n) return rk_reader_fail(r, "%" PRId64 " elements declared, the blocks hold %" PRId64, n, done);
    return 0;
}

static int read_elements(gmsh *g)
{
    rk_reader *r = &g->r;
    if (!g->have_nodes) return rk_reader_fail(r, "$Elements before $Nodes");
    if (g->have_elements) return rk_reader_fail(r, "a second $Elements section");
    g->have_elements = 1;
    int rc;
    if (g->major == 2) {
        int64_t n;
        if (rk_text_int64(r, &n, "number of elements")) return -1;
        enter_binary(g);
        if (rk_check_count(r, n, INT64_MAX, 4, 8, "element")) return -1;
        rc = g->binary ? read_elements_v2_binary(g, n) : read_elements_v2_ascii(g, n);
    } else {
        enter_binary(g);
        rc = read_elements_v4(g);
    }
    return rc ? -1 : end_section(g, "$EndElements");
}

/* $Entities (4.1): only volumes matter, for their physical tags. */
static int read_entities(gmsh *g)
{
    rk_reader *r = &g->r;
    int64_t count[4];
    enter_binary(g);
    for (int d = 0; d < 4; d++)
        if (read_count(g, &count[d], "number of entities") ||
            rk_check_count(r, count[d], RK_MESH_MAX_COUNT, 5, 28, "entity"))
            return -1;
    free(g->vol_tag);
    free(g->vol_phys);
    g->vol_tag = rk_calloc((size_t)count[3], sizeof *g->vol_tag, r->err);
    g->vol_phys = rk_calloc((size_t)count[3], sizeof *g->vol_phys, r->err);
    if (!g->vol_tag || !g->vol_phys) return -1;
    g->nvol = 0;
    g->have_entities = 1;
    for (int d = 0; d < 4; d++) {
        for (int64_t e = 0; e < count[d]; e++) {
            int64_t tag, nphys, phys, first_phys = 0, nbound, bound;
            double box;
            if (rk_read_integer(r, RK_I32, &tag, "entity tag")) return -1;
            for (int k = 0; k < (d == 0 ? 3 : 6); k++)
                if (rk_read_real(r, RK_F64, &box, "entity bounding box")) return -1;
            if (read_count(g, &nphys, "number of physical tags") ||
                rk_check_count(r, nphys, INT32_MAX, 1, 4, "physical tag"))
                return -1;
            for (int64_t k = 0; k < nphys; k++) {
                if (rk_read_integer(r, RK_I32, &phys, "physical tag")) return -1;
                if (k == 0) first_phys = phys;
            }
            if (d > 0) {
                if (read_count(g, &nbound, "number of bounding entities") ||
                    rk_check_count(r, nbound, INT32_MAX, 1, 4, "bounding entity"))
                    return -1;
                for (int64_t k = 0; k < nbound; k++)
                    if (rk_read_integer(r, RK_I32, &bound, "bounding entity")) return -1;
            }
            if (d == 3) {
                g->vol_tag[g->nvol] = tag;
                g->vol_phys[g->nvol++] = first_phys;
            }
        }
    }
    return end_section(g, "$EndEntities");
}

static int read_sections(gmsh *g)
{
    rk_reader *r = &g->r;
    if (read_format(g)) return -1;
    rk_token tok;
    while (rk_next_token(r, &tok)) {
        int rc;
        if (rk_token_is(tok, "$Nodes")) rc = read_nodes(g);
        else if (rk_token_is(tok, "$Elements")) rc = read_elements(g);
        else if (rk_token_is(tok, "$Entities") && g->major == 4) rc = read_entities(g);
        else if (tok.len > 1 && tok.len < 64 && tok.s[0] == '$' && strncmp(tok.s, "$End", 4) != 0) {
            /* A section we do not need ($PhysicalNames, $NodeData, $Periodic, ...). */
            char end[80];
            snprintf(end, sizeof end, "$End%.*s", (int)tok.len - 1, tok.s + 1);
            rc = rk_skip_past(r, end);
        } else {
            char shown[40];
            rc = rk_reader_fail(r, "unexpected '%s' between sections", rk_token_str(tok, shown, sizeof shown));
        }
        if (rc) return -1;
    }
    if (!g->have_nodes) return rk_reader_fail(r, "no $Nodes section");
    if (!g->have_elements) return rk_reader_fail(r, "no $Elements section");
    return 0;
}

int rk_read_gmsh(const char *path, rk_mesh *m, rk_error *err)
{
    gmsh g = {0};
    *m = (rk_mesh){0};
    if (rk_reader_open(&g.r, path, 0, err)) return -1;
    int rc = read_sections(&g);
    if (rc == 0) {
        m->nv = (int)g.nv;
        m->nt = (int)g.nt;
        m->X = g.X;
        m->tets = g.tets;
        m->tet_tag = g.tet_tag;
        g.X = NULL;
        g.tets = g.tet_tag = NULL;
    }
    free(g.X);
    free(g.node_tag);
    free(g.tets);
    free(g.tet_tag);
    free(g.vol_tag);
    free(g.vol_phys);
    rk_tag_map_free(&g.nodes);
    rk_reader_close(&g.r);
    return rc;
}
