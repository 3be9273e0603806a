/* rk_splats_write: a 3DGS PLY (binary little-endian) with the splats moved and deformed
 * (splats_deform.c for one splat's covariance and normal, sh_rotate.c for the colour). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/binary_reader_impl.h"
#include "mesh/mesh_impl.h"
#include "mesh/ply_impl.h"

static int type_of(const char *name, rk_scalar *t)
{
    static const struct {
        const char *name;
        rk_scalar type;
    } types[] = {{"char", RK_I8},  {"uchar", RK_U8}, {"short", RK_I16}, {"ushort", RK_U16}, {"int", RK_I32},
                 {"uint", RK_U32}, {"float", RK_F32}, {"double", RK_F64}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (strcmp(name, types[i].name) == 0) {
            *t = types[i].type;
            return 0;
        }
    return -1;
}

/* v as type t, little-endian, at out (rk_scalar_size(t) bytes). Integers are rounded and clamped
 * (they are only ever copied values, exact already; PLY has no 64-bit integers). */
static void put_value(unsigned char *out, rk_scalar t, double v)
{
    unsigned char b[8] = {0};
    size_t n = rk_scalar_size(t);
    double r = nearbyint(v);
#define CLAMP(lo, hi) (r < (lo) ? (lo) : r > (hi) ? (hi) : r)
    switch (t) {
    case RK_I8: { int8_t x = (int8_t)CLAMP(-128.0, 127.0); memcpy(b, &x, 1); break; }
    case RK_U8: { uint8_t x = (uint8_t)CLAMP(0.0, 255.0); memcpy(b, &x, 1); break; }
    case RK_I16: { int16_t x = (int16_t)CLAMP(-32768.0, 32767.0); memcpy(b, &x, 2); break; }
    case RK_U16: { uint16_t x = (uint16_t)CLAMP(0.0, 65535.0); memcpy(b, &x, 2); break; }
    case RK_I32: { int32_t x = (int32_t)CLAMP(-2147483648.0, 2147483647.0); memcpy(b, &x, 4); break; }
    case RK_U32: { uint32_t x = (uint32_t)CLAMP(0.0, 4294967295.0); memcpy(b, &x, 4); break; }
    case RK_I64: case RK_U64: break; /* not PLY types: type_of never gives them */
    case RK_F32: { float x = (float)v; memcpy(b, &x, 4); break; }
    case RK_F64: memcpy(b, &v, 8); break;
    }
#undef CLAMP
    if (!rk_host_little_endian())
        for (size_t i = 0; i < n / 2; i++) {
            unsigned char c = b[i];
            b[i] = b[n - 1 - i];
            b[n - 1 - i] = c;
        }
    memcpy(out, b, n);
}

static int in_range(int col, int nprop) { return col >= -1 && col < nprop; }

/* The splat set must be one rk_splats_read could have made. */
static int check_splats(const char *path, const rk_splats *s, rk_error *err)
{
    if (s->n <= 0 || s->nprop <= 0 || !s->prop || !s->values)
        return rk_fail(err, "%s: no splats to write (%d splats, %d properties)", path, s->n, s->nprop);
    int bad = s->nrest < 0 || s->nrest > RK_SPLATS_MAX_REST || s->sh_degree < 0 || s->sh_degree > RK_SPLATS_MAX_DEGREE ||
              s->nrest != 3 * ((s->sh_degree + 1) * (s->sh_degree + 1) - 1) || !in_range(s->opacity, s->nprop);
    for (int a = 0; a < 3; a++)
        bad |= s->xyz[a] < 0 || s->xyz[a] >= s->nprop || !in_range(s->scale[a], s->nprop) ||
               !in_range(s->f_dc[a], s->nprop) || !in_range(s->normal[a], s->nprop);
    for (int a = 0; a < 4; a++) bad |= !in_range(s->rot[a], s->nprop);
    for (int a = 0; a < s->nrest && !bad; a++) bad |= s->f_rest[a] < 0 || s->f_rest[a] >= s->nprop;
    if (bad) return rk_fail(err, "%s: the splat set is inconsistent (a column index or the SH degree is out of range)", path);
    for (int j = 0; j < s->nprop; j++) {
        rk_scalar t;
        if (type_of(s->prop[j].type, &t) || memchr(s->prop[j].name, '\0', RK_SPLATS_NAME_MAX) == NULL ||
            s->prop[j].name[0] == '\0' || strpbrk(s->prop[j].name, " \t\r\n"))
            return rk_fail(err, "%s: property %d has a bad name or type", path, j);
    }
    return 0;
}

/* Output types: a column the deformation can change (centre, scales, rotation, normal, f_rest)
 * that had an integer type becomes float. */
static void output_types(const rk_splats *s, rk_scalar *type)
{
    for (int j = 0; j < s->nprop; j++) type_of(s->prop[j].type, &type[j]);
    int cols[3 + 3 + 4 + 3 + RK_SPLATS_MAX_REST], nc = 0;
    for (int a = 0; a < 3; a++) cols[nc++] = s->xyz[a], cols[nc++] = s->scale[a], cols[nc++] = s->normal[a];
    for (int a = 0; a < 4; a++) cols[nc++] = s->rot[a];
    for (int a = 0; a < s->nrest; a++) cols[nc++] = s->f_rest[a];
    for (int k = 0; k < nc; k++)
        if (cols[k] >= 0 && type[cols[k]] != RK_F32 && type[cols[k]] != RK_F64) type[cols[k]] = RK_F32;
}

static int is_identity(const double R[9])
{
    for (int i = 0; i < 9; i++)
        if (R[i] != (i % 4 == 0 ? 1.0 : 0.0)) return 0;
    return 1;
}

/* Splat i's row deformed in place. */
static int deform_row(const char *path, const rk_splats *s, int i, const double *Fi, const rk_sh_rotator *rot,
                      double *row, rk_error *err)
{
    double RF[9];
    if (rk_polar_rotation(Fi, RF))
        return rk_fail(err, "%s: splat %d: the deformation gradient F has rank below 2 or is not finite", path, i);
    if (s->scale[0] >= 0 && s->rot[0] >= 0) {
        double q[4], sc[3], qo[4], so[3];
        for (int a = 0; a < 4; a++) q[a] = row[s->rot[a]];
        for (int a = 0; a < 3; a++) sc[a] = row[s->scale[a]];
        if (rk_splat_deform_covariance(Fi, RF, q, sc, qo, so))
            return rk_fail(err, "%s: splat %d: F Sigma F^T is singular or not finite (the splat collapsed under F)", path, i);
        for (int a = 0; a < 4; a++) row[s->rot[a]] = qo[a];
        for (int a = 0; a < 3; a++) row[s->scale[a]] = so[a];
    }
    if (s->sh_degree > 0 && !is_identity(RF)) {
        double M[RK_SH_ROTATION_SIZE], in[15], out[15];
        int K = s->nrest / 3;
        rk_sh_rotator_matrices(rot, RF, s->sh_degree, M);
        for (int c = 0; c < 3; c++) {
            for (int k = 0; k < K; k++) in[k] = row[s->f_rest[c * K + k]];
            rk_sh_apply(M, s->sh_degree, in, out);
            for (int k = 0; k < K; k++) row[s->f_rest[c * K + k]] = out[k];
        }
    }
    if (s->normal[0] >= 0) {
        double n[3], no[3];
        for (int a = 0; a < 3; a++) n[a] = row[s->normal[a]];
        rk_splat_deform_normal(Fi, n, no);
        for (int a = 0; a < 3; a++) row[s->normal[a]] = no[a];
    }
    return 0;
}

static int write_rows(FILE *fp, const char *path, const rk_splats *s, const rk_scalar *type, const double *x,
                      const double *F, double *row, unsigned char *bytes, rk_error *err)
{
    rk_sh_rotator rot;
    if (F && s->sh_degree > 0 && rk_sh_rotator_init(&rot, err)) return rk_error_prefix(err, "%s", path);
    for (int i = 0; i < s->n; i++) {
        memcpy(row, s->values + (size_t)i * s->nprop, (size_t)s->nprop * sizeof *row);
        if (x)
            for (int a = 0; a < 3; a++) {
                double v = x[3 * (size_t)i + a];
                if (!isfinite(v)) return rk_fail(err, "%s: splat %d: non-finite deformed centre", path, i);
                row[s->xyz[a]] = v;
            }
        if (F && deform_row(path, s, i, F + 9 * (size_t)i, &rot, row, err)) return -1;
        size_t at = 0;
        for (int j = 0; j < s->nprop; j++) {
            if (type[j] == RK_F32 && isfinite(row[j]) && !isfinite((float)row[j]))
                return rk_fail(err, "%s: splat %d: %s = %g does not fit a float", path, i, s->prop[j].name, row[j]);
            put_value(bytes + at, type[j], row[j]);
            at += rk_scalar_size(type[j]);
        }
        if (fwrite(bytes, 1, at, fp) != at) return rk_fail(err, "%s: write failed (disk full?)", path);
    }
    return 0;
}

int rk_splats_write(const char *path, const rk_splats *s, const double *x, const double *F, rk_error *err)
{
    if (check_splats(path, s, err)) return -1;
    if (F)
        for (size_t k = 0; k < 9 * (size_t)s->n; k++)
            if (!isfinite(F[k])) return rk_fail(err, "%s: splat %zu: non-finite deformation gradient", path, k / 9);
    rk_scalar *type = rk_calloc((size_t)s->nprop, sizeof *type, err);
    double *row = type ? rk_calloc((size_t)s->nprop, sizeof *row, err) : NULL;
    unsigned char *bytes = row ? rk_calloc((size_t)s->nprop, 8, err) : NULL;
    if (!bytes) {
        free(type);
        free(row);
        return rk_error_prefix(err, "%s", path);
    }
    output_types(s, type);
    rk_atomic_file f;
    int rc = rk_atomic_open(&f, path, err);
    if (rc == 0) {
        fprintf(f.fp, "ply\nformat binary_little_endian 1.0\ncomment written by romkit\nelement vertex %d\n", s->n);
        for (int j = 0; j < s->nprop; j++) fprintf(f.fp, "property %s %s\n", rk_ply_type_name(type[j]), s->prop[j].name);
        fprintf(f.fp, "end_header\n");
        rc = write_rows(f.fp, path, s, type, x, F, row, bytes, err);
        if (rc) rk_atomic_abort(&f);
        else rc = rk_atomic_commit(&f, err);
    }
    free(type);
    free(row);
    free(bytes);
    return rc;
}
