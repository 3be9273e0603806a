/* The test meshes in tests/data/meshes load with exactly the counts SOURCES.md lists. */
#include "testlib.h"
#include "mesh/mesh.h"

/* Total tet volume, and the volume enclosed by the boundary (must agree if it is outward). */
static void volumes(const rk_mesh *m, double *tets, double *enclosed)
{
    rk_error err;
    *tets = 0;
    for (int t = 0; t < m->nt; t++) {
        const int *v = m->tets + 4 * t;
        *tets += rk_tet_signed_volume(m->X + 3 * v[0], m->X + 3 * v[1], m->X + 3 * v[2], m->X + 3 * v[3]);
    }
    rk_surface s = {m->nv, 0, m->X, NULL};
    *enclosed = -1;
    if (rk_mesh_boundary(m, &s.tris, &s.nf, &err) == 0) *enclosed = rk_surface_volume(&s);
    free(s.tris);
}

static int load_counts(const char *rel, int nv, int nt, char *why, size_t cap)
{
    rk_error err;
    rk_mesh m;
    rk_mesh_report rep;
    if (rk_mesh_load(test_data(rel), RK_MESH_KEEP_FLAT, &m, &rep, &err)) {
        snprintf(why, cap, "%s", err.msg);
        return 0;
    }
    double vt, vb;
    volumes(&m, &vt, &vb);
    int ok = m.nv == nv && m.nt == nt && rep.reoriented == 0 && rep.unused_removed == 0 && rep.components == 1 &&
             rep.min_volume > 0 && rep.min_quality > 0 && rep.mean_quality <= 1 && fabs(vt - vb) <= 1e-9 * vt;
    snprintf(why, cap, "%s: %d vertices, %d tets, %d reoriented, %d unused, %d components, volume %g, enclosed %g", rel,
             m.nv, m.nt, rep.reoriented, rep.unused_removed, rep.components, vt, vb);
    rk_mesh_free(&m);
    return ok;
}

TEST(medit_octopus)
{
    char why[512];
    CHECK(load_counts("meshes/octopus-low.mesh", 452, 1140, why, sizeof why), "%s", why);
}

TEST(tetgen_armadillo_by_node_and_by_ele)
{
    char why[512];
    CHECK(load_counts("meshes/armadillo_4k.node", 1180, 3717, why, sizeof why), "%s", why);
    CHECK(load_counts("meshes/armadillo_4k.ele", 1180, 3717, why, sizeof why), "%s", why);
}

TEST(gmsh41_ascii_bunny)
{
    char why[512];
    CHECK(load_counts("meshes/bunny_19k.msh", 4670, 19379, why, sizeof why), "%s", why);
}

TEST(gmsh22_binary_dinosaur)
{
    char why[512];
    CHECK(load_counts("meshes/dinosaur_bin.msh", 13270, 49973, why, sizeof why), "%s", why);
}

TEST(bunny_first_tet_is_read_as_written)
{
    /* The file's first element is "1 3192 3371 3647 4062"; node tags are 1..4670. */
    rk_error err;
    rk_mesh m;
    CHECK_OK(rk_mesh_load(test_data("meshes/bunny_19k.msh"), RK_MESH_KEEP_FLAT, &m, NULL, &err));
    int ok = m.tets[0] == 3191 && m.tets[1] == 3370 && m.tets[2] == 3646 && m.tets[3] == 4061;
    int got[4] = {m.tets[0], m.tets[1], m.tets[2], m.tets[3]};
    rk_mesh_free(&m);
    CHECK(ok, "first tet %d %d %d %d", got[0], got[1], got[2], got[3]);
}

TEST(surfaces_load_and_pass_the_check)
{
    rk_error err;
    rk_surface s;
    CHECK_OK(rk_surface_load(test_data("meshes/spot.obj"), &s, &err));
    int nv = s.nv, nf = s.nf, rc = rk_surface_check(&s, "spot", &err);
    double vol = rk_surface_volume(&s);
    rk_surface_free(&s);
    CHECK(nv == 11533 && nf == 23062, "spot: %d vertices %d faces", nv, nf);
    CHECK(rc == 0, "spot: %s", err.msg);
    /* The enclosed volume, sum over faces of det[a b c] / 6, computed from the file by awk, not
     * by the reader (one command line):
     *   awk '$1=="v"{x[++n]=$2;y[n]=$3;z[n]=$4} $1=="f"{split($2,a,"/");split($3,b,"/");split($4,c,"/");
     *        i=a[1];j=b[1];k=c[1]; v+=(x[i]*(y[j]*z[k]-z[j]*y[k])-y[i]*(x[j]*z[k]-z[j]*x[k])
     *        +z[i]*(x[j]*y[k]-y[j]*x[k]))/6} END{printf "%.16g\n", v}' tests/data/meshes/spot.obj
     * prints 0.6879862645150604 (Python's float sum gives the same digits). */
    CHECK_CLOSE(vol, 0.6879862645150604, 1e-12);

    CHECK_OK(rk_surface_load(test_data("meshes/decimated-knight.off"), &s, &err));
    nv = s.nv, nf = s.nf, rc = rk_surface_check(&s, "knight", &err);
    rk_surface_free(&s);
    CHECK(nv == 502 && nf == 1000, "knight: %d vertices %d faces", nv, nf);
    CHECK(rc == 0, "knight: %s", err.msg);
}

TEST(gaussian_splat_points)
{
    rk_error err;
    double *X;
    int n;
    CHECK_OK(rk_points_load(test_data("meshes/donut_3dgs.ply"), &X, &n, &err));
    double sum = 0;
    for (int i = 0; i < n; i++) sum += X[3 * i];
    double first[3] = {X[0], X[1], X[2]}, last_x = X[3 * (n - 1)];
    free(X);
    /* The count is SOURCES.md's. The coordinates and the x checksum were read from the file by
     * Python, not by the reader (binary little-endian, 14 float properties per splat, x y z first;
     * one command line):
     *   python3 -c "import struct; b = open('tests/data/meshes/donut_3dgs.ply', 'rb').read();
     *     o = b.index(b'end_header\n') + 11; x = [struct.unpack_from('<3f', b, o + 56 * i) for i in range(45624)];
     *     print(repr(sum(p[0] for p in x)), x[0], x[-1][0])"
     * prints 197.2652318054209 (0.018263084813952446, 0.0904652550816536, 0.040593795478343964)
     * -0.06805410236120224: the float32 values widened to double, summed in file order (math.fsum,
     * exact, rounds to the same double). */
    CHECK(n == 45624, "%d splats", n);
    CHECK(first[0] == (double)0.018263084813952446f && first[1] == (double)0.0904652550816536f &&
              first[2] == (double)0.040593795478343964f,
          "first splat at %.9g %.9g %.9g", first[0], first[1], first[2]);
    CHECK(last_x == (double)-0.06805410236120224f, "last splat x %.9g", last_x);
    CHECK_CLOSE(sum, 197.2652318054209, 1e-12);
}

TEST(splats_are_not_a_surface_nor_a_tet_mesh)
{
    rk_error err;
    rk_surface s;
    rk_mesh m;
    CHECK(rk_surface_load(test_data("meshes/donut_3dgs.ply"), &s, &err) != 0, "point cloud accepted as a surface");
    CHECK(strstr(err.msg, "donut_3dgs.ply") && strstr(err.msg, "no face element"), "message: %s", err.msg);
    CHECK(rk_mesh_load(test_data("meshes/spot.obj"), RK_MESH_KEEP_FLAT, &m, NULL, &err) != 0,
          "surface accepted as a tet mesh");
    CHECK(strstr(err.msg, "surface"), "message: %s", err.msg);
    CHECK(rk_mesh_load("/nonexistent/x.msh", RK_MESH_KEEP_FLAT, &m, NULL, &err) != 0 &&
              strstr(err.msg, "/nonexistent/x.msh"),
          "message: %s", err.msg);
}

int main(void)
{
    RUN(medit_octopus);
    RUN(tetgen_armadillo_by_node_and_by_ele);
    RUN(gmsh41_ascii_bunny);
    RUN(gmsh22_binary_dinosaur);
    RUN(bunny_first_tet_is_read_as_written);
    RUN(surfaces_load_and_pass_the_check);
    RUN(gaussian_splat_points);
    RUN(splats_are_not_a_surface_nor_a_tet_mesh);
    return test_finish();
}
