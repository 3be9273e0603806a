/* Gmsh 4.1 writer, ASCII or binary (little-endian, 8-byte size_t). Consecutive tets with
 * the same tag form one element block on its own volume entity; $Entities gives each such
 * volume the tag as its physical tag (none when the tag is 0 or the mesh has no tags). */
#include <math.h>

#include "mesh/mesh_impl.h"
#include "util/util.h"

typedef struct {
    FILE *fp;
    int binary;
    int line_start;
} gmsh_out;

static void separate(gmsh_out *o)
{
    if (!o->line_start) fputc(' ', o->fp);
    o->line_start = 0;
}

static void put_size(gmsh_out *o, uint64_t v)
{
    if (o->binary) {
        rk_put_u64(o->fp, v, 0);
        return;
    }
    separate(o);
    fprintf(o->fp, "%llu", (unsigned long long)v);
}

static void put_int(gmsh_out *o, int v)
{
    if (o->binary) {
        rk_put_i32(o->fp, v, 0);
        return;
    }
    separate(o);
    fprintf(o->fp, "%d", v);
}

static void put_real(gmsh_out *o, double v)
{
    if (o->binary) {
        rk_put_f64(o->fp, v, 0);
        return;
    }
    separate(o);
    fprintf(o->fp, "%.17g", v);
}

static void end_line(gmsh_out *o)
{
    if (!o->binary) fputc('\n', o->fp);
    o->line_start = 1;
}

/* Section keywords are text in both variants; binary data ends with a newline. */
static void section(gmsh_out *o, const char *end, const char *begin)
{
    if (end) fprintf(o->fp, "%s%s\n", o->binary ? "\n" : "", end);
    if (begin) fprintf(o->fp, "%s\n", begin);
    o->line_start = 1;
}

static int tag_of(const rk_mesh *m, int t) { return m->tet_tag ? m->tet_tag[t] : 0; }

static int count_blocks(const rk_mesh *m)
{
    int blocks = 1;
    for (int t = 1; t < m->nt; t++) blocks += tag_of(m, t) != tag_of(m, t - 1);
    return blocks;
}

static void write_entities(gmsh_out *o, const rk_mesh *m, const double *X, int blocks)
{
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (size_t i = 0; i < (size_t)m->nv; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], X[3 * i + k]);
            hi[k] = fmax(hi[k], X[3 * i + k]);
        }
    section(o, NULL, "$Entities");
    for (int d = 0; d < 4; d++) put_size(o, d == 3 ? (uint64_t)blocks : 0);
    end_line(o);
    for (int b = 0, t = 0; b < blocks; b++) {
        int tag = tag_of(m, t);
        put_int(o, b + 1);
        for (int k = 0; k < 6; k++) put_real(o, k < 3 ? lo[k] : hi[k - 3]);
        put_size(o, tag != 0);
        if (tag != 0) put_int(o, tag);
        put_size(o, 0); /* bounding surfaces */
        end_line(o);
        while (t < m->nt && tag_of(m, t) == tag) t++;
    }
    section(o, "$EndEntities", NULL);
}

static void write_nodes(gmsh_out *o, const rk_mesh *m, const double *X)
{
    section(o, NULL, "$Nodes");
    put_size(o, 1);
    put_size(o, (uint64_t)m->nv);
    put_size(o, 1);
    put_size(o, (uint64_t)m->nv);
    end_line(o);
    put_int(o, 3);
    put_int(o, 1);
    put_int(o, 0);
    put_size(o, (uint64_t)m->nv);
    end_line(o);
    for (int i = 0; i < m->nv; i++) {
        put_size(o, (uint64_t)i + 1);
        end_line(o);
    }
    for (size_t i = 0; i < (size_t)m->nv; i++) {
        for (int k = 0; k < 3; k++) put_real(o, X[3 * i + k]);
        end_line(o);
    }
    section(o, "$EndNodes", NULL);
}

static void write_elements(gmsh_out *o, const rk_mesh *m, int blocks)
{
    section(o, NULL, "$Elements");
    put_size(o, (uint64_t)blocks);
    put_size(o, (uint64_t)m->nt);
    put_size(o, 1);
    put_size(o, (uint64_t)m->nt);
    end_line(o);
    for (int b = 0, t = 0; b < blocks; b++) {
        int end = t;
        while (end < m->nt && tag_of(m, end) == tag_of(m, t)) end++;
        put_int(o, 3);
        put_int(o, b + 1);
        put_int(o, 4);
        put_size(o, (uint64_t)(end - t));
        end_line(o);
        for (; t < end; t++) {
            put_size(o, (uint64_t)t + 1);
            for (int k = 0; k < 4; k++) put_size(o, (uint64_t)m->tets[4 * (size_t)t + k] + 1);
            end_line(o);
        }
    }
    section(o, "$EndElements", NULL);
}

int rk_write_gmsh(const char *path, const rk_mesh *m, const double *X, int binary, rk_error *err)
{
    rk_atomic_file f;
    if (rk_atomic_open(&f, path, err)) return -1;
    gmsh_out o = {f.fp, binary, 1};
    fprintf(f.fp, "$MeshFormat\n4.1 %d 8\n", binary);
    if (binary) {
        rk_put_i32(f.fp, 1, 0); /* byte-order mark */
        fputc('\n', f.fp);
    }
    fprintf(f.fp, "$EndMeshFormat\n");
    int blocks = count_blocks(m);
    write_entities(&o, m, X, blocks);
    write_nodes(&o, m, X);
    write_elements(&o, m, blocks);
    return rk_atomic_commit(&f, err);
}
