/* The one PLY header parser (ply_impl.h) and reading past rows a reader does not keep. */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/mesh_impl.h"
#include "mesh/ply_impl.h"

static const struct {
    const char *name;
    rk_scalar type;
} type_names[] = {{"char", RK_I8},     {"int8", RK_I8},     {"uchar", RK_U8},    {"uint8", RK_U8},
                  {"short", RK_I16},   {"int16", RK_I16},   {"ushort", RK_U16},  {"uint16", RK_U16},
                  {"int", RK_I32},     {"int32", RK_I32},   {"uint", RK_U32},    {"uint32", RK_U32},
                  {"float", RK_F32},   {"float32", RK_F32}, {"double", RK_F64},  {"float64", RK_F64}};

const char *rk_ply_type_name(rk_scalar t)
{
    if (t == RK_I64) return "int64";
    if (t == RK_U64) return "uint64";
    for (size_t i = 0; i < sizeof type_names / sizeof type_names[0]; i++)
        if (type_names[i].type == t) return type_names[i].name; /* the first, classic name */
    return "double";
}

static int scalar_type(rk_reader *r, rk_scalar *t)
{
    rk_token tok;
    char shown[40];
    if (!rk_next_token_on_line(r, &tok)) return rk_reader_fail(r, "expected a property type");
    for (size_t i = 0; i < sizeof type_names / sizeof type_names[0]; i++)
        if (rk_token_is(tok, type_names[i].name)) {
            *t = type_names[i].type;
            return 0;
        }
    return rk_reader_fail(r, "unknown property type '%s'", rk_token_str(tok, shown, sizeof shown));
}

static int read_property(rk_ply_file *p)
{
    rk_reader *r = &p->r;
    if (p->nelements == 0) return rk_reader_fail(r, "property before any element");
    rk_ply_element *e = &p->elements[p->nelements - 1];
    if (e->nprops == RK_PLY_MAX_PROPS) return rk_reader_fail(r, "more than %d properties", RK_PLY_MAX_PROPS);
    if (rk_grow(&e->props, &e->cap, (size_t)e->nprops + 1, sizeof *e->props, r->err))
        return rk_error_prefix(r->err, "%s", r->path);
    rk_ply_property *prop = &e->props[e->nprops++];
    memset(prop, 0, sizeof *prop);
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

static int read_header(rk_ply_file *p)
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
            if (p->nelements == RK_PLY_MAX_ELEMENTS)
                return rk_reader_fail(r, "more than %d elements", RK_PLY_MAX_ELEMENTS);
            rk_ply_element *e = &p->elements[p->nelements++];
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

int rk_ply_open(rk_ply_file *p, const char *path, rk_error *err)
{
    memset(p, 0, sizeof *p);
    if (rk_reader_open(&p->r, path, 0, err)) return -1;
    if (read_header(p)) {
        rk_ply_close(p);
        return -1;
    }
    return 0;
}

void rk_ply_close(rk_ply_file *p)
{
    for (int i = 0; i < p->nelements; i++) {
        free(p->elements[i].props);
        p->elements[i].props = NULL;
    }
    p->nelements = 0;
    rk_reader_close(&p->r);
}

int rk_ply_check_rows(rk_ply_file *p, const rk_ply_element *e)
{
    size_t bytes = 0;
    for (int i = 0; i < e->nprops; i++)
        bytes += rk_scalar_size(e->props[i].is_list ? e->props[i].count_type : e->props[i].type);
    char what[64];
    snprintf(what, sizeof what, "'%.*s' element", (int)(e->name.len < 40 ? e->name.len : 40), e->name.s);
    return rk_check_count(&p->r, e->count, RK_MESH_MAX_COUNT, e->nprops, bytes, what);
}

int rk_ply_skip_list(rk_ply_file *p, const rk_ply_property *q)
{
    int64_t n;
    double ignored;
    if (rk_read_integer(&p->r, q->count_type, &n, "list length") ||
        rk_check_count(&p->r, n, INT32_MAX, 1, rk_scalar_size(q->type), "list item"))
        return -1;
    for (int64_t k = 0; k < n; k++)
        if (rk_read_real(&p->r, q->type, &ignored, "list item")) return -1;
    return 0;
}

int rk_ply_skip_rows(rk_ply_file *p, const rk_ply_element *e)
{
    if (rk_ply_check_rows(p, e)) return -1;
    for (int64_t row = 0; row < e->count; row++)
        for (int i = 0; i < e->nprops; i++) {
            const rk_ply_property *q = &e->props[i];
            double ignored;
            if (q->is_list ? rk_ply_skip_list(p, q) : rk_read_real(&p->r, q->type, &ignored, "property")) return -1;
        }
    return 0;
}
