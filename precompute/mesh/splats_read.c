/* rk_splats_read: a 3D Gaussian Splatting PLY (Kerbl et al. 2023; the layout of graphdeco-inria
 * gaussian-splatting's save_ply: x y z, nx ny nz, f_dc_0..2, f_rest_0..3K-1 channel-major,
 * opacity, scale_0..2, rot_0..3), or any PLY point cloud. The header is ply_header.c's; every
 * property of the vertex element is kept in file order, the ones 3DGS defines are resolved by name
 * (mesh.h). */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/mesh_impl.h"
#include "mesh/ply_impl.h"

void rk_splats_free(rk_splats *s)
{
    free(s->X);
    free(s->prop);
    free(s->values);
    memset(s, 0, sizeof *s);
}

/* Column of the property called name, or -1. */
static int column(const rk_splats *s, const char *name)
{
    for (int j = 0; j < s->nprop; j++)
        if (strcmp(s->prop[j].name, name) == 0) return j;
    return -1;
}

/* A group of properties (x y z, scale_0..2, ...): all present, or (when optional) none. */
static int resolve_group(const char *path, rk_splats *s, const char *const *names, int count, int *cols, int optional,
                         rk_error *err)
{
    int found = 0;
    for (int k = 0; k < count; k++) found += (cols[k] = column(s, names[k])) >= 0;
    if (found == count || (found == 0 && optional)) return 0;
    for (int k = 0; k < count; k++)
        if (cols[k] < 0) {
            if (found == 0) return rk_fail(err, "%s: the vertex element has no '%s' property", path, names[k]);
            return rk_fail(err, "%s: the vertex element has '%s' but no '%s' property", path,
                           names[k == 0 ? 1 : 0], names[k]);
        }
    return 0;
}

/* f_rest_<j>: j, or -1 when name is not of that form. */
static int rest_index(const char *name)
{
    if (strncmp(name, "f_rest_", 7) != 0 || name[7] == '\0') return -1;
    long j = 0;
    for (const char *c = name + 7; *c; c++) {
        if (*c < '0' || *c > '9' || j > 100000) return -1;
        j = 10 * j + (*c - '0');
    }
    if (name[7] == '0' && name[8] != '\0') return -1; /* f_rest_07 is not f_rest_7 */
    return (int)j;
}

static int resolve_rest(const char *path, rk_splats *s, rk_error *err)
{
    int count = 0;
    for (int j = 0; j < s->nprop; j++) count += rest_index(s->prop[j].name) >= 0;
    int degree = -1;
    for (int d = 0; d <= RK_SPLATS_MAX_DEGREE; d++)
        if (count == 3 * ((d + 1) * (d + 1) - 1)) degree = d;
    if (degree < 0)
        return rk_fail(err,
                       "%s: %d f_rest properties: 3DGS stores 3((d+1)^2 - 1) of them for a degree d in 1..3 (9, 24 or "
                       "45), or none",
                       path, count);
    for (int k = 0; k < RK_SPLATS_MAX_REST; k++) s->f_rest[k] = -1;
    for (int j = 0; j < s->nprop; j++) {
        int k = rest_index(s->prop[j].name);
        if (k < 0) continue;
        if (k >= count)
            return rk_fail(err, "%s: property '%s' but only %d f_rest properties (f_rest_0..f_rest_%d)", path,
                           s->prop[j].name, count, count - 1);
        s->f_rest[k] = j; /* duplicates were refused before */
    }
    s->nrest = count;
    s->sh_degree = degree;
    return 0;
}

/* Names, types and the known columns, from the header. */
static int read_properties(rk_ply_file *p, const rk_ply_element *e, rk_splats *s, rk_error *err)
{
    const char *path = p->r.path;
    s->prop = rk_calloc(e->nprops ? (size_t)e->nprops : 1, sizeof *s->prop, err);
    if (!s->prop) return rk_error_prefix(err, "%s", path);
    s->nprop = e->nprops;
    for (int j = 0; j < e->nprops; j++) {
        const rk_ply_property *q = &e->props[j];
        char shown[48];
        rk_token_str(q->name, shown, sizeof shown);
        if (q->is_list) return rk_fail(err, "%s: vertex property '%s' is a list; splat files have none", path, shown);
        if (q->name.len >= RK_SPLATS_NAME_MAX)
            return rk_fail(err, "%s: vertex property '%s' has a name longer than %d characters", path, shown,
                           RK_SPLATS_NAME_MAX - 1);
        for (size_t c = 0; c < q->name.len; c++)
            if ((unsigned char)q->name.s[c] <= ' ' || (unsigned char)q->name.s[c] >= 127)
                return rk_fail(err, "%s: vertex property '%s' has a name with a non-printable character", path, shown);
        memcpy(s->prop[j].name, q->name.s, q->name.len);
        snprintf(s->prop[j].type, sizeof s->prop[j].type, "%s", rk_ply_type_name(q->type));
        for (int k = 0; k < j; k++)
            if (strcmp(s->prop[k].name, s->prop[j].name) == 0)
                return rk_fail(err, "%s: vertex property '%s' appears twice", path, s->prop[j].name);
    }
    static const char *const xyz[] = {"x", "y", "z"}, *const scale[] = {"scale_0", "scale_1", "scale_2"},
                             *const rot[] = {"rot_0", "rot_1", "rot_2", "rot_3"},
                             *const dc[] = {"f_dc_0", "f_dc_1", "f_dc_2"}, *const nrm[] = {"nx", "ny", "nz"};
    if (resolve_group(path, s, xyz, 3, s->xyz, 0, err) || resolve_group(path, s, scale, 3, s->scale, 1, err) ||
        resolve_group(path, s, rot, 4, s->rot, 1, err) || resolve_group(path, s, dc, 3, s->f_dc, 1, err) ||
        resolve_group(path, s, nrm, 3, s->normal, 1, err) || resolve_rest(path, s, err))
        return -1;
    s->opacity = column(s, "opacity");
    s->has_splat_attributes = s->scale[0] >= 0 && s->rot[0] >= 0 && s->opacity >= 0 && s->f_dc[0] >= 0;
    return 0;
}

/* Every value the deformation uses must be finite; the quaternion must have a length. */
static int validate(const char *path, rk_splats *s, rk_error *err)
{
    for (int i = 0; i < s->n; i++) {
        const double *row = s->values + (size_t)i * s->nprop;
        for (int a = 0; a < 3; a++) {
            s->X[3 * (size_t)i + a] = row[s->xyz[a]];
            if (!isfinite(row[s->xyz[a]]))
                return rk_fail(err, "%s: vertex %d: non-finite coordinate %s = %g", path, i, s->prop[s->xyz[a]].name,
                               row[s->xyz[a]]);
        }
        int known[3 + 4 + 3 + RK_SPLATS_MAX_REST], nk = 0;
        for (int a = 0; a < 3; a++) known[nk++] = s->scale[a];
        for (int a = 0; a < 4; a++) known[nk++] = s->rot[a];
        for (int a = 0; a < 3; a++) known[nk++] = s->normal[a];
        for (int a = 0; a < s->nrest; a++) known[nk++] = s->f_rest[a];
        for (int k = 0; k < nk; k++)
            if (known[k] >= 0 && !isfinite(row[known[k]]))
                return rk_fail(err, "%s: vertex %d: non-finite %s = %g", path, i, s->prop[known[k]].name, row[known[k]]);
        if (s->rot[0] >= 0) {
            double len2 = 0;
            for (int a = 0; a < 4; a++) len2 += row[s->rot[a]] * row[s->rot[a]];
            if (!(len2 > 0)) return rk_fail(err, "%s: vertex %d: the quaternion rot_0..3 has zero length", path, i);
        }
    }
    return 0;
}

static int read_vertices(rk_ply_file *p, const rk_ply_element *e, rk_splats *s, rk_error *err)
{
    const char *path = p->r.path;
    if (read_properties(p, e, s, err) || rk_ply_check_rows(p, e)) return -1;
    if (e->count == 0) return rk_fail(err, "%s: the vertex element is empty (no splats)", path);
    s->n = (int)e->count;
    s->X = rk_calloc(3 * (size_t)s->n, sizeof *s->X, err);
    s->values = s->X ? rk_calloc((size_t)s->n * (size_t)s->nprop, sizeof *s->values, err) : NULL;
    if (!s->values) return rk_error_prefix(err, "%s", path);
    /* Each value as its declared type holds it: an ASCII "property float" value is rounded to
     * float (as a binary file would have stored it), an integer one must be an integer. */
    for (size_t k = 0; k < (size_t)s->n * (size_t)s->nprop; k++) {
        rk_scalar t = e->props[k % (size_t)s->nprop].type;
        if (t == RK_F32 || t == RK_F64) {
            if (rk_read_real(&p->r, t, &s->values[k], "vertex property")) return -1;
            if (t == RK_F32) s->values[k] = (float)s->values[k];
        } else {
            int64_t v;
            if (rk_read_integer(&p->r, t, &v, "vertex property")) return -1;
            s->values[k] = (double)v;
        }
    }
    return validate(path, s, err);
}

int rk_splats_read(const char *path, rk_splats *s, rk_error *err)
{
    rk_ply_file p;
    memset(s, 0, sizeof *s);
    if (rk_ply_open(&p, path, err)) return -1;
    int rc = 1; /* 1: no vertex element yet */
    for (int i = 0; i < p.nelements && rc == 1; i++) {
        const rk_ply_element *e = &p.elements[i];
        if (rk_token_is(e->name, "vertex")) rc = read_vertices(&p, e, s, err); /* what follows (faces) is not read */
        else if (rk_ply_skip_rows(&p, e)) rc = -1;
    }
    rk_ply_close(&p);
    if (rc == 1) rc = rk_fail(err, "%s: no vertex element", path);
    if (rc) rk_splats_free(s);
    return rc;
}
