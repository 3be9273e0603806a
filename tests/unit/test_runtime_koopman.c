/* The runtime steps a Koopman asset as the precompute's operator does: single steps, forces as
 * impulses, the time-step rescale of Eq. 21 and the damping edit of Sec. 7.2 against the
 * library's rollout; jumps of N steps against N single steps; damaged eigenvalue tables refused.
 * Built twice: in float (the default runtime) and in double (test_runtime_koopman_double), where
 * the jump must match single steps to 1e-6 relative. */
#include <stdint.h>

#include "testlib.h"
#include "asset/asset.h"
#include "formats/rombin_read.h"
#include "koopman/koopman.h"
#include "pipeline/pipeline.h"
#include "runtime/romrt.h"
#include "runtime_gpu.h"

#ifdef ROMRT_DOUBLE
#define REAL_TYPE ROMBIN_REAL_F64
#define TOL_LIBRARY 1e-9   /* the runtime against the library's rollout, relative */
#define TOL_JUMP 1e-6      /* the bound, in double */
#else
#define REAL_TYPE ROMBIN_REAL_F32
#define TOL_LIBRARY 5e-4
#define TOL_JUMP 5e-4
#endif

static const char *scene_json =
    "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1.0, 0.1, 0.1], \"cells\": [10, 2, 2]}},"
    " \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.3, \"density\": 1000},"
    " \"fixed\": [{\"box\": [[-0.01, -1, -1], [0.01, 1, 1]]}]}],"
    " \"gravity\": [0, -9.81, 0], \"damping\": {\"mass\": 0.5},"
    " \"time\": {\"step\": 0.01, \"duration\": 1.5},"
    " \"rom\": {\"basis\": \"pod\", \"size\": 10, \"koopman\": {\"rank\": 30, \"clamp\": true,"
    "   \"trajectories\": [{}, {\"gravity\": [0, 0, -9.81]}]},"
    "   \"asset\": {\"show\": \"all\", \"groups\": [{\"name\": \"tip\", \"box\": [[0.95, -1, -1], [1.1, 1, 1]]}]}}}";

typedef struct {
    rk_scene scene;
    rk_scene_sim sim;
    rk_koopman k;
    double *accel;
    unsigned char *asset;
    size_t bytes;
    void *arena;
    romrt_model *m;
} fixture;

static void fixture_close(fixture *f)
{
    rk_koopman_free(&f->k);
    rk_scene_sim_free(&f->sim);
    rk_scene_free(&f->scene);
    free(f->accel);
    free(f->asset);
    free(f->arena);
}

static int open_asset(fixture *f, rk_error *err)
{
    romrt_error rerr;
    size_t need;
    free(f->arena);
    f->arena = NULL;
    if (romrt_arena_size(f->asset, f->bytes, &need, &rerr) != ROMRT_OK) return rk_fail(err, "arena size: %s", rerr.message);
    f->arena = aligned_alloc(16, (need + 15) / 16 * 16);
    if (!f->arena || romrt_open(f->asset, f->bytes, f->arena, need, &f->m, &rerr) != ROMRT_OK)
        return rk_fail(err, "open: %s", rerr.message);
    return 0;
}

/* The scene's operator (two trajectories: gravity along -y and -z), baked with every vertex shown
 * in source order (show all: stored vertex i is source vertex i). */
static int fixture_open(fixture *f, rk_error *err)
{
    memset(f, 0, sizeof *f);
    rk_koopman_scene_info ki;
    if (rk_scene_parse(scene_json, "test.json", &f->scene, err) || rk_scene_build(&f->scene, &f->sim, err) ||
        rk_koopman_scene_fit(&f->sim, &f->scene.entries[0].koop, NULL, NULL, 0, &f->k, &ki, err))
        return -1;
    const rk_asset_options *ao = &f->scene.entries[0].asset;
    int nv = f->sim.mesh.nv;
    f->accel = rk_calloc((size_t)3 * nv, sizeof(double), err);
    if (!f->accel) return -1;
    for (int i = 0; i < 3 * nv; i++) f->accel[i] = f->sim.options.gravity[i % 3];
    rk_koopman_geometry g = {.nv = nv, .X = f->sim.mesh.X, .vertex_mass = f->sim.fem.vertex_mass, .accel = f->accel,
                             .trajectories = 2};
    rombin_writer w;
    rombin_writer_init(&w, REAL_TYPE, 0);
    int rc = rk_asset_bake_koopman(&f->k, &g, ao, NULL, &w, NULL, err) || rombin_serialize(&w, &f->asset, &f->bytes, err);
    rombin_writer_free(&w);
    return rc ? -1 : open_asset(f, err);
}

/* max |runtime - library| / max |library displacement| over the shown vertices. */
static double difference(const fixture *f, const double *z)
{
    int nv = f->sim.mesh.nv;
    double *u = calloc((size_t)3 * nv, sizeof(double)), worst = 0, scale = 1e-300;
    romrt_real *x = calloc((size_t)3 * nv, sizeof(romrt_real));
    rk_koopman_positions(&f->k, z, u);
    romrt_positions(f->m, x, nv, 3);
    for (int i = 0; i < 3 * nv; i++) {
        worst = fmax(worst, fabs((double)x[i] - f->sim.mesh.X[i] - u[i]));
        scale = fmax(scale, fabs(u[i]));
    }
    free(u);
    free(x);
    return worst / scale;
}

/* The library's training step: the impulse a h^2 (Eq. 19), then K, damped by (1 - damping). */
static void library_step(const fixture *f, const double *a, double damping, double *z)
{
    rk_koopman_impulse(&f->k, a, z);
    rk_koopman_advance(&f->k, z, 1, 1, damping);
}

TEST(steps_as_the_library_does)
{
    rk_error err;
    fixture f;
    CHECK_OK(fixture_open(&f, &err));
    CHECK(romrt_model_kind(f.m) == ROMRT_KIND_KOOPMAN, "kind %d", (int)romrt_model_kind(f.m));
    double *z = calloc((size_t)f.k.r, sizeof(double)), worst = 0;
    for (int t = 0; t < 150; t++) {
        CHECK(romrt_step(f.m, NULL) == ROMRT_OK, "step %d", t);
        library_step(&f, f.accel, 0, z);
        worst = fmax(worst, difference(&f, z));
    }
    printf("# 150 steps under gravity, r = %d: runtime against library %.2e (tol %.0e)\n", f.k.r, worst, TOL_LIBRARY);
    CHECK(worst < TOL_LIBRARY, "runtime differs from the library by %.3g", worst);
    /* a force on the tip group: the runtime spreads it evenly, the library takes f / m per vertex */
    int tip = romrt_find_group(f.m, "tip");
    romrt_real F[3] = {0, 0, 2};
    CHECK(tip >= 0 && romrt_add_force(f.m, tip, F) == ROMRT_OK, "tip group %d", tip);
    int nv = f.sim.mesh.nv, count = 0;
    double *a = calloc((size_t)3 * nv, sizeof(double));
    for (int v = 0; v < nv; v++) count += f.sim.mesh.X[3 * v] > 0.95;
    for (int v = 0; v < nv; v++) {
        for (int c = 0; c < 3; c++) a[3 * v + c] = f.accel[3 * v + c];
        if (f.sim.mesh.X[3 * v] > 0.95) a[3 * v + 2] += F[2] / count / f.sim.fem.vertex_mass[v];
    }
    worst = 0;
    for (int t = 0; t < 50; t++) {
        romrt_step(f.m, NULL);
        library_step(&f, a, 0, z);
        worst = fmax(worst, difference(&f, z));
    }
    printf("# 50 steps pushed at the tip: %.2e\n", worst);
    CHECK(worst < TOL_LIBRARY, "pushed: runtime differs from the library by %.3g", worst);
    /* 1% damping (Sec. 7.2), then the time step rescaled to 3h (Eq. 21): under gravity, one step
     * of 3h is three training steps exactly (the library's closed-form forced map) */
    romrt_clear_forces(f.m);
    CHECK(romrt_set_damping(f.m, (romrt_real)0.01, NULL) == ROMRT_OK, "damping refused");
    worst = 0;
    for (int t = 0; t < 50; t++) {
        romrt_step(f.m, NULL);
        library_step(&f, f.accel, 0.01, z);
        worst = fmax(worst, difference(&f, z));
    }
    printf("# 50 steps with 1%% damping: %.2e\n", worst);
    CHECK(worst < TOL_LIBRARY, "damped: runtime differs from the library by %.3g", worst);
    CHECK(romrt_set_damping(f.m, 0, NULL) == ROMRT_OK &&
          romrt_set_time_step(f.m, (romrt_real)(3 * f.k.h), NULL) == ROMRT_OK, "edits refused");
    worst = 0;
    for (int t = 0; t < 50; t++) {
        romrt_step(f.m, NULL);
        CHECK_OK(rk_koopman_forced(&f.k, 3, f.accel, z, &err));
        worst = fmax(worst, difference(&f, z));
    }
    printf("# 50 steps of 3h under gravity against 150 training steps: %.2e\n", worst);
    CHECK(worst < TOL_LIBRARY, "rescaled: runtime differs from the library by %.3g", worst);
    CHECK(fabs((double)romrt_time_step(f.m) - 3 * f.k.h) < 1e-6, "time step %g", (double)romrt_time_step(f.m));
    CHECK(romrt_set_time_step(f.m, -1, NULL) == ROMRT_E_ARGUMENT && romrt_set_damping(f.m, 1, NULL) == ROMRT_E_ARGUMENT,
          "nonsense edits accepted");
    free(a);
    free(z);
    fixture_close(&f);
}

/* A jump of n steps against n single steps from the same state, forces held. */
static double jump_against_steps(fixture *f, unsigned long n)
{
    int nv = f->sim.mesh.nv, count = romrt_state_size(f->m);
    romrt_real *state = calloc((size_t)count, sizeof(romrt_real));
    romrt_real *a = calloc((size_t)3 * nv, sizeof(romrt_real)), *b = calloc((size_t)3 * nv, sizeof(romrt_real));
    romrt_get_state(f->m, state, count);
    for (unsigned long s = 0; s < n; s++) romrt_step(f->m, NULL);
    romrt_positions(f->m, a, nv, 3);
    romrt_set_state(f->m, state, count);
    romrt_jump(f->m, n, NULL);
    romrt_positions(f->m, b, nv, 3);
    double worst = 0, scale = 1e-300;
    for (int i = 0; i < 3 * nv; i++) {
        worst = fmax(worst, fabs((double)a[i] - b[i]));
        scale = fmax(scale, fabs((double)a[i] - f->sim.mesh.X[i]));
    }
    romrt_set_state(f->m, state, count);
    free(state);
    free(a);
    free(b);
    return worst / scale;
}

TEST(a_jump_equals_single_steps)
{
    rk_error err;
    fixture f;
    CHECK_OK(fixture_open(&f, &err));
    romrt_real F[3] = {1, 0, 0};
    for (int t = 0; t < 40; t++) romrt_step(f.m, NULL);
    romrt_add_force(f.m, romrt_find_group(f.m, "tip"), F);
    static const unsigned long N[] = {1, 7, 1000, 100000};
    for (int i = 0; i < 4; i++) {
        double d = jump_against_steps(&f, N[i]);
        printf("# jump of %lu steps against single steps: %.2e (tol %.0e)\n", N[i], d, TOL_JUMP);
        CHECK(d < TOL_JUMP, "jump of %lu differs by %.3g", N[i], d);
    }
    double t0 = romrt_time(f.m);
    CHECK(romrt_jump(f.m, 250, NULL) == ROMRT_OK && fabs(romrt_time(f.m) - t0 - 2.5) < 1e-4,
          "the clock moved %g s for 250 steps of 0.01", romrt_time(f.m) - t0);
    fixture_close(&f);
}

/* Two hours at 60 Hz, 432,000 steps (O(r) each): the clock reads steps x h, where a float running
 * sum of 1/60 s reads 7183.14 s (16.9 s short, measured); and an engine deforming on the GPU gets
 * the asset's output rows (KOUT) and the eigen-coordinates y, X + KOUT y = romrt_positions. */
TEST(two_hours_of_steps_keep_the_clock_and_the_rows)
{
    rk_error err;
    fixture f;
    CHECK_OK(fixture_open(&f, &err));
    romrt_error rerr;
    CHECK(romrt_set_time_step(f.m, (romrt_real)(1.0 / 60), &rerr) == ROMRT_OK, "%s", rerr.message);
    romrt_real F[3] = {0, 0.5, 0};
    romrt_add_force(f.m, romrt_find_group(f.m, "tip"), F);
    const long N = 432000;
    for (long k = 0; k < N; k++)
        if (romrt_step(f.m, &rerr) != ROMRT_OK) CHECK(0, "step %ld: %s", k, rerr.message);
    double h = (double)romrt_time_step(f.m), want = (double)N * h;
    float sum = 0;
    for (long k = 0; k < N; k++) sum += (float)h;
    printf("# %ld steps of %.9g s: clock %.9f s, steps x h %.9f s (a float sum: %.3f s)\n", N, h, romrt_time(f.m), want,
           (double)sum);
    CHECK(fabs(romrt_time(f.m) - want) <= 1e-9 * want, "the clock reads %.9f s after %ld steps of %.9g s", romrt_time(f.m),
          N, h);
    /* a jump and a change of step keep counting from where the clock is */
    CHECK(romrt_jump(f.m, 1000, &rerr) == ROMRT_OK && romrt_set_time_step(f.m, (romrt_real)0.02, &rerr) == ROMRT_OK &&
              romrt_step(f.m, &rerr) == ROMRT_OK, "%s", rerr.message);
    want += 1000 * h + (double)(romrt_real)0.02;
    CHECK(fabs(romrt_time(f.m) - want) <= 1e-9 * want, "after a jump and a new step: %.9f s, want %.9f", romrt_time(f.m), want);
    double d = rt_gpu_mismatch(f.m);
    printf("# Koopman (r = %d): |X + KOUT y - positions| %.2e of the motion\n", romrt_reduced_size(f.m), d);
#ifdef ROMRT_DOUBLE
    CHECK(d >= 0 && d < 1e-12, "X + KOUT y differs by %g", d);
#else
    CHECK(d >= 0 && d < 1e-5, "X + KOUT y differs by %g", d);
#endif
    fixture_close(&f);
}

static void put_u32(unsigned char *p, uint32_t v)
{
    for (int b = 0; b < 4; b++) p[b] = (unsigned char)(v >> (8 * b));
}

/* Patches KEIG value i of the asset (recomputing the chunk CRC) and expects romrt_open to refuse. */
static int refuses_keig(fixture *f, int i, double value, const char *needle)
{
    rombin_file file;
    rombin_error e;
    rombin_chunk c;
    unsigned char *copy = aligned_alloc(16, (f->bytes + 15) / 16 * 16);
    memcpy(copy, f->asset, f->bytes);
    rombin_open(&file, copy, f->bytes, NULL, &e);
    rombin_find(&file, ROMBIN_KEIG, &c);
    unsigned char *p = (unsigned char *)c.data;
    if (REAL_TYPE == ROMBIN_REAL_F32) {
        float x = (float)value;
        memcpy(p + 4 * i, &x, 4);
    } else {
        memcpy(p + 8 * i, &value, 8);
    }
    /* the entry's CRC, then the table's (formats/ROMBIN.md) */
    for (unsigned k = 0; k < file.count; k++) {
        rombin_chunk ck;
        rombin_chunk_get(&file, k, &ck);
        if (strcmp(ck.id, ROMBIN_KEIG) == 0) put_u32(copy + ROMBIN_HEADER_BYTES + ROMBIN_ENTRY_BYTES * k + ROMBIN_E_CRC,
                                                    rombin_crc32(0, c.data, (size_t)c.stored));
    }
    uint32_t table = rombin_crc32(0, copy, ROMBIN_H_TABLE_CRC);
    table = rombin_crc32(table, copy + ROMBIN_HEADER_BYTES, ROMBIN_ENTRY_BYTES * (size_t)file.count);
    put_u32(copy + ROMBIN_H_TABLE_CRC, table);
    size_t need;
    romrt_error rerr;
    romrt_status st = romrt_arena_size(copy, f->bytes, &need, &rerr);
    void *arena = aligned_alloc(16, 1 << 20);
    romrt_model *m;
    if (st == ROMRT_OK) st = romrt_open(copy, f->bytes, arena, 1 << 20, &m, &rerr);
    int ok = st == ROMRT_E_MODEL && strstr(rerr.message, needle) && strcmp(rerr.chunk, "KEIG") == 0;
    if (!ok) printf("# KEIG[%d] = %g: status %d, %s\n", i, value, (int)st, rerr.message);
    free(copy);
    free(arena);
    return ok;
}

TEST(damaged_eigenvalues_are_refused)
{
    rk_error err;
    fixture f;
    CHECK_OK(fixture_open(&f, &err));
    int pair = -1;
    for (int j = 0; j < f.k.r && pair < 0; j++)
        if (f.k.lambda_im[j] > 0) pair = j;
    CHECK(pair >= 0, "no complex pair in the fitted operator");
    if (pair >= 0) {
        CHECK(refuses_keig(&f, 2 * pair + 3, 0.5, "conjugate"), "a pair whose conjugate is wrong was accepted");
        CHECK(refuses_keig(&f, 2 * pair + 1, -0.25, "conjugate"), "a pair starting with a negative imaginary part");
    }
    CHECK(refuses_keig(&f, 0, 12.0, "|lambda| >= 10"), "a huge eigenvalue was accepted");
    fixture_close(&f);
}

TEST(open_kind_names_a_missing_model)
{
    rk_error err;
    fixture f;
    CHECK_OK(fixture_open(&f, &err));
    size_t need;
    romrt_error rerr;
    romrt_model *m;
    CHECK(romrt_arena_size_kind(f.asset, f.bytes, ROMRT_KIND_KOOPMAN, &need, &rerr) == ROMRT_OK, "%s", rerr.message);
    CHECK(romrt_open_kind(f.asset, f.bytes, ROMRT_KIND_KOOPMAN, f.arena, need, &m, &rerr) == ROMRT_OK &&
              romrt_model_kind(m) == ROMRT_KIND_KOOPMAN, "%s", rerr.message);
    CHECK(romrt_arena_size_kind(f.asset, f.bytes, ROMRT_KIND_REDUCED, &need, &rerr) == ROMRT_E_UNSUPPORTED &&
              strstr(rerr.message, "has no reduced model"), "a Koopman-only asset: %s", rerr.message);
    CHECK(romrt_arena_size_kind(f.asset, f.bytes, (romrt_kind)7, &need, &rerr) == ROMRT_E_ARGUMENT, "kind 7 accepted");
    fixture_close(&f);
}

int main(void)
{
    RUN(steps_as_the_library_does);
    RUN(a_jump_equals_single_steps);
    RUN(damaged_eigenvalues_are_refused);
    RUN(two_hours_of_steps_keep_the_clock_and_the_rows);
    RUN(open_kind_names_a_missing_model);
    return test_finish();
}
