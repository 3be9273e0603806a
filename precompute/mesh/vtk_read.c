/* Legacy VTK reader: DATASET UNSTRUCTURED_GRID, ASCII or BINARY (big-endian, per the spec).
 * POINTS float|double; CELLS in the classic layout ("CELLS n size" then "npts i j k ...")
 * or the 5.x layout (OFFSETS + CONNECTIVITY); CELL_TYPES 10 = tet (24, the quadratic tet,
 * gives its 4 corners); other cells are skipped. FIELD and METADATA blocks are skipped. A
 * CELL_DATA "SCALARS tag" array (what rk_mesh_write writes) becomes tet_tag; reading stops
 * at any other point or cell attribute. */
#include <inttypes.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/binary_reader_impl.h"
#include "mesh/mesh_impl.h"

typedef struct {
    rk_reader r;
    int binary;
    double *X;
    int64_t nv;
    int64_t ncells;      /* -1 until CELLS */
    int64_t *offsets;    /* ncells + 1 */
    int64_t *conn;
    int64_t *types;      /* ncells */
    int64_t *tags;       /* ncells, from CELL_DATA SCALARS tag */
} vtk;

static int data_type(rk_reader *r, rk_scalar *t)
{
    static const struct {
        const char *name;
        rk_scalar type;
    } names[] = {{"unsigned_char", RK_U8},  {"char", RK_I8},          {"unsigned_short", RK_U16},
                 {"short", RK_I16},         {"unsigned_int", RK_U32}, {"int", RK_I32},
                 {"unsigned_long", RK_U64}, {"long", RK_I64},         {"float", RK_F32},
                 {"double", RK_F64},        {"vtktypeint64", RK_I64}, {"vtktypeuint64", RK_U64},
                 {"vtktypeint32", RK_I32},  {"vtktypeuint32", RK_U32}};
    rk_token tok;
    char shown[40];
    if (!rk_next_token(r, &tok)) return rk_reader_fail(r, "expected a data type, found end of file");
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (rk_token_is_nocase(tok, names[i].name)) {
            *t = names[i].type;
            return 0;
        }
    return rk_reader_fail(r, "unsupported data type '%s'", rk_token_str(tok, shown, sizeof shown));
}

/* Binary data starts on the line after its keyword line and is followed by a newline. */
static void begin_data(vtk *v)
{
    if (!v->binary) return;
    rk_skip_line(&v->r);
    rk_reader_set_binary(&v->r, 1, 1);
}

static void end_data(vtk *v) { rk_reader_set_binary(&v->r, 0, 0); }

/* n integers of type t into a new array. */
static int read_ints(vtk *v, int64_t n, rk_scalar t, int64_t **out, const char *what)
{
    begin_data(v);
    if (rk_check_count(&v->r, n, RK_MESH_MAX_COUNT * 11LL, 1, rk_scalar_size(t), what)) return -1;
    int64_t *a = rk_calloc((size_t)n, sizeof *a, v->r.err);
    if (!a) return -1;
    *out = a;
    for (int64_t i = 0; i < n; i++)
        if (rk_read_integer(&v->r, t, &a[i], what)) return -1;
    end_data(v);
    return 0;
}

static int read_points(vtk *v)
{
    rk_scalar t;
    if (v->X) return rk_reader_fail(&v->r, "a second POINTS block");
    if (rk_text_int64(&v->r, &v->nv, "number of points") || data_type(&v->r, &t)) return -1;
    begin_data(v);
    if (rk_check_count(&v->r, v->nv, RK_MESH_MAX_COUNT, 3, 3 * rk_scalar_size(t), "point")) return -1;
    v->X = rk_calloc((size_t)v->nv * 3, sizeof *v->X, v->r.err);
    if (!v->X) return -1;
    for (int64_t i = 0; i < 3 * v->nv; i++)
        if (rk_read_real(&v->r, t, &v->X[i], "point coordinate")) return -1;
    end_data(v);
    return 0;
}

/* Classic layout: for each cell "npts id..." -> offsets + connectivity. */
static int split_classic_cells(vtk *v, int64_t *list, int64_t size)
{
    v->offsets = rk_calloc((size_t)v->ncells + 1, sizeof *v->offsets, v->r.err);
    v->conn = rk_calloc((size_t)size, sizeof *v->conn, v->r.err);
    if (!v->offsets || !v->conn) return -1;
    int64_t at = 0, nconn = 0;
    for (int64_t c = 0; c < v->ncells; c++) {
        int64_t npts = at < size ? list[at] : -1;
        if (npts < 0 || npts > size - at - 1)
            return rk_reader_fail(&v->r, "CELLS: cell %" PRId64 " has a bad point count (list size %" PRId64 ")", c, size);
        memcpy(v->conn + nconn, list + at + 1, (size_t)npts * sizeof *list);
        nconn += npts;
        at += npts + 1;
        v->offsets[c + 1] = nconn;
    }
    if (at != size) return rk_reader_fail(&v->r, "CELLS: list size %" PRId64 " but the cells use %" PRId64, size, at);
    return 0;
}

static int read_cells(vtk *v)
{
    rk_reader *r = &v->r;
    int64_t a, b;
    rk_token tok;
    if (v->ncells >= 0) return rk_reader_fail(r, "a second CELLS block");
    if (rk_text_int64(r, &a, "number of cells") || rk_text_int64(r, &b, "cell list size")) return -1;
    if (rk_peek_token(r, &tok) && rk_token_is(tok, "OFFSETS")) {
        /* VTK 5: "CELLS noffsets nconn", OFFSETS <type> ..., CONNECTIVITY <type> ... */
        rk_scalar t;
        if (a < 1) return rk_reader_fail(r, "CELLS: %" PRId64 " offsets (need at least 1)", a);
        v->ncells = a - 1;
        if (rk_expect_word(r, "OFFSETS", 0) || data_type(r, &t) || read_ints(v, a, t, &v->offsets, "cell offset") ||
            rk_expect_word(r, "CONNECTIVITY", 0) || data_type(r, &t) || read_ints(v, b, t, &v->conn, "cell connectivity"))
            return -1;
        if (v->offsets[0] != 0) return rk_reader_fail(r, "OFFSETS: the first offset is not 0");
        for (int64_t c = 0; c < v->ncells; c++)
            if (v->offsets[c + 1] < v->offsets[c] || v->offsets[c + 1] > b)
                return rk_reader_fail(r, "OFFSETS: offset %" PRId64 " of cell %" PRId64 " is out of order or range",
                                      v->offsets[c + 1], c);
        return 0;
    }
    int64_t *list = NULL;
    if (rk_check_count(r, a, RK_MESH_MAX_COUNT * 2LL, 1, 4, "cell")) return -1;
    v->ncells = a;
    int rc = read_ints(v, b, RK_I32, &list, "cell list");
    if (rc == 0) rc = split_classic_cells(v, list, b);
    free(list);
    return rc;
}

static int read_cell_types(vtk *v)
{
    int64_t n;
    if (v->ncells < 0) return rk_reader_fail(&v->r, "CELL_TYPES before CELLS");
    if (v->types) return rk_reader_fail(&v->r, "a second CELL_TYPES block");
    if (rk_text_int64(&v->r, &n, "number of cell types")) return -1;
    if (n != v->ncells) return rk_reader_fail(&v->r, "CELL_TYPES has %" PRId64 " entries for %" PRId64 " cells", n, v->ncells);
    return read_ints(v, n, RK_I32, &v->types, "cell type");
}

/* FIELD name n, then n arrays "name components tuples type" + data: all skipped. */
static int skip_field(vtk *v)
{
    rk_reader *r = &v->r;
    rk_token tok;
    int64_t narrays, ncomp, ntuples;
    double ignored;
    if (!rk_next_token(r, &tok) || rk_text_int64(r, &narrays, "number of field arrays")) return -1;
    for (int64_t a = 0; a < narrays; a++) {
        rk_scalar t;
        if (!rk_next_token(r, &tok)) return rk_reader_fail(r, "expected a field array name, found end of file");
        if (rk_text_int64(r, &ncomp, "field components") || rk_text_int64(r, &ntuples, "field tuples") ||
            data_type(r, &t))
            return -1;
        if (ncomp < 0 || ncomp > 1024) return rk_reader_fail(r, "bad field component count %" PRId64, ncomp);
        begin_data(v);
        if (rk_check_count(r, ntuples, INT64_MAX / 1024, (int)ncomp, (size_t)ncomp * rk_scalar_size(t), "field tuple"))
            return -1;
        for (int64_t i = 0; i < ncomp * ntuples; i++)
            if (rk_read_real(r, t, &ignored, "field value")) return -1;
        end_data(v);
    }
    return 0;
}

/* METADATA ... up to an empty line. */
static void skip_metadata(vtk *v)
{
    rk_reader *r = &v->r;
    rk_skip_line(r);
    while (r->pos < r->len) {
        char line[8];
        rk_read_line(r, line, sizeof line);
        if (line[0] == '\0') break;
    }
}

/* CELL_DATA n followed by "SCALARS tag <type> [1]" [LOOKUP_TABLE name]: the tags. *stop is
 * set when the block holds something else (reading ends there: the mesh is complete). */
static int read_cell_data(vtk *v, int *stop)
{
    rk_reader *r = &v->r;
    int64_t n, ncomp = 1;
    rk_token tok, name;
    rk_scalar t;
    *stop = 1;
    if (rk_text_int64(r, &n, "number of cell data")) return -1;
    if (v->ncells < 0 || n != v->ncells) return rk_reader_fail(r, "CELL_DATA %" PRId64 " does not match the cells", n);
    if (!rk_peek_token(r, &tok) || !rk_token_is_nocase(tok, "SCALARS")) return 0;
    rk_next_token(r, &tok);
    if (!rk_next_token(r, &name)) return rk_reader_fail(r, "expected a SCALARS name, found end of file");
    if (!rk_token_is(name, "tag")) return 0;
    if (data_type(r, &t)) return -1;
    if (rk_next_token_on_line(r, &tok)) {
        char buf[16];
        rk_token_str(tok, buf, sizeof buf);
        ncomp = atoi(buf);
    }
    if (ncomp != 1) return rk_reader_fail(r, "SCALARS tag must have 1 component");
    if (rk_peek_token(r, &tok) && rk_token_is_nocase(tok, "LOOKUP_TABLE")) {
        rk_next_token(r, &tok);
        rk_next_token(r, &tok);
    }
    if (read_ints(v, n, t, &v->tags, "cell tag")) return -1;
    *stop = 0;
    return 0;
}

static int read_header(vtk *v)
{
    rk_reader *r = &v->r;
    char line[300];
    rk_token tok;
    rk_read_line(r, line, sizeof line);
    if (strncmp(line, "# vtk DataFile Version", 22) != 0)
        return rk_reader_fail(r, "not a legacy VTK file (first line is not '# vtk DataFile Version ...')");
    rk_read_line(r, line, sizeof line); /* title */
    if (!rk_next_token(r, &tok)) return rk_reader_fail(r, "expected ASCII or BINARY, found end of file");
    if (rk_token_is_nocase(tok, "BINARY")) v->binary = 1;
    else if (!rk_token_is_nocase(tok, "ASCII")) return rk_reader_fail(r, "expected ASCII or BINARY");
    if (rk_expect_word(r, "DATASET", 1)) return -1;
    if (!rk_next_token(r, &tok) || !rk_token_is_nocase(tok, "UNSTRUCTURED_GRID")) {
        char shown[40];
        return rk_reader_fail(r, "dataset '%s' is not an UNSTRUCTURED_GRID", rk_token_str(tok, shown, sizeof shown));
    }
    return 0;
}

static int read_blocks(vtk *v)
{
    rk_reader *r = &v->r;
    rk_token tok;
    if (read_header(v)) return -1;
    while (rk_next_token(r, &tok)) {
        int rc = 0, stop = 0;
        if (rk_token_is_nocase(tok, "POINTS")) rc = read_points(v);
        else if (rk_token_is_nocase(tok, "CELLS")) rc = read_cells(v);
        else if (rk_token_is_nocase(tok, "CELL_TYPES")) rc = read_cell_types(v);
        else if (rk_token_is_nocase(tok, "FIELD")) rc = skip_field(v);
        else if (rk_token_is_nocase(tok, "METADATA")) skip_metadata(v);
        else if (rk_token_is_nocase(tok, "CELL_DATA")) rc = read_cell_data(v, &stop);
        else if (rk_token_is_nocase(tok, "POINT_DATA")) stop = 1;
        else {
            char shown[40];
            return rk_reader_fail(r, "unexpected '%s'", rk_token_str(tok, shown, sizeof shown));
        }
        if (rc) return -1;
        if (stop) break;
    }
    if (!v->X) return rk_reader_fail(r, "no POINTS");
    if (v->ncells < 0) return rk_reader_fail(r, "no CELLS");
    if (!v->types) return rk_reader_fail(r, "no CELL_TYPES");
    return 0;
}

/* The tets among the cells, with indices checked. */
static int collect_tets(vtk *v, rk_mesh *m)
{
    rk_reader *r = &v->r;
    int64_t nt = 0;
    for (int64_t c = 0; c < v->ncells; c++) nt += v->types[c] == 10 || v->types[c] == 24;
    m->tets = rk_calloc((size_t)nt * 4, sizeof *m->tets, r->err);
    if (v->tags) m->tet_tag = rk_calloc((size_t)nt, sizeof *m->tet_tag, r->err);
    if (!m->tets || (v->tags && !m->tet_tag)) return -1;
    for (int64_t c = 0; c < v->ncells; c++) {
        int64_t type = v->types[c], at = v->offsets[c], npts = v->offsets[c + 1] - at;
        if (type != 10 && type != 24) continue;
        if (npts != (type == 10 ? 4 : 10))
            return rk_fail(r->err, "%s: cell %" PRId64 " of type %" PRId64 " has %" PRId64 " points", r->path, c, type, npts);
        for (int k = 0; k < 4; k++) {
            int64_t i = v->conn[at + k];
            if (i < 0 || i >= v->nv)
                return rk_fail(r->err, "%s: cell %" PRId64 " references point %" PRId64 ", but there are %" PRId64 " points",
                               r->path, c, i, v->nv);
            m->tets[4 * (size_t)m->nt + (size_t)k] = (int)i;
        }
        if (v->tags) {
            if (v->tags[c] < INT32_MIN || v->tags[c] > INT32_MAX)
                return rk_fail(r->err, "%s: tag of cell %" PRId64 " does not fit an int", r->path, c);
            m->tet_tag[m->nt] = (int)v->tags[c];
        }
        m->nt++;
    }
    return 0;
}

int rk_read_vtk(const char *path, rk_mesh *m, rk_error *err)
{
    vtk v = {.ncells = -1};
    *m = (rk_mesh){0};
    if (rk_reader_open(&v.r, path, 0, err)) return -1;
    int rc = read_blocks(&v);
    if (rc == 0) {
        m->nv = (int)v.nv;
        m->X = v.X;
        v.X = NULL;
        rc = collect_tets(&v, m);
    }
    if (rc) rk_mesh_free(m);
    free(v.X);
    free(v.offsets);
    free(v.conn);
    free(v.types);
    free(v.tags);
    rk_reader_close(&v.r);
    return rc;
}
