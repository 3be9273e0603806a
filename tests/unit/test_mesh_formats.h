/* Helpers for the mesh tests: temporary files, mesh comparison, and hand-written variants
 * of the formats that romkit reads but does not write itself (Gmsh 2.2, sparse/permuted
 * node tags, mixed element types, big-endian binaries, MEDIT with extra sections, 1-based
 * TetGen with attributes, VTK 5.x layout, ASCII STL/PLY). They are written independently of
 * the library's writers so the readers are tested against something other than themselves. */
#ifndef TEST_MESH_FORMATS_H
#define TEST_MESH_FORMATS_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "mesh/mesh.h"

/* A mesh from literal arrays (copied, so rk_mesh_free works). */
static inline rk_mesh make_mesh(int nv, const double *X, int nt, const int *tets)
{
    rk_mesh m = {.nv = nv, .nt = nt, .X = malloc(sizeof(double) * 3 * (size_t)nv),
                 .tets = malloc(sizeof(int) * 4 * (size_t)nt)};
    memcpy(m.X, X, sizeof(double) * 3 * (size_t)nv);
    memcpy(m.tets, tets, sizeof(int) * 4 * (size_t)nt);
    return m;
}

/* ---- temporary files ---- */

/* A fresh path $TMPDIR/rk_mesh_XXXXXX<suffix> (created empty; /tmp without TMPDIR). */
static inline void tmp_path(char *out, size_t cap, const char *suffix)
{
    snprintf(out, cap, "%s/rk_mesh_XXXXXX%s", tl_tmpdir(), suffix);
    int fd = mkstemps(out, (int)strlen(suffix));
    if (fd >= 0) close(fd);
}

static inline long file_size(const char *path)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) return -1;
    fseek(fp, 0, SEEK_END);
    long n = ftell(fp);
    fclose(fp);
    return n;
}

static inline unsigned char *read_all(const char *path, long *n)
{
    *n = file_size(path);
    if (*n < 0) return NULL;
    unsigned char *buf = malloc((size_t)*n + 1);
    FILE *fp = fopen(path, "rb");
    if (!buf || !fp || fread(buf, 1, (size_t)*n, fp) != (size_t)*n) {
        free(buf);
        if (fp) fclose(fp);
        return NULL;
    }
    fclose(fp);
    buf[*n] = 0; /* usable as a string when the file is text */
    return buf;
}

static inline int write_all(const char *path, const void *buf, long n)
{
    FILE *fp = fopen(path, "wb");
    if (!fp) return -1;
    size_t got = fwrite(buf, 1, (size_t)n, fp);
    return fclose(fp) == 0 && got == (size_t)n ? 0 : -1;
}

/* ---- comparison ---- */

/* Same tets in the same order with the same corner coordinates (vertex numbering may
 * differ); as_float compares float-rounded coordinates; tags: compare tet_tag. */
static inline int same_mesh(const rk_mesh *a, const rk_mesh *b, int as_float, int tags, char *why, size_t cap)
{
    if (a->nv != b->nv || a->nt != b->nt) {
        snprintf(why, cap, "counts %d/%d vs %d/%d", a->nv, a->nt, b->nv, b->nt);
        return 0;
    }
    for (int t = 0; t < a->nt; t++)
        for (int k = 0; k < 4; k++)
            for (int d = 0; d < 3; d++) {
                double x = a->X[3 * a->tets[4 * t + k] + d], y = b->X[3 * b->tets[4 * t + k] + d];
                if (as_float) x = (float)x, y = (float)y; /* ASCII floats come back as doubles */
                if (x != y) {
                    snprintf(why, cap, "tet %d corner %d coordinate %d: %.17g vs %.17g", t, k, d, x, y);
                    return 0;
                }
            }
    if (tags) {
        for (int t = 0; t < a->nt; t++) {
            int ta = a->tet_tag ? a->tet_tag[t] : 0, tb = b->tet_tag ? b->tet_tag[t] : 0;
            if (ta != tb) {
                snprintf(why, cap, "tet %d tag %d vs %d", t, ta, tb);
                return 0;
            }
        }
    }
    return 1;
}

/* ---- format variants ---- */

/* Sparse node tags, so a reader that assumes 1..n fails. */
static inline long sparse_tag(int i) { return 3L * i + 5; }

/* Gmsh 2.2 ASCII: nodes in reverse order with sparse numbers, a point and a triangle element
 * before the tets, two tags per element (physical = tet_tag). */
static inline int write_gmsh22_ascii(const char *path, const rk_mesh *m)
{
    FILE *fp = fopen(path, "w");
    if (!fp) return -1;
    fprintf(fp, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"body\"\n$EndPhysicalNames\n");
    fprintf(fp, "$Nodes\n%d\n", m->nv);
    for (int i = m->nv - 1; i >= 0; i--)
        fprintf(fp, "%ld %.17g %.17g %.17g\n", sparse_tag(i), m->X[3 * i], m->X[3 * i + 1], m->X[3 * i + 2]);
    fprintf(fp, "$EndNodes\n$Elements\n%d\n", m->nt + 2);
    fprintf(fp, "1 15 2 0 1 %ld\n", sparse_tag(0));
    fprintf(fp, "2 2 2 0 1 %ld %ld %ld\n", sparse_tag(0), sparse_tag(1), sparse_tag(2));
    for (int t = 0; t < m->nt; t++) {
        const int *v = m->tets + 4 * t;
        fprintf(fp, "%d 4 2 %d 9 %ld %ld %ld %ld\n", t + 3, m->tet_tag ? m->tet_tag[t] : 0, sparse_tag(v[0]),
                sparse_tag(v[1]), sparse_tag(v[2]), sparse_tag(v[3]));
    }
    fprintf(fp, "$EndElements\n");
    return fclose(fp);
}

static inline void put_bytes(FILE *fp, const void *p, size_t n, int big_endian)
{
    const unsigned char *b = p;
    uint16_t probe = 1;
    int host_le = *(const unsigned char *)&probe == 1;
    for (size_t i = 0; i < n; i++) fputc(b[(big_endian == host_le) ? n - 1 - i : i], fp);
}
static inline void put_i32(FILE *fp, int32_t v, int be) { put_bytes(fp, &v, 4, be); }
static inline void put_i64(FILE *fp, int64_t v, int be) { put_bytes(fp, &v, 8, be); }
static inline void put_f32(FILE *fp, float v, int be) { put_bytes(fp, &v, 4, be); }
static inline void put_f64(FILE *fp, double v, int be) { put_bytes(fp, &v, 8, be); }

/* Gmsh 2.2 binary in either byte order, sparse node numbers, a triangle block first. */
static inline int write_gmsh22_binary(const char *path, const rk_mesh *m, int be)
{
    FILE *fp = fopen(path, "wb");
    if (!fp) return -1;
    fprintf(fp, "$MeshFormat\n2.2 1 8\n");
    put_i32(fp, 1, be);
    fprintf(fp, "\n$EndMeshFormat\n$Nodes\n%d\n", m->nv);
    for (int i = 0; i < m->nv; i++) {
        put_i32(fp, (int32_t)sparse_tag(i), be);
        for (int k = 0; k < 3; k++) put_f64(fp, m->X[3 * i + k], be);
    }
    fprintf(fp, "\n$EndNodes\n$Elements\n%d\n", m->nt + 1);
    put_i32(fp, 2, be), put_i32(fp, 1, be), put_i32(fp, 2, be);
    put_i32(fp, 1, be), put_i32(fp, 0, be), put_i32(fp, 1, be);
    for (int k = 0; k < 3; k++) put_i32(fp, (int32_t)sparse_tag(k), be);
    put_i32(fp, 4, be), put_i32(fp, m->nt, be), put_i32(fp, 2, be);
    for (int t = 0; t < m->nt; t++) {
        put_i32(fp, t + 2, be);
        put_i32(fp, m->tet_tag ? m->tet_tag[t] : 0, be);
        put_i32(fp, 9, be);
        for (int k = 0; k < 4; k++) put_i32(fp, (int32_t)sparse_tag(m->tets[4 * t + k]), be);
    }
    fprintf(fp, "\n$EndElements\n");
    return fclose(fp);
}

/* Gmsh 4.1, ASCII or binary: $PhysicalNames, $Entities with a physical tag per volume
 * (volume 10 + tag carries physical tag `tag`), nodes in three blocks (a point, then even
 * and odd vertices, the odd block parametric) with sparse tags, a triangle block first,
 * one tet block per run of equal tags, and an unknown $NodeData section at the end. */
typedef struct {
    FILE *fp;
    int binary;
} g41;
static inline void g41_size(g41 *o, long v)
{
    if (o->binary) put_i64(o->fp, v, 0);
    else fprintf(o->fp, "%ld ", v);
}
static inline void g41_int(g41 *o, int v)
{
    if (o->binary) put_i32(o->fp, v, 0);
    else fprintf(o->fp, "%d ", v);
}
static inline void g41_real(g41 *o, double v)
{
    if (o->binary) put_f64(o->fp, v, 0);
    else fprintf(o->fp, "%.17g ", v);
}
static inline void g41_nl(g41 *o)
{
    if (!o->binary) fputc('\n', o->fp);
}
static inline int write_gmsh41_variant(const char *path, const rk_mesh *m, int binary)
{
    g41 o = {fopen(path, "wb"), binary};
    if (!o.fp) return -1;
    int tag_of[3] = {1, 2, 3}; /* tags used by the tests are 1..3 */
    fprintf(o.fp, "$MeshFormat\n4.1 %d 8\n", binary);
    if (binary) put_i32(o.fp, 1, 0), fputc('\n', o.fp);
    fprintf(o.fp, "$EndMeshFormat\n$PhysicalNames\n3\n3 1 \"a\"\n3 2 \"b\"\n3 3 \"c\"\n$EndPhysicalNames\n$Entities\n");
    g41_size(&o, 1), g41_size(&o, 0), g41_size(&o, 1), g41_size(&o, 3), g41_nl(&o);
    g41_int(&o, 1), g41_real(&o, 0), g41_real(&o, 0), g41_real(&o, 0), g41_size(&o, 0), g41_nl(&o);
    g41_int(&o, 1); /* surface 1, bounded by nothing */
    for (int k = 0; k < 6; k++) g41_real(&o, 0);
    g41_size(&o, 0), g41_size(&o, 0), g41_nl(&o);
    for (int v = 0; v < 3; v++) {
        g41_int(&o, 10 + tag_of[v]);
        for (int k = 0; k < 6; k++) g41_real(&o, k);
        g41_size(&o, 1), g41_int(&o, tag_of[v]), g41_size(&o, 1), g41_int(&o, 1), g41_nl(&o);
    }
    fprintf(o.fp, "%s$EndEntities\n$Nodes\n", binary ? "\n" : "");
    int nodd = m->nv / 2, neven = m->nv - nodd - 1;
    g41_size(&o, 3), g41_size(&o, m->nv), g41_size(&o, sparse_tag(0)), g41_size(&o, sparse_tag(m->nv - 1)), g41_nl(&o);
    g41_int(&o, 0), g41_int(&o, 1), g41_int(&o, 0), g41_size(&o, 1), g41_nl(&o);
    g41_size(&o, sparse_tag(0)), g41_nl(&o);
    g41_real(&o, m->X[0]), g41_real(&o, m->X[1]), g41_real(&o, m->X[2]), g41_nl(&o);
    for (int parity = 0; parity < 2; parity++) {
        int first = parity ? 1 : 2, count = parity ? nodd : neven;
        g41_int(&o, 3), g41_int(&o, 11), g41_int(&o, parity), g41_size(&o, count), g41_nl(&o);
        for (int i = first; i < m->nv; i += 2) g41_size(&o, sparse_tag(i)), g41_nl(&o);
        for (int i = first; i < m->nv; i += 2) {
            for (int k = 0; k < 3; k++) g41_real(&o, m->X[3 * i + k]);
            for (int k = 0; parity && k < 3; k++) g41_real(&o, 0.25 * k); /* u v w */
            g41_nl(&o);
        }
    }
    fprintf(o.fp, "%s$EndNodes\n$Elements\n", binary ? "\n" : "");
    int runs = 0;
    for (int t = 0; t < m->nt; t++) runs += t == 0 || m->tet_tag[t] != m->tet_tag[t - 1];
    g41_size(&o, runs + 1), g41_size(&o, m->nt + 1), g41_size(&o, 1), g41_size(&o, m->nt + 1000), g41_nl(&o);
    g41_int(&o, 2), g41_int(&o, 1), g41_int(&o, 2), g41_size(&o, 1), g41_nl(&o);
    g41_size(&o, 1), g41_size(&o, sparse_tag(0)), g41_size(&o, sparse_tag(1)), g41_size(&o, sparse_tag(2)), g41_nl(&o);
    for (int t = 0; t < m->nt;) {
        int end = t;
        while (end < m->nt && m->tet_tag[end] == m->tet_tag[t]) end++;
        g41_int(&o, 3), g41_int(&o, 10 + m->tet_tag[t]), g41_int(&o, 4), g41_size(&o, end - t), g41_nl(&o);
        for (; t < end; t++) {
            g41_size(&o, 1000 + t);
            for (int k = 0; k < 4; k++) g41_size(&o, sparse_tag(m->tets[4 * t + k]));
            g41_nl(&o);
        }
    }
    fprintf(o.fp, "%s$EndElements\n$NodeData\n1\n\"T\"\n1\n0\n3\n0\n1\n1\n%ld 0.5\n$EndNodeData\n", binary ? "\n" : "",
            sparse_tag(0));
    return fclose(o.fp);
}

/* MEDIT: lower-case keywords, comments, Dimension on its own line, extra sections. */
static inline int write_medit_variant(const char *path, const rk_mesh *m)
{
    FILE *fp = fopen(path, "w");
    if (!fp) return -1;
    fprintf(fp, "# exported by something\nmeshversionformatted 1\ndimension\n3\n\nvertices\n%d\n", m->nv);
    for (int i = 0; i < m->nv; i++) fprintf(fp, "%.17g %.17g %.17g %d\n", m->X[3 * i], m->X[3 * i + 1], m->X[3 * i + 2], i % 4);
    fprintf(fp, "Corners\n2\n1\n2\nEdges\n1\n1 2 7\n# a comment between sections\nTriangles\n1\n1 2 3 0\n");
    fprintf(fp, "TETRAHEDRA\n%d\n", m->nt);
    for (int t = 0; t < m->nt; t++) {
        const int *v = m->tets + 4 * t;
        fprintf(fp, "%d %d %d %d %d\n", v[0] + 1, v[1] + 1, v[2] + 1, v[3] + 1, m->tet_tag ? m->tet_tag[t] : 0);
    }
    fprintf(fp, "NormalAtVertices\n0\nend\n");
    return fclose(fp);
}

/* TetGen, 1-based, 2 attributes and a boundary marker per point, a region attribute. */
static inline int write_tetgen_1based(const char *stem, const rk_mesh *m)
{
    char path[512];
    snprintf(path, sizeof path, "%s.node", stem);
    FILE *fp = fopen(path, "w");
    if (!fp) return -1;
    fprintf(fp, "# node file\n%d 3 2 1\n", m->nv);
    for (int i = 0; i < m->nv; i++)
        fprintf(fp, "%d %.17g %.17g %.17g 0.5 -1 %d\n", i + 1, m->X[3 * i], m->X[3 * i + 1], m->X[3 * i + 2], i % 2);
    fclose(fp);
    snprintf(path, sizeof path, "%s.ele", stem);
    fp = fopen(path, "w");
    if (!fp) return -1;
    fprintf(fp, "%d 4 1\n", m->nt);
    for (int t = 0; t < m->nt; t++) {
        const int *v = m->tets + 4 * t;
        fprintf(fp, "  %d  %d %d %d %d  %d.0\n", t + 1, v[0] + 1, v[1] + 1, v[2] + 1, v[3] + 1, m->tet_tag ? m->tet_tag[t] : 0);
    }
    fprintf(fp, "# generated\n");
    return fclose(fp);
}

/* VTK 5.1: FIELD data and METADATA, OFFSETS/CONNECTIVITY (int64), a vertex and a triangle
 * cell among the tets, CELL_DATA tags. ASCII or BINARY. */
static inline int write_vtk51(const char *path, const rk_mesh *m, int binary)
{
    FILE *fp = fopen(path, "wb");
    if (!fp) return -1;
    int nc = m->nt + 2;
    fprintf(fp, "# vtk DataFile Version 5.1\nvariant\n%s\nDATASET UNSTRUCTURED_GRID\nFIELD FieldData 1\nTIME 1 1 double\n",
            binary ? "BINARY" : "ASCII");
    if (binary) put_f64(fp, 0.5, 1), fputc('\n', fp);
    else fprintf(fp, "0.5\n");
    fprintf(fp, "POINTS %d double\n", m->nv);
    for (int i = 0; i < 3 * m->nv; i++) {
        if (binary) put_f64(fp, m->X[i], 1);
        else fprintf(fp, "%.17g\n", m->X[i]);
    }
    fprintf(fp, "%sMETADATA\nINFORMATION 0\n\n", binary ? "\n" : "");
    fprintf(fp, "CELLS %d %d\nOFFSETS vtktypeint64\n", nc + 1, 4 * m->nt + 4);
    /* cells: vertex(1 point), triangle(3), then the tets */
    long off = 0;
    for (int c = 0; c <= nc; c++) {
        if (binary) put_i64(fp, off, 1);
        else fprintf(fp, "%ld\n", off);
        off += c == 0 ? 1 : c == 1 ? 3 : 4;
    }
    fprintf(fp, "%sCONNECTIVITY vtktypeint64\n", binary ? "\n" : "");
    long conn[4 * 8];
    for (int c = 0; c < nc; c++) {
        int n = c == 0 ? 1 : c == 1 ? 3 : 4;
        for (int k = 0; k < n; k++) conn[k] = c < 2 ? k : m->tets[4 * (c - 2) + k];
        for (int k = 0; k < n; k++) {
            if (binary) put_i64(fp, conn[k], 1);
            else fprintf(fp, "%ld ", conn[k]);
        }
        if (!binary) fputc('\n', fp);
    }
    fprintf(fp, "%sCELL_TYPES %d\n", binary ? "\n" : "", nc);
    for (int c = 0; c < nc; c++) {
        int type = c == 0 ? 1 : c == 1 ? 5 : 10;
        if (binary) put_i32(fp, type, 1);
        else fprintf(fp, "%d\n", type);
    }
    fprintf(fp, "%sCELL_DATA %d\nSCALARS tag int 1\nLOOKUP_TABLE default\n", binary ? "\n" : "", nc);
    for (int c = 0; c < nc; c++) {
        int tag = c < 2 ? 99 : (m->tet_tag ? m->tet_tag[c - 2] : 0);
        if (binary) put_i32(fp, tag, 1);
        else fprintf(fp, "%d\n", tag);
    }
    fprintf(fp, "%sPOINT_DATA %d\nSCALARS temperature float 1\nLOOKUP_TABLE default\n", binary ? "\n" : "", m->nv);
    return fclose(fp);
}

/* Classic VTK with float points and a triangle cell first (BINARY or ASCII). */
static inline int write_vtk_float(const char *path, const rk_mesh *m, int binary)
{
    FILE *fp = fopen(path, "wb");
    if (!fp) return -1;
    fprintf(fp, "# vtk DataFile Version 2.0\nfloat points\n%s\nDATASET UNSTRUCTURED_GRID\nPOINTS %d float\n",
            binary ? "BINARY" : "ASCII", m->nv);
    for (int i = 0; i < 3 * m->nv; i++) {
        if (binary) put_f32(fp, (float)m->X[i], 1);
        else fprintf(fp, "%.9g\n", (float)m->X[i]);
    }
    fprintf(fp, "%sCELLS %d %d\n", binary ? "\n" : "", m->nt + 1, 5 * m->nt + 4);
    int tri[4] = {3, 0, 1, 2};
    for (int k = 0; k < 4; k++) {
        if (binary) put_i32(fp, tri[k], 1);
        else fprintf(fp, "%d ", tri[k]);
    }
    if (!binary) fputc('\n', fp);
    for (int t = 0; t < m->nt; t++) {
        if (binary) put_i32(fp, 4, 1);
        else fprintf(fp, "4");
        for (int k = 0; k < 4; k++) {
            if (binary) put_i32(fp, m->tets[4 * t + k], 1);
            else fprintf(fp, " %d", m->tets[4 * t + k]);
        }
        if (!binary) fputc('\n', fp);
    }
    fprintf(fp, "%sCELL_TYPES %d\n", binary ? "\n" : "", m->nt + 1);
    for (int c = 0; c <= m->nt; c++) {
        if (binary) put_i32(fp, c == 0 ? 5 : 10, 1);
        else fprintf(fp, "%d\n", c == 0 ? 5 : 10);
    }
    return fclose(fp);
}

static inline int write_stl_ascii(const char *path, const rk_surface *s)
{
    FILE *fp = fopen(path, "w");
    if (!fp) return -1;
    fprintf(fp, "solid test object\n");
    for (int f = 0; f < s->nf; f++) {
        fprintf(fp, "  facet normal 0 0 1\n    outer loop\n");
        for (int k = 0; k < 3; k++) {
            const double *p = s->X + 3 * s->tris[3 * f + k];
            fprintf(fp, "      vertex %.9g %.9g %.9g\n", (float)p[0], (float)p[1], (float)p[2]);
        }
        fprintf(fp, "    endloop\n  endfacet\n");
    }
    fprintf(fp, "endsolid test object\n");
    return fclose(fp);
}

/* PLY with extra vertex properties (normal, colour) and an extra element, ASCII or
 * binary big-endian. */
static inline int write_ply_variant(const char *path, const rk_surface *s, int big_endian_binary)
{
    FILE *fp = fopen(path, "wb");
    if (!fp) return -1;
    int bin = big_endian_binary;
    fprintf(fp, "ply\nformat %s 1.0\ncomment variant\nelement vertex %d\nproperty float nx\nproperty double x\n"
                "property double y\nproperty double z\nproperty uchar red\nelement face %d\n"
                "property list uchar int vertex_indices\nproperty short flags\nelement material 1\n"
                "property list int float values\nend_header\n",
            bin ? "binary_big_endian" : "ascii", s->nv, s->nf);
    for (int i = 0; i < s->nv; i++) {
        if (bin) {
            put_f32(fp, 0.5f, 1);
            for (int k = 0; k < 3; k++) put_f64(fp, s->X[3 * i + k], 1);
            fputc(200, fp);
        } else {
            fprintf(fp, "0.5 %.17g %.17g %.17g 200\n", s->X[3 * i], s->X[3 * i + 1], s->X[3 * i + 2]);
        }
    }
    for (int f = 0; f < s->nf; f++) {
        const int *t = s->tris + 3 * f;
        if (bin) {
            fputc(3, fp);
            for (int k = 0; k < 3; k++) put_i32(fp, t[k], 1);
            fputc(0, fp), fputc(7, fp);
        } else {
            fprintf(fp, "3 %d %d %d 7\n", t[0], t[1], t[2]);
        }
    }
    if (bin) put_i32(fp, 2, 1), put_f32(fp, 1, 1), put_f32(fp, 2, 1);
    else fprintf(fp, "2 1 2\n");
    return fclose(fp);
}

#endif
