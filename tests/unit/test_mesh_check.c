/* rk_mesh_check, rk_mesh_box, rk_mesh_boundary, rk_mesh_transform and the boundary writers. */
#include "testlib.h"
#include "test_mesh_formats.h"

/* A mesh from literal arrays (copied, so rk_mesh_free works). */
static rk_mesh make_mesh(int nv, const double *X, int nt, const int *tets)
{
    rk_mesh m = {nv, nt, malloc(sizeof(double) * 3 * (size_t)nv), malloc(sizeof(int) * 4 * (size_t)nt), NULL};
    memcpy(m.X, X, sizeof(double) * 3 * (size_t)nv);
    memcpy(m.tets, tets, sizeof(int) * 4 * (size_t)nt);
    return m;
}

static const double unit_tet[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};

TEST(regular_tet_has_quality_one)
{
    const double s = 1 / sqrt(2.0);
    double X[] = {1, 0, -s, -1, 0, -s, 0, 1, s, 0, -1, s};
    double q = rk_tet_radius_ratio(X, X + 3, X + 6, X + 9);
    CHECK_CLOSE(q, 1.0, 1e-12);
    CHECK_CLOSE(rk_tet_signed_volume(unit_tet, unit_tet + 3, unit_tet + 6, unit_tet + 9), 1.0 / 6, 1e-15);
    /* The corner tet of a cube: 3 * r_in / r_out = 3 (3 - sqrt 3) / 6 / (sqrt 3 / 2). */
    double expect = 3 * ((3 - sqrt(3.0)) / 6) / (sqrt(3.0) / 2);
    CHECK_CLOSE(rk_tet_radius_ratio(unit_tet, unit_tet + 3, unit_tet + 6, unit_tet + 9), expect, 1e-12);
}

TEST(inverted_tet_is_reoriented_and_counted)
{
    rk_error err;
    rk_mesh_report rep;
    int tets[] = {0, 1, 2, 3, 0, 2, 1, 3}; /* the second is the first, inverted: two tets, same place */
    double X[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    rk_mesh m = make_mesh(4, X, 2, tets);
    CHECK_OK(rk_mesh_check(&m, "test", &rep, &err));
    int *t = m.tets + 4;
    double v = rk_tet_signed_volume(m.X + 3 * t[0], m.X + 3 * t[1], m.X + 3 * t[2], m.X + 3 * t[3]);
    int first_untouched = m.tets[0] == 0 && m.tets[1] == 1 && m.tets[2] == 2 && m.tets[3] == 3;
    rk_mesh_free(&m);
    CHECK(rep.reoriented == 1, "reoriented %d", rep.reoriented);
    CHECK(v > 0 && first_untouched, "volume after %g", v);
    CHECK_CLOSE(rep.min_volume, 1.0 / 6, 1e-15);
}

TEST(degenerate_tet_is_rejected_by_index)
{
    rk_error err;
    double X[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 0};
    int tets[] = {0, 1, 2, 3, 0, 1, 4, 2}; /* tet 1 is flat: all in z = 0 */
    rk_mesh m = make_mesh(5, X, 2, tets);
    int rc = rk_mesh_check(&m, "flat.mesh", NULL, &err);
    rk_mesh_free(&m);
    CHECK(rc != 0, "flat tet accepted");
    CHECK(strstr(err.msg, "flat.mesh: tet 1 ") && strstr(err.msg, "degenerate"), "message: %s", err.msg);

    int twice[] = {0, 1, 2, 2};
    m = make_mesh(5, X, 1, twice);
    rc = rk_mesh_check(&m, "twice", NULL, &err);
    rk_mesh_free(&m);
    CHECK(rc != 0 && strstr(err.msg, "tet 0") && strstr(err.msg, "twice"), "message: %s", err.msg);

    /* Tiny but not flat relative to the mesh size: kept. */
    double Y[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0.5, 0.5, 1e-9};
    int small[] = {0, 1, 2, 3, 0, 1, 2, 4};
    m = make_mesh(5, Y, 2, small);
    rc = rk_mesh_check(&m, "small", NULL, &err);
    rk_mesh_free(&m);
    CHECK(rc == 0, "a small, valid tet was rejected: %s", err.msg);
}

TEST(bad_indices_and_coordinates_are_rejected)
{
    rk_error err;
    double X[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    int out[] = {0, 1, 2, 4};
    rk_mesh m = make_mesh(4, X, 1, out);
    int rc = rk_mesh_check(&m, "idx", NULL, &err);
    rk_mesh_free(&m);
    CHECK(rc != 0 && strstr(err.msg, "idx: tet 0 references vertex 4"), "message: %s", err.msg);

    int ok[] = {0, 1, 2, 3};
    X[4] = NAN;
    m = make_mesh(4, X, 1, ok);
    rc = rk_mesh_check(&m, "nan", NULL, &err);
    rk_mesh_free(&m);
    CHECK(rc != 0 && strstr(err.msg, "vertex 1") && strstr(err.msg, "non-finite"), "message: %s", err.msg);

    m = make_mesh(4, unit_tet, 0, ok);
    rc = rk_mesh_check(&m, "empty", NULL, &err);
    rk_mesh_free(&m);
    CHECK(rc != 0 && strstr(err.msg, "no tetrahedra"), "message: %s", err.msg);
}

TEST(unused_vertices_are_removed_and_components_counted)
{
    rk_error err;
    rk_mesh_report rep;
    /* Two separate tets; vertex 2 and vertex 7 unused. */
    double X[] = {0, 0, 0, 1, 0, 0, 9, 9, 9, 0, 1, 0, 0, 0, 1, 5, 0, 0, 6, 0, 0, 8, 8, 8, 5, 1, 0, 5, 0, 1};
    int tets[] = {0, 1, 3, 4, 5, 6, 8, 9};
    rk_mesh m = make_mesh(10, X, 2, tets);
    CHECK_OK(rk_mesh_check(&m, "two", &rep, &err));
    int expect_tets[] = {0, 1, 2, 3, 4, 5, 6, 7};
    int same = memcmp(m.tets, expect_tets, sizeof expect_tets) == 0;
    double x6 = m.X[3 * 6], x2 = m.X[3 * 2 + 1];
    int nv = m.nv;
    rk_mesh_free(&m);
    CHECK(rep.unused_removed == 2 && nv == 8, "removed %d, nv %d", rep.unused_removed, nv);
    CHECK(same, "tets not remapped");
    CHECK(x6 == 5 && x2 == 1, "coordinates not moved with their vertices");
    CHECK(rep.components == 2, "components %d", rep.components);
    CHECK(rep.bbox_min[0] == 0 && rep.bbox_max[0] == 6 && rep.bbox_max[2] == 1, "bbox excludes unused vertices");
}

/* Every face of the box's tets, counted by sorted vertex triple. */
static int cmp3(const void *a, const void *b)
{
    const int *x = a, *y = b;
    for (int k = 0; k < 3; k++)
        if (x[k] != y[k]) return x[k] < y[k] ? -1 : 1;
    return 0;
}

TEST(box_is_conforming_positive_and_exact)
{
    rk_error err;
    rk_mesh m;
    rk_mesh_report rep;
    const double size[3] = {1.5, 2, 3};
    const int cells[3] = {3, 4, 5};
    CHECK_OK(rk_mesh_box(size, cells, &m, &err));
    CHECK(m.nv == 4 * 5 * 6 && m.nt == 6 * 60, "%d vertices %d tets", m.nv, m.nt);
    double total = 0;
    int negative = 0;
    for (int t = 0; t < m.nt; t++) {
        const int *v = m.tets + 4 * t;
        double vol = rk_tet_signed_volume(m.X + 3 * v[0], m.X + 3 * v[1], m.X + 3 * v[2], m.X + 3 * v[3]);
        negative += vol <= 0;
        total += vol;
    }
    CHECK(negative == 0, "%d tets not positively oriented", negative);
    CHECK_CLOSE(total, 1.5 * 2 * 3, 1e-12);

    /* Conformity: every face is shared by 1 (boundary) or 2 (interior) tets, and the number
     * of single faces is what the 2 * (3*4 + 4*5 + 3*5) boundary quads split in 2 give. */
    int nf = 4 * m.nt, *faces = malloc(sizeof(int) * 3 * (size_t)nf);
    for (int t = 0; t < m.nt; t++)
        for (int l = 0; l < 4; l++) {
            int *f = faces + 3 * (4 * t + l), n = 0;
            for (int k = 0; k < 4; k++)
                if (k != l) f[n++] = m.tets[4 * t + k];
            for (int i = 1; i < 3; i++)
                for (int j = i; j > 0 && f[j - 1] > f[j]; j--) {
                    int swap = f[j];
                    f[j] = f[j - 1];
                    f[j - 1] = swap;
                }
        }
    qsort(faces, (size_t)nf, 3 * sizeof(int), cmp3);
    int single = 0, pairs = 0, more = 0;
    for (int i = 0; i < nf;) {
        int j = i + 1;
        while (j < nf && cmp3(faces + 3 * i, faces + 3 * j) == 0) j++;
        single += j - i == 1, pairs += j - i == 2, more += j - i > 2;
        i = j;
    }
    free(faces);
    int quads = 2 * (3 * 4 + 4 * 5 + 3 * 5);
    CHECK(more == 0 && single == 2 * quads && 2 * pairs + single == nf, "%d boundary, %d interior, %d over-shared faces",
          single, pairs, more);

    int *tris, nb;
    CHECK_OK(rk_mesh_boundary(&m, &tris, &nb, &err));
    rk_surface s = {m.nv, nb, m.X, tris};
    double enclosed = rk_surface_volume(&s);
    int closed = rk_surface_check(&s, "box boundary", &err) == 0;
    free(tris);
    CHECK(nb == 2 * quads, "boundary has %d faces", nb);
    CHECK(closed, "%s", err.msg);
    CHECK_CLOSE(enclosed, 9.0, 1e-12);

    CHECK_OK(rk_mesh_check(&m, "box", &rep, &err));
    rk_mesh_free(&m);
    CHECK(rep.reoriented == 0 && rep.components == 1 && rep.unused_removed == 0, "box report: %d reoriented, %d components",
          rep.reoriented, rep.components);
}

TEST(box_rejects_bad_arguments)
{
    rk_error err;
    rk_mesh m;
    const double size[3] = {1, 1, 1}, bad_size[3] = {1, 0, 1};
    const int cells[3] = {1, 1, 1}, bad_cells[3] = {1, 0, 1}, huge[3] = {2000, 2000, 2000};
    CHECK(rk_mesh_box(bad_size, cells, &m, &err) != 0, "zero size accepted");
    CHECK(rk_mesh_box(size, bad_cells, &m, &err) != 0, "zero cells accepted");
    CHECK(rk_mesh_box(size, huge, &m, &err) != 0 && strstr(err.msg, "too many"), "message: %s", err.msg);
}

TEST(transform_scales_then_translates)
{
    rk_error err;
    rk_mesh m;
    const double size[3] = {1, 1, 1}, shift[3] = {1, 2, 3};
    const int cells[3] = {1, 1, 1};
    CHECK_OK(rk_mesh_box(size, cells, &m, &err));
    rk_mesh_transform(&m, 2, shift);
    rk_mesh_report rep;
    CHECK_OK(rk_mesh_check(&m, "box", &rep, &err));
    rk_mesh_free(&m);
    CHECK(rep.bbox_min[0] == 1 && rep.bbox_min[2] == 3 && rep.bbox_max[1] == 4, "bbox %g %g %g", rep.bbox_min[0],
          rep.bbox_min[2], rep.bbox_max[1]);
    CHECK_CLOSE(rep.min_volume, 8.0 / 6, 1e-12);
}

TEST(boundary_surface_writers_use_deformed_positions)
{
    rk_error err;
    rk_mesh m;
    CHECK_OK(rk_mesh_load(test_data("meshes/bunny_19k.msh"), &m, NULL, &err));
    double *x = malloc(sizeof(double) * 3 * (size_t)m.nv);
    for (int i = 0; i < m.nv; i++) {
        x[3 * i] = 2 * m.X[3 * i];
        x[3 * i + 1] = m.X[3 * i + 1];
        x[3 * i + 2] = m.X[3 * i + 2];
    }
    double vol = 0;
    for (int t = 0; t < m.nt; t++) {
        const int *v = m.tets + 4 * t;
        vol += rk_tet_signed_volume(x + 3 * v[0], x + 3 * v[1], x + 3 * v[2], x + 3 * v[3]);
    }
    int *tris, nb;
    CHECK_OK(rk_mesh_boundary(&m, &tris, &nb, &err));
    free(tris);
    const char *suffixes[] = {".obj", ".ply", ".off"};
    for (int i = 0; i < 3; i++) {
        char path[256];
        rk_surface s;
        tmp_path(path, sizeof path, suffixes[i]);
        int rc = rk_mesh_write(path, &m, x, &err) || rk_surface_load(path, &s, &err) ||
                 rk_surface_check(&s, path, &err);
        remove(path);
        CHECK(rc == 0, "%s", err.msg);
        double enclosed = rk_surface_volume(&s);
        int nf = s.nf;
        rk_surface_free(&s);
        CHECK(nf == nb, "%s: %d faces, boundary has %d", suffixes[i], nf, nb);
        CHECK_CLOSE(enclosed, vol, 1e-10);
    }
    free(x);
    rk_mesh_free(&m);
}

int main(void)
{
    RUN(regular_tet_has_quality_one);
    RUN(inverted_tet_is_reoriented_and_counted);
    RUN(degenerate_tet_is_rejected_by_index);
    RUN(bad_indices_and_coordinates_are_rejected);
    RUN(unused_vertices_are_removed_and_components_counted);
    RUN(box_is_conforming_positive_and_exact);
    RUN(box_rejects_bad_arguments);
    RUN(transform_scales_then_translates);
    RUN(boundary_surface_writers_use_deformed_positions);
    return test_finish();
}
