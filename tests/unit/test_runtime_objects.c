/* Several objects colliding in the runtime (COBJ and the collision surface; runtime/contact*.c): a
 * block of tets falls onto a slab resting on a plane, both baked into one asset with their own
 * RKPM skinning bases, stepped by this test's runtime (float, or double in
 * test_runtime_objects_double). On every step, with the positions X + U q of the runtime's q in
 * double: no vertex of either object is inside the other's boundary (cloud_inside.h: the exact
 * parity of a segment's crossings with its deformed triangles), no edge crosses a triangle (the
 * contact stage's exact test, precompute/contact/measure.c), every value finite; at the end the
 * block rests on the slab at most 2 dhat above it (the barrier's reach, where 1.5's sphere proxies
 * kept it rho_a + rho_b = 7 cm up). Damaged COBJ is refused naming the chunk, 1.5's CRAD is refused
 * naming the version, and a reader that does not know COBJ refuses the asset (it is critical). */
#include <stdio.h>

#include "testlib.h"
#include "asset_patch.h"
#include "cloud_inside.h"
#include "runtime_fixture.h"
#include "pipeline/pipeline.h"
#include "rom/rom.h"
#include "formats/rombin_read.h"
#include "runtime/romrt.h"

#ifdef ROMRT_DOUBLE
#define ASSET_REAL ROMBIN_REAL_F64
#define PRECISION "double"
#else
#define ASSET_REAL ROMBIN_REAL_F32
#define PRECISION "float"
#endif

/* A slab of 0.05 m cells just above the plane y = 0, and a block of the same cells 0.148 m above it. */
static const char *SCENE =
    "{\"objects\": ["
    "  {\"mesh\": {\"box\": {\"size\": [0.4, 0.1, 0.4], \"cells\": [8, 2, 8]}, \"translate\": [0, 0.002, 0]},"
    "   \"material\": {\"model\": \"neohookean\", \"young\": 2e5, \"poisson\": 0.4, \"density\": 1000}},"
    "  {\"mesh\": {\"box\": {\"size\": [0.2, 0.2, 0.2], \"cells\": [4, 4, 4]}, \"translate\": [0.1, 0.25, 0.1]},"
    "   \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000}}],"
    " \"gravity\": [0, -9.81, 0], \"damping\": {\"mass\": 2},"
    " \"obstacles\": [{\"plane\": {\"point\": [0, 0, 0], \"normal\": [0, 1, 0]}}],"
    " \"contact\": {\"dhat\": 0.002}, \"time\": {\"step\": 0.01, \"duration\": 0.8},"
    " \"rom\": {\"basis\": \"rkpm_skinning\", \"size\": 2}}";

static const void *chunk_data(const unsigned char *asset, size_t bytes, const char *id, size_t *count, size_t elem)
{
    rombin_file file;
    rombin_chunk c;
    rombin_error e;
    if (rombin_open(&file, asset, bytes, NULL, &e) || !rombin_find(&file, id, &c)) return NULL;
    *count = (size_t)c.raw / elem;
    return c.data;
}

static int object_of(const rk_scene_sim *sim, int v)
{
    return v >= sim->object_first_vertex[1];
}

/* What a drop measured. */
typedef struct {
    double least, block_low, slab_top, moved;
    int inside, crossings, finite, failed, steps;
    long iterations;
    size_t ncv;
} drop_result;

/* Bakes json, steps it `steps` times with the runtime and checks every step (the header's list). */
static int run_drop(const char *json, int steps, drop_result *out, rk_error *err)
{
    romrt_error rerr;
    rt_fixture f;
    memset(out, 0, sizeof *out);
    out->steps = steps, out->finite = 1, out->least = INFINITY;
    if (rt_fixture_open(&f, json, ASSET_REAL, err, &rerr)) {
        rt_fixture_close(&f);
        return -1;
    }
    size_t ncv = 0, nrad = 0;
    const uint32_t *cv = chunk_data(f.asset, f.bytes, ROMBIN_CVTX, &ncv, 4);
    const uint32_t *cobj = chunk_data(f.asset, f.bytes, ROMBIN_COBJ, &ncv, 4);
    romrt_model *m = f.m;
    if (!cv || !cobj || chunk_data(f.asset, f.bytes, ROMBIN_CRAD, &nrad, 4)) {
        rt_fixture_close(&f);
        return rk_fail(err, "CVTX and COBJ expected, and no CRAD");
    }
    out->ncv = ncv;
    int *tris = NULL, nf = 0, r = f.R.model.r, ndof = 3 * f.sim.mesh.nv, nv = f.sim.mesh.nv;
    int first1 = f.sim.object_first_vertex[1];
    cloud_surface surf[2] = {{0}};
    if (rk_mesh_boundary(&f.sim.mesh, &tris, &nf, err) || cloud_surface_init(&surf[0], tris, nf, 0, first1) ||
        cloud_surface_init(&surf[1], tris, nf, first1, nv)) {
        free(tris);
        cloud_surface_free(&surf[0]);
        rt_fixture_close(&f);
        return rk_fail(err, "the objects' boundaries");
    }
    double *x = calloc((size_t)ndof, sizeof(double)), qd[256], low_hist[10] = {0};
    romrt_real q[256];
    /* the heights are a cloud's points' (its proxy's vertices follow), or every vertex of a mesh */
    int end0 = f.sim.object_points ? f.sim.object_points[0] : first1;
    int end1 = f.sim.object_points ? first1 + f.sim.object_points[1] : nv;
    for (int k = 0; k < steps; k++) {
        if (romrt_step(m, &rerr) != ROMRT_OK) {
            out->failed = 1;
            rk_fail(err, "step %d: %s", k, rerr.message);
            break;
        }
        romrt_step_info info;
        info.size = sizeof info;
        romrt_last_step(m, &info, NULL);
        out->iterations += info.newton_iterations;
        romrt_reduced_coordinates(m, q, 256, NULL);
        for (int j = 0; j < r; j++) qd[j] = q[j], out->finite &= isfinite(qd[j]);
        rk_rom_positions(f.R.basis.U, ndof, r, f.sim.mesh.X, qd, x);
        /* every vertex (collision vertices and a cloud's points) against the other object's
         * boundary (its mesh's, or its voxel proxy's): odd exact crossings along a segment */
        for (int o = 0; o < 2; o++) cloud_surface_box(&surf[o], x);
        for (int v = 0; v < nv; v++) out->inside += cloud_surface_inside(&surf[1 - object_of(&f.sim, v)], x, x + 3 * v);
        /* the surfaces' crossings by the exact segment-triangle test, and their least distance */
        int crossed = 0;
        double least = INFINITY;
        if (rk_contact_measure(&f.R.model.contact, x, &crossed, &least, err)) {
            out->failed = 1;
            break;
        }
        out->crossings += crossed;
        out->least = fmin(out->least, least);
        out->block_low = INFINITY, out->slab_top = -INFINITY;
        for (int v = 0; v < end0; v++) out->slab_top = fmax(out->slab_top, x[3 * v + 1]);
        for (int v = first1; v < end1; v++) out->block_low = fmin(out->block_low, x[3 * v + 1]);
        low_hist[k % 10] = out->block_low;
    }
    for (int k = 1; k < 10; k++) out->moved = fmax(out->moved, fabs(low_hist[k] - low_hist[0]));
    free(x);
    free(tris);
    for (int k = 0; k < 2; k++) cloud_surface_free(&surf[k]);
    rt_fixture_close(&f);
    return out->failed ? -1 : 0;
}

static void report(const char *label, const drop_result *d)
{
    printf("# %s, %s runtime, %d steps (%ld Newton iterations), %zu collision vertices: %d vertex-inside-other events, "
           "%d crossings, smallest surface distance %.3g m; the block's lowest point %.5f m over the slab's highest %.5f m "
           "(gap %.5f, 2 dhat = 0.004), moving %.2g m over the last 10 steps\n",
           label, PRECISION, d->steps, d->iterations, d->ncv, d->inside, d->crossings, d->least, d->block_low, d->slab_top,
           d->block_low - d->slab_top, d->moved);
}

TEST(a_block_falls_onto_a_slab_and_rests_on_it)
{
    rk_error err = {{0}};
    drop_result d;
    int rc = run_drop(SCENE, 80, &d, &err);
    report("meshes", &d);
    CHECK(rc == 0, "%s", err.msg);
    CHECK(d.finite, "a reduced coordinate is not finite");
    CHECK(d.inside == 0, "%d times a vertex was inside the other object", d.inside);
    CHECK(d.crossings == 0, "%d edge-triangle crossings", d.crossings);
    CHECK(d.least > 0, "smallest surface distance %g", d.least);
    /* resting on it within the barrier's reach (the block's flat bottom on the slab's flat top), not
     * the 2 rho = 7 cm of 1.5's proxies nor the fall's 0.146 m */
    CHECK(d.block_low > d.slab_top && d.block_low - d.slab_top <= 2 * 0.002, "the block rests %g over the slab",
          d.block_low - d.slab_top);
    CHECK(d.moved < 1e-3, "the block still moves %g m over 10 steps", d.moved);
}

/* test_pipeline_clouds_collide's two point clouds (4 cm spacing, voxel proxies of twice that), the
 * block started higher (0.31 m: it falls about as far as it did from 0.35 m when the surfaces
 * stopped 7.6 cm apart), stepped 100 times: on the nearer surfaces the soft block still rang by
 * 2 mm at step 80 (1.6-2.8 mm from 0.25, 0.31 and 0.35 m), by 0.3-0.6 mm at step 100. */
TEST(a_block_of_points_falls_onto_a_slab_of_points)
{
    char slab_path[512], block_path[512];
    const char *slab = tl_scratch(slab_path, sizeof slab_path, "rt_slab.ply"),
               *block = tl_scratch(block_path, sizeof block_path, "rt_block.ply");
    char json[2048];
    CHECK(cloud_slab_block_scene(json, sizeof json, slab, block, 0.31, "\"damping\": {\"mass\": 2}, ") == 0,
          "the clouds' scene");
    rk_error err = {{0}};
    drop_result d;
    int rc = run_drop(json, 100, &d, &err);
    remove(slab);
    remove(block);
    report("point clouds", &d);
    CHECK(rc == 0, "%s", err.msg);
    CHECK(d.finite, "a reduced coordinate is not finite");
    CHECK(d.inside == 0, "%d times a vertex was inside the other object's proxy", d.inside);
    CHECK(d.crossings == 0, "%d edge-triangle crossings of the proxies", d.crossings);
    CHECK(d.least > 0, "smallest surface distance %g", d.least);
    /* each cloud's surface sits about s/2 off its points (s = 4 cm, their spacing: rk_points_proxy
     * pulls the flat faces in from g/2 = s, where they were before), and the surfaces stop within
     * 2 dhat: within s + 2 dhat, 3.7-3.8 cm (at g/2: 7.6 cm; the voxel surfaces: 7.8 cm), resting, not
     * still falling (it started 0.23 m over) */
    CHECK(d.block_low > d.slab_top && d.block_low - d.slab_top < 0.04 + 0.004 + 0.001, "the block rests %g over the slab",
          d.block_low - d.slab_top);
    CHECK(d.moved < 1e-3, "the block still moves %g m over 10 steps", d.moved);
}

/* romrt_open on a copy of the asset with `id` patched at value `index` to `value` (n bytes). */
static romrt_status open_patched(const rt_fixture *f, const char *id, size_t offset, const void *value, size_t n,
                                 romrt_error *rerr)
{
    unsigned char *bad = aligned_alloc(16, (f->bytes + 15) / 16 * 16);
    memcpy(bad, f->asset, f->bytes);
    asset_patch_chunk(bad, id, offset, value, n);
    size_t need;
    romrt_status st = romrt_arena_size(bad, f->bytes, &need, rerr);
    if (st == ROMRT_OK) {
        void *arena = aligned_alloc(16, (need + 15) / 16 * 16);
        romrt_model *m;
        st = romrt_open(bad, f->bytes, arena, need, &m, rerr);
        free(arena);
    }
    free(bad);
    return st;
}

TEST(damaged_object_chunks_are_refused)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture f;
    CHECK_OK(rt_fixture_open(&f, SCENE, ASSET_REAL, &err, &rerr));
    size_t ncv = 0;
    CHECK(chunk_data(f.asset, f.bytes, ROMBIN_COBJ, &ncv, 4) != NULL && ncv > 1, "no COBJ");
    uint32_t past = 0xFFFFFFFFu, *zeros = calloc(ncv, 4);
    struct {
        const char *what, *id;
        size_t offset;
        const void *value;
        size_t n;
        const char *chunk;
    } cases[] = {
        {"every vertex in object 0", ROMBIN_COBJ, 0, zeros, 4 * ncv, ROMBIN_COBJ},
        {"an object index past the collision vertices", ROMBIN_COBJ, 4, &past, 4, ROMBIN_COBJ},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        romrt_status st = open_patched(&f, cases[k].id, cases[k].offset, cases[k].value, cases[k].n, &rerr);
        printf("# %s: status %d, %s: %s\n", cases[k].what, (int)st, rerr.chunk, rerr.message);
        CHECK(st == ROMRT_E_MODEL && strcmp(rerr.chunk, cases[k].chunk) == 0, "%s: status %d, chunk %s", cases[k].what,
              (int)st, rerr.chunk);
    }
    free(zeros);
    { /* a 1.5 asset's CRAD (here the optional VMAP renamed): refused naming the version, not run with exact contact */
        unsigned char *old = aligned_alloc(16, (f.bytes + 15) / 16 * 16);
        uint32_t count, crc;
        size_t need = 0;
        memcpy(old, f.asset, f.bytes);
        memcpy(&count, old + ROMBIN_H_CHUNKS, 4);
        for (uint32_t i = 0; i < count; i++)
            if (memcmp(old + ROMBIN_HEADER_BYTES + (size_t)i * ROMBIN_ENTRY_BYTES + ROMBIN_E_ID, ROMBIN_VMAP, 4) == 0)
                memcpy(old + ROMBIN_HEADER_BYTES + (size_t)i * ROMBIN_ENTRY_BYTES + ROMBIN_E_ID, ROMBIN_CRAD, 4);
        crc = rombin_crc32(0, old, ROMBIN_H_TABLE_CRC);
        crc = rombin_crc32(crc, old + ROMBIN_HEADER_BYTES, (size_t)count * ROMBIN_ENTRY_BYTES);
        memcpy(old + ROMBIN_H_TABLE_CRC, &crc, 4);
        romrt_status st = romrt_arena_size(old, f.bytes, &need, &rerr);
        printf("# a 1.5 asset with CRAD: status %d, %s: %s\n", (int)st, rerr.chunk, rerr.message);
        CHECK(st == ROMRT_E_UNSUPPORTED && strcmp(rerr.chunk, ROMBIN_CRAD) == 0 && strstr(rerr.message, "1.5") != NULL,
              "CRAD: status %d, chunk %s, %s", (int)st, rerr.chunk, rerr.message);
        free(old);
    }
    /* a reader of format 1.4, which knows neither chunk, must refuse the asset: they are critical */
    static const char *const old_known[] = {ROMBIN_HEAD, ROMBIN_PARM, ROMBIN_VERT, ROMBIN_WGHT, ROMBIN_MASS, ROMBIN_LOAD,
                                            ROMBIN_DAMP, ROMBIN_ELEM, ROMBIN_ELMR, ROMBIN_PLAN, ROMBIN_CONT, ROMBIN_CVTX,
                                            ROMBIN_SKIN, ROMBIN_ROWS, 0};
    rombin_file file;
    rombin_error e;
    int rc = rombin_open(&file, f.asset, f.bytes, old_known, &e);
    CHECK(rc == ROMBIN_E_UNSUPPORTED, "a reader without COBJ: %d, %s", rc, e.message);
    rt_fixture_close(&f);
}

int main(void)
{
    RUN(a_block_falls_onto_a_slab_and_rests_on_it);
    RUN(a_block_of_points_falls_onto_a_slab_of_points);
    RUN(damaged_object_chunks_are_refused);
    return test_finish();
}
