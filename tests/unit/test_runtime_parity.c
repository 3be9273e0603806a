/* The runtime against the double-precision reduced simulator (precompute/rom) on the same baked
 * model: the trajectories of the shown vertices agree to 1e-10 relative in a double build of the
 * runtime (this file compiled with -DROMRT_DOUBLE, test_runtime_parity_double) and to 1e-4 in
 * the float build. Relative: the largest position difference over all steps and vertices, over
 * the largest displacement. Also: forces on a named group, state save/restore, reset. */
#include "runtime_fixture.h"
#include "asset_patch.h"

#ifdef ROMRT_DOUBLE
#define PARITY_TOL 1e-10
#define ASSET_REAL ROMBIN_REAL_F64
#else
#define PARITY_TOL 1e-4
#define ASSET_REAL ROMBIN_REAL_F32
#endif

/* A cantilever under gravity with damping and a pushed tip; BE or BDF2, soft (E = 2e5: strains
 * ~1e-2) or stiff (E = 2e8: ~1e-5, where float keeps digits only through physics_impl.h's
 * displacement-gradient forms). */
static const char *cantilever(const char *integrator, double young)
{
    static char json[2048];
    snprintf(json, sizeof json,
             "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1, 0.1, 0.1], \"cells\": [10, 2, 2]}},"
             " \"material\": {\"model\": \"neohookean\", \"young\": %g, \"poisson\": 0.4, \"density\": 1000},"
             " \"fixed\": [{\"box\": [[-1, -1, -1], [0.01, 2, 2]]}]}],"
             " \"gravity\": [0, -9.81, 0], \"damping\": {\"mass\": 0.5, \"stiffness\": 0.001},"
             " \"time\": {\"step\": 0.01, \"duration\": 0.4, \"integrator\": \"%s\"},"
             " \"rom\": {\"basis\": \"modes\", \"size\": 10, \"cubature\": {\"tolerance\": 0.02},"
             "  \"asset\": {\"groups\": [{\"name\": \"tip\", \"box\": [[0.99, -1, -1], [2, 1, 1]]}]}}}",
             young, integrator);
    return json;
}

/* A block dropped on a ground plane while one end twists: contact, pins and BDF2. Its float32
 * tolerance is looser: the stiff pin penalty (1e4 (lambda + 2 mu) / (rho L^2), rom.h) makes the
 * solution sensitive to the float32 rounding of the asset's own data: a double runtime stepping
 * the same float32 asset already differs from the reference by 3e-3, and float arithmetic about
 * triples that (bake float64 and build with ROMRT_DOUBLE for such scenes). */
#ifdef ROMRT_DOUBLE
#define PINNED_TOL PARITY_TOL
#else
#define PINNED_TOL 2e-2
#endif
static const char *twisted_drop =
    "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.6, 0.1, 0.1], \"cells\": [6, 2, 2]}},"
    " \"material\": {\"model\": \"stvk\", \"young\": 1e5, \"poisson\": 0.3, \"density\": 500},"
    " \"moving\": [{\"box\": [[0.59, -1, -1], [1, 1, 1]], \"twist\": {\"axis\": [1, 0, 0], \"degrees_per_second\": 90}}]}],"
    " \"gravity\": [0, -9.81, 0], \"obstacles\": [{\"plane\": {\"point\": [0, -0.02, 0], \"normal\": [0, 1, 0]}}],"
    " \"time\": {\"step\": 0.01, \"duration\": 0.3, \"integrator\": \"bdf2\"},"
    " \"rom\": {\"basis\": \"skinning\", \"size\": 3}}";

/* Steps both `steps` times (the runtime with `push` on group 0, the precompute with the same
 * force projected) and returns the relative trajectory difference. */
static double run_both(rt_fixture *f, int steps, const double push[3], rk_error *err, int *failed)
{
    rk_rom s;
    int n = romrt_shown_count(f->m), r = f->R.model.r, ndof = 3 * f->sim.mesh.nv;
    double worst = 0, scale = 0, *ref = calloc((size_t)3 * n, sizeof(double));
    romrt_real *xyz = calloc((size_t)3 * n, sizeof(romrt_real));
    romrt_error rerr;
    *failed = 0;
    if (push) { /* the runtime spreads the total force evenly over the group */
        romrt_real fr[3] = {(romrt_real)push[0], (romrt_real)push[1], (romrt_real)push[2]};
        size_t g;
        if (romrt_find_group(f->m, "tip", &g, NULL) || romrt_add_force(f->m, g, fr, NULL) != ROMRT_OK) *failed = 1;
        const rk_box tip = {{0.99, -1, -1}, {2, 1, 1}}, *b = &tip; /* the scene's group box */
        int count = 0;
        for (int v = 0; v < f->sim.mesh.nv; v++) count += rk_box_contains(b, &f->sim.mesh.X[3 * v], 1e-9);
        for (int v = 0; v < f->sim.mesh.nv; v++)
            if (rk_box_contains(b, &f->sim.mesh.X[3 * v], 1e-9))
                for (int a = 0; a < 3; a++)
                    for (int j = 0; j < r; j++) f->R.model.f[j] += f->R.basis.U[(size_t)ndof * j + 3 * v + a] * push[a] / count;
    }
    /* the reduced simulator's iterates are the fresh mode's (the default may keep Newton's matrix) */
    if (romrt_set_hessian_reuse(f->m, 1, &rerr) != ROMRT_OK) *failed = 1;
    if (*failed || rk_rom_init(&s, &f->R.model, NULL, f->v0, err)) {
        *failed = 1;
        free(ref);
        free(xyz);
        return INFINITY;
    }
    for (int k = 0; k < steps && !*failed; k++) {
        if (rk_rom_step(&s, err) || romrt_step(f->m, &rerr) != ROMRT_OK) {
            if (!err->msg[0]) snprintf(err->msg, sizeof err->msg, "runtime: %s", rerr.message);
            *failed = 1;
            break;
        }
        rt_fixture_reference(f, s.q, ref);
        romrt_positions(f->m, xyz, 3 * (size_t)n, 3, NULL);
        for (int i = 0; i < 3 * n; i++) {
            worst = fmax(worst, fabs((double)xyz[i] - ref[i]));
            scale = fmax(scale, fabs(ref[i] - f->sim.mesh.X[3 * (int)f->vmap[i / 3] + i % 3]));
        }
    }
    rk_rom_free(&s);
    free(ref);
    free(xyz);
    return worst / scale;
}

/* Opens the scene, runs both for `steps`, and checks the relative difference against tol.
 * Leaves the calling test (through CHECK) on failure. */
#define CHECK_PARITY(label, json, steps, push, tol, extra_check)                                          \
    do {                                                                                                  \
        rk_error err = {{0}};                                                                             \
        romrt_error rerr;                                                                                 \
        rt_fixture f;                                                                                     \
        int failed;                                                                                       \
        CHECK_OK(rt_fixture_open(&f, json, ASSET_REAL, &err, &rerr));                                     \
        double rel = run_both(&f, steps, push, &err, &failed);                                            \
        CHECK(!failed, "%s", err.msg);                                                                    \
        printf("# %s: relative difference %.3g (tol %g), r = %d, %d cubature elements, %d contact vertices\n", \
               label, rel, (double)(tol), f.R.model.r, f.R.model.quad.count, f.R.model.ncv);             \
        CHECK(extra_check, "%s: the scene lacks what it should exercise", label);                         \
        CHECK(rel <= (tol), "relative difference %.3g above %g", rel, (double)(tol));                     \
        rt_fixture_close(&f);                                                                             \
    } while (0)

TEST(cantilever_backward_euler_matches_reduced_simulator)
{
    CHECK_PARITY("cantilever BE", cantilever("backward_euler", 2e5), 40, NULL, PARITY_TOL, f.R.model.C != NULL);
}

TEST(cantilever_bdf2_with_a_pushed_tip_matches)
{
    const double push[3] = {0, 0, 0.05};
    CHECK_PARITY("cantilever BDF2, pushed", cantilever("bdf2", 2e5), 40, push, PARITY_TOL, 1);
}

TEST(stiff_cantilever_matches)
{
    CHECK_PARITY("stiff cantilever (E = 2e8) BE", cantilever("backward_euler", 2e8), 40, NULL, PARITY_TOL, 1);
}

TEST(twisted_drop_on_a_plane_matches)
{
    CHECK_PARITY("twisted drop (contact, pins, BDF2)", twisted_drop, 30, NULL, PINNED_TOL,
                 f.R.model.has_contact && f.R.model.npins > 0);
}

/* A soft beam sagging under gravity, RKPM skinning eigenmodes (r = 60, through SKIN's weights;
 * ill-conditioned coordinates: float32 rounding moves q well before it moves the positions). The
 * drift this scale does not show (the float solve ending without its last Newton step, a fifth of
 * the demo beam's motion over 100 steps) is checked by make bench's float32 row beside float64. */
static const char *sagging_rkpm =
    "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1, 0.2, 0.2], \"cells\": [10, 2, 2]}},"
    " \"material\": {\"model\": \"neohookean\", \"young\": 2e4, \"poisson\": 0.45, \"density\": 1000},"
    " \"fixed\": [{\"box\": [[-1, -1, -1], [0.01, 2, 2]]}]}],"
    " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": 0.01, \"duration\": 0.6, \"integrator\": \"backward_euler\"},"
    " \"rom\": {\"basis\": \"rkpm_skinning\", \"size\": 4, \"kernels\": 60, \"integration_points\": 4000,"
    "  \"cubature\": {\"tolerance\": 0.02}}}";

TEST(sagging_rkpm_beam_matches)
{
    CHECK_PARITY("sagging RKPM beam", sagging_rkpm, 60, NULL, PARITY_TOL, f.R.model.r == 60);
}

/* The same beam mesh-free (freeform paper Eq. 22): the energy and the mass at 600 grid points with the
 * weights' gradients, a cubature of them in the asset (IPNT), stepped through the skinning path. */
static const char *sagging_mesh_free =
    "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1, 0.2, 0.2], \"cells\": [10, 2, 2]}},"
    " \"material\": {\"model\": \"neohookean\", \"young\": 2e4, \"poisson\": 0.45, \"density\": 1000},"
    " \"fixed\": [{\"box\": [[-1, -1, -1], [0.01, 2, 2]]}]}],"
    " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": 0.01, \"duration\": 0.6, \"integrator\": \"backward_euler\"},"
    " \"rom\": {\"basis\": \"rkpm_skinning\", \"size\": 4, \"kernels\": 60, \"integration_points\": 4000,"
    "  \"mesh_free\": {\"points\": 600}, \"cubature\": {\"tolerance\": 0.02}}}";

/* HEAD field k of the fixture's asset. */
static uint32_t head_field(const rt_fixture *f, int k)
{
    rombin_file file;
    rombin_chunk c;
    rombin_error e;
    if (rombin_open(&file, f->asset, f->bytes, NULL, &e) || !rombin_find(&file, ROMBIN_HEAD, &c)) return UINT32_MAX;
    return ((const uint32_t *)(const void *)c.data)[k];
}

TEST(mesh_free_rkpm_beam_matches)
{
    CHECK_PARITY("mesh-free RKPM beam", sagging_mesh_free, 60, NULL, PARITY_TOL,
                 f.R.points.n >= 500 && f.R.model.quad.count < f.R.points.n &&
                     head_field(&f, ROMBIN_HEAD_POINTS) == (uint32_t)f.R.model.quad.count &&
                     head_field(&f, ROMBIN_HEAD_ELEMENTS) == 0 &&
                     /* the scene sets no newton.max_iterations: the runtime keeps the reduced
                      * solvers' limit, not full order's (fom.h, rk_fom_max_iter) */
                     head_field(&f, ROMBIN_HEAD_NEWTON_MAX_ITER) == RK_REDUCED_DEFAULT_MAX_ITER);
}

/* The projected volume (rom.volume "projected", VPRS) through each of the runtime's three elastic
 * paths: the modes cantilever's elements with G formed at open (a constant pressure), the RKPM
 * beam's elements through the skinning weights (the weights' pressure space), and its mesh-free
 * points (the weights times (1, x, y, z)); nu = 0.4 and 0.45, stable Neo-Hookean. */
static const char *with_volume(const char *json, const char *keys)
{
    static char out[2048];
    const char *rom = strstr(json, "\"rom\": {");
    snprintf(out, sizeof out, "%.*s\"rom\": {%s, %s", (int)(rom - json), json, keys, rom + strlen("\"rom\": {"));
    return out;
}

TEST(projected_volume_matches_on_every_path)
{
    char scene[2048];
    snprintf(scene, sizeof scene, "%s", with_volume(cantilever("backward_euler", 2e5), "\"volume\": \"projected\", \"pressure\": \"constant\""));
    CHECK_PARITY("modes cantilever, projected volume", scene, 40, NULL, PARITY_TOL, f.R.model.quad.vol_k == 1);
    snprintf(scene, sizeof scene, "%s", with_volume(sagging_rkpm, "\"volume\": \"projected\""));
    CHECK_PARITY("RKPM beam, projected volume", scene, 60, NULL, PARITY_TOL, f.R.model.quad.vol_k > 1 && f.R.points.n == 0);
    snprintf(scene, sizeof scene, "%s", with_volume(sagging_mesh_free, "\"volume\": \"projected\", \"pressure\": \"weights_affine\""));
    CHECK_PARITY("mesh-free RKPM beam, projected volume", scene, 60, NULL, PARITY_TOL,
                 f.R.model.quad.vol_k > 5 && f.R.points.n > 0);
}

/* The asset's VPRS one real short (its CRCs recomputed and the freed real zeroed as padding, so the
 * container takes it): the runtime
 * refuses the count by name, as it would k > r or a count that is not a whole k per point. */
TEST(a_projected_volume_of_the_wrong_size_is_refused)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture f;
    CHECK_OK(rt_fixture_open(&f, with_volume(sagging_mesh_free, "\"volume\": \"projected\""), ASSET_REAL, &err, &rerr));
    unsigned char *bad = aligned_alloc(16, (f.bytes + 15) / 16 * 16);
    memcpy(bad, f.asset, f.bytes);
    uint32_t count, crc;
    int found = 0;
    memcpy(&count, bad + ROMBIN_H_CHUNKS, 4);
    for (uint32_t i = 0; i < count; i++) {
        unsigned char *e = bad + ROMBIN_HEADER_BYTES + (size_t)i * ROMBIN_ENTRY_BYTES;
        uint64_t off, stored;
        if (memcmp(e + ROMBIN_E_ID, ROMBIN_VPRS, 4) != 0) continue;
        memcpy(&off, e + ROMBIN_E_OFFSET, 8);
        memcpy(&stored, e + ROMBIN_E_STORED, 8);
        stored -= ASSET_REAL == ROMBIN_REAL_F32 ? 4 : 8;
        memset(bad + off + stored, 0, ASSET_REAL == ROMBIN_REAL_F32 ? 4 : 8); /* now padding: zero */
        memcpy(e + ROMBIN_E_STORED, &stored, 8);
        memcpy(e + ROMBIN_E_RAW, &stored, 8);
        crc = rombin_crc32(0, bad + off, (size_t)stored);
        memcpy(e + ROMBIN_E_CRC, &crc, 4);
        found = 1;
    }
    crc = rombin_crc32(0, bad, ROMBIN_H_TABLE_CRC);
    crc = rombin_crc32(crc, bad + ROMBIN_HEADER_BYTES, (size_t)count * ROMBIN_ENTRY_BYTES);
    memcpy(bad + ROMBIN_H_TABLE_CRC, &crc, 4);
    size_t need;
    romrt_status st = romrt_arena_size(bad, f.bytes, &need, &rerr);
    if (st == ROMRT_OK) {
        void *arena = aligned_alloc(16, (need + 15) / 16 * 16);
        romrt_model *m;
        st = romrt_open(bad, f.bytes, arena, need, &m, &rerr);
        free(arena);
    }
    printf("# VPRS one real short: status %d, %s: %s\n", (int)st, rerr.chunk, rerr.message);
    CHECK(found && st == ROMRT_E_MODEL && strcmp(rerr.chunk, "VPRS") == 0 &&
              strstr(rerr.message, "not 1 to r per element or integration point"),
          "found %d, status %d, %s: %s", found, (int)st, rerr.chunk, rerr.message);
    free(bad);
    rt_fixture_close(&f);
}

/* A point cloud (a 9 x 3 x 3 lattice of points, no mesh) hanging from its left end and falling
 * onto a plane under its right end: the cloud's proxy surface meets the plane. */
static const char *hanging_cloud = /* %s: the cloud's file */
    "{\"objects\": [{\"mesh\": {\"points\": \"%s\"},"
    " \"material\": {\"model\": \"neohookean\", \"young\": 2e4, \"poisson\": 0.4, \"density\": 1000},"
    " \"fixed\": [{\"box\": [[-1, -1, -1], [0.01, 2, 2]]}]}],"
    " \"gravity\": [0, -9.81, 0], \"obstacles\": [{\"plane\": {\"point\": [0, -0.16, 0], \"normal\": [0, 1, 0]}}],"
    " \"time\": {\"step\": 0.01, \"duration\": 0.4, \"integrator\": \"backward_euler\"},"
    " \"rom\": {\"basis\": \"rkpm_skinning\", \"size\": 3, \"kernels\": 40}}";

static int write_cloud(const char *path)
{
    FILE *fp = fopen(path, "w");
    if (!fp) return -1;
    fprintf(fp, "ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
            21 * 5 * 5);
    for (int i = 0; i < 21; i++)
        for (int j = 0; j < 5; j++)
            for (int k = 0; k < 5; k++) fprintf(fp, "%g %g %g\n", 0.05 * i, 0.05 * j - 0.1, 0.05 * k - 0.1);
    return fclose(fp);
}

TEST(point_cloud_on_a_plane_matches)
{
    char cloud[512], json[2048];
    tl_scratch(cloud, sizeof cloud, "parity_cloud.ply");
    snprintf(json, sizeof json, hanging_cloud, cloud);
    CHECK(write_cloud(cloud) == 0, "cannot write %s", cloud);
    CHECK_PARITY("point cloud on a plane", json, 40, NULL, PINNED_TOL,
                 f.R.points.n > 0 && head_field(&f, ROMBIN_HEAD_POINTS) > 0 && romrt_shown_count(f.m) == 21 * 5 * 5 &&
                     f.R.model.has_contact);
    remove(cloud);
}

/* A bar thrown at 2 m/s onto a sphere and a plane, with friction: the asset's VEL0 starts the
 * runtime moving as the reduced simulator starts (romkit compare's free run), and a reset returns
 * to that velocity, not to rest. */
static const char *thrown_bar =
    "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.3, 0.1, 0.1], \"cells\": [6, 2, 2]}},"
    " \"material\": {\"model\": \"neohookean\", \"young\": 2e5, \"poisson\": 0.4, \"density\": 1000},"
    " \"velocity\": [0.5, -2, 0]}],"
    " \"obstacles\": [{\"sphere\": {\"center\": [0.05, -0.2, 0], \"radius\": 0.08}},"
    "  {\"plane\": {\"point\": [0, -0.3, 0], \"normal\": [0, 1, 0]}}],"
    " \"contact\": {\"dhat\": 0.002, \"friction\": 0.3},"
    " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": 0.01, \"duration\": 0.3, \"integrator\": \"backward_euler\"},"
    " \"rom\": {\"basis\": \"skinning\", \"size\": 4}}";

TEST(thrown_bar_starts_moving_and_matches)
{
    CHECK_PARITY("thrown bar (VEL0, sphere, plane, friction)", thrown_bar, 30, NULL, PINNED_TOL,
                 f.v0 != NULL && f.R.model.has_contact);
}

TEST(reset_returns_to_the_baked_velocity)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture f;
    CHECK_OK(rt_fixture_open(&f, thrown_bar, ASSET_REAL, &err, &rerr));
    CHECK(f.v0 != NULL, "the thrown bar baked no VEL0");
    int r = f.R.model.r, ns = romrt_state_size(f.m);
    romrt_real *state = calloc((size_t)ns, sizeof(romrt_real));
    for (int pass = 0; pass < 2; pass++) { /* at open, then after steps and a reset */
        CHECK(romrt_get_state(f.m, state, ns, NULL) == ROMRT_OK, "get_state");
        for (int j = 0; j < r; j++) {
            const romrt_real *q = state + (ns - 5 * r), *v = q + r;
            CHECK(q[j] == 0, "pass %d: q[%d] = %g, not the rest shape", pass, j, (double)q[j]);
            CHECK(v[j] == (romrt_real)f.v0[j], "pass %d: v[%d] = %g, VEL0 holds %g", pass, j, (double)v[j], f.v0[j]);
        }
        for (int k = 0; k < 5; k++) CHECK(romrt_step(f.m, &rerr) == ROMRT_OK, "%s", rerr.message);
        CHECK(romrt_reset(f.m, NULL) == ROMRT_OK, "reset");
    }
    free(state);
    rt_fixture_close(&f);
}

TEST(a_non_finite_initial_velocity_is_refused_by_name)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture f;
    CHECK_OK(rt_fixture_open(&f, thrown_bar, ASSET_REAL, &err, &rerr));
    unsigned char nan_bytes[8];
    if (ASSET_REAL == ROMBIN_REAL_F32) {
        float x = NAN;
        memcpy(nan_bytes, &x, 4);
    } else {
        double x = NAN;
        memcpy(nan_bytes, &x, 8);
    }
    asset_patch_chunk(f.asset, ROMBIN_VEL0, 0, nan_bytes, ASSET_REAL == ROMBIN_REAL_F32 ? 4 : 8);
    size_t need;
    romrt_status st = romrt_arena_size(f.asset, f.bytes, &need, &rerr);
    CHECK(st == ROMRT_E_MODEL && strcmp(rerr.chunk, ROMBIN_VEL0) == 0 && strstr(rerr.message, "not finite"),
          "a NaN in VEL0: status %d, chunk '%s', '%s'", (int)st, rerr.chunk, rerr.message);
    rt_fixture_close(&f);
}

TEST(state_restores_and_reset_returns_to_rest)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture f;
    CHECK_OK(rt_fixture_open(&f, cantilever("bdf2", 2e5), ASSET_REAL, &err, &rerr));
    /* bit-identical replay needs a fresh Newton matrix: a restored state drops a kept one (romrt.h) */
    CHECK(romrt_set_hessian_reuse(f.m, 1, &rerr) == ROMRT_OK, "%s", rerr.message);
    int n = romrt_shown_count(f.m), ns = romrt_state_size(f.m);
    romrt_real *state = calloc((size_t)ns, sizeof(romrt_real)), *a = calloc((size_t)3 * n, sizeof(romrt_real)),
               *b = calloc((size_t)3 * n, sizeof(romrt_real));
    for (int k = 0; k < 5; k++) CHECK(romrt_step(f.m, &rerr) == ROMRT_OK, "%s", rerr.message);
    CHECK(romrt_get_state(f.m, state, ns, NULL) == ROMRT_OK, "get_state");
    for (int k = 0; k < 5; k++) romrt_step(f.m, &rerr);
    romrt_positions(f.m, a, 3 * (size_t)n, 3, NULL);
    CHECK(romrt_set_state(f.m, state, ns, NULL) == ROMRT_OK, "set_state");
    for (int k = 0; k < 5; k++) romrt_step(f.m, &rerr);
    romrt_positions(f.m, b, 3 * (size_t)n, 3, NULL);
    CHECK(memcmp(a, b, sizeof(romrt_real) * 3 * n) == 0, "replaying from a saved state differs");
    state[2] = (romrt_real)NAN;
    CHECK(romrt_set_state(f.m, state, ns, NULL) == ROMRT_E_ARGUMENT, "a NaN state must be refused");
    CHECK(romrt_set_state(f.m, state, ns - 1, NULL) == ROMRT_E_ARGUMENT, "a state of the wrong size must be refused");
    romrt_reset(f.m, NULL);
    romrt_positions(f.m, a, 3 * (size_t)n, 3, NULL);
    for (int i = 0; i < 3 * n; i++)
        CHECK(a[i] == (romrt_real)f.sim.mesh.X[3 * (int)f.vmap[i / 3] + i % 3], "reset: vertex %d not at rest", i / 3);
    CHECK(romrt_time(f.m) == 0, "reset: time %g", (double)romrt_time(f.m));
    free(state);
    free(a);
    free(b);
    rt_fixture_close(&f);
}

int main(void)
{
    RUN(cantilever_backward_euler_matches_reduced_simulator);
    RUN(cantilever_bdf2_with_a_pushed_tip_matches);
    RUN(stiff_cantilever_matches);
    RUN(twisted_drop_on_a_plane_matches);
    RUN(sagging_rkpm_beam_matches);
    RUN(mesh_free_rkpm_beam_matches);
    RUN(projected_volume_matches_on_every_path);
    RUN(a_projected_volume_of_the_wrong_size_is_refused);
    RUN(point_cloud_on_a_plane_matches);
    RUN(thrown_bar_starts_moving_and_matches);
    RUN(reset_returns_to_the_baked_velocity);
    RUN(a_non_finite_initial_velocity_is_refused_by_name);
    RUN(state_restores_and_reset_returns_to_rest);
    return test_finish();
}
