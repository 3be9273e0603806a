/* A closed surface baked through a simulation cage (mesh.cage): the asset shows the original surface
 * (every vertex, every triangle), its stored rows are the cage's, interpolated; bad cage keys are
 * refused naming where. */
#include "formats/rombin_read.h"
#include "icosphere.h"
#include "pipeline/method_fixed.h"
#include "pipeline/pipeline.h"
#include "testlib.h"

/* The sphere's OBJ and a scene around it: skinning eigenmodes and cubature, hung from its top. */
static char obj[512];

static int sphere_scene(char *json, size_t cap, rk_surface *s, rk_error *err)
{
    if (icosphere(4, 0.5, s, err)) return -1; /* 2562 vertices, 5120 triangles */
    tl_scratch(obj, sizeof obj, "cage_sphere.obj");
    if (rk_surface_write(obj, s, err)) return -1;
    snprintf(json, cap,
             "{\"objects\": [{\"mesh\": {\"file\": \"%s\", \"cage\": {\"max_tets\": 3000}},"
             " \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000},"
             " \"fixed\": [{\"box\": [[-1, 0.4, -1], [1, 1, 1]]}]}],"
             " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": 0.01, \"duration\": 0.05},"
             " \"rom\": {\"basis\": \"skinning\", \"size\": 4, \"cubature\": {\"tolerance\": 0.05}}}",
             obj);
    return 0;
}

TEST(asset_shows_the_original_surface)
{
    rk_error err;
    char json[2048];
    rk_surface s = {0};
    CHECK_OK(sphere_scene(json, sizeof json, &s, &err));
    rk_scene scene;
    CHECK_OK(rk_scene_parse(json, "cage.json", &scene, &err));
    const rk_rom_entry *e;
    CHECK_OK(rk_scene_entry(&scene, 0, &e, &err));
    rk_bake_request req = {0};
    rk_baked b;
    int rc = rk_scene_bake(&scene, e, &req, &b, &err);
    rk_scene_free(&scene);
    CHECK(rc == 0, "bake: %s", err.msg);

    rombin_file f;
    rombin_error re;
    rombin_chunk head, surf, vert, vmap, wght;
    CHECK(rombin_open(&f, b.data, b.bytes, NULL, &re) == ROMBIN_OK, "open: %s", re.message);
    CHECK(rombin_find(&f, ROMBIN_HEAD, &head) && rombin_find(&f, ROMBIN_SURF, &surf) && rombin_find(&f, ROMBIN_VERT, &vert) &&
              rombin_find(&f, ROMBIN_VMAP, &vmap) && rombin_find(&f, ROMBIN_WGHT, &wght),
          "HEAD, SURF, VERT, VMAP and WGHT (a skinning basis, as weights)");
    const uint32_t *h = (const uint32_t *)head.data, *map = (const uint32_t *)vmap.data;
    uint32_t shown = h[ROMBIN_HEAD_SHOWN], stored = h[ROMBIN_HEAD_VERTICES], cage_nv = h[ROMBIN_HEAD_SOURCE_VERTICES];
    CHECK(shown == (uint32_t)s.nv, "%u shown vertices, the sphere has %d", shown, s.nv);
    CHECK(surf.raw == 4 * 3 * (uint64_t)s.nf, "SURF holds %llu triangles, the sphere %d", (unsigned long long)(surf.raw / 12), s.nf);
    CHECK(stored > shown, "the cage's element and contact vertices are stored after the shown ones (%u stored)", stored);
    CHECK(h[ROMBIN_HEAD_SOURCE_TETS] <= 3000, "cage of %u tets", h[ROMBIN_HEAD_SOURCE_TETS]);
    /* the shown vertices are the sphere's, in order, at their own rest positions (float32 VERT) */
    const float *X = (const float *)vert.data;
    double worst = 0;
    for (int i = 0; i < s.nv; i++) {
        CHECK(map[i] == cage_nv + (uint32_t)i, "VMAP[%d] = %u, expected %u", i, map[i], cage_nv + i);
        for (int a = 0; a < 3; a++) worst = fmax(worst, fabs(X[3 * i + a] - s.X[3 * i + a]));
    }
    CHECK(worst < 1e-7, "shown vertices up to %g from the sphere's", worst);
    /* the triangles are the sphere's over the shown vertices */
    const uint32_t *T = (const uint32_t *)surf.data;
    for (int k = 0; k < 3 * s.nf; k++) CHECK(T[k] == (uint32_t)s.tris[k], "SURF[%d] = %u, the sphere's %d", k, T[k], s.tris[k]);
    /* skinning weights at an embedded point are the tet's interpolated: a partition of unity like
     * the cage vertices' own (the constant weight and the eigenfunctions' sum are what they are,
     * so compare the shown vertices' sums to the stored cage vertices') */
    uint32_t H = (uint32_t)(wght.raw / 4 / stored);
    const float *W = (const float *)wght.data;
    double lo = INFINITY, hi = -INFINITY, clo = INFINITY, chi = -INFINITY;
    for (uint32_t i = 0; i < stored; i++) {
        double sum = 0;
        for (uint32_t j = 0; j < H; j++) sum += W[(size_t)i * H + j];
        if (i < shown) lo = fmin(lo, sum), hi = fmax(hi, sum);
        else clo = fmin(clo, sum), chi = fmax(chi, sum);
    }
    CHECK(lo >= clo - 1e-5 && hi <= chi + 1e-5, "embedded weight sums [%g, %g] outside the cage's [%g, %g]", lo, hi, clo, chi);
    cJSON *cage = cJSON_GetObjectItem(b.report, "cage");
    CHECK(cage && cJSON_GetObjectItem(cage, "outside") && cJSON_GetObjectItem(cage, "outside")->valuedouble == 0,
          "the report says no vertex is outside the cage");
    CHECK(cJSON_GetObjectItem(cage, "surface_triangles")->valuedouble == s.nf, "report's surface triangles");
    rk_baked_free(&b);
    rk_surface_free(&s);
}

/* An RKPM basis's weights exist anywhere: the asset's embedded vertices carry them evaluated at
 * their own points (rk_rkpm_interpolate on the basis's kernels here), not interpolated in the tet. */
TEST(rkpm_weights_are_taken_at_the_points)
{
    rk_error err;
    char json[2048], *at;
    rk_surface s = {0};
    CHECK_OK(sphere_scene(json, sizeof json, &s, &err));
    at = strstr(json, "\"rom\"");
    CHECK(at != NULL, "scene text");
    snprintf(at, sizeof json - (size_t)(at - json), "\"rom\": {\"basis\": \"rkpm_skinning\", \"size\": 4, \"kernels\": 200}}");
    rk_scene scene;
    CHECK_OK(rk_scene_parse(json, "cage.json", &scene, &err));
    const rk_rom_entry *e;
    rk_scene_sim sim;
    rk_scene_rom R;
    rk_bake_request req = {0};
    rk_baked b;
    int rc = rk_scene_entry(&scene, 0, &e, &err) || rk_scene_bake(&scene, e, &req, &b, &err);
    if (rc == 0 && rk_scene_build(&scene, &sim, &err)) rc = -1, rk_baked_free(&b);
    if (rc == 0 && rk_scene_rom_build(&scene, &sim, e, NULL, 0, &R, &err)) rc = -1, rk_baked_free(&b), rk_scene_sim_free(&sim);
    rk_scene_free(&scene);
    CHECK(rc == 0, "%s", err.msg);
    int n = sim.embedded.nv, m = R.basis.m, reg = 0;
    double *W = calloc((size_t)n * m, sizeof(double));
    rc = !W || rk_rkpm_interpolate(R.basis.rkpm, sim.embedded.X, n, R.basis.C, m, W, NULL, &reg, &err);
    rombin_file f;
    rombin_error re;
    rombin_chunk wght, head;
    int opened = rc == 0 && rombin_open(&f, b.data, b.bytes, NULL, &re) == ROMBIN_OK && rombin_find(&f, ROMBIN_WGHT, &wght) &&
                 rombin_find(&f, ROMBIN_HEAD, &head);
    double worst = 0, worst_tet = 0;
    if (opened) {
        const float *A = (const float *)wght.data;
        uint32_t H = (uint32_t)(wght.raw / 4 / ((const uint32_t *)head.data)[ROMBIN_HEAD_VERTICES]);
        opened = H == (uint32_t)m;
        for (int i = 0; opened && i < n; i++) {
            const int *t = sim.mesh.tets + 4 * sim.embedded.tet[i];
            for (int j = 0; j < m; j++) {
                double lin = 0; /* what the tet would interpolate */
                for (int k = 0; k < 4; k++) lin += sim.embedded.bary[4 * i + k] * R.basis.W[(size_t)sim.mesh.nv * j + t[k]];
                worst = fmax(worst, fabs(A[(size_t)i * H + j] - W[(size_t)n * j + i]));
                worst_tet = fmax(worst_tet, fabs(lin - W[(size_t)n * j + i]));
            }
        }
    }
    free(W);
    rk_scene_rom_free(&R);
    rk_scene_sim_free(&sim);
    rk_baked_free(&b);
    rk_surface_free(&s);
    CHECK(rc == 0, "rk_rkpm_interpolate: %s", err.msg);
    CHECK(opened, "the asset has WGHT with %d weights a vertex", m);
    CHECK(worst < 1e-6, "the asset's weights are up to %g from the basis at the points", worst);
    CHECK(worst_tet > 100 * worst, "interpolating in the tet would differ by only %g (so this checks nothing)", worst_tet);
}

/* A caged object beside an uncaged one: the asset shows the sphere's surface and the box's boundary
 * (its 56 boundary vertices and 108 triangles), each at its own rest positions. */
TEST(uncaged_objects_show_their_boundary)
{
    rk_error err;
    char json[4096];
    rk_surface s = {0};
    CHECK_OK(sphere_scene(json, sizeof json, &s, &err)); /* writes the sphere's OBJ */
    snprintf(json, sizeof json,
             "{\"objects\": [{\"mesh\": {\"file\": \"%s\", \"cage\": {\"max_tets\": 3000}},"
             " \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.3, \"density\": 1000}},"
             " {\"mesh\": {\"box\": {\"size\": [0.3, 0.3, 0.3], \"cells\": [3, 3, 3]}, \"translate\": [2, 0, 0]},"
             " \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.3, \"density\": 1000}}],"
             " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": 0.01, \"duration\": 0.05},"
             " \"rom\": {\"basis\": \"rkpm_skinning\", \"size\": 1, \"kernels\": 200}}", obj);
    rk_scene scene;
    CHECK_OK(rk_scene_parse(json, "two.json", &scene, &err));
    const rk_rom_entry *e;
    rk_bake_request req = {0};
    rk_baked b;
    int rc = rk_scene_entry(&scene, 0, &e, &err) || rk_scene_bake(&scene, e, &req, &b, &err);
    rk_scene_free(&scene);
    CHECK(rc == 0, "bake: %s (scene %s)", err.msg, json);
    rombin_file f;
    rombin_error re;
    rombin_chunk head, surf, vert;
    int ok = rombin_open(&f, b.data, b.bytes, NULL, &re) == ROMBIN_OK && rombin_find(&f, ROMBIN_HEAD, &head) &&
             rombin_find(&f, ROMBIN_SURF, &surf) && rombin_find(&f, ROMBIN_VERT, &vert);
    uint32_t shown = ok ? ((const uint32_t *)head.data)[ROMBIN_HEAD_SHOWN] : 0;
    uint64_t tris = ok ? surf.raw / 12 : 0;
    int box_ok = ok;
    const float *X = ok ? (const float *)vert.data : NULL;
    for (uint32_t i = (uint32_t)s.nv; ok && i < shown; i++) /* the box's vertices: on its placed boundary */
        box_ok &= (fabs(X[3 * i] - 2) < 1e-6 || fabs(X[3 * i] - 2.3) < 1e-6 || fabs(X[3 * i + 1]) < 1e-6 ||
                   fabs(X[3 * i + 1] - 0.3) < 1e-6 || fabs(X[3 * i + 2]) < 1e-6 || fabs(X[3 * i + 2] - 0.3) < 1e-6);
    rk_baked_free(&b);
    rk_surface_free(&s);
    CHECK(ok, "asset chunks");
    CHECK(shown == 2562 + 56 && tris == 5120 + 108, "%u shown vertices, %llu triangles", shown, (unsigned long long)tris);
    CHECK(box_ok, "a shown box vertex is off the box's boundary");
}

/* A cage goes around a surface file only, with max_tets, and not beside max_volume. */
TEST(refuses_bad_cage_keys)
{
    static const struct {
        const char *mesh, *want;
    } cases[] = {
        {"{\"box\": {\"size\": [1, 1, 1], \"cells\": [1, 1, 1]}, \"cage\": {\"max_tets\": 500}}", "objects[0].mesh.cage"},
        {"{\"file\": \"a.msh\", \"cage\": {\"max_tets\": 500}}", "closed surface file"},
        {"{\"file\": \"a.obj\", \"cage\": {}}", "needs max_tets"},
        {"{\"file\": \"a.obj\", \"cage\": {\"max_tets\": 50}}", "max_tets"},
        {"{\"file\": \"a.obj\", \"cage\": {\"max_tets\": 500, \"tets\": 3}}", "tets"},
        {"{\"file\": \"a.obj\", \"max_volume\": 0.1, \"cage\": {\"max_tets\": 500}}", "max_volume"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char json[512];
        snprintf(json, sizeof json, "{\"objects\": [{\"mesh\": %s, \"material\": {\"young\": 1e5, \"poisson\": 0.3, "
                                    "\"density\": 1000}}], \"time\": {\"step\": 0.01, \"duration\": 0.1}}", cases[i].mesh);
        rk_scene scene;
        rk_error err;
        int rc = rk_scene_parse(json, "bad.json", &scene, &err);
        if (rc == 0) rk_scene_free(&scene);
        CHECK(rc != 0, "case %zu accepted", i);
        CHECK(strstr(err.msg, cases[i].want) && strstr(err.msg, "bad.json"), "case %zu: %s", i, err.msg);
    }
}

int main(void)
{
    RUN(asset_shows_the_original_surface);
    RUN(rkpm_weights_are_taken_at_the_points);
    RUN(uncaged_objects_show_their_boundary);
    RUN(refuses_bad_cage_keys);
    remove(obj);
    return test_finish();
}
