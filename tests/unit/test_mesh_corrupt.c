/* Bad input never crashes a reader: every format, truncated at many offsets and with bytes
 * changed at random, either loads as a valid mesh or fails with a message naming the file.
 * Targeted corruptions check the message itself (line, byte offset, element index), that
 * huge counts fail before allocating, and that an inverted tet is repaired. Runs under
 * ASan/UBSan in `make test-sanitize`. */
#include "testlib.h"
#include "test_mesh_formats.h"

typedef enum { TET, SURFACE, POINTS } kind;

/* Whether a loaded mesh is valid: indices in range, every tet of volume >= 0 and, for a
 * simulation (flat tets dropped), of volume > 0 and not flat, with ghosts on existing vertices. */
static int valid_mesh(const rk_mesh *m, rk_mesh_flat_policy policy)
{
    int bad = m->nv <= 0 || m->nt <= 0;
    for (int i = 0; i < 4 * m->nt && !bad; i++) bad = m->tets[i] < 0 || m->tets[i] >= m->nv;
    for (int i = 0; i < 4 * m->nghost && !bad; i++) bad = m->ghost[i] < 0 || m->ghost[i] >= m->nv;
    for (int t = 0; t < m->nt && !bad; t++) {
        const int *v = m->tets + 4 * t;
        const double *a = m->X + 3 * v[0], *b = m->X + 3 * v[1], *c = m->X + 3 * v[2], *d = m->X + 3 * v[3];
        double vol = rk_tet_signed_volume(a, b, c, d);
        bad = policy == RK_MESH_DROP_FLAT ? !(vol > 0) || rk_tet_is_flat(a, b, c, d, NULL, NULL) : !(vol >= 0);
    }
    return !bad;
}

/* Loads `path` as `k`; 1 when the outcome is acceptable (valid result or a message naming
 * `name`), else 0 with the reason in why. A tet mesh is loaded for a conversion and for a
 * simulation. */
static int acceptable(const char *path, kind k, const char *name, char *why, size_t cap)
{
    rk_error err;
    err.msg[0] = '\0';
    int rc;
    if (k == TET) {
        rc = 0;
        for (int policy = 0; policy < 2 && rc == 0; policy++) {
            rk_mesh m;
            rk_mesh_report rep;
            rc = rk_mesh_load(path, (rk_mesh_flat_policy)policy, &m, &rep, &err);
            if (rc) break;
            int valid = valid_mesh(&m, (rk_mesh_flat_policy)policy);
            rk_mesh_free(&m);
            if (!valid) {
                snprintf(why, cap, "%s loaded into an invalid mesh (%s)", path, policy ? "simulation" : "conversion");
                return 0;
            }
        }
    } else if (k == SURFACE) {
        rk_surface s;
        rc = rk_surface_load(path, &s, &err);
        if (rc == 0) {
            rk_error ignored;
            rk_surface_check(&s, path, &ignored); /* may fail, must not crash */
            rk_surface_free(&s);
        }
    } else {
        double *X;
        int n;
        rc = rk_points_load(path, &X, &n, &err);
        if (rc == 0) free(X);
    }
    if (rc != 0 && !strstr(err.msg, name)) {
        snprintf(why, cap, "message does not name %s: %s", name, err.msg);
        return 0;
    }
    return 1;
}

static uint64_t rng_state = 12345;
static uint32_t rng(void)
{
    rng_state = rng_state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (uint32_t)(rng_state >> 33);
}

/* Bytes that steer parsers into interesting places. */
static unsigned char nasty_byte(void)
{
    static const char palette[] = "0123456789-+.eE \n\t$#nax/";
    uint32_t r = rng();
    if (r % 3 == 0) return (unsigned char)(rng() & 0xFF);
    if (r % 3 == 1) return (unsigned char)palette[rng() % (sizeof palette - 1)];
    static const unsigned char extremes[] = {0x00, 0xFF, 0x7F, 0x80};
    return extremes[rng() % 4];
}

/* Truncates `target` (inside a set of files that `load_path` loads) at every 1/20 of its
 * length and a few single-byte cuts, then applies `flips` random byte changes. */
static int torture(const char *target, const char *load_path, kind k, const char *name, int flips, char *why,
                   size_t cap)
{
    long n;
    unsigned char *orig = read_all(target, &n), *copy = malloc((size_t)n + 1);
    int ok = orig && copy;
    long cuts[24];
    int ncuts = 0;
    for (int i = 0; i < 20; i++) cuts[ncuts++] = n * i / 20;
    cuts[ncuts++] = n - 1;
    cuts[ncuts++] = n > 1 ? n - 2 : 0;
    cuts[ncuts++] = 1;
    for (int i = 0; ok && i < ncuts; i++) {
        write_all(target, orig, cuts[i]);
        if (!acceptable(load_path, k, name, why, cap)) {
            size_t len = strlen(why);
            snprintf(why + len, cap - len, " (truncated to %ld of %ld bytes)", cuts[i], n);
            ok = 0;
        }
    }
    for (int i = 0; ok && i < flips; i++) {
        memcpy(copy, orig, (size_t)n);
        int changes = 1 + (int)(rng() % 3);
        long at = 0;
        for (int c = 0; c < changes && n > 0; c++) {
            at = (long)(rng() % (uint32_t)n);
            copy[at] = nasty_byte();
        }
        write_all(target, copy, n);
        if (!acceptable(load_path, k, name, why, cap)) {
            size_t len = strlen(why);
            snprintf(why + len, cap - len, " (random change %d, last at byte %ld)", i, at);
            ok = 0;
        }
    }
    if (orig) write_all(target, orig, n);
    free(orig);
    free(copy);
    return ok;
}

/* A small tagged box with one vertex unused and sparse geometry: 27 vertices, 48 tets. */
static void small_mesh(rk_mesh *m)
{
    rk_error err;
    const double size[3] = {1, 2, 3};
    const int cells[3] = {2, 2, 2};
    rk_mesh_box(size, cells, m, &err);
    m->tet_tag = malloc(sizeof(int) * (size_t)m->nt);
    for (int t = 0; t < m->nt; t++) m->tet_tag[t] = 1 + t / 17;
}

typedef int (*mesh_writer)(const char *path, const rk_mesh *m);
static int own_ascii(const char *p, const rk_mesh *m) { rk_error e; return rk_mesh_write(p, m, NULL, &e); }
static int own_binary(const char *p, const rk_mesh *m) { rk_error e; return rk_mesh_write_binary(p, m, NULL, &e); }
static int g22_ascii(const char *p, const rk_mesh *m) { return write_gmsh22_ascii(p, m); }
static int g22_le(const char *p, const rk_mesh *m) { return write_gmsh22_binary(p, m, 0); }
static int g22_be(const char *p, const rk_mesh *m) { return write_gmsh22_binary(p, m, 1); }
static int g41_ascii(const char *p, const rk_mesh *m) { return write_gmsh41_variant(p, m, 0); }
static int g41_bin(const char *p, const rk_mesh *m) { return write_gmsh41_variant(p, m, 1); }
static int medit_var(const char *p, const rk_mesh *m) { return write_medit_variant(p, m); }
static int vtk51_ascii(const char *p, const rk_mesh *m) { return write_vtk51(p, m, 0); }
static int vtk51_bin(const char *p, const rk_mesh *m) { return write_vtk51(p, m, 1); }
static int vtkf_bin(const char *p, const rk_mesh *m) { return write_vtk_float(p, m, 1); }

TEST(tet_readers_survive_truncation_and_random_changes)
{
    static const struct {
        const char *name, *suffix;
        mesh_writer write;
    } formats[] = {
        {"gmsh 4.1 ascii", ".msh", own_ascii},  {"gmsh 4.1 binary", ".msh", own_binary},
        {"gmsh 2.2 ascii", ".msh", g22_ascii},  {"gmsh 2.2 binary LE", ".msh", g22_le},
        {"gmsh 2.2 binary BE", ".msh", g22_be}, {"gmsh 4.1 variant", ".msh", g41_ascii},
        {"gmsh 4.1 variant binary", ".msh", g41_bin}, {"medit", ".mesh", own_ascii},
        {"medit variant", ".mesh", medit_var}, {"vtk ascii", ".vtk", own_ascii},
        {"vtk binary", ".vtk", own_binary},    {"vtk 5.1 ascii", ".vtk", vtk51_ascii},
        {"vtk 5.1 binary", ".vtk", vtk51_bin}, {"vtk float binary", ".vtk", vtkf_bin},
    };
    rk_mesh m;
    small_mesh(&m);
    for (size_t f = 0; f < sizeof formats / sizeof formats[0]; f++) {
        char path[256], why[1400];
        tmp_path(path, sizeof path, formats[f].suffix);
        int ok = formats[f].write(path, &m) == 0 && acceptable(path, TET, path, why, sizeof why) &&
                 torture(path, path, TET, path, 250, why, sizeof why);
        remove(path);
        if (!ok) rk_mesh_free(&m);
        CHECK(ok, "%s: %s", formats[f].name, why);
    }
    /* TetGen: two files, each corrupted in turn; messages name the pair's stem. */
    char stem[256], node[300], ele[300], why[1400];
    tmp_path(stem, sizeof stem, "");
    snprintf(node, sizeof node, "%s.node", stem);
    snprintf(ele, sizeof ele, "%s.ele", stem);
    int ok = write_tetgen_1based(stem, &m) == 0 && torture(node, node, TET, stem, 150, why, sizeof why) &&
             torture(ele, node, TET, stem, 150, why, sizeof why);
    remove(stem);
    remove(node);
    remove(ele);
    rk_mesh_free(&m);
    CHECK(ok, "tetgen: %s", why);
}

TEST(real_files_survive_truncation)
{
    /* The test data itself, cut at every 1/20 (a few random changes too). */
    const char *files[] = {"meshes/dinosaur_bin.msh", "meshes/bunny_19k.msh", "meshes/octopus-low.mesh"};
    for (int i = 0; i < 3; i++) {
        char path[256], why[1400];
        long n;
        unsigned char *buf = read_all(test_data(files[i]), &n);
        CHECK(buf, "cannot read %s", files[i]);
        tmp_path(path, sizeof path, strrchr(files[i], '.'));
        write_all(path, buf, n);
        free(buf);
        int ok = torture(path, path, TET, path, 10, why, sizeof why);
        remove(path);
        CHECK(ok, "%s: %s", files[i], why);
    }
}

typedef int (*surface_writer)(const char *path, const rk_surface *s);
static int surf_own(const char *p, const rk_surface *s) { rk_error e; return rk_surface_write(p, s, &e); }
static int ply_ascii(const char *p, const rk_surface *s) { return write_ply_variant(p, s, 0); }
static int ply_be(const char *p, const rk_surface *s) { return write_ply_variant(p, s, 1); }
static int stl_ascii(const char *p, const rk_surface *s) { return write_stl_ascii(p, s); }

TEST(surface_and_point_readers_survive_truncation_and_random_changes)
{
    static const struct {
        const char *name, *suffix;
        surface_writer write;
    } formats[] = {
        {"obj", ".obj", surf_own}, {"off", ".off", surf_own}, {"stl binary", ".stl", surf_own},
        {"stl ascii", ".stl", stl_ascii}, {"ply binary LE", ".ply", surf_own}, {"ply ascii", ".ply", ply_ascii},
        {"ply binary BE", ".ply", ply_be},
    };
    rk_error err;
    rk_mesh m;
    rk_surface s = {0};
    const double size[3] = {1, 1, 1};
    const int cells[3] = {2, 1, 1};
    CHECK_OK(rk_mesh_box(size, cells, &m, &err));
    s.nv = m.nv;
    s.X = m.X;
    CHECK_OK(rk_mesh_boundary(&m, &s.tris, &s.nf, &err));
    int ok = 1;
    char why[1400];
    for (size_t f = 0; ok && f < sizeof formats / sizeof formats[0]; f++) {
        char path[256];
        tmp_path(path, sizeof path, formats[f].suffix);
        ok = formats[f].write(path, &s) == 0 && torture(path, path, SURFACE, path, 250, why, sizeof why);
        if (ok && formats[f].suffix[1] == 'p') ok = torture(path, path, POINTS, path, 100, why, sizeof why);
        remove(path);
        if (!ok) {
            size_t len = strlen(why);
            snprintf(why + len, sizeof why - len, " [%s]", formats[f].name);
        }
    }
    free(s.tris);
    rk_mesh_free(&m);
    CHECK(ok, "%s", why);
}

/* Writes text to a fresh temporary file with the suffix; path in out. */
static void text_file(char *out, size_t cap, const char *suffix, const char *text)
{
    tmp_path(out, cap, suffix);
    write_all(out, text, (long)strlen(text));
}

static const char *medit_head = "MeshVersionFormatted 1\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n";

TEST(messages_name_the_line)
{
    rk_error err;
    rk_mesh m;
    char path[256], text[1024], want[400];
    snprintf(text, sizeof text, "%sTetrahedra\n1\n1 2 3 999 0\nEnd\n", medit_head);
    text_file(path, sizeof path, ".mesh", text);
    int rc = rk_mesh_load(path, RK_MESH_KEEP_FLAT, &m, NULL, &err);
    remove(path);
    snprintf(want, sizeof want, "%s:11: tet 1 references vertex 999", path);
    CHECK(rc != 0 && strstr(err.msg, want), "message: %s", err.msg);

    /* A Gmsh element record one node short, reported with its element number and line. */
    rk_mesh box;
    const double size[3] = {1, 1, 1};
    const int cells[3] = {1, 1, 1};
    CHECK_OK(rk_mesh_box(size, cells, &box, &err));
    tmp_path(path, sizeof path, ".msh");
    rc = rk_mesh_write(path, &box, NULL, &err);
    rk_mesh_free(&box);
    CHECK(rc == 0, "%s", err.msg);
    long n;
    char *buf = (char *)read_all(path, &n);
    char *line = strstr(buf, "\n3 1 4 6\n");
    CHECK(line, "element block not found");
    for (int skip = 0; skip < 5; skip++) line = strchr(line + 1, '\n'); /* to the end of "4 a b c d" */
    while (*line != ' ') line--; /* drop " d" */
    memmove(line, strchr(line + 1, '\n'), strlen(strchr(line + 1, '\n')) + 1);
    int lineno = 1;
    for (char *c = buf; c < line; c++) lineno += *c == '\n';
    write_all(path, buf, (long)strlen(buf));
    free(buf);
    rc = rk_mesh_load(path, RK_MESH_KEEP_FLAT, &m, NULL, &err);
    remove(path);
    snprintf(want, sizeof want, "%s:%d: expected 4 node indices for tet element 4, got 3", path, lineno);
    CHECK(rc != 0 && strstr(err.msg, want), "message: %s (wanted %s)", err.msg, want);
}

TEST(binary_messages_name_the_byte_offset)
{
    rk_error err;
    rk_mesh m;
    char path[256];
    long n;
    tmp_path(path, sizeof path, ".msh");
    unsigned char *buf = read_all(test_data("meshes/dinosaur_bin.msh"), &n);
    CHECK(buf, "no data");
    write_all(path, buf, n / 2); /* cut inside the element records */
    free(buf);
    int rc = rk_mesh_load(path, RK_MESH_KEEP_FLAT, &m, NULL, &err);
    remove(path);
    char want[300];
    snprintf(want, sizeof want, "%s: byte ", path);
    CHECK(rc != 0 && strstr(err.msg, want) && strstr(err.msg, "truncated"), "message: %s", err.msg);
}

TEST(huge_counts_fail_before_allocating)
{
    rk_error err;
    rk_mesh m;
    rk_surface s;
    char path[256];
    struct {
        const char *suffix, *text;
    } cases[] = {
        {".mesh", "MeshVersionFormatted 1\nDimension 3\nVertices\n2000000000\n0 0 0 0\n"},
        {".msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1000000000000000 1 1000000000000000\n"},
        {".msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n268435455\n1 0 0 0\n"},
        {".vtk", "# vtk DataFile Version 3.0\nx\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 200000000 double\n0 0 0\n"},
        {".vtk", "# vtk DataFile Version 3.0\nx\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 double\n"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        text_file(path, sizeof path, cases[i].suffix, cases[i].text);
        int rc = rk_mesh_load(path, RK_MESH_KEEP_FLAT, &m, NULL, &err);
        remove(path);
        CHECK(rc != 0 && strstr(err.msg, path), "case %zu: %s", i, rc ? err.msg : "accepted");
        CHECK(strstr(err.msg, "count") || strstr(err.msg, "truncated") || strstr(err.msg, "too large"),
              "case %zu: %s", i, err.msg);
    }
    /* Binary headers with huge counts. */
    tmp_path(path, sizeof path, ".stl");
    unsigned char stl[84 + 50] = {0};
    stl[80] = stl[81] = stl[82] = stl[83] = 0xFF;
    write_all(path, stl, sizeof stl);
    int rc = rk_surface_load(path, &s, &err);
    remove(path);
    CHECK(rc != 0 && strstr(err.msg, path) && strstr(err.msg, "triangle count"), "stl: %s", err.msg);
    text_file(path, sizeof path, ".ply", "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                                         "property float y\nproperty float z\nend_header\n");
    double *X;
    int np;
    rc = rk_points_load(path, &X, &np, &err);
    remove(path);
    CHECK(rc != 0 && strstr(err.msg, "count"), "ply: %s", err.msg);
    /* The 4.1 binary node count patched to 2^60 in a file we write. */
    rk_mesh box;
    const double size[3] = {1, 1, 1};
    const int cells[3] = {1, 1, 1};
    CHECK_OK(rk_mesh_box(size, cells, &box, &err));
    tmp_path(path, sizeof path, ".msh");
    rk_mesh_write_binary(path, &box, NULL, &err);
    rk_mesh_free(&box);
    long n;
    unsigned char *buf = read_all(path, &n);
    long at = 0;
    while (at + 7 <= n && memcmp(buf + at, "$Nodes\n", 7) != 0) at++; /* binary: no strstr */
    CHECK(at + 7 + 16 <= n, "no $Nodes");
    buf[at + 7 + 8 + 7] = 0x10; /* the second size_t (numNodes), little-endian: its top byte */
    write_all(path, buf, n);
    free(buf);
    rc = rk_mesh_load(path, RK_MESH_KEEP_FLAT, &m, NULL, &err);
    remove(path);
    CHECK(rc != 0 && strstr(err.msg, "node count"), "msh binary: %s", err.msg);
}

TEST(non_finite_flat_repeated_and_inverted_tets_in_files)
{
    rk_error err;
    rk_mesh m;
    rk_mesh_report rep;
    char path[256], text[1024];
    snprintf(text, sizeof text, "MeshVersionFormatted 1\nDimension 3\nVertices\n4\n0 0 0 0\n1 nan 0 0\n0 1 0 0\n0 0 1 0\n"
                                "Tetrahedra\n1\n1 2 3 4 0\nEnd\n");
    text_file(path, sizeof path, ".mesh", text);
    int rc = rk_mesh_load(path, RK_MESH_KEEP_FLAT, &m, NULL, &err);
    remove(path);
    CHECK(rc != 0 && strstr(err.msg, path) && strstr(err.msg, "vertex 1") && strstr(err.msg, "non-finite"), "nan: %s",
          err.msg);

    /* A flat tet (tet 1, in z = 0) loads: kept as it is for a conversion, dropped (with vertex 5,
     * which only it uses) for a simulation. */
    snprintf(text, sizeof text, "%s1 1 0 0\nTetrahedra\n2\n1 2 3 4 0\n1 2 5 3 0\nEnd\n",
             "MeshVersionFormatted 1\nDimension 3\nVertices\n5\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n");
    text_file(path, sizeof path, ".mesh", text);
    rc = rk_mesh_load(path, RK_MESH_KEEP_FLAT, &m, &rep, &err);
    int kept = rc == 0 && m.nt == 2 && m.nv == 5 && m.tets[4] == 0 && m.tets[6] == 4 && rep.flat == 1;
    if (rc == 0) rk_mesh_free(&m);
    int rc2 = rk_mesh_load(path, RK_MESH_DROP_FLAT, &m, &rep, &err);
    int dropped = rc2 == 0 && m.nt == 1 && m.nv == 4 && rep.flat_dropped == 1 && rep.orphans_removed == 1;
    if (rc2 == 0) rk_mesh_free(&m);
    remove(path);
    CHECK(kept, "converting a flat tet: %s", rc ? err.msg : "changed");
    CHECK(dropped, "simulating a flat tet: %s", rc2 ? err.msg : "not dropped");

    /* A tet that uses a vertex twice is no tet: an error either way, naming the file and the tet. */
    snprintf(text, sizeof text, "%s1 1 0 0\nTetrahedra\n2\n1 2 3 4 0\n1 2 5 2 0\nEnd\n",
             "MeshVersionFormatted 1\nDimension 3\nVertices\n5\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n");
    text_file(path, sizeof path, ".mesh", text);
    rc = rk_mesh_load(path, RK_MESH_KEEP_FLAT, &m, NULL, &err);
    remove(path);
    CHECK(rc != 0 && strstr(err.msg, path) && strstr(err.msg, "tet 1 ") && strstr(err.msg, "twice"), "twice: %s",
          err.msg);

    /* The box with tet 5 inverted, through a Gmsh file: loads, 1 reoriented, all positive. */
    rk_mesh box;
    const double size[3] = {1, 1, 1};
    const int cells[3] = {2, 2, 2};
    CHECK_OK(rk_mesh_box(size, cells, &box, &err));
    int swap = box.tets[4 * 5 + 0];
    box.tets[4 * 5 + 0] = box.tets[4 * 5 + 1];
    box.tets[4 * 5 + 1] = swap;
    tmp_path(path, sizeof path, ".msh");
    rc = rk_mesh_write(path, &box, NULL, &err) || rk_mesh_load(path, RK_MESH_KEEP_FLAT, &m, &rep, &err);
    remove(path);
    rk_mesh_free(&box);
    CHECK(rc == 0, "%s", err.msg);
    int positive = 1;
    for (int t = 0; t < m.nt; t++) {
        const int *v = m.tets + 4 * t;
        positive &= rk_tet_signed_volume(m.X + 3 * v[0], m.X + 3 * v[1], m.X + 3 * v[2], m.X + 3 * v[3]) > 0;
    }
    rk_mesh_free(&m);
    CHECK(rep.reoriented == 1 && positive, "reoriented %d, all positive %d", rep.reoriented, positive);
}

int main(void)
{
    RUN(tet_readers_survive_truncation_and_random_changes);
    RUN(real_files_survive_truncation);
    RUN(surface_and_point_readers_survive_truncation_and_random_changes);
    RUN(messages_name_the_line);
    RUN(binary_messages_name_the_byte_offset);
    RUN(huge_counts_fail_before_allocating);
    RUN(non_finite_flat_repeated_and_inverted_tets_in_files);
    return test_finish();
}
