/* Surface readers (OBJ, OFF, STL, PLY), rk_surface_write and rk_surface_check. */
#include "testlib.h"
#include "test_mesh_formats.h"

static int write_text(const char *path, const char *text) { return write_all(path, text, (long)strlen(text)); }

/* Same faces in order with the same corner coordinates (float-rounded when as_float). */
static int same_surface(const rk_surface *a, const rk_surface *b, int as_float, char *why, size_t cap)
{
    if (a->nv != b->nv || a->nf != b->nf) {
        snprintf(why, cap, "counts %d/%d vs %d/%d", a->nv, a->nf, b->nv, b->nf);
        return 0;
    }
    for (int f = 0; f < a->nf; f++)
        for (int k = 0; k < 3; k++)
            for (int d = 0; d < 3; d++) {
                double x = a->X[3 * a->tris[3 * f + k] + d], y = b->X[3 * b->tris[3 * f + k] + d];
                if (as_float) x = (float)x, y = (float)y;
                if (x != y) {
                    snprintf(why, cap, "face %d corner %d: %.17g vs %.17g", f, k, x, y);
                    return 0;
                }
            }
    return 1;
}

#define SURFACE_ROUND_TRIP(suffix, write_call, as_float)                                 \
    do {                                                                                \
        char path[256], why[256];                                                       \
        rk_surface back;                                                                \
        tmp_path(path, sizeof path, suffix);                                            \
        int rc = (write_call) || rk_surface_load(path, &back, &err);                    \
        remove(path);                                                                   \
        CHECK(rc == 0, "%s: %s", suffix, err.msg);                                      \
        int same = same_surface(&s, &back, as_float, why, sizeof why);                  \
        int checked = rk_surface_check(&back, suffix, &err) == 0;                       \
        rk_surface_free(&back);                                                         \
        CHECK(same, "%s: %s", suffix, why);                                             \
        CHECK(checked, "%s", err.msg);                                                  \
    } while (0)

TEST(surface_formats_round_trip)
{
    rk_error err;
    rk_surface s;
    CHECK_OK(rk_surface_load(test_data("meshes/decimated-knight.off"), &s, &err));
    SURFACE_ROUND_TRIP(".obj", rk_surface_write(path, &s, &err), 0);
    SURFACE_ROUND_TRIP(".off", rk_surface_write(path, &s, &err), 0);
    SURFACE_ROUND_TRIP(".ply", rk_surface_write(path, &s, &err), 0);
    SURFACE_ROUND_TRIP(".ply", write_ply_variant(path, &s, 0), 0);
    SURFACE_ROUND_TRIP(".ply", write_ply_variant(path, &s, 1), 0);
    /* STL repeats corners per triangle: the reader welds them back (the knight's vertices
     * are distinct in float precision), so counts and corners match. */
    SURFACE_ROUND_TRIP(".stl", rk_surface_write(path, &s, &err), 1);
    SURFACE_ROUND_TRIP(".stl", write_stl_ascii(path, &s), 1);
    rk_surface_free(&s);
}

static const char *cube_obj =
    "# a unit cube with quads, texture and normal references, negative indices\n"
    "mtllib cube.mtl\no cube\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1 1.0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n"
    "usemtl gold\ns off\n"
    "f 1/1 4/2 3/3 2/1\n"            /* z = 0, normal -z */
    "f 5//1 6//1 7//1 8//1\n"        /* z = 1 */
    "f -8/1/1 -7/2/1 -3/3/1 -4/1/1\n" /* y = 0: 1 2 6 5 */
    "f 2 3 7 6\n"
    "f 3 4 8 7\n"
    "f 4 1 5 8\n";

TEST(obj_polygons_references_and_negative_indices)
{
    rk_error err;
    rk_surface s;
    char path[256];
    tmp_path(path, sizeof path, ".obj");
    write_text(path, cube_obj);
    int rc = rk_surface_load(path, &s, &err);
    remove(path);
    CHECK(rc == 0, "%s", err.msg);
    int nv = s.nv, nf = s.nf;
    int ok = rk_surface_check(&s, "cube", &err) == 0;
    double vol = rk_surface_volume(&s);
    rk_surface_free(&s);
    CHECK(nv == 8 && nf == 12, "%d vertices %d faces", nv, nf);
    CHECK(ok, "%s", err.msg);
    CHECK_CLOSE(vol, 1.0, 1e-15);
}

TEST(off_with_counts_on_the_header_line_and_colours)
{
    rk_error err;
    rk_surface s;
    char path[256];
    tmp_path(path, sizeof path, ".off");
    write_text(path, "COFF 8 6 12\n# vertices with colours\n"
                     "0 0 0 1 0 0 1\n1 0 0 1 0 0 1\n1 1 0 1 0 0 1\n0 1 0 1 0 0 1\n"
                     "0 0 1 1 0 0 1\n1 0 1 1 0 0 1\n1 1 1 1 0 0 1\n0 1 1 1 0 0 1\n"
                     "4 0 3 2 1 255 0 0\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n");
    int rc = rk_surface_load(path, &s, &err);
    remove(path);
    CHECK(rc == 0, "%s", err.msg);
    int nf = s.nf, ok = rk_surface_check(&s, "cube", &err) == 0;
    rk_surface_free(&s);
    CHECK(nf == 12 && ok, "%d faces, check: %s", nf, ok ? "ok" : err.msg);
}

TEST(malformed_surfaces_name_file_and_line)
{
    rk_error err;
    rk_surface s;
    char path[256];
    tmp_path(path, sizeof path, ".obj");
    write_text(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
    int rc = rk_surface_load(path, &s, &err);
    char want[300];
    snprintf(want, sizeof want, "%s:4: face references vertex 4", path);
    CHECK(rc != 0 && strstr(err.msg, want), "message: %s", err.msg);
    write_text(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 0 2\n");
    rc = rk_surface_load(path, &s, &err);
    CHECK(rc != 0 && strstr(err.msg, ":4: face reference 0"), "message: %s", err.msg);
    write_text(path, "v 0 0 0\nv 1 0 zero\n");
    rc = rk_surface_load(path, &s, &err);
    CHECK(rc != 0 && strstr(err.msg, ":2: expected vertex z"), "message: %s", err.msg);
    remove(path);
}

/* The cube of cube_obj as triangles, for breaking in various ways. */
static int load_cube(rk_surface *s, rk_error *err)
{
    char path[256];
    tmp_path(path, sizeof path, ".obj");
    write_text(path, cube_obj);
    int rc = rk_surface_load(path, s, err);
    remove(path);
    return rc;
}

TEST(open_surface_names_the_edge)
{
    rk_error err;
    rk_surface s;
    CHECK_OK(load_cube(&s, &err));
    s.nf--; /* drop the last triangle: (3, 4, 7) after the fan, 0-based */
    int rc = rk_surface_check(&s, "cube", &err);
    rk_surface_free(&s);
    CHECK(rc != 0 && strstr(err.msg, "cube: not closed: edge (3, 4)"), "message: %s", err.msg);
}

TEST(inconsistent_and_non_manifold_surfaces_are_rejected)
{
    rk_error err;
    rk_surface s;
    CHECK_OK(load_cube(&s, &err));
    int swap = s.tris[1]; /* flip face 0 only */
    s.tris[1] = s.tris[2];
    s.tris[2] = swap;
    int rc = rk_surface_check(&s, "cube", &err);
    CHECK(rc != 0 && strstr(err.msg, "inconsistently oriented") && strstr(err.msg, "faces 0 and"), "message: %s",
          err.msg);
    rk_surface_free(&s);

    CHECK_OK(load_cube(&s, &err));
    s.tris = realloc(s.tris, sizeof(int) * 3 * (size_t)(s.nf + 2));
    int extra[6] = {0, 1, 6, 1, 0, 6}; /* a fin on edge (0, 1) */
    memcpy(s.tris + 3 * s.nf, extra, sizeof extra);
    s.nf += 2;
    rc = rk_surface_check(&s, "cube", &err);
    rk_surface_free(&s);
    CHECK(rc != 0 && strstr(err.msg, "not edge-manifold: edge (0, 1) is shared by 4 faces"), "message: %s", err.msg);
}

TEST(inside_out_surface_is_reported_or_flipped)
{
    rk_error err;
    rk_surface s;
    CHECK_OK(load_cube(&s, &err));
    for (int f = 0; f < s.nf; f++) {
        int swap = s.tris[3 * f + 1];
        s.tris[3 * f + 1] = s.tris[3 * f + 2];
        s.tris[3 * f + 2] = swap;
    }
    int rc = rk_surface_check(&s, "cube", &err);
    CHECK(rc != 0 && strstr(err.msg, "inside out"), "message: %s", err.msg);
    int flipped = 0;
    rc = rk_surface_check_and_orient(&s, "cube", &flipped, &err);
    double vol = rk_surface_volume(&s);
    int ok = rk_surface_check(&s, "cube", &err) == 0;
    rk_surface_free(&s);
    CHECK(rc == 0 && flipped == 1, "not flipped: %s", err.msg);
    CHECK(ok && vol > 0.999, "volume after flip %g", vol);

    /* An open surface is not "merely inside out": no flip, an error. */
    CHECK_OK(load_cube(&s, &err));
    s.nf--;
    rc = rk_surface_check_and_orient(&s, "cube", &flipped, &err);
    rk_surface_free(&s);
    CHECK(rc != 0 && flipped == 0 && strstr(err.msg, "not closed"), "message: %s", err.msg);
}

TEST(non_finite_and_degenerate_faces_are_rejected)
{
    rk_error err;
    rk_surface s;
    CHECK_OK(load_cube(&s, &err));
    s.X[3 * 5 + 1] = INFINITY;
    int rc = rk_surface_check(&s, "cube", &err);
    CHECK(rc != 0 && strstr(err.msg, "vertex 5") && strstr(err.msg, "non-finite"), "message: %s", err.msg);
    s.X[3 * 5 + 1] = 0;
    s.tris[3 * 2 + 1] = s.tris[3 * 2];
    rc = rk_surface_check(&s, "cube", &err);
    rk_surface_free(&s);
    CHECK(rc != 0 && strstr(err.msg, "face 2") && strstr(err.msg, "repeats a vertex"), "message: %s", err.msg);
}

int main(void)
{
    RUN(surface_formats_round_trip);
    RUN(obj_polygons_references_and_negative_indices);
    RUN(off_with_counts_on_the_header_line_and_colours);
    RUN(malformed_surfaces_name_file_and_line);
    RUN(open_surface_names_the_edge);
    RUN(inconsistent_and_non_manifold_surfaces_are_rejected);
    RUN(inside_out_surface_is_reported_or_flipped);
    RUN(non_finite_and_degenerate_faces_are_rejected);
    return test_finish();
}
