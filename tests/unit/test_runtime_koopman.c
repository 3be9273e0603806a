/* The runtime steps a Koopman asset as the precompute's operator does: single steps, forces as
 * impulses, the time-step rescale of Eq. 21 and the damping edit of Sec. 7.2 against the
 * library's rollout; jumps of N steps against N single steps, and jumps of up to 10^9 steps over
 * eigenvalues at and next to 1, -1 and 0 against repeated squaring in long double; damaged
 * eigenvalue tables refused. Built twice: in float (the default runtime) and in double
 * (test_runtime_koopman_double), where the jump must match single steps to 1e-6 relative. */
#include <float.h>
#include <stdint.h>

#include "testlib.h"
#include "asset_patch.h"
#include "asset/asset.h"
#include "formats/rombin_read.h"
#include "koopman/koopman.h"
#include "pipeline/pipeline.h"
#include "pipeline/method_koopman.h"
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
        rk_koopman_scene_fit(&f->sim, rk_koopman_of(&f->scene.entries[0]), NULL, NULL, 0, &f->k, &ki, err))
        return -1;
    const rk_asset_options *ao = &f->scene.entries[0].asset;
    int nv = f->sim.mesh.nv;
    f->accel = rk_calloc((size_t)3 * nv, sizeof(double), err);
    if (!f->accel) return -1;
    for (int i = 0; i < 3 * nv; i++) f->accel[i] = f->sim.options.gravity[i % 3];
    rk_koopman_geometry g = {.nv = nv, .X = f->sim.mesh.X, .vertex_mass = f->sim.fem.vertex_mass, .accel = f->accel,
                             .trajectories = 2};
    rk_asset_options o = *ao;
    o.real_type = REAL_TYPE;
    o.compress = 0;
    return rk_asset_koopman_serialized(&f->k, &g, &o, NULL, NULL, &f->asset, &f->bytes, err) ? -1 : open_asset(f, err);
}

/* max |runtime - library| / max |library displacement| over the shown vertices. */
static double difference(const fixture *f, const double *z)
{
    int nv = f->sim.mesh.nv;
    double *u = calloc((size_t)3 * nv, sizeof(double)), worst = 0, scale = 1e-300;
    romrt_real *x = calloc((size_t)3 * nv, sizeof(romrt_real));
    rk_koopman_positions(&f->k, z, u);
    romrt_positions(f->m, x, 3 * (size_t)nv, 3, NULL);
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

/* The force f on the asset's "tip" group. */
static romrt_status koopman_push_tip(romrt_model *m, const romrt_real f[3])
{
    size_t tip;
    romrt_status st = romrt_find_group(m, "tip", &tip, NULL);
    return st ? st : romrt_add_force(m, tip, f, NULL);
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
    size_t tip;
    romrt_real F[3] = {0, 0, 2};
    CHECK(romrt_find_group(f.m, "tip", &tip, NULL) == ROMRT_OK && romrt_add_force(f.m, tip, F, NULL) == ROMRT_OK,
          "tip group");
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
    romrt_clear_forces(f.m, NULL);
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
    romrt_get_state(f->m, state, count, NULL);
    for (unsigned long s = 0; s < n; s++) romrt_step(f->m, NULL);
    romrt_positions(f->m, a, 3 * (size_t)nv, 3, NULL);
    romrt_set_state(f->m, state, count, NULL);
    romrt_jump(f->m, n, NULL);
    romrt_positions(f->m, b, 3 * (size_t)nv, 3, NULL);
    double worst = 0, scale = 1e-300;
    for (int i = 0; i < 3 * nv; i++) {
        worst = fmax(worst, fabs((double)a[i] - b[i]));
        scale = fmax(scale, fabs((double)a[i] - f->sim.mesh.X[i]));
    }
    romrt_set_state(f->m, state, count, NULL);
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
    CHECK(koopman_push_tip(f.m, F) == ROMRT_OK, "push");
#ifdef ROMRT_DOUBLE
    /* in double, 10^6 single steps too (float's own steps drift by more than TOL_JUMP by then) */
    static const unsigned long N[] = {1, 7, 1000, 100000, 1000000};
#else
    static const unsigned long N[] = {1, 7, 1000, 100000};
#endif
    for (int i = 0; i < (int)(sizeof N / sizeof N[0]); i++) {
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
    CHECK(koopman_push_tip(f.m, F) == ROMRT_OK, "push");
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
    printf("# Koopman (r = %d): |X + KOUT y - positions| %.2e of the motion\n", (int)romrt_reduced_size(f.m), d);
#ifdef ROMRT_DOUBLE
    CHECK(d >= 0 && d < 1e-12, "X + KOUT y differs by %g", d);
#else
    CHECK(d >= 0 && d < 1e-5, "X + KOUT y differs by %g", d);
#endif
    fixture_close(&f);
}

/* A copy of the asset (aligned, malloc'd) with KEIG values `at`.. replaced by `values` (n of them,
 * in the asset's real type; asset_patch.h recomputes the CRCs). */
static unsigned char *patched_keig(const fixture *f, int at, const double *values, int n)
{
    unsigned char *copy = aligned_alloc(16, (f->bytes + 15) / 16 * 16);
    memcpy(copy, f->asset, f->bytes);
    for (int i = 0; i < n; i++) {
        if (REAL_TYPE == ROMBIN_REAL_F32) {
            float x = (float)values[i];
            asset_patch_chunk(copy, ROMBIN_KEIG, 4 * (size_t)(at + i), &x, 4);
        } else {
            asset_patch_chunk(copy, ROMBIN_KEIG, 8 * (size_t)(at + i), &values[i], 8);
        }
    }
    return copy;
}

/* Patches KEIG value i of the asset and expects romrt_open to refuse. */
static int refuses_keig(fixture *f, int i, double value, const char *needle)
{
    unsigned char *copy = patched_keig(f, i, &value, 1);
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

/* A chunk's values as doubles (n of them). */
static void chunk_values(const unsigned char *asset, size_t bytes, const char *id, double *out, int n)
{
    rombin_file file;
    rombin_error e;
    rombin_chunk c;
    rombin_open(&file, asset, bytes, NULL, &e);
    rombin_find(&file, id, &c);
    for (int i = 0; i < n; i++) {
        if (REAL_TYPE == ROMBIN_REAL_F32) {
            float x;
            memcpy(&x, c.data + 4 * i, 4);
            out[i] = x;
        } else {
            memcpy(&out[i], c.data + 8 * i, 8);
        }
    }
}

typedef struct {
    long double re, im;
} ld_complex;

static ld_complex ld_mul(ld_complex a, ld_complex b)
{
    return (ld_complex){a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re};
}

/* The jump the runtime replaced, in long double: P = mu^N and G = sum_{k<N} mu^k by binary
 * powering from the top bit (doubling: S <- S + P S, P <- P^2; adding one: P <- P mu, S <- S + P,
 * with S = sum_{k=1}^n mu^k; G = 1 + S - P). */
static void squaring(ld_complex mu, unsigned long n, ld_complex *P, ld_complex *G)
{
    ld_complex S = {0, 0};
    unsigned long bit = 1;
    *P = (ld_complex){1, 0};
    while (bit <= n / 2) bit <<= 1;
    for (; n && bit; bit >>= 1) {
        ld_complex PS = ld_mul(*P, S);
        S.re += PS.re, S.im += PS.im;
        *P = ld_mul(*P, *P);
        if (n & bit) {
            *P = ld_mul(*P, mu);
            S.re += P->re, S.im += P->im;
        }
    }
    *G = (ld_complex){1 + S.re - P->re, S.im - P->im};
}

/* Eigenvalues where a closed form can go wrong, written over the fitted ones (the structure of
 * real slots and pairs kept): exactly 1 (the forcing sum is N), 1 - delta (mu^N - 1 and mu - 1
 * both tiny), -1 and -(1 - delta) (the sign is N's parity), 0 (0^0 = 1), -0.5, a pair on the unit
 * circle, a pair next to 1 (|mu| = 1 - delta, angle 1e-3), a pair next to -1, an ordinary pair.
 * delta: 1e-9 in double, 2^-20 in float (the float nearest to 1 - 1e-9 is 1). Then jumps of N = 1
 * .. 10^9 steps from a moving state with gravity and a pushed force held, against the squaring
 * above in long double from the same state, each block's error relative to the size of the
 * terms it sums, |P| |y| + |G| |c|. A jump computes its powers in double from the step factors,
 * so the error may grow like N eps_double (N arg mu and N log |mu| inherit their factor's rounding,
 * as repeated squaring's does), on top of the state's own rounding in romrt_real. */
TEST(a_jump_of_any_length_matches_repeated_squaring)
{
    rk_error err;
    fixture f;
    CHECK_OK(fixture_open(&f, &err));
    int r = f.k.r;
    double delta = REAL_TYPE == ROMBIN_REAL_F32 ? 0x1p-20 : 1e-9;
    const double reals[] = {1, 1 - delta, -1, -(1 - delta), 0, -0.5};
    const double pairs[][2] = {{cos(0.7), sin(0.7)}, {(1 - delta) * cos(1e-3), (1 - delta) * sin(1e-3)},
                               {cos(M_PI - 1e-3), sin(M_PI - 1e-3)}, {0.9 * cos(0.3), 0.9 * sin(0.3)}};
    const char *real_name[] = {"1", "1 - delta", "-1", "-(1 - delta)", "0", "-0.5"};
    const char *pair_name[] = {"e^0.7i", "(1 - delta) e^0.001i", "e^(pi - 0.001)i", "0.9 e^0.3i"};
    double *eig = calloc((size_t)2 * r, sizeof(double));
    int *kind = calloc((size_t)r, sizeof(int)), nreal = 0, npair = 0, pairs_left = 0;
    for (int j = 0; j < r; j++) pairs_left += f.k.lambda_im[j] > 0;
    for (int j = 0; j < r; j++) {
        if (f.k.lambda_im[j] < 0) continue; /* a conjugate, written with its pair */
        /* a pair's two slots hold two real eigenvalues instead while reals are short */
        int as_reals = f.k.lambda_im[j] > 0 && nreal < 6 && pairs_left > 4;
        pairs_left -= f.k.lambda_im[j] > 0;
        if (f.k.lambda_im[j] == 0 || as_reals) {
            for (int i = 0; i < (as_reals ? 2 : 1); i++, nreal++) {
                kind[j + i] = nreal % 6;
                eig[2 * (j + i)] = reals[nreal % 6];
            }
        } else { /* a pair's first, then its conjugate */
            kind[j] = kind[j + 1] = 6 + npair % 4;
            eig[2 * j] = eig[2 * j + 2] = pairs[npair % 4][0];
            eig[2 * j + 1] = pairs[npair % 4][1];
            eig[2 * j + 3] = -pairs[npair++ % 4][1];
        }
    }
    CHECK(nreal >= 6 && npair >= 4, "the fitted operator has %d real slots and %d pairs (6 and 4 needed)", nreal, npair);
    unsigned char *asset = patched_keig(&f, 0, eig, 2 * r);
    chunk_values(asset, f.bytes, ROMBIN_KEIG, eig, 2 * r); /* as stored (float in float) */
    double *acc = calloc((size_t)r, sizeof(double)), prm[8];
    chunk_values(asset, f.bytes, ROMBIN_KACC, acc, r);
    chunk_values(asset, f.bytes, ROMBIN_KPRM, prm, 8);
    size_t need;
    romrt_error rerr;
    romrt_model *m;
    void *arena = NULL;
    romrt_status st = romrt_arena_size(asset, f.bytes, &need, &rerr);
    if (st == ROMRT_OK) arena = aligned_alloc(16, (need + 15) / 16 * 16);
    if (arena) st = romrt_open(asset, f.bytes, arena, need, &m, &rerr);
    CHECK(arena && st == ROMRT_OK, "the patched asset: %s", rerr.message);
    /* a moving state: y_j = 0.01 (j + 1) / r, alternating in sign; a force held on the tip */
    int ns = romrt_state_size(m);
    romrt_real *state = calloc((size_t)ns, sizeof(romrt_real)), *y = calloc((size_t)r, sizeof(romrt_real));
    romrt_real F[3] = {0, 0.5, 1};
    CHECK(koopman_push_tip(m, F) == ROMRT_OK, "push");
    romrt_get_state(m, state, ns, NULL);
    int head = ns - 5 * r; /* the clock and have_prev, then y */
    for (int j = 0; j < r; j++) state[head + j] = (romrt_real)(0.01 * (j + 1) / r * (j % 2 ? -1 : 1));
    CHECK(romrt_set_state(m, state, ns, NULL) == ROMRT_OK, "set_state");
    static const unsigned long N[] = {1, 2, 7, 1000, 1000000, 1000000000};
    double eps = REAL_TYPE == ROMBIN_REAL_F32 ? FLT_EPSILON : DBL_EPSILON, worst_all = 0;
    for (int n = 0; n < 6; n++) {
        double worst_kind[10] = {0}, tol = 8 * eps + 16 * (double)N[n] * DBL_EPSILON;
        CHECK(romrt_set_state(m, state, ns, NULL) == ROMRT_OK && romrt_jump(m, N[n], &rerr) == ROMRT_OK, "jump %lu: %s",
              N[n], rerr.message);
        romrt_reduced_coordinates(m, y, r, NULL);
        long double h2 = (long double)prm[0] * prm[0];
        for (int j = 0; j < r; j++) {
            int pair = eig[2 * j + 1] != 0, w = pair ? 2 : 1;
            ld_complex mu = {eig[2 * j], eig[2 * j + 1]}, P, G;
            /* c = h^2 (KACC + f_app), then one step's sum of mu^t, mu (sigma = 1): the runtime's forcing */
            ld_complex cin = {h2 * (acc[j] + state[head + 4 * r + j]), pair ? h2 * (acc[j + 1] + state[head + 4 * r + j + 1]) : 0};
            ld_complex y0 = {state[head + j], pair ? state[head + j + 1] : 0};
            /* a pair's block acts on w = y_j - i y_{j+1} as multiplication by mu (runtime/koopman.c) */
            cin.im = -cin.im, y0.im = -y0.im;
            ld_complex c = ld_mul(mu, cin);
            squaring(mu, N[n], &P, &G);
            ld_complex ref = ld_mul(P, y0), Gc = ld_mul(G, c);
            ref.re += Gc.re, ref.im += Gc.im;
            long double got_re = y[j], got_im = pair ? -(long double)y[j + 1] : 0;
            long double size = hypotl(P.re, P.im) * hypotl(y0.re, y0.im) + hypotl(G.re, G.im) * hypotl(c.re, c.im);
            double e = (double)(hypotl(got_re - ref.re, got_im - ref.im) / (size > 0 ? size : 1));
            worst_kind[kind[j]] = fmax(worst_kind[kind[j]], e);
            j += w - 1;
        }
        printf("# N = %lu (tol %.1e):", N[n], tol);
        for (int k = 0; k < 10; k++) {
            printf(" %s %.1e%s", k < 6 ? real_name[k] : pair_name[k - 6], worst_kind[k], k < 9 ? "," : "\n");
            worst_all = fmax(worst_all, worst_kind[k] / tol);
            CHECK(worst_kind[k] <= tol, "N = %lu, mu = %s: off by %.3g (tol %.3g)", N[n], k < 6 ? real_name[k] :
                  pair_name[k - 6], worst_kind[k], tol);
        }
    }
    printf("# worst error over the tolerance: %.2f\n", worst_all);
    free(state);
    free(y);
    free(arena);
    free(asset);
    free(eig);
    free(kind);
    free(acc);
    fixture_close(&f);
}

int main(void)
{
    RUN(steps_as_the_library_does);
    RUN(a_jump_equals_single_steps);
    RUN(a_jump_of_any_length_matches_repeated_squaring);
    RUN(damaged_eigenvalues_are_refused);
    RUN(two_hours_of_steps_keep_the_clock_and_the_rows);
    RUN(open_kind_names_a_missing_model);
    return test_finish();
}
