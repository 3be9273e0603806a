/* rk_surface_write: OBJ, OFF, PLY (binary little-endian) and STL (binary). */
#include <math.h>
#include <string.h>

#include "mesh/mesh_impl.h"
#include "util/util.h"

static void write_obj(FILE *fp, const rk_surface *s)
{
    fprintf(fp, "# written by romkit\n");
    for (size_t i = 0; i < (size_t)s->nv; i++) fprintf(fp, "v %.17g %.17g %.17g\n", s->X[3 * i], s->X[3 * i + 1], s->X[3 * i + 2]);
    for (size_t f = 0; f < (size_t)s->nf; f++)
        fprintf(fp, "f %d %d %d\n", s->tris[3 * f] + 1, s->tris[3 * f + 1] + 1, s->tris[3 * f + 2] + 1);
}

static void write_off(FILE *fp, const rk_surface *s)
{
    fprintf(fp, "OFF\n%d %d 0\n", s->nv, s->nf);
    for (size_t i = 0; i < (size_t)s->nv; i++) fprintf(fp, "%.17g %.17g %.17g\n", s->X[3 * i], s->X[3 * i + 1], s->X[3 * i + 2]);
    for (size_t f = 0; f < (size_t)s->nf; f++) fprintf(fp, "3 %d %d %d\n", s->tris[3 * f], s->tris[3 * f + 1], s->tris[3 * f + 2]);
}

static void write_ply(FILE *fp, const rk_surface *s)
{
    fprintf(fp,
            "ply\nformat binary_little_endian 1.0\ncomment written by romkit\nelement vertex %d\n"
            "property double x\nproperty double y\nproperty double z\nelement face %d\n"
            "property list uchar int vertex_indices\nend_header\n",
            s->nv, s->nf);
    for (size_t i = 0; i < 3 * (size_t)s->nv; i++) rk_put_f64(fp, s->X[i], 0);
    for (size_t f = 0; f < (size_t)s->nf; f++) {
        fputc(3, fp);
        for (int k = 0; k < 3; k++) rk_put_i32(fp, s->tris[3 * f + k], 0);
    }
}

static void write_stl(FILE *fp, const rk_surface *s)
{
    char header[80];
    memset(header, 0, sizeof header);
    snprintf(header, sizeof header, "binary STL written by romkit");
    fwrite(header, 1, sizeof header, fp);
    unsigned char count[4] = {(unsigned char)s->nf, (unsigned char)(s->nf >> 8), (unsigned char)(s->nf >> 16),
                              (unsigned char)(s->nf >> 24)};
    fwrite(count, 1, 4, fp);
    for (size_t f = 0; f < (size_t)s->nf; f++) {
        const double *a = s->X + 3 * (size_t)s->tris[3 * f], *b = s->X + 3 * (size_t)s->tris[3 * f + 1],
                     *c = s->X + 3 * (size_t)s->tris[3 * f + 2];
        double u[3], v[3], n[3];
        for (int k = 0; k < 3; k++) {
            u[k] = b[k] - a[k];
            v[k] = c[k] - a[k];
        }
        n[0] = u[1] * v[2] - u[2] * v[1];
        n[1] = u[2] * v[0] - u[0] * v[2];
        n[2] = u[0] * v[1] - u[1] * v[0];
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int k = 0; k < 3; k++) rk_put_f32(fp, (float)(len > 0 ? n[k] / len : 0), 0);
        for (int k = 0; k < 3; k++) rk_put_f32(fp, (float)a[k], 0);
        for (int k = 0; k < 3; k++) rk_put_f32(fp, (float)b[k], 0);
        for (int k = 0; k < 3; k++) rk_put_f32(fp, (float)c[k], 0);
        fputc(0, fp);
        fputc(0, fp);
    }
}

int rk_surface_write(const char *path, const rk_surface *s, rk_error *err)
{
    void (*writer)(FILE *, const rk_surface *) = NULL;
    if (rk_path_has_ext(path, ".obj")) writer = write_obj;
    else if (rk_path_has_ext(path, ".off")) writer = write_off;
    else if (rk_path_has_ext(path, ".ply")) writer = write_ply;
    else if (rk_path_has_ext(path, ".stl")) writer = write_stl;
    else return rk_fail(err, "%s: unknown surface format (expected .obj, .off, .ply or .stl)", path);
    for (size_t i = 0; i < 3 * (size_t)s->nf; i++)
        if (s->tris[i] < 0 || s->tris[i] >= s->nv)
            return rk_fail(err, "%s: face %zu references vertex %d of %d", path, i / 3, s->tris[i], s->nv);
    rk_atomic_file f;
    if (rk_atomic_open(&f, path, err)) return -1;
    writer(f.fp, s);
    return rk_atomic_commit(&f, err);
}
