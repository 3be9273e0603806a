/* rk_mesh_check (slivers and flat tets included), rk_mesh_box, rk_mesh_boundary, rk_mesh_transform
 * and the boundary writers. */
#include "testlib.h"
#include "test_mesh_formats.h"

static const double unit_tet[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};

/* |a - b| <= tol |b|: CHECK_CLOSE's tolerance is absolute below 1, too loose for tiny volumes. */
#define CHECK_REL(a, b, tol) \
    CHECK(fabs((a) - (b)) <= (tol) * fabs(b), "%s = %.12g, expected %.12g (relative %g)", #a, (a), (b), (tol))

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
    CHECK_OK(rk_mesh_check(&m, "test", RK_MESH_KEEP_FLAT, &rep, &err));
    int *t = m.tets + 4;
    double v = rk_tet_signed_volume(m.X + 3 * t[0], m.X + 3 * t[1], m.X + 3 * t[2], m.X + 3 * t[3]);
    int first_untouched = m.tets[0] == 0 && m.tets[1] == 1 && m.tets[2] == 2 && m.tets[3] == 3;
    rk_mesh_free(&m);
    CHECK(rep.reoriented == 1, "reoriented %d", rep.reoriented);
    CHECK(v > 0 && first_untouched, "volume after %g", v);
    CHECK_CLOSE(rep.min_volume, 1.0 / 6, 1e-15);
}

/* Tet 1 is flat (all four vertices in z = 0, volume exactly 0); vertex 4 only it uses, and it
 * lies outside the rest, so dropping it shrinks the bounding box. Vertex 5 is used by no tet. */
static const double flat_X[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 2, 1, 0, 5, 5, 5};
static const int flat_tets[] = {0, 1, 2, 3, 0, 1, 4, 2};

TEST(flat_tet_is_kept_and_listed_when_converting)
{
    rk_error err;
    rk_mesh_report rep;
    rk_mesh m = make_mesh(6, flat_X, 2, flat_tets);
    CHECK_OK(rk_mesh_check(&m, "flat.mesh", RK_MESH_KEEP_FLAT, &rep, &err));
    int intact = m.nt == 2 && m.nv == 5 && memcmp(m.tets, flat_tets, sizeof flat_tets) == 0;
    rk_mesh_free(&m);
    CHECK(intact, "the conversion changed the tets");
    CHECK(rep.slivers == 1 && rep.flat == 1 && rep.flat_dropped == 0 && rep.orphans_removed == 0,
          "slivers %d, flat %d, dropped %d, orphans %d", rep.slivers, rep.flat, rep.flat_dropped, rep.orphans_removed);
    CHECK(rep.nlisted == 1 && rep.listed[0].tet == 1 && rep.listed[0].flat && rep.listed[0].volume == 0 &&
              rep.listed[0].v[2] == 4,
          "listed %d: tet %d", rep.nlisted, rep.listed[0].tet);
    CHECK(rep.unused_removed == 1 && rep.min_volume == 0 && rep.min_quality == 0, "unused %d, min volume %g",
          rep.unused_removed, rep.min_volume);
    CHECK(rep.bbox_max[0] == 2, "bounding box ends at x = %g", rep.bbox_max[0]);
    CHECK_REL(rep.sliver_volume, 1e-12 * pow(sqrt(4 + 1 + 1), 3), 1e-12);
}

TEST(flat_tet_and_its_own_vertices_are_dropped_when_simulating)
{
    rk_error err;
    rk_mesh_report rep;
    rk_mesh m = make_mesh(6, flat_X, 2, flat_tets);
    m.tet_tag = malloc(2 * sizeof(int));
    m.tet_tag[0] = 7;
    m.tet_tag[1] = 9;
    CHECK_OK(rk_mesh_check(&m, "flat.mesh", RK_MESH_DROP_FLAT, &rep, &err));
    int kept = m.nt == 1 && m.nv == 4 && memcmp(m.tets, flat_tets, 4 * sizeof(int)) == 0 && m.tet_tag[0] == 7;
    rk_mesh_free(&m);
    CHECK(kept, "expected tet 0 alone, on vertices 0..3, with its tag");
    CHECK(rep.flat == 1 && rep.flat_dropped == 1 && rep.orphans_removed == 1 && rep.unused_removed == 1,
          "flat %d, dropped %d, orphans %d, unused %d", rep.flat, rep.flat_dropped, rep.orphans_removed,
          rep.unused_removed);
    CHECK(rep.bbox_max[0] == 1 && rep.min_quality > 0.5, "box to x = %g, min quality %g", rep.bbox_max[0],
          rep.min_quality);
    CHECK_CLOSE(rep.min_volume, 1.0 / 6, 1e-15);

    /* Nothing left to simulate is an error; converting the same tet is not. */
    int one[] = {0, 1, 4, 2};
    m = make_mesh(6, flat_X, 1, one);
    int rc = rk_mesh_check(&m, "allflat.mesh", RK_MESH_DROP_FLAT, NULL, &err);
    rk_mesh_free(&m);
    CHECK(rc != 0 && strstr(err.msg, "allflat.mesh") && strstr(err.msg, "flat"), "message: %s", err.msg);
    m = make_mesh(6, flat_X, 1, one);
    rc = rk_mesh_check(&m, "allflat.mesh", RK_MESH_KEEP_FLAT, NULL, &err);
    rk_mesh_free(&m);
    CHECK(rc == 0, "converting a flat tet failed: %s", err.msg);
}

/* A flat tet inside the body: T = (a, b, c, d) with d inside triangle abc, all in z = 0; tet Q
 * below covers abc, three tets P above cover the fan abd, bcd, cad. Every face of T is shared. */
TEST(flat_tet_inside_the_body_stays_a_ghost)
{
    rk_error err;
    double X[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.25, 0.25, 0, 0.3, 0.3, 1, 0.3, 0.3, -1};
    int tets[] = {0, 1, 2, 3, 0, 1, 2, 5, 0, 1, 3, 4, 1, 2, 3, 4, 2, 0, 3, 4};
    int nf[2], closed[2], nt[2], nghost[2], ghosts = -1;
    for (int policy = 0; policy < 2; policy++) {
        rk_mesh_report rep;
        rk_mesh m = make_mesh(6, X, 5, tets);
        CHECK_OK(rk_mesh_check(&m, "inside", (rk_mesh_flat_policy)policy, &rep, &err));
        int *tris;
        int rc = rk_mesh_boundary(&m, &tris, &nf[policy], &err);
        rk_surface surf = {m.nv, nf[policy], m.X, rc ? NULL : tris};
        closed[policy] = rc == 0 && rk_surface_check(&surf, "inside boundary", &err) == 0;
        if (rc == 0) free(tris);
        nt[policy] = m.nt;
        nghost[policy] = m.nghost;
        if (policy) ghosts = rep.ghosts;
        rk_mesh_free(&m);
    }
    /* Dropped from the material, kept in the topology: the same six outer faces either way (ten,
     * a zero-width pocket among them, if T were simply gone). */
    CHECK(nt[0] == 5 && nghost[0] == 0 && nt[1] == 4 && nghost[1] == 1 && ghosts == 1, "tets %d %d, ghosts %d %d",
          nt[0], nt[1], nghost[0], nghost[1]);
    CHECK(nf[0] == 6 && nf[1] == 6 && closed[0] && closed[1], "boundary faces %d and %d: %s", nf[0], nf[1], err.msg);
    /* On the boundary instead (Q gone: abc is a boundary face), T is simply dropped. */
    rk_mesh_report rep;
    int open[] = {0, 1, 2, 3, 0, 1, 3, 4, 1, 2, 3, 4, 2, 0, 3, 4};
    rk_mesh m = make_mesh(6, X, 4, open);
    CHECK_OK(rk_mesh_check(&m, "open", RK_MESH_DROP_FLAT, &rep, &err));
    int n = m.nt, g = m.nghost;
    rk_mesh_free(&m);
    CHECK(n == 3 && g == 0 && rep.flat_dropped == 1 && rep.ghosts == 0, "%d tets, %d ghosts", n, g);
}

TEST(thin_sliver_is_kept_by_both_policies)
{
    rk_error err;
    /* Tet 1's apex is 1e-11 from its base: a sliver (volume 1.7e-12 <= 1e-12 diag^3 = 5.2e-12)
     * 30 times thicker than the rounding threshold (2.27e-13 x its longest edge, sqrt 2). */
    double X[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0.25, 0.25, -1e-11};
    int tets[] = {0, 1, 2, 3, 0, 2, 1, 4};
    for (int policy = 0; policy < 2; policy++) {
        rk_mesh_report rep;
        rk_mesh m = make_mesh(5, X, 2, tets);
        CHECK_OK(rk_mesh_check(&m, "thin", (rk_mesh_flat_policy)policy, &rep, &err));
        int nt = m.nt, nv = m.nv;
        rk_mesh_free(&m);
        CHECK(nt == 2 && nv == 5, "policy %d: %d tets, %d vertices", policy, nt, nv);
        CHECK(rep.slivers == 1 && rep.flat == 0 && rep.listed[0].tet == 1 && !rep.listed[0].flat,
              "policy %d: slivers %d, flat %d", policy, rep.slivers, rep.flat);
        CHECK_REL(rep.listed[0].volume, 1e-11 / 6, 1e-4);
    }
}

/* The unit corner tet with its apex at height h over the base, then scaled and moved. */
static int corner_is_flat(double h, double scale, double shift, double *thickness)
{
    double X[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.3, h};
    for (int i = 0; i < 12; i++) X[i] = scale * X[i] + shift;
    return rk_tet_is_flat(X, X + 3, X + 6, X + 9, thickness, NULL);
}

TEST(flatness_is_thickness_against_rounding)
{
    double h, size;
    /* The unit corner tet: its thinnest height is over its slanted face, 3V/A = 1/sqrt(3). */
    CHECK(!rk_tet_is_flat(unit_tet, unit_tet + 3, unit_tet + 6, unit_tet + 9, &h, &size), "unit tet is flat");
    CHECK_CLOSE(h, 1 / sqrt(3.0), 1e-15);
    CHECK_CLOSE(size, sqrt(2.0), 1e-15);
    /* The threshold is RK_MESH_FLAT = 1024 DBL_EPSILON = 2.3e-13 of the size (~1.2 here), whatever
     * the scale. */
    for (int e = -6; e <= 6; e += 3) {
        double scale = pow(10, e);
        CHECK(!corner_is_flat(1e-12, scale, 0, &h), "scale %g: thickness %g taken for flat", scale, h);
        CHECK_REL(h, 1e-12 * scale, 1e-3);
        CHECK(corner_is_flat(1e-13, scale, 0, &h), "scale %g: thickness %g taken for a sliver", scale, h);
        CHECK(corner_is_flat(0, scale, 0, &h), "scale %g: flat tet not flat", scale);
    }
    /* The same 1e-12 thick tet a kilometre from the origin: its coordinates are rounded to
     * 1.1e-13 there, so its thickness is noise. */
    CHECK(corner_is_flat(1e-12, 1, 1000, &h), "thickness %g at 1 km taken for a sliver", h);
    /* Collinear and coincident vertices are flat (0/0 thickness). */
    double line[12] = {0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3}, same[12] = {1, 2, 3, 1, 2, 3, 1, 2, 3, 1, 2, 3};
    CHECK(rk_tet_is_flat(line, line + 3, line + 6, line + 9, NULL, NULL), "collinear tet not flat");
    CHECK(rk_tet_is_flat(same, same + 3, same + 6, same + 9, NULL, NULL), "coincident tet not flat");
}

TEST(vertex_used_twice_is_still_an_error)
{
    rk_error err;
    int twice[] = {0, 1, 2, 2};
    for (int policy = 0; policy < 2; policy++) {
        rk_mesh m = make_mesh(4, unit_tet, 1, twice);
        int rc = rk_mesh_check(&m, "twice.mesh", (rk_mesh_flat_policy)policy, NULL, &err);
        rk_mesh_free(&m);
        CHECK(rc != 0 && strstr(err.msg, "twice.mesh: tet 0 ") && strstr(err.msg, "vertex 2 twice"), "message: %s",
              err.msg);
    }

    /* Tiny but not flat relative to the mesh size: kept. */
    double Y[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0.5, 0.5, 1e-9};
    int small[] = {0, 1, 2, 3, 0, 1, 2, 4};
    rk_mesh m = make_mesh(5, Y, 2, small);
    int rc = rk_mesh_check(&m, "small", RK_MESH_DROP_FLAT, NULL, &err);
    int nt = m.nt;
    rk_mesh_free(&m);
    CHECK(rc == 0 && nt == 2, "a small, valid tet was rejected: %s", err.msg);
}

TEST(bad_indices_and_coordinates_are_rejected)
{
    rk_error err;
    double X[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    int out[] = {0, 1, 2, 4};
    rk_mesh m = make_mesh(4, X, 1, out);
    int rc = rk_mesh_check(&m, "idx", RK_MESH_KEEP_FLAT, NULL, &err);
    rk_mesh_free(&m);
    CHECK(rc != 0 && strstr(err.msg, "idx: tet 0 references vertex 4"), "message: %s", err.msg);

    int ok[] = {0, 1, 2, 3};
    X[4] = NAN;
    m = make_mesh(4, X, 1, ok);
    rc = rk_mesh_check(&m, "nan", RK_MESH_KEEP_FLAT, NULL, &err);
    rk_mesh_free(&m);
    CHECK(rc != 0 && strstr(err.msg, "vertex 1") && strstr(err.msg, "non-finite"), "message: %s", err.msg);

    m = make_mesh(4, unit_tet, 0, ok);
    rc = rk_mesh_check(&m, "empty", RK_MESH_KEEP_FLAT, NULL, &err);
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
    CHECK_OK(rk_mesh_check(&m, "two", RK_MESH_KEEP_FLAT, &rep, &err));
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

    CHECK_OK(rk_mesh_check(&m, "box", RK_MESH_KEEP_FLAT, &rep, &err));
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
    CHECK_OK(rk_mesh_check(&m, "box", RK_MESH_KEEP_FLAT, &rep, &err));
    rk_mesh_free(&m);
    CHECK(rep.bbox_min[0] == 1 && rep.bbox_min[2] == 3 && rep.bbox_max[1] == 4, "bbox %g %g %g", rep.bbox_min[0],
          rep.bbox_min[2], rep.bbox_max[1]);
    CHECK_CLOSE(rep.min_volume, 8.0 / 6, 1e-12);
}

TEST(boundary_surface_writers_use_deformed_positions)
{
    rk_error err;
    rk_mesh m;
    CHECK_OK(rk_mesh_load(test_data("meshes/bunny_19k.msh"), RK_MESH_KEEP_FLAT, &m, NULL, &err));
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
    RUN(flat_tet_is_kept_and_listed_when_converting);
    RUN(flat_tet_and_its_own_vertices_are_dropped_when_simulating);
    RUN(flat_tet_inside_the_body_stays_a_ghost);
    RUN(thin_sliver_is_kept_by_both_policies);
    RUN(flatness_is_thickness_against_rounding);
    RUN(vertex_used_twice_is_still_an_error);
    RUN(bad_indices_and_coordinates_are_rejected);
    RUN(unused_vertices_are_removed_and_components_counted);
    RUN(box_is_conforming_positive_and_exact);
    RUN(box_rejects_bad_arguments);
    RUN(transform_scales_then_translates);
    RUN(boundary_surface_writers_use_deformed_positions);
    return test_finish();
}
