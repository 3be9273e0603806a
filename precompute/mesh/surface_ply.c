/* PLY reader (ASCII, binary little- and big-endian), for surfaces and point clouds.
 * Elements are read in header order (the header by ply_header.c, shared with the Gaussian-splat
 * reader). From "vertex" only x, y, z are kept (any other property, e.g. a Gaussian splat's
 * f_dc_0, opacity, scale_0, rot_0, is read past: rk_splats_read keeps them); from "face" the
 * list vertex_indices (or vertex_index), fan-triangulated. Other elements are read past. Rows
 * are parsed property by property, so ASCII and binary share the code. */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/mesh_impl.h"
#include "mesh/ply_impl.h"

#define MAX_POLYGON 4096

/* The vertices' x, y, z, and with tag != NULL their whole-number "tag" property when there is one
 * (*tag stays NULL without). */
static int read_vertices(rk_ply_file *p, const rk_ply_element *e, rk_surface *s, int **tag)
{
    int axis_prop[3] = {-1, -1, -1}, tag_prop = -1;
    for (int i = 0; i < e->nprops; i++) {
        const rk_ply_property *q = &e->props[i];
        if (!q->is_list && q->name.len == 1 && q->name.s[0] >= 'x' && q->name.s[0] <= 'z')
            axis_prop[q->name.s[0] - 'x'] = i;
        if (!q->is_list && tag && rk_token_is(q->name, "tag")) tag_prop = i;
    }
    if (axis_prop[0] < 0 || axis_prop[1] < 0 || axis_prop[2] < 0)
        return rk_reader_fail(&p->r, "the vertex element lacks an x, y or z property");
    if (rk_ply_check_rows(p, e)) return -1;
    s->X = rk_calloc((size_t)e->count * 3, sizeof *s->X, p->r.err);
    if (!s->X) return -1;
    if (tag_prop >= 0 && !(*tag = rk_calloc((size_t)e->count + 1, sizeof **tag, p->r.err))) return -1;
    s->nv = (int)e->count;
    for (int64_t v = 0; v < e->count; v++) {
        for (int i = 0; i < e->nprops; i++) {
            const rk_ply_property *q = &e->props[i];
            double value;
            if (q->is_list) {
                if (rk_ply_skip_list(p, q)) return -1;
                continue;
            }
            if (rk_read_real(&p->r, q->type, &value, "vertex property")) return -1;
            for (int a = 0; a < 3; a++)
                if (axis_prop[a] == i) s->X[3 * v + a] = value;
            if (i == tag_prop) {
                if (!(fabs(value) <= 2147483647.0 && value == floor(value)))
                    return rk_reader_fail(&p->r, "vertex %" PRId64 ": tag %g is not a whole number", v, value);
                (*tag)[v] = (int)value;
            }
        }
    }
    return 0;
}

static int is_face_list(const rk_ply_property *q)
{
    return q->is_list && (rk_token_is(q->name, "vertex_indices") || rk_token_is(q->name, "vertex_index"));
}

/* The face element: each row's face list turned into polygons, every other property read past. */
static int read_faces(rk_ply_file *p, const rk_ply_element *e, rk_surface_builder *b)
{
    int poly[MAX_POLYGON];
    if (rk_ply_check_rows(p, e)) return -1;
    for (int64_t row = 0; row < e->count; row++) {
        for (int i = 0; i < e->nprops; i++) {
            const rk_ply_property *q = &e->props[i];
            int64_t n, index;
            double ignored;
            if (!q->is_list) {
                if (rk_read_real(&p->r, q->type, &ignored, "property")) return -1;
                continue;
            }
            if (!is_face_list(q)) {
                if (rk_ply_skip_list(p, q)) return -1;
                continue;
            }
            if (rk_read_integer(&p->r, q->count_type, &n, "list length") ||
                rk_check_count(&p->r, n, MAX_POLYGON, 1, rk_scalar_size(q->type), "list item"))
                return -1;
            for (int64_t k = 0; k < n; k++) {
                if (rk_read_integer(&p->r, q->type, &index, "vertex index")) return -1;
                if (index < 0 || index >= b->s.nv)
                    return rk_reader_fail(&p->r, "face %" PRId64 " references vertex %" PRId64 ", but there are %d",
                                          row, index, b->s.nv);
                poly[k] = (int)index;
            }
            if (n < 3) return rk_reader_fail(&p->r, "face %" PRId64 " has %" PRId64 " vertices", row, n);
            if (rk_sb_polygon(b, poly, (int)n, p->r.err)) return rk_error_prefix(p->r.err, "%s", p->r.path);
        }
    }
    return 0;
}

static int read_body(rk_ply_file *p, rk_surface_builder *b, int want_faces, int **tag)
{
    int have_vertices = 0, have_faces = 0;
    for (int i = 0; i < p->nelements; i++) {
        const rk_ply_element *e = &p->elements[i];
        int is_faces = rk_token_is(e->name, "face");
        if (rk_token_is(e->name, "vertex") && !have_vertices) {
            if (read_vertices(p, e, &b->s, tag)) return -1;
            b->vcap = 3 * (size_t)b->s.nv;
            have_vertices = 1;
            if (!want_faces) return 0;
        } else if (is_faces && want_faces && !have_vertices) {
            return rk_reader_fail(&p->r, "faces before vertices are not supported");
        } else if (is_faces && want_faces ? read_faces(p, e, b) : rk_ply_skip_rows(p, e)) {
            return -1;
        }
        have_faces |= is_faces;
    }
    if (!have_vertices) return rk_reader_fail(&p->r, "no vertex element");
    if (want_faces && !have_faces) return rk_reader_fail(&p->r, "no face element (a point cloud, not a surface)");
    return 0;
}

int rk_read_ply(const char *path, rk_surface *s, int want_faces, int **tag, rk_error *err)
{
    rk_ply_file p;
    rk_surface_builder b = {0};
    *s = (rk_surface){0};
    if (tag) *tag = NULL;
    if (rk_ply_open(&p, path, err)) return -1;
    int rc = read_body(&p, &b, want_faces, tag);
    rk_ply_close(&p);
    if (rc && tag) {
        free(*tag);
        *tag = NULL;
    }
    if (rc) rk_surface_free(&b.s);
    else *s = b.s;
    return rc;
}
