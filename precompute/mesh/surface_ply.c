/* PLY reader (ASCII, binary little- and big-endian), for surfaces and point clouds.
 * Elements are read in header order. From "vertex" only x, y, z are kept (any other
 * property, e.g. a Gaussian splat's f_dc_0, opacity, scale_0, rot_0, is read past); from
 * "face" the list vertex_indices (or vertex_index), fan-triangulated. Other elements are
 * read past. Rows are parsed property by property, so ASCII and binary share the code. */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/binary_reader_impl.h"
#include "mesh/mesh_impl.h"

#define MAX_ELEMENTS 16
#define MAX_PROPS 64
#define MAX_POLYGON 4096

typedef struct {
    rk_token name;
    rk_scalar type;       /* of the value, or of the list items */
    int is_list;
    rk_scalar count_type; /* of the list length */
} ply_property;

typedef struct {
    rk_token name;
    int64_t count;
    int nprops;
    ply_property props[MAX_PROPS];
} ply_element;

typedef struct {
    rk_reader r;
    int binary, big_endian;
    int nelements;
    ply_element elements[MAX_ELEMENTS];
} ply_file;

static int scalar_type(rk_reader *r, rk_scalar *t)
{
    static const struct {
        const char *name;
        rk_scalar type;
    } names[] = {{"char", RK_I8},     {"int8", RK_I8},     {"uchar", RK_U8},    {"uint8", RK_U8},
                 {"short", RK_I16},   {"int16", RK_I16},   {"ushort", RK_U16},  {"uint16", RK_U16},
                 {"int", RK_I32},     {"int32", RK_I32},   {"uint", RK_U32},    {"uint32", RK_U32},
                 {"float", RK_F32},   {"float32", RK_F32}, {"double", RK_F64},  {"float64", RK_F64}};
    rk_token tok;
    char shown[40];
    if (!rk_next_token_on_line(r, &tok)) return rk_reader_fail(r, "expected a property type");
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (rk_token_is(tok, names[i].name)) {
            *t = names[i].type;
            return 0;
        }
    return rk_reader_fail(r, "unknown property type '%s'", rk_token_str(tok, shown, sizeof shown));
}

static int read_property(ply_file *p)
{
    rk_reader *r = &p->r;
    if (p->nelements == 0) return rk_reader_fail(r, "property before any element");
    ply_element *e = &p->elements[p->nelements - 1];
    if (e->nprops == MAX_PROPS) return rk_reader_fail(r, "more than %d properties", MAX_PROPS);
    ply_property *prop = &e->props[e->nprops++];
    rk_token tok;
    if (rk_peek_token(r, &tok) && rk_token_is(tok, "list")) {
        rk_next_token(r, &tok);
        prop->is_list = 1;
        if (scalar_type(r, &prop->count_type)) return -1;
    }
    if (scalar_type(r, &prop->type)) return -1;
    if (!rk_next_token_on_line(r, &prop->name)) return rk_reader_fail(r, "expected a property name");
    return 0;
}

static int read_header(ply_file *p)
{
    rk_reader *r = &p->r;
    rk_token tok;
    if (!rk_next_token(r, &tok) || !rk_token_is(tok, "ply")) return rk_reader_fail(r, "not a PLY file (no 'ply' line)");
    rk_skip_line(r);
    int have_format = 0;
    while (rk_next_token(r, &tok)) {
        if (rk_token_is(tok, "end_header")) {
            if (!have_format) return rk_reader_fail(r, "no format line");
            rk_skip_line(r);
            rk_reader_set_binary(r, p->binary, p->big_endian);
            return 0;
        }
        if (rk_token_is(tok, "format")) {
            if (!rk_next_token_on_line(r, &tok)) return rk_reader_fail(r, "expected a format");
            if (rk_token_is(tok, "ascii")) p->binary = 0;
            else if (rk_token_is(tok, "binary_little_endian")) p->binary = 1, p->big_endian = 0;
            else if (rk_token_is(tok, "binary_big_endian")) p->binary = 1, p->big_endian = 1;
            else return rk_reader_fail(r, "unknown format");
            have_format = 1;
        } else if (rk_token_is(tok, "element")) {
            if (p->nelements == MAX_ELEMENTS) return rk_reader_fail(r, "more than %d elements", MAX_ELEMENTS);
            ply_element *e = &p->elements[p->nelements++];
            if (!rk_next_token_on_line(r, &e->name)) return rk_reader_fail(r, "expected an element name");
            if (rk_text_int64(r, &e->count, "element count")) return -1;
            if (e->count < 0) return rk_reader_fail(r, "negative element count");
        } else if (rk_token_is(tok, "property")) {
            if (read_property(p)) return -1;
        } else if (!rk_token_is(tok, "comment") && !rk_token_is(tok, "obj_info")) {
            char shown[40];
            return rk_reader_fail(r, "unexpected header line '%s'", rk_token_str(tok, shown, sizeof shown));
        }
        rk_skip_line(r);
    }
    return rk_reader_fail(r, "no end_header");
}

/* Guards the row count by the least a row can take. */
static int check_rows(ply_file *p, const ply_element *e)
{
    size_t bytes = 0;
    for (int i = 0; i < e->nprops; i++)
        bytes += rk_scalar_size(e->props[i].is_list ? e->props[i].count_type : e->props[i].type);
    char what[64];
    snprintf(what, sizeof what, "'%.*s' element", (int)(e->name.len < 40 ? e->name.len : 40), e->name.s);
    return rk_check_count(&p->r, e->count, RK_MESH_MAX_COUNT, e->nprops, bytes, what);
}

static int read_vertices(ply_file *p, const ply_element *e, rk_surface *s)
{
    int axis[MAX_PROPS], found = 0;
    for (int i = 0; i < e->nprops; i++) {
        const ply_property *q = &e->props[i];
        axis[i] = -1;
        if (!q->is_list && q->name.len == 1 && q->name.s[0] >= 'x' && q->name.s[0] <= 'z') {
            axis[i] = q->name.s[0] - 'x';
            found |= 1 << axis[i];
        }
    }
    if (found != 7) return rk_reader_fail(&p->r, "the vertex element lacks an x, y or z property");
    if (check_rows(p, e)) return -1;
    s->X = rk_calloc((size_t)e->count * 3, sizeof *s->X, p->r.err);
    if (!s->X) return -1;
    s->nv = (int)e->count;
    for (int64_t v = 0; v < e->count; v++) {
        for (int i = 0; i < e->nprops; i++) {
            const ply_property *q = &e->props[i];
            double value;
            int64_t n;
            if (!q->is_list) {
                if (rk_read_real(&p->r, q->type, &value, "vertex property")) return -1;
                if (axis[i] >= 0) s->X[3 * v + axis[i]] = value;
                continue;
            }
            if (rk_read_integer(&p->r, q->count_type, &n, "list length") ||
                rk_check_count(&p->r, n, INT32_MAX, 1, rk_scalar_size(q->type), "list item"))
                return -1;
            for (int64_t k = 0; k < n; k++)
                if (rk_read_real(&p->r, q->type, &value, "list item")) return -1;
        }
    }
    return 0;
}

static int is_face_list(const ply_property *q)
{
    return q->is_list && (rk_token_is(q->name, "vertex_indices") || rk_token_is(q->name, "vertex_index"));
}

/* Any element: each row's properties, with face lists turned into polygons when b != NULL. */
static int read_rows(ply_file *p, const ply_element *e, rk_surface_builder *b)
{
    int poly[MAX_POLYGON];
    if (check_rows(p, e)) return -1;
    for (int64_t row = 0; row < e->count; row++) {
        for (int i = 0; i < e->nprops; i++) {
            const ply_property *q = &e->props[i];
            int64_t n, index;
            double ignored;
            if (!q->is_list) {
                if (rk_read_real(&p->r, q->type, &ignored, "property")) return -1;
                continue;
            }
            int keep = b && is_face_list(q);
            if (rk_read_integer(&p->r, q->count_type, &n, "list length") ||
                rk_check_count(&p->r, n, keep ? MAX_POLYGON : INT32_MAX, 1, rk_scalar_size(q->type), "list item"))
                return -1;
            for (int64_t k = 0; k < n; k++) {
                if (!keep) {
                    if (rk_read_real(&p->r, q->type, &ignored, "list item")) return -1;
                    continue;
                }
                if (rk_read_integer(&p->r, q->type, &index, "vertex index")) return -1;
                if (index < 0 || index >= b->s.nv)
                    return rk_reader_fail(&p->r, "face %" PRId64 " references vertex %" PRId64 ", but there are %d",
                                          row, index, b->s.nv);
                poly[k] = (int)index;
            }
            if (keep) {
                if (n < 3) return rk_reader_fail(&p->r, "face %" PRId64 " has %" PRId64 " vertices", row, n);
                if (rk_sb_polygon(b, poly, (int)n, p->r.err)) return rk_error_prefix(p->r.err, "%s", p->r.path);
            }
        }
    }
    return 0;
}

static int read_body(ply_file *p, rk_surface_builder *b, int want_faces)
{
    int have_vertices = 0, have_faces = 0;
    for (int i = 0; i < p->nelements; i++) {
        const ply_element *e = &p->elements[i];
        int is_faces = rk_token_is(e->name, "face");
        if (rk_token_is(e->name, "vertex") && !have_vertices) {
            if (read_vertices(p, e, &b->s)) return -1;
            b->vcap = 3 * (size_t)b->s.nv;
            have_vertices = 1;
            if (!want_faces) return 0;
        } else if (is_faces && want_faces && !have_vertices) {
            return rk_reader_fail(&p->r, "faces before vertices are not supported");
        } else if (read_rows(p, e, is_faces && want_faces ? b : NULL)) {
            return -1;
        }
        have_faces |= is_faces;
    }
    if (!have_vertices) return rk_reader_fail(&p->r, "no vertex element");
    if (want_faces && !have_faces) return rk_reader_fail(&p->r, "no face element (a point cloud, not a surface)");
    return 0;
}

int rk_read_ply(const char *path, rk_surface *s, int want_faces, rk_error *err)
{
    ply_file p;
    rk_surface_builder b = {0};
    memset(&p, 0, sizeof p);
    *s = (rk_surface){0};
    if (rk_reader_open(&p.r, path, 0, err)) return -1;
    int rc = read_header(&p);
    if (rc == 0) rc = read_body(&p, &b, want_faces);
    rk_reader_close(&p.r);
    if (rc) rk_surface_free(&b.s);
    else *s = b.s;
    return rc;
}
