/* Gaussian-splat (3DGS) PLY reading, writing and deformation (rk_splats_read, rk_splats_write,
 * rk_sh_rotate). The donut in tests/data/meshes is a real 3DGS capture (degree 0); the degree-3
 * files, normals, odd types and broken files are written here. The deformation is checked against
 * what it must be (F Sigma F^T, R q, F^-T n, the colour seen from turned directions), with the
 * 3DGS basis, the polar rotation and the quaternion algebra written out again below. */
#include <stdint.h>
#include <sys/stat.h>
#include <dirent.h>
#include <unistd.h>

#include "testlib.h"
#include "mesh/mesh.h"

/* ---- a scratch directory ---- */

static char scratch[512];

static const char *tmp_path(const char *name)
{
    static char buf[4][256];
    static int slot;
    if (!scratch[0]) {
        snprintf(scratch, sizeof scratch, "%s/rk_splats_XXXXXX", tl_tmpdir());
        if (!mkdtemp(scratch)) return "/nonexistent/scratch";
    }
    char *out = buf[slot++ & 3];
    snprintf(out, 256, "%s/%s", scratch, name);
    return out;
}

static void remove_scratch(void)
{
    if (!scratch[0]) return;
    DIR *d = opendir(scratch);
    struct dirent *e;
    char p[512];
    while (d && (e = readdir(d)))
        if (e->d_name[0] != '.') {
            snprintf(p, sizeof p, "%s/%s", scratch, e->d_name);
            remove(p);
        }
    if (d) closedir(d);
    rmdir(scratch);
}

/* Files in the scratch directory whose name starts with prefix (a writer's leftovers). */
static int files_starting(const char *prefix)
{
    DIR *d = opendir(scratch);
    struct dirent *e;
    int count = 0;
    while (d && (e = readdir(d))) count += strncmp(e->d_name, prefix, strlen(prefix)) == 0;
    if (d) closedir(d);
    return count;
}

static int file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* ---- small algebra, written independently of the library ---- */

static double uni(uint64_t *st, double lo, double hi) { return lo + (hi - lo) * rk_uniform(st); }

static void quat_matrix(const double q[4], double R[9])
{
    double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    double w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
    double M[9] = {w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y),
                   2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x),
                   2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z};
    memcpy(R, M, sizeof M);
}

/* Hamilton product a b (w x y z). */
static void quat_mul(const double a[4], const double b[4], double c[4])
{
    c[0] = a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3];
    c[1] = a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2];
    c[2] = a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1];
    c[3] = a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0];
}

static void random_quat(uint64_t *st, double q[4])
{
    double n;
    do {
        for (int i = 0; i < 4; i++) q[i] = uni(st, -1, 1);
        n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    } while (n < 0.1 || n > 1);
    for (int i = 0; i < 4; i++) q[i] /= n;
}

static void random_rotation(uint64_t *st, double R[9])
{
    double q[4];
    random_quat(st, q);
    quat_matrix(q, R);
}

static void mat_mul(const double *A, const double *B, double *C)
{
    double T[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) T[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
    memcpy(C, T, sizeof T);
}

static void mat_t(const double *A, double *T)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) T[3 * j + i] = A[3 * i + j];
}

static double mat_det(const double *A)
{
    return A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) + A[2] * (A[3] * A[7] - A[4] * A[6]);
}

static void mat_inv(const double *A, double *B)
{
    double d = mat_det(A);
    B[0] = (A[4] * A[8] - A[5] * A[7]) / d, B[1] = (A[2] * A[7] - A[1] * A[8]) / d, B[2] = (A[1] * A[5] - A[2] * A[4]) / d;
    B[3] = (A[5] * A[6] - A[3] * A[8]) / d, B[4] = (A[0] * A[8] - A[2] * A[6]) / d, B[5] = (A[2] * A[3] - A[0] * A[5]) / d;
    B[6] = (A[3] * A[7] - A[4] * A[6]) / d, B[7] = (A[1] * A[6] - A[0] * A[7]) / d, B[8] = (A[0] * A[4] - A[1] * A[3]) / d;
}

/* Polar rotation of F (det F > 0) by Newton's iteration R <- (R + R^-T) / 2 (Higham 1986). */
static void polar(const double *F, double *R)
{
    double Ri[9], RiT[9];
    memcpy(R, F, 9 * sizeof *R);
    for (int it = 0; it < 100; it++) {
        mat_inv(R, Ri);
        mat_t(Ri, RiT);
        double change = 0;
        for (int k = 0; k < 9; k++) {
            double v = 0.5 * (R[k] + RiT[k]);
            change += fabs(v - R[k]);
            R[k] = v;
        }
        if (change < 1e-15) break;
    }
}

/* Sigma = R diag(exp(2 s)) R^T. */
static void covariance(const double q[4], const double s[3], double *S)
{
    double R[9];
    quat_matrix(q, R);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            S[3 * i + j] = 0;
            for (int k = 0; k < 3; k++) S[3 * i + j] += R[3 * i + k] * exp(2 * s[k]) * R[3 * j + k];
        }
}

static double frob(const double *A)
{
    double s = 0;
    for (int k = 0; k < 9; k++) s += A[k] * A[k];
    return sqrt(s);
}

/* The 3DGS basis (gaussian-splatting utils/sh_utils.py), bands 1..3 at direction d. */
static void sh_basis(const double d[3], double Y[15])
{
    const double C1 = 0.4886025119029199;
    const double C2[5] = {1.0925484305920792, -1.0925484305920792, 0.31539156525252005, -1.0925484305920792,
                          0.5462742152960396};
    const double C3[7] = {-0.5900435899266435, 2.890611442640554, -0.4570457994644658, 0.3731763325901154,
                          -0.4570457994644658, 1.445305721320277, -0.5900435899266435};
    double x = d[0], y = d[1], z = d[2], xx = x * x, yy = y * y, zz = z * z;
    double v[15] = {-C1 * y, C1 * z, -C1 * x,
                    C2[0] * x * y, C2[1] * y * z, C2[2] * (2 * zz - xx - yy), C2[3] * x * z, C2[4] * (xx - yy),
                    C3[0] * y * (3 * xx - yy), C3[1] * x * y * z, C3[2] * y * (4 * zz - xx - yy),
                    C3[3] * z * (2 * zz - 3 * xx - 3 * yy), C3[4] * x * (4 * zz - xx - yy), C3[5] * z * (xx - yy),
                    C3[6] * x * (xx - 3 * yy)};
    memcpy(Y, v, sizeof v);
}

/* View-dependent colour (bands 1..degree) of one channel's K coefficients, seen from d. */
static double sh_colour(const double *c, int degree, const double d[3])
{
    double Y[15], v = 0;
    int K = (degree + 1) * (degree + 1) - 1;
    sh_basis(d, Y);
    for (int k = 0; k < K; k++) v += c[k] * Y[k];
    return v;
}

static void random_direction(uint64_t *st, double d[3])
{
    double n;
    do {
        for (int i = 0; i < 3; i++) d[i] = uni(st, -1, 1);
        n = test_norm(d, 3);
    } while (n < 0.1 || n > 1);
    for (int i = 0; i < 3; i++) d[i] /= n;
}

/* ---- synthetic files ---- */

typedef enum { ASCII, BINARY_LE, BINARY_BE } ply_format;

/* A PLY with one vertex element (names/types, n rows of values) and, when faces, a face element
 * after it. Values are written as their type holds them (floats rounded to float). */
static int write_ply(const char *path, ply_format fmt, int nprop, const char *const *names, const char *const *types,
                     int n, const double *values, int faces)
{
    FILE *fp = fopen(path, "wb");
    if (!fp) return -1;
    fprintf(fp, "ply\nformat %s 1.0\ncomment synthetic splats\nelement vertex %d\n",
            fmt == ASCII ? "ascii" : fmt == BINARY_LE ? "binary_little_endian" : "binary_big_endian", n);
    for (int j = 0; j < nprop; j++) fprintf(fp, "property %s %s\n", types[j], names[j]);
    if (faces) fprintf(fp, "element face 1\nproperty list uchar int vertex_indices\n");
    fprintf(fp, "end_header\n");
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < nprop; j++) {
            double v = values[(size_t)i * nprop + j];
            unsigned char b[8];
            size_t len;
            if (strcmp(types[j], "float") == 0) {
                float f = (float)v;
                memcpy(b, &f, 4), len = 4;
                if (fmt == ASCII) fprintf(fp, "%.9g ", (double)f);
            } else if (strcmp(types[j], "double") == 0) {
                memcpy(b, &v, 8), len = 8;
                if (fmt == ASCII) fprintf(fp, "%.17g ", v);
            } else if (strcmp(types[j], "uchar") == 0) {
                b[0] = (unsigned char)v, len = 1;
                if (fmt == ASCII) fprintf(fp, "%d ", b[0]);
            } else { /* short */
                int16_t h = (int16_t)v;
                memcpy(b, &h, 2), len = 2;
                if (fmt == ASCII) fprintf(fp, "%d ", h);
            }
            if (fmt == BINARY_BE)
                for (size_t k = 0; k < len / 2; k++) {
                    unsigned char c = b[k];
                    b[k] = b[len - 1 - k];
                    b[len - 1 - k] = c;
                }
            if (fmt != ASCII) fwrite(b, 1, len, fp);
        }
        if (fmt == ASCII) fprintf(fp, "\n");
    }
    if (faces) {
        if (fmt == ASCII) fprintf(fp, "3 0 1 2\n");
        else {
            unsigned char three = 3;
            fwrite(&three, 1, 1, fp);
            for (int32_t k = 0; k < 3; k++) {
                unsigned char b[4];
                memcpy(b, &k, 4);
                if (fmt == BINARY_BE)
                    for (int m = 0; m < 2; m++) {
                        unsigned char c = b[m];
                        b[m] = b[3 - m];
                        b[3 - m] = c;
                    }
                fwrite(b, 1, 4, fp);
            }
        }
    }
    return fclose(fp);
}

/* A full degree-`degree` splat layout as gaussian-splatting's save_ply writes it, plus two
 * properties 3DGS does not know (a uchar and a short) and a double one. */
#define MAXP 80
typedef struct {
    int nprop;
    char namebuf[MAXP][24];
    const char *names[MAXP];
    const char *types[MAXP];
    int n;
    double *values;
} synth;

static void synth_add(synth *s, const char *name, const char *type)
{
    snprintf(s->namebuf[s->nprop], sizeof s->namebuf[0], "%s", name);
    s->names[s->nprop] = s->namebuf[s->nprop];
    s->types[s->nprop] = type;
    s->nprop++;
}

static int synth_col(const synth *s, const char *name)
{
    for (int j = 0; j < s->nprop; j++)
        if (strcmp(s->names[j], name) == 0) return j;
    return -1;
}

/* Random splats: centres in [-1,1]^3, log scales in [-4, 0], unnormalized quaternions, normals
 * (non-unit), SH in [-0.5, 0.5], opacity logits, a label and a count. */
static void synth_make(synth *s, int n, int degree, int normals, uint64_t seed)
{
    static const char *const base[] = {"x", "y", "z"};
    memset(s, 0, sizeof *s);
    for (int a = 0; a < 3; a++) synth_add(s, base[a], "float");
    if (normals)
        for (int a = 0; a < 3; a++) synth_add(s, a == 0 ? "nx" : a == 1 ? "ny" : "nz", "float");
    for (int a = 0; a < 3; a++) {
        char nm[24];
        snprintf(nm, sizeof nm, "f_dc_%d", a);
        synth_add(s, nm, "float");
    }
    int K = (degree + 1) * (degree + 1) - 1;
    for (int k = 0; k < 3 * K; k++) {
        char nm[24];
        snprintf(nm, sizeof nm, "f_rest_%d", k);
        synth_add(s, nm, "float");
    }
    synth_add(s, "opacity", "float");
    synth_add(s, "label", "uchar");
    for (int a = 0; a < 3; a++) {
        char nm[24];
        snprintf(nm, sizeof nm, "scale_%d", a);
        synth_add(s, nm, "float");
    }
    for (int a = 0; a < 4; a++) {
        char nm[24];
        snprintf(nm, sizeof nm, "rot_%d", a);
        synth_add(s, nm, "float");
    }
    synth_add(s, "weight", "double");
    synth_add(s, "count", "short");
    s->n = n;
    s->values = calloc((size_t)n * s->nprop, sizeof *s->values);
    uint64_t st = seed;
    for (int i = 0; i < n; i++) {
        double *row = s->values + (size_t)i * s->nprop;
        for (int j = 0; j < s->nprop; j++) {
            const char *nm = s->names[j];
            double v;
            if (strncmp(nm, "scale_", 6) == 0) v = uni(&st, -4, 0);
            else if (strncmp(nm, "rot_", 4) == 0) v = uni(&st, -2, 2);
            else if (strcmp(nm, "label") == 0) v = (double)(rk_splitmix64(&st) % 256);
            else if (strcmp(nm, "count") == 0) v = (double)((int)(rk_splitmix64(&st) % 60000) - 30000);
            else if (strcmp(nm, "weight") == 0) v = uni(&st, -1e3, 1e3);
            else if (nm[0] == 'f') v = uni(&st, -0.5, 0.5);
            else v = uni(&st, -1, 1);
            if (strcmp(s->types[j], "float") == 0) v = (float)v;
            row[j] = v;
        }
    }
}

/* ---- tests ---- */

#define DONUT "meshes/donut_3dgs.ply"

TEST(reads_the_donut)
{
    rk_error err;
    rk_splats s;
    CHECK_OK(rk_splats_read(test_data(DONUT), &s, &err));
    static const char *const names[] = {"x", "y", "z", "f_dc_0", "f_dc_1", "f_dc_2", "opacity",
                                        "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"};
    int ok = s.n == 45624 && s.nprop == 14 && s.sh_degree == 0 && s.nrest == 0 && s.has_splat_attributes &&
             s.normal[0] == -1 && s.opacity == 6 && s.xyz[0] == 0 && s.scale[0] == 7 && s.rot[0] == 10 && s.f_dc[2] == 5;
    for (int j = 0; j < 14 && ok; j++) ok = strcmp(s.prop[j].name, names[j]) == 0 && strcmp(s.prop[j].type, "float") == 0;
    int finite = 1;
    for (size_t k = 0; k < (size_t)s.n * s.nprop; k++) finite &= isfinite(s.values[k]) != 0;
    for (int i = 0; i < s.n; i++)
        for (int a = 0; a < 3; a++) finite &= s.X[3 * i + a] == s.values[(size_t)i * 14 + a];
    rk_splats_free(&s);
    CHECK(ok, "counts, names, types or columns are not the donut's");
    CHECK(finite, "a value is not finite, or X is not the x y z columns");
}

/* Every value equal after a write and a read; rotations compared as matrices, scales to float
 * rounding. With F = NULL every value is bit for bit. */
TEST(donut_round_trip)
{
    rk_error err;
    rk_splats s, back, plain;
    CHECK_OK(rk_splats_read(test_data(DONUT), &s, &err));
    double *F = calloc(9 * (size_t)s.n, sizeof *F);
    for (int i = 0; i < s.n; i++) F[9 * i] = F[9 * i + 4] = F[9 * i + 8] = 1;
    const char *out = tmp_path("donut_identity.ply"), *out_plain = tmp_path("donut_plain.ply");
    double t0 = rk_now();
    int rc = rk_splats_write(out, &s, s.X, F, &err);
    double seconds = rk_now() - t0;
    free(F);
    if (rc) rk_splats_free(&s);
    CHECK(rc == 0, "write: %s", err.msg);
    printf("# donut: %d splats written through F = I in %.3f s\n", s.n, seconds);
    CHECK_OK(rk_splats_read(out, &back, &err));
    CHECK_OK(rk_splats_write(out_plain, &s, NULL, NULL, &err));
    CHECK_OK(rk_splats_read(out_plain, &plain, &err));
    int same_layout = back.n == s.n && back.nprop == s.nprop && plain.nprop == s.nprop;
    for (int j = 0; j < s.nprop && same_layout; j++)
        same_layout = strcmp(back.prop[j].name, s.prop[j].name) == 0 && strcmp(back.prop[j].type, s.prop[j].type) == 0;
    int plain_exact = memcmp(plain.values, s.values, (size_t)s.n * s.nprop * sizeof *s.values) == 0;
    int other_exact = 1, scale_exact = 0, worst_i = -1;
    double worst_scale = 0, worst_rot = 0;
    for (int i = 0; i < s.n; i++) {
        const double *a = s.values + (size_t)i * s.nprop, *b = back.values + (size_t)i * s.nprop;
        for (int j = 0; j < 7; j++) other_exact &= a[j] == b[j];
        for (int k = 0; k < 3; k++) {
            double d = fabs(a[7 + k] - b[7 + k]), ulp = nextafterf((float)fabs(a[7 + k]), INFINITY) - fabsf((float)a[7 + k]);
            scale_exact += d == 0;
            if (d / ulp > worst_scale) worst_scale = d / ulp, worst_i = i;
        }
        double Ra[9], Rb[9];
        quat_matrix(a + 10, Ra);
        quat_matrix(b + 10, Rb);
        for (int k = 0; k < 9; k++) worst_rot = fmax(worst_rot, fabs(Ra[k] - Rb[k]));
        double qb = sqrt(b[10] * b[10] + b[11] * b[11] + b[12] * b[12] + b[13] * b[13]);
        worst_rot = fmax(worst_rot, fabs(qb - 1));
        if (b[10] < 0) worst_rot = 1;
    }
    printf("# donut F = I: %d of %d scales bit-exact, worst %.2g float ulp (splat %d); rotation matrices to %.2g\n",
           scale_exact, 3 * s.n, worst_scale, worst_i, worst_rot);
    rk_splats_free(&s);
    rk_splats_free(&back);
    rk_splats_free(&plain);
    CHECK(same_layout, "names, types or count changed");
    CHECK(plain_exact, "F = NULL, x = NULL did not copy every value bit for bit");
    CHECK(other_exact, "x y z, f_dc or opacity changed under F = I");
    CHECK(worst_scale <= 1, "a scale moved by %g float ulp under F = I", worst_scale);
    CHECK(worst_rot <= 1e-6, "rotation matrices (or unit length, w >= 0) differ by %g under F = I", worst_rot);
}

/* Degree 3, normals, extra properties, faces after the vertices: ASCII, binary little- and
 * big-endian files read the same; written back (binary) and read again, every value is the same. */
TEST(synthetic_round_trip)
{
    rk_error err;
    synth sy;
    synth_make(&sy, 50, 3, 1, 11);
    static const ply_format fmts[] = {ASCII, BINARY_LE, BINARY_BE};
    static const char *const files[] = {"syn_ascii.ply", "syn_le.ply", "syn_be.ply"};
    for (int f = 0; f < 3; f++) {
        rk_splats s, back;
        const char *path = tmp_path(files[f]);
        CHECK(write_ply(path, fmts[f], sy.nprop, sy.names, sy.types, sy.n, sy.values, 1) == 0, "cannot write %s", path);
        CHECK_OK(rk_splats_read(path, &s, &err));
        int ok = s.n == 50 && s.nprop == sy.nprop && s.sh_degree == 3 && s.nrest == 45 && s.has_splat_attributes &&
                 s.normal[0] == 3 && s.normal[2] == 5 && s.f_rest[44] == synth_col(&sy, "f_rest_44") &&
                 s.opacity == synth_col(&sy, "opacity") && s.rot[3] == synth_col(&sy, "rot_3");
        for (int j = 0; j < s.nprop && ok; j++)
            ok = strcmp(s.prop[j].name, sy.names[j]) == 0 && strcmp(s.prop[j].type, sy.types[j]) == 0;
        /* ASCII: %.9g of a float reads back as that float; double as %.17g: exact. */
        int equal = 1;
        for (size_t k = 0; k < (size_t)s.n * s.nprop && ok; k++) equal &= s.values[k] == sy.values[k];
        const char *out = tmp_path("syn_back.ply");
        int rc = rk_splats_write(out, &s, NULL, NULL, &err);
        if (rc == 0) rc = rk_splats_read(out, &back, &err);
        if (rc) rk_splats_free(&s);
        CHECK(rc == 0, "%s: %s", files[f], err.msg);
        int again = back.nprop == s.nprop &&
                    memcmp(back.values, s.values, (size_t)s.n * s.nprop * sizeof *s.values) == 0;
        for (int j = 0; j < s.nprop && again; j++) again = strcmp(back.prop[j].type, s.prop[j].type) == 0;
        rk_splats_free(&s);
        rk_splats_free(&back);
        CHECK(ok, "%s: layout or resolved columns wrong", files[f]);
        CHECK(equal, "%s: values differ from what was written", files[f]);
        CHECK(again, "%s: written and read again, a value or type changed", files[f]);
    }
    free(sy.values);
}

/* F = I on degree 3 with normals: SH untouched, normals normalized, everything else kept. */
TEST(synthetic_identity)
{
    rk_error err;
    synth sy;
    rk_splats s, back;
    synth_make(&sy, 40, 3, 1, 12);
    const char *path = tmp_path("syn_id.ply"), *out = tmp_path("syn_id_out.ply");
    CHECK(write_ply(path, BINARY_LE, sy.nprop, sy.names, sy.types, sy.n, sy.values, 0) == 0, "cannot write");
    CHECK_OK(rk_splats_read(path, &s, &err));
    double *F = calloc(9 * (size_t)s.n, sizeof *F);
    for (int i = 0; i < s.n; i++) F[9 * i] = F[9 * i + 4] = F[9 * i + 8] = 1;
    int rc = rk_splats_write(out, &s, NULL, F, &err);
    free(F);
    if (rc == 0) rc = rk_splats_read(out, &back, &err);
    if (rc) rk_splats_free(&s);
    CHECK(rc == 0, "%s", err.msg);
    int sh_same = 1, kept = 1;
    double normal_err = 0;
    for (int i = 0; i < s.n; i++) {
        const double *a = s.values + (size_t)i * s.nprop, *b = back.values + (size_t)i * s.nprop;
        for (int k = 0; k < s.nrest; k++) sh_same &= a[s.f_rest[k]] == b[s.f_rest[k]];
        double len = sqrt(a[3] * a[3] + a[4] * a[4] + a[5] * a[5]);
        for (int k = 0; k < 3; k++) normal_err = fmax(normal_err, fabs(b[3 + k] - a[3 + k] / len));
        for (int j = 0; j < s.nprop; j++) {
            const char *nm = s.prop[j].name;
            if (nm[0] == 'n' || strncmp(nm, "rot", 3) == 0 || strncmp(nm, "scale", 5) == 0) continue;
            kept &= a[j] == b[j];
        }
    }
    rk_splats_free(&s);
    rk_splats_free(&back);
    free(sy.values);
    CHECK(sh_same, "F = I changed an SH coefficient");
    CHECK(kept, "F = I changed a centre, colour, opacity or an unknown property");
    CHECK(normal_err <= 1e-7, "normals not normalized under F = I (%g)", normal_err);
}

/* Random F (det > 0) on random splats: the written rotation and scales give F Sigma F^T, the
 * quaternions are unit, normals are F^-T n, and the colour seen from R_F d is the old one from d. */
TEST(deformation)
{
    rk_error err;
    synth sy;
    rk_splats s, back;
    synth_make(&sy, 300, 3, 1, 13);
    const char *path = tmp_path("def_in.ply"), *out = tmp_path("def_out.ply");
    CHECK(write_ply(path, BINARY_LE, sy.nprop, sy.names, sy.types, sy.n, sy.values, 0) == 0, "cannot write");
    free(sy.values);
    CHECK_OK(rk_splats_read(path, &s, &err));
    uint64_t st = 99;
    double *F = malloc(9 * (size_t)s.n * sizeof *F), *x = malloc(3 * (size_t)s.n * sizeof *x);
    for (int i = 0; i < s.n; i++) {
        double R1[9], R2[9], D[9] = {0};
        random_rotation(&st, R1);
        random_rotation(&st, R2);
        for (int k = 0; k < 3; k++) D[4 * k] = uni(&st, 0.4, 2.5); /* det > 0, stretch and squash */
        mat_mul(R1, D, F + 9 * i);
        mat_mul(F + 9 * i, R2, F + 9 * i);
        for (int a = 0; a < 3; a++) x[3 * i + a] = s.X[3 * i + a] + uni(&st, -0.5, 0.5);
    }
    int rc = rk_splats_write(out, &s, x, F, &err);
    if (rc == 0) rc = rk_splats_read(out, &back, &err);
    if (rc) {
        free(F), free(x);
        rk_splats_free(&s);
    }
    CHECK(rc == 0, "%s", err.msg);
    double cov_err = 0, unit_err = 0, normal_err = 0, colour_err = 0, centre_err = 0;
    int finite = 1, w_neg = 0, K = s.nrest / 3;
    for (int i = 0; i < s.n; i++) {
        const double *a = s.values + (size_t)i * s.nprop, *b = back.values + (size_t)i * s.nprop, *Fi = F + 9 * i;
        double q[4], sc[3], q2[4], sc2[3], S[9], S2[9], FT[9];
        for (int k = 0; k < 4; k++) q[k] = a[s.rot[k]], q2[k] = b[s.rot[k]];
        for (int k = 0; k < 3; k++) sc[k] = a[s.scale[k]], sc2[k] = b[s.scale[k]], finite &= isfinite(sc2[k]) != 0;
        covariance(q, sc, S);
        mat_t(Fi, FT);
        mat_mul(Fi, S, S);
        mat_mul(S, FT, S); /* F Sigma F^T */
        covariance(q2, sc2, S2);
        for (int k = 0; k < 9; k++) S2[k] -= S[k];
        cov_err = fmax(cov_err, frob(S2) / frob(S));
        unit_err = fmax(unit_err, fabs(sqrt(q2[0] * q2[0] + q2[1] * q2[1] + q2[2] * q2[2] + q2[3] * q2[3]) - 1));
        w_neg += q2[0] < 0;
        for (int k = 0; k < 3; k++) centre_err = fmax(centre_err, fabs(b[s.xyz[k]] - (float)x[3 * i + k]));
        /* normal: parallel to F^-T n, unit */
        double Fi_inv[9], n2[3], expect[3];
        mat_inv(Fi, Fi_inv);
        for (int k = 0; k < 3; k++)
            expect[k] = Fi_inv[k] * a[s.normal[0]] + Fi_inv[3 + k] * a[s.normal[1]] + Fi_inv[6 + k] * a[s.normal[2]];
        double el = test_norm(expect, 3);
        for (int k = 0; k < 3; k++) n2[k] = b[s.normal[k]], normal_err = fmax(normal_err, fabs(n2[k] - expect[k] / el));
        /* colour from R_F d with the new coefficients = colour from d with the old */
        double RF[9];
        polar(Fi, RF);
        for (int t = 0; t < 3; t++) {
            double d[3], rd[3], c_old[15], c_new[15];
            random_direction(&st, d);
            for (int k = 0; k < 3; k++) rd[k] = RF[3 * k] * d[0] + RF[3 * k + 1] * d[1] + RF[3 * k + 2] * d[2];
            for (int c = 0; c < 3; c++) {
                for (int k = 0; k < K; k++) c_old[k] = a[s.f_rest[c * K + k]], c_new[k] = b[s.f_rest[c * K + k]];
                colour_err = fmax(colour_err, fabs(sh_colour(c_new, 3, rd) - sh_colour(c_old, 3, d)));
            }
        }
    }
    printf("# deformation of %d splats: covariance %.2g relative, |q| - 1 %.2g, normals %.2g, colour %.2g\n", s.n,
           cov_err, unit_err, normal_err, colour_err);
    free(F), free(x);
    rk_splats_free(&s);
    rk_splats_free(&back);
    CHECK(finite, "a written scale is not finite");
    CHECK(w_neg == 0, "%d quaternions with w < 0", w_neg);
    CHECK(cov_err <= 1e-6, "written (rot, scale) give F Sigma F^T to only %g", cov_err);
    CHECK(unit_err <= 1e-6, "a quaternion is not unit (%g)", unit_err);
    CHECK(centre_err == 0, "a centre is not the deformed one rounded to float (%g)", centre_err);
    CHECK(normal_err <= 1e-6, "normals differ from F^-T n normalized by %g", normal_err);
    /* coefficients up to 0.5 stored as float: 15 terms of ~3e-8 rounding */
    CHECK(colour_err <= 1e-6, "rotated SH colours differ by %g", colour_err);
}

/* F = a rotation: scales stay, the quaternion becomes R q; also for splats with two or three equal
 * scales, whose axes the covariance alone does not determine. */
TEST(pure_rotation)
{
    rk_error err;
    synth sy;
    rk_splats s, back;
    synth_make(&sy, 200, 1, 0, 14);
    int s0 = synth_col(&sy, "scale_0"), s1 = synth_col(&sy, "scale_1"), s2 = synth_col(&sy, "scale_2");
    for (int i = 0; i < sy.n; i++) {
        double *row = sy.values + (size_t)i * sy.nprop;
        if (i % 4 == 1) row[s1] = row[s0];
        if (i % 4 == 2) row[s2] = row[s1];
        if (i % 4 == 3) row[s1] = row[s2] = row[s0];
    }
    const char *path = tmp_path("rot_in.ply"), *out = tmp_path("rot_out.ply");
    CHECK(write_ply(path, BINARY_LE, sy.nprop, sy.names, sy.types, sy.n, sy.values, 0) == 0, "cannot write");
    free(sy.values);
    CHECK_OK(rk_splats_read(path, &s, &err));
    uint64_t st = 5;
    double *F = malloc(9 * (size_t)s.n * sizeof *F), (*rq)[4] = malloc((size_t)s.n * sizeof *rq);
    for (int i = 0; i < s.n; i++) {
        random_quat(&st, rq[i]);
        quat_matrix(rq[i], F + 9 * i);
    }
    int rc = rk_splats_write(out, &s, NULL, F, &err);
    if (rc == 0) rc = rk_splats_read(out, &back, &err);
    if (rc) {
        free(F), free(rq);
        rk_splats_free(&s);
    }
    CHECK(rc == 0, "%s", err.msg);
    double scale_err = 0, quat_err = 0;
    for (int i = 0; i < s.n; i++) {
        const double *a = s.values + (size_t)i * s.nprop, *b = back.values + (size_t)i * s.nprop;
        double q[4], expect[4], len = 0;
        for (int k = 0; k < 4; k++) q[k] = a[s.rot[k]], len += q[k] * q[k];
        for (int k = 0; k < 4; k++) q[k] /= sqrt(len);
        quat_mul(rq[i], q, expect);
        double sign = expect[0] < 0 ? -1 : 1;
        for (int k = 0; k < 4; k++) quat_err = fmax(quat_err, fabs(b[s.rot[k]] - sign * expect[k]));
        for (int k = 0; k < 3; k++) scale_err = fmax(scale_err, fabs(b[s.scale[k]] - a[s.scale[k]]));
    }
    printf("# pure rotation: scales within %.2g, quaternion R q within %.2g\n", scale_err, quat_err);
    free(F), free(rq);
    rk_splats_free(&s);
    rk_splats_free(&back);
    CHECK(scale_err <= 1e-6, "scales changed by %g under a rotation", scale_err);
    CHECK(quat_err <= 1e-6, "the quaternion is not R q (%g)", quat_err);
}

/* The colour from R d with rotated coefficients is the colour from d with the old ones, for every
 * degree, in double; rotating by R1 then R2 is rotating by R2 R1. */
TEST(sh_rotation)
{
    rk_error err;
    uint64_t st = 2024;
    double worst = 0, worst_comp = 0;
    for (int trial = 0; trial < 50; trial++) {
        for (int degree = 1; degree <= 3; degree++) {
            int K = (degree + 1) * (degree + 1) - 1;
            double R[9], c[2 * 15], rot[2 * 15];
            random_rotation(&st, R);
            for (int k = 0; k < 2 * K; k++) c[k] = rot[k] = uni(&st, -1, 1);
            CHECK_OK(rk_sh_rotate(R, degree, 2, rot, &err));
            for (int t = 0; t < 5; t++) {
                double d[3], rd[3];
                random_direction(&st, d);
                for (int k = 0; k < 3; k++) rd[k] = R[3 * k] * d[0] + R[3 * k + 1] * d[1] + R[3 * k + 2] * d[2];
                for (int ch = 0; ch < 2; ch++)
                    worst = fmax(worst, fabs(sh_colour(rot + ch * K, degree, rd) - sh_colour(c + ch * K, degree, d)));
            }
        }
        double R1[9], R2[9], R21[9], a[15], b[15];
        random_rotation(&st, R1);
        random_rotation(&st, R2);
        mat_mul(R2, R1, R21);
        for (int k = 0; k < 15; k++) a[k] = b[k] = uni(&st, -1, 1);
        CHECK_OK(rk_sh_rotate(R1, 3, 1, a, &err));
        CHECK_OK(rk_sh_rotate(R2, 3, 1, a, &err));
        CHECK_OK(rk_sh_rotate(R21, 3, 1, b, &err));
        for (int k = 0; k < 15; k++) worst_comp = fmax(worst_comp, fabs(a[k] - b[k]));
    }
    printf("# SH rotation: colour %.2g, composition %.2g\n", worst, worst_comp);
    CHECK(worst <= 1e-10, "colour from R d with rotated coefficients differs by %g", worst);
    CHECK(worst_comp <= 1e-10, "R1 then R2 differs from R2 R1 by %g", worst_comp);
    /* a reflection, and a bad degree, are refused */
    double mirror[9] = {-1, 0, 0, 0, 1, 0, 0, 0, 1}, c[15] = {0};
    CHECK(rk_sh_rotate(mirror, 3, 1, c, &err) != 0 && strstr(err.msg, "rotation"), "a reflection was accepted");
    double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    CHECK(rk_sh_rotate(I, 4, 1, c, &err) != 0 && strstr(err.msg, "degree 4"), "degree 4 accepted: %s", err.msg);
}

/* A PLY with only x y z is a valid point cloud; deformed, only its centres move. */
TEST(plain_point_cloud)
{
    rk_error err;
    rk_splats s, back;
    static const char *const names[] = {"x", "y", "z"}, *const types[] = {"float", "float", "float"};
    double v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0.5};
    const char *path = tmp_path("cloud.ply"), *out = tmp_path("cloud_out.ply");
    CHECK(write_ply(path, ASCII, 3, names, types, 3, v, 1) == 0, "cannot write");
    CHECK_OK(rk_splats_read(path, &s, &err));
    int ok = s.n == 3 && s.nprop == 3 && !s.has_splat_attributes && s.sh_degree == 0 && s.rot[0] == -1 &&
             s.scale[0] == -1 && s.opacity == -1 && s.f_dc[0] == -1 && s.normal[0] == -1 && s.X[8] == 0.5;
    double F[27] = {2, 0, 0, 0, 1, 0, 0, 0, 1, 2, 0, 0, 0, 1, 0, 0, 0, 1, 2, 0, 0, 0, 1, 0, 0, 0, 1};
    double x[9] = {1, 2, 3, 4, 5, 6, 7, 8, 9};
    int rc = rk_splats_write(out, &s, x, F, &err);
    if (rc == 0) rc = rk_splats_read(out, &back, &err);
    rk_splats_free(&s);
    CHECK(rc == 0, "%s", err.msg);
    int moved = back.n == 3 && memcmp(back.X, x, sizeof x) == 0;
    rk_splats_free(&back);
    CHECK(ok, "the point cloud's columns are wrong");
    CHECK(moved, "the centres are not the deformed ones");
}

/* The file's first `keep` bytes, as another file. */
static int truncated_copy(const char *from, const char *to, long keep)
{
    FILE *a = fopen(from, "rb"), *b = fopen(to, "wb");
    int rc = a && b ? 0 : -1;
    for (long k = 0; k < keep && rc == 0; k++) {
        int c = fgetc(a);
        if (c == EOF) break;
        fputc(c, b);
    }
    if (a) fclose(a);
    if (b) fclose(b);
    return rc;
}

/* Reads path and expects a failure whose message holds every one of the words. */
static int fails_with(const char *path, const char *w1, const char *w2, char *msg, size_t cap)
{
    rk_error err;
    rk_splats s;
    err.msg[0] = '\0';
    if (rk_splats_read(path, &s, &err) == 0) {
        rk_splats_free(&s);
        snprintf(msg, cap, "%s was read without an error", path);
        return 0;
    }
    snprintf(msg, cap, "%s", err.msg);
    return s.n == 0 && s.values == NULL && strstr(err.msg, path) && strstr(err.msg, w1) && (!w2 || strstr(err.msg, w2));
}

TEST(read_errors)
{
    char msg[1100];
    /* truncated binary: the donut cut in the middle of its rows */
    const char *cut = tmp_path("cut.ply");
    CHECK(truncated_copy(test_data(DONUT), cut, 1200000) == 0, "cannot copy");
    CHECK(fails_with(cut, "truncated", "vertex", msg, sizeof msg), "truncated: %s", msg);
    printf("# truncated: %s\n", msg);

    static const char *const xyz_names[] = {"y", "z", "opacity"}, *const f3[] = {"float", "float", "float"};
    double v3[6] = {1, 2, 3, 4, 5, 6};
    const char *nox = tmp_path("nox.ply");
    CHECK(write_ply(nox, ASCII, 3, xyz_names, f3, 2, v3, 0) == 0, "cannot write");
    CHECK(fails_with(nox, "no 'x'", NULL, msg, sizeof msg), "missing x: %s", msg);
    printf("# missing x: %s\n", msg);

    /* f_rest count 44: degree 3 less one */
    synth sy;
    synth_make(&sy, 3, 3, 0, 15);
    int last = synth_col(&sy, "f_rest_44");
    sy.names[last] = "something_else";
    const char *r44 = tmp_path("rest44.ply");
    CHECK(write_ply(r44, BINARY_LE, sy.nprop, sy.names, sy.types, sy.n, sy.values, 0) == 0, "cannot write");
    CHECK(fails_with(r44, "44 f_rest", NULL, msg, sizeof msg), "f_rest 44: %s", msg);
    printf("# f_rest 44: %s\n", msg);

    /* a NaN position at vertex 2, a zero quaternion at vertex 1 */
    sy.names[last] = "f_rest_44";
    sy.values[2 * sy.nprop + synth_col(&sy, "y")] = NAN;
    const char *nan = tmp_path("nan.ply");
    CHECK(write_ply(nan, BINARY_LE, sy.nprop, sy.names, sy.types, sy.n, sy.values, 0) == 0, "cannot write");
    CHECK(fails_with(nan, "vertex 2", "non-finite", msg, sizeof msg), "NaN: %s", msg);
    printf("# NaN: %s\n", msg);
    sy.values[2 * sy.nprop + synth_col(&sy, "y")] = 0.25;
    for (int k = 0; k < 4; k++) {
        char nm[8];
        snprintf(nm, sizeof nm, "rot_%d", k);
        sy.values[1 * sy.nprop + synth_col(&sy, nm)] = 0;
    }
    const char *zq = tmp_path("zeroq.ply");
    CHECK(write_ply(zq, ASCII, sy.nprop, sy.names, sy.types, sy.n, sy.values, 0) == 0, "cannot write");
    CHECK(fails_with(zq, "vertex 1", "quaternion", msg, sizeof msg), "zero quaternion: %s", msg);
    printf("# zero quaternion: %s\n", msg);

    /* half a group: scale_2 missing */
    int s2 = synth_col(&sy, "scale_2");
    sy.names[s2] = "scale_x";
    sy.values[1 * sy.nprop + synth_col(&sy, "rot_0")] = 1;
    const char *half = tmp_path("half.ply");
    CHECK(write_ply(half, ASCII, sy.nprop, sy.names, sy.types, sy.n, sy.values, 0) == 0, "cannot write");
    CHECK(fails_with(half, "scale_2", NULL, msg, sizeof msg), "half a group: %s", msg);
    free(sy.values);
}

/* Bad input never crashes: a degree-2 file with normals and faces, ASCII and binary, cut at every
 * 7th byte and with bytes changed at random, either reads (and then writes back) or fails with a
 * message naming the file. */
TEST(corrupt_files)
{
    synth sy;
    synth_make(&sy, 6, 2, 1, 17);
    uint64_t st = 321;
    int reads = 0, failures = 0;
    for (int fmt = 0; fmt < 2; fmt++) {
        const char *good = tmp_path("fz_good.ply"), *bad = tmp_path("fz_bad.ply"), *out = tmp_path("fz_out.ply");
        CHECK(write_ply(good, fmt ? BINARY_LE : ASCII, sy.nprop, sy.names, sy.types, sy.n, sy.values, 1) == 0, "write");
        FILE *fp = fopen(good, "rb");
        CHECK(fp != NULL, "cannot open %s", good);
        static unsigned char buf[1 << 16];
        long len = (long)fread(buf, 1, sizeof buf, fp);
        fclose(fp);
        for (int trial = 0; trial < len / 7 + 300; trial++) {
            long keep = len;
            unsigned char saved[4];
            long at[4] = {0};
            int changes = 0;
            if (trial < len / 7) keep = 7L * trial;
            else {
                changes = 1 + (int)(rk_splitmix64(&st) % 4);
                for (int c = 0; c < changes; c++) {
                    at[c] = (long)(rk_splitmix64(&st) % (uint64_t)len);
                    saved[c] = buf[at[c]];
                    buf[at[c]] = (unsigned char)rk_splitmix64(&st);
                }
            }
            fp = fopen(bad, "wb");
            CHECK(fp != NULL, "cannot write %s", bad);
            fwrite(buf, 1, (size_t)keep, fp);
            fclose(fp);
            for (int c = changes - 1; c >= 0; c--) buf[at[c]] = saved[c];
            rk_error err;
            rk_splats s;
            err.msg[0] = '\0';
            if (rk_splats_read(bad, &s, &err) == 0) {
                reads++;
                double *F = calloc(9 * (size_t)s.n, sizeof *F);
                for (int i = 0; i < s.n; i++) F[9 * i] = 1.5, F[9 * i + 4] = 1, F[9 * i + 8] = 0.5;
                int rc = rk_splats_write(out, &s, NULL, F, &err); /* may fail (a huge scale), must not crash */
                free(F);
                rk_splats_free(&s);
                CHECK(rc == 0 || strstr(err.msg, out), "write after a corrupt read: %s", err.msg);
            } else {
                failures++;
                CHECK(strstr(err.msg, bad) != NULL, "message does not name the file: %s", err.msg);
            }
        }
    }
    free(sy.values);
    printf("# corrupt splat files: %d read, %d refused with a message\n", reads, failures);
}

TEST(write_errors)
{
    rk_error err;
    rk_splats s;
    synth sy;
    synth_make(&sy, 10, 2, 1, 16);
    const char *path = tmp_path("w_in.ply");
    CHECK(write_ply(path, BINARY_LE, sy.nprop, sy.names, sy.types, sy.n, sy.values, 0) == 0, "cannot write");
    free(sy.values);
    CHECK_OK(rk_splats_read(path, &s, &err));
    /* a bad path: an error naming it, no file */
    const char *bad = "/nonexistent_rk_dir/out.ply";
    int rc = rk_splats_write(bad, &s, NULL, NULL, &err);
    int named = rc != 0 && strstr(err.msg, bad) != NULL;
    /* a collapsed splat (F = 0 at splat 7): an error naming it, nothing left in the directory */
    double *F = calloc(9 * (size_t)s.n, sizeof *F);
    for (int i = 0; i < s.n; i++)
        if (i != 7) F[9 * i] = F[9 * i + 4] = F[9 * i + 8] = 1;
    const char *out = tmp_path("w_collapsed.ply");
    int rc2 = rk_splats_write(out, &s, NULL, F, &err);
    int named2 = rc2 != 0 && strstr(err.msg, out) && strstr(err.msg, "splat 7");
    char msg2[1024];
    snprintf(msg2, sizeof msg2, "%s", err.msg);
    /* F of rank 2 at splat 3: the splat flattens to nothing */
    for (int i = 0; i < s.n; i++) F[9 * i] = F[9 * i + 4] = F[9 * i + 8] = 1;
    F[9 * 3 + 8] = 0;
    int rc4 = rk_splats_write(out, &s, NULL, F, &err);
    int named4 = rc4 != 0 && strstr(err.msg, "splat 3") && strstr(err.msg, "singular");
    char msg4[1024];
    snprintf(msg4, sizeof msg4, "%s", err.msg);
    /* a non-finite centre */
    double *x = malloc(3 * (size_t)s.n * sizeof *x);
    memcpy(x, s.X, 3 * (size_t)s.n * sizeof *x);
    x[3 * 4 + 1] = INFINITY;
    int rc3 = rk_splats_write(out, &s, x, NULL, &err);
    int named3 = rc3 != 0 && strstr(err.msg, "splat 4");
    free(F), free(x);
    rk_splats_free(&s);
    CHECK(named, "bad path: rc %d, %s", rc, err.msg);
    CHECK(!file_exists(bad), "a file was left at %s", bad);
    CHECK(named2, "collapsed splat: %s", msg2);
    CHECK(named3, "non-finite centre: %s", err.msg);
    CHECK(named4, "flattened splat: %s", msg4);
    CHECK(!file_exists(out) && files_starting("w_collapsed") == 0, "the failed write left a file behind");
    printf("# collapsed: %s\n# flattened: %s\n", msg2, msg4);
}

int main(void)
{
    RUN(reads_the_donut);
    RUN(donut_round_trip);
    RUN(synthetic_round_trip);
    RUN(synthetic_identity);
    RUN(deformation);
    RUN(pure_rotation);
    RUN(sh_rotation);
    RUN(plain_point_cloud);
    RUN(read_errors);
    RUN(corrupt_files);
    RUN(write_errors);
    remove_scratch();
    return test_finish();
}
