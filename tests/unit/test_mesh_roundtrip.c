/* Every tet format round-trips: through romkit's own writers (ASCII and binary) and through
 * hand-written variants (test_mesh_formats.h) of the layouts romkit does not write. The
 * loaded mesh must have the same tets, in order, with the same corner coordinates and tags. */
#include "testlib.h"
#include "test_mesh_formats.h"

/* armadillo with tags 1..3 in runs of varying length (so Gmsh gets several blocks). */
static int tagged_mesh(rk_mesh *m, rk_error *err)
{
    if (rk_mesh_load(test_data("meshes/armadillo_4k.node"), RK_MESH_KEEP_FLAT, m, NULL, err)) return -1;
    m->tet_tag = malloc(sizeof(int) * (size_t)m->nt);
    for (int t = 0; t < m->nt; t++) m->tet_tag[t] = 1 + (t / 7 + t / 100) % 3;
    return 0;
}

/* Writes with `write`, loads back and compares. */
#define ROUND_TRIP(suffix, write_call, as_float, tags)                                       \
    do {                                                                                    \
        char path[256], why[256];                                                           \
        tmp_path(path, sizeof path, suffix);                                                \
        int wrc = (write_call);                                                             \
        rk_mesh back;                                                                       \
        rk_mesh_report rep;                                                                 \
        int lrc = wrc == 0 ? rk_mesh_load(path, RK_MESH_KEEP_FLAT, &back, &rep, &err) : -1; \
        remove(path);                                                                       \
        CHECK(wrc == 0, "writing %s failed: %s", suffix, err.msg);                          \
        CHECK(lrc == 0, "loading %s failed: %s", suffix, err.msg);                          \
        int same = same_mesh(&m, &back, as_float, tags, why, sizeof why);                   \
        int reo = rep.reoriented;                                                           \
        rk_mesh_free(&back);                                                                \
        CHECK(same, "%s: %s", suffix, why);                                                 \
        CHECK(reo == 0, "%s: %d reoriented", suffix, reo);                                  \
    } while (0)

TEST(own_writers_round_trip)
{
    rk_error err;
    rk_mesh m;
    CHECK_OK(tagged_mesh(&m, &err));
    ROUND_TRIP(".msh", rk_mesh_write(path, &m, NULL, &err), 0, 1);
    ROUND_TRIP(".msh", rk_mesh_write_binary(path, &m, NULL, &err), 0, 1);
    ROUND_TRIP(".vtk", rk_mesh_write(path, &m, NULL, &err), 0, 1);
    ROUND_TRIP(".vtk", rk_mesh_write_binary(path, &m, NULL, &err), 0, 1);
    ROUND_TRIP(".mesh", rk_mesh_write(path, &m, NULL, &err), 0, 1);
    rk_mesh_free(&m);
}

TEST(tetgen_writer_round_trips_both_files)
{
    rk_error err;
    rk_mesh m, back;
    CHECK_OK(tagged_mesh(&m, &err));
    char stem[256], node[300], ele[300], why[256];
    tmp_path(stem, sizeof stem, "");
    snprintf(node, sizeof node, "%s.node", stem);
    snprintf(ele, sizeof ele, "%s.ele", stem);
    int wrc = rk_mesh_write(node, &m, NULL, &err);
    int lrc = wrc == 0 ? rk_mesh_load(ele, RK_MESH_KEEP_FLAT, &back, NULL, &err) : -1;
    remove(stem);
    remove(node);
    remove(ele);
    CHECK(wrc == 0 && lrc == 0, "%s", err.msg);
    int same = same_mesh(&m, &back, 0, 1, why, sizeof why);
    rk_mesh_free(&back);
    rk_mesh_free(&m);
    CHECK(same, "%s", why);
}

TEST(untagged_mesh_stays_untagged)
{
    rk_error err;
    rk_mesh m;
    CHECK_OK(rk_mesh_load(test_data("meshes/octopus-low.mesh"), RK_MESH_KEEP_FLAT, &m, NULL, &err));
    CHECK(m.tet_tag == NULL, "octopus has all-zero refs: expected no tags");
    const char *suffixes[] = {".msh", ".vtk", ".mesh"};
    for (int i = 0; i < 3; i++) {
        char path[256];
        rk_mesh back;
        tmp_path(path, sizeof path, suffixes[i]);
        int rc = rk_mesh_write(path, &m, NULL, &err) || rk_mesh_load(path, RK_MESH_KEEP_FLAT, &back, NULL, &err);
        remove(path);
        CHECK(rc == 0, "%s", err.msg);
        int tagged = back.tet_tag != NULL;
        rk_mesh_free(&back);
        CHECK(!tagged, "%s came back with tags", suffixes[i]);
    }
    rk_mesh_free(&m);
}

TEST(large_binary_mesh_round_trips)
{
    rk_error err;
    rk_mesh m;
    CHECK_OK(rk_mesh_load(test_data("meshes/dinosaur_bin.msh"), RK_MESH_KEEP_FLAT, &m, NULL, &err));
    ROUND_TRIP(".msh", rk_mesh_write_binary(path, &m, NULL, &err), 0, 1);
    ROUND_TRIP(".vtk", rk_mesh_write_binary(path, &m, NULL, &err), 0, 1);
    rk_mesh_free(&m);
}

TEST(gmsh_variants)
{
    rk_error err;
    rk_mesh m;
    CHECK_OK(tagged_mesh(&m, &err));
    ROUND_TRIP(".msh", write_gmsh22_ascii(path, &m), 0, 1);
    ROUND_TRIP(".msh", write_gmsh22_binary(path, &m, 0), 0, 1);
    ROUND_TRIP(".msh", write_gmsh22_binary(path, &m, 1), 0, 1);
    ROUND_TRIP(".msh", write_gmsh41_variant(path, &m, 0), 0, 1);
    ROUND_TRIP(".msh", write_gmsh41_variant(path, &m, 1), 0, 1);
    rk_mesh_free(&m);
}

TEST(medit_tetgen_vtk_variants)
{
    rk_error err;
    rk_mesh m;
    CHECK_OK(tagged_mesh(&m, &err));
    ROUND_TRIP(".mesh", write_medit_variant(path, &m), 0, 1);
    ROUND_TRIP(".vtk", write_vtk51(path, &m, 0), 0, 1);
    ROUND_TRIP(".vtk", write_vtk51(path, &m, 1), 0, 1);
    ROUND_TRIP(".vtk", write_vtk_float(path, &m, 0), 1, 0);
    ROUND_TRIP(".vtk", write_vtk_float(path, &m, 1), 1, 0);

    char stem[256], node[300], ele[300], why[256];
    tmp_path(stem, sizeof stem, "");
    snprintf(node, sizeof node, "%s.node", stem);
    snprintf(ele, sizeof ele, "%s.ele", stem);
    rk_mesh back;
    int rc = write_tetgen_1based(stem, &m) || rk_mesh_load(node, RK_MESH_KEEP_FLAT, &back, NULL, &err);
    remove(stem);
    remove(node);
    remove(ele);
    CHECK(rc == 0, "1-based TetGen: %s", err.msg);
    int same = same_mesh(&m, &back, 0, 1, why, sizeof why);
    rk_mesh_free(&back);
    rk_mesh_free(&m);
    CHECK(same, "1-based TetGen: %s", why);
}

TEST(deformed_positions_are_written)
{
    rk_error err;
    rk_mesh m, back;
    CHECK_OK(rk_mesh_load(test_data("meshes/octopus-low.mesh"), RK_MESH_KEEP_FLAT, &m, NULL, &err));
    double *x = malloc(sizeof(double) * 3 * (size_t)m.nv);
    for (int i = 0; i < 3 * m.nv; i++) x[i] = 2 * m.X[i] + 1;
    char path[256];
    tmp_path(path, sizeof path, ".vtk");
    int rc = rk_mesh_write(path, &m, x, &err) || rk_mesh_load(path, RK_MESH_KEEP_FLAT, &back, NULL, &err);
    remove(path);
    CHECK(rc == 0, "%s", err.msg);
    int ok = back.nv == m.nv;
    for (int i = 0; ok && i < 3 * m.nv; i++) ok = back.X[i] == x[i];
    free(x);
    rk_mesh_free(&back);
    rk_mesh_free(&m);
    CHECK(ok, "deformed positions not written");
}

int main(void)
{
    RUN(own_writers_round_trip);
    RUN(tetgen_writer_round_trips_both_files);
    RUN(untagged_mesh_stays_untagged);
    RUN(large_binary_mesh_round_trips);
    RUN(gmsh_variants);
    RUN(medit_tetgen_vtk_variants);
    RUN(deformed_positions_are_written);
    return test_finish();
}
