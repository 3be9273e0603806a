/* What an engine relies on in romrt.h (issue 21): romrt_positions and the other buffer writers
 * take the buffer's capacity (and a stride) and refuse a short one writing nothing, checked with
 * canaries around and inside the buffers (make test-sanitize runs this under AddressSanitizer, and
 * tests/integration/runtime_abi.sh builds the runtime with ASan for the same calls on exact-size
 * heap buffers); the rest positions and basis rows of the shown vertices give x = X + U q as
 * romrt_positions does, for dense rows and for a skinning basis stored as its weights; the clock
 * kept in double across a saved state; time-driven pins (a twist) following that clock two hours
 * in; the version. Built twice: float and double (test_runtime_engine_double). */
#include "runtime_fixture.h"
#include "runtime_gpu.h"

#ifdef ROMRT_DOUBLE
#define ASSET_REAL ROMBIN_REAL_F64
#define GPU_TOL 1e-12
#else
#define ASSET_REAL ROMBIN_REAL_F32
#define GPU_TOL 1e-5
#endif

#define CANARY ((romrt_real)-1234.5)

static const char *cantilever =
    "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1, 0.1, 0.1], \"cells\": [10, 2, 2]}},"
    " \"material\": {\"model\": \"neohookean\", \"young\": 2e5, \"poisson\": 0.4, \"density\": 1000},"
    " \"fixed\": [{\"box\": [[-1, -1, -1], [0.01, 2, 2]]}]}],"
    " \"gravity\": [0, -9.81, 0], \"damping\": {\"mass\": 0.5},"
    " \"time\": {\"step\": 0.01, \"duration\": 0.3},"
    " \"rom\": {\"basis\": \"modes\", \"size\": 10, \"cubature\": {\"tolerance\": 0.02},"
    "  \"asset\": {\"groups\": [{\"name\": \"tip\", \"box\": [[0.99, -1, -1], [2, 1, 1]]}]}}}";

/* A skinning block thrown onto a plane: its asset stores the weights (SKIN, WGHT), not rows. */
static const char *skinned =
    "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.6, 0.1, 0.1], \"cells\": [6, 2, 2]}},"
    " \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.4, \"density\": 500},"
    " \"velocity\": [0, -0.2, 0.3]}],"
    " \"gravity\": [0, -9.81, 0], \"obstacles\": [{\"plane\": {\"point\": [0, -0.02, 0], \"normal\": [0, 1, 0]}}],"
    " \"time\": {\"step\": 0.01, \"duration\": 0.3, \"integrator\": \"bdf2\"},"
    " \"rom\": {\"basis\": \"skinning\", \"size\": 3, \"cubature\": {\"tolerance\": 0.05}}}";

/* One end twisting at 90 degrees a second (a period of 4 s): a pin driven by the clock. */
static const char *twisting =
    "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.6, 0.1, 0.1], \"cells\": [6, 2, 2]}},"
    " \"material\": {\"model\": \"stvk\", \"young\": 1e5, \"poisson\": 0.3, \"density\": 500},"
    " \"fixed\": [{\"box\": [[-1, -1, -1], [0.01, 1, 1]]}],"
    " \"moving\": [{\"box\": [[0.59, -1, -1], [1, 1, 1]], \"twist\": {\"axis\": [1, 0, 0], \"degrees_per_second\": 90}}]}],"
    " \"gravity\": [0, 0, 0], \"time\": {\"step\": 0.01, \"duration\": 0.2},"
    " \"rom\": {\"basis\": \"modes\", \"size\": 12}}";

static int all_canary(const romrt_real *b, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (b[i] != CANARY) return 0;
    return 1;
}

static void fill(romrt_real *b, size_t n)
{
    for (size_t i = 0; i < n; i++) b[i] = CANARY;
}

TEST(short_buffers_are_refused_and_left_alone)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture f;
    CHECK_OK(rt_fixture_open(&f, cantilever, ASSET_REAL, &err, &rerr));
    const romrt_real push[3] = {0, 0, 2};
    size_t tip;
    CHECK(romrt_find_group(f.m, "tip", &tip, &rerr) == ROMRT_OK && romrt_add_force(f.m, tip, push, &rerr) == ROMRT_OK,
          "push: %s", rerr.message);
    for (int k = 0; k < 10; k++) CHECK(romrt_step(f.m, &rerr) == ROMRT_OK, "%s", rerr.message);
    size_t n = romrt_shown_count(f.m), r = romrt_reduced_size(f.m), S = 5, pad = 8;
    size_t room = S * (n + 2) + pad, nr = 3 * n * r, need = S * (n - 1) + 3;
    romrt_real *buf = malloc(sizeof *buf * room), *packed = malloc(sizeof *packed * 3 * n);
    romrt_real *rows = malloc(sizeof *rows * (nr + pad)), *q = malloc(sizeof *q * (r + pad));
    CHECK(buf && packed && rows && q && n > 1, "setup");
    /* too small a capacity (in reals), too small a stride, NULL: refused, nothing written, the
     * error says why */
    romrt_status (*const writers[2])(const romrt_model *, romrt_real *, size_t, size_t, romrt_error *) = {
        romrt_positions, romrt_rest_positions};
    for (int w = 0; w < 2; w++) {
        fill(buf, room);
        rerr.message[0] = 0;
        CHECK(writers[w](f.m, buf, 3 * n - 1, 3, &rerr) == ROMRT_E_ARGUMENT && all_canary(buf, room) &&
                  rerr.status == ROMRT_E_ARGUMENT && strstr(rerr.message, "needed"),
              "writer %d: capacity 3 n - 1: %s", w, rerr.message);
        CHECK(writers[w](f.m, buf, need - 1, S, NULL) == ROMRT_E_ARGUMENT && all_canary(buf, room),
              "writer %d: stride %zu, one real short", w, S);
        CHECK(writers[w](f.m, buf, 0, 3, NULL) == ROMRT_E_ARGUMENT && all_canary(buf, room), "writer %d: capacity 0", w);
        CHECK(writers[w](f.m, buf, (size_t)-1, 2, NULL) == ROMRT_E_ARGUMENT && all_canary(buf, room), "writer %d: stride 2", w);
        CHECK(writers[w](f.m, buf, (size_t)-1, 0, NULL) == ROMRT_E_ARGUMENT && all_canary(buf, room), "writer %d: stride 0", w);
        CHECK(writers[w](f.m, buf, (size_t)-1, (size_t)-1 / 2, NULL) == ROMRT_E_ARGUMENT && all_canary(buf, room),
              "writer %d: a stride whose span overflows", w);
        CHECK(writers[w](f.m, NULL, 3 * n, 3, &rerr) == ROMRT_E_ARGUMENT && strstr(rerr.message, "NULL") &&
                  writers[w](NULL, buf, 3 * n, 3, &rerr) == ROMRT_E_ARGUMENT && strstr(rerr.message, "model"),
              "writer %d: NULL: %s", w, rerr.message);
        /* interleaved: stride 5, exactly the reals the last vertex needs: the xyz of each, nothing
         * between or after */
        CHECK(writers[w](f.m, packed, 3 * n, 3, NULL) == ROMRT_OK, "writer %d: packed", w);
        CHECK(writers[w](f.m, buf, need, S, NULL) == ROMRT_OK, "writer %d: stride %zu", w, S);
        for (size_t i = 0; i < n; i++) {
            CHECK(memcmp(buf + S * i, packed + 3 * i, 3 * sizeof *buf) == 0,
                  "writer %d: vertex %zu differs from the packed call", w, i);
            CHECK(all_canary(buf + S * i + 3, i + 1 < n ? S - 3 : 0), "writer %d: wrote between vertices at %zu", w, i);
        }
        CHECK(all_canary(buf + need, room - need), "writer %d: wrote past vertex n - 1", w);
        /* a larger capacity still writes the shown vertices only */
        fill(buf, room);
        CHECK(writers[w](f.m, buf, 3 * n + 6, 3, NULL) == ROMRT_OK && all_canary(buf + 3 * n, room - 3 * n),
              "writer %d: wrote past the shown vertices", w);
    }
    /* basis rows: 3 n r reals */
    fill(rows, nr + pad);
    CHECK(romrt_basis_rows(f.m, rows, nr - 1, NULL) == ROMRT_E_ARGUMENT && all_canary(rows, nr + pad), "rows: one short");
    CHECK(romrt_basis_rows(f.m, rows, 0, NULL) == ROMRT_E_ARGUMENT && all_canary(rows, nr + pad), "rows: capacity 0");
    CHECK(romrt_basis_rows(f.m, rows, nr, NULL) == ROMRT_OK && all_canary(rows + nr, pad), "rows: wrote past 3 n r");
    CHECK(!all_canary(rows, 1), "rows: nothing written");
    /* q: r reals */
    fill(q, (size_t)r + pad);
    CHECK(romrt_reduced_coordinates(f.m, q, r - 1, NULL) == ROMRT_E_ARGUMENT && all_canary(q, r + pad), "q: one short");
    CHECK(romrt_reduced_coordinates(f.m, q, r + 3, NULL) == ROMRT_OK && all_canary(q + r, pad), "q: wrote past r");
    free(buf), free(packed), free(rows), free(q);
    rt_fixture_close(&f);
}

/* x = X + U q from the accessors against romrt_positions, at rest and after pushed steps. */
static void gpu_check(const char *name, const char *json, int weights, int steps)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture f;
    CHECK_OK(rt_fixture_open(&f, json, ASSET_REAL, &err, &rerr));
    rombin_file file;
    rombin_chunk c;
    rombin_error e;
    CHECK(rombin_open(&file, f.asset, f.bytes, NULL, &e) == 0, "%s", e.message);
    CHECK(rombin_find(&file, ROMBIN_WGHT, &c) == weights && rombin_find(&file, ROMBIN_ROWS, &c) == !weights,
          "%s: expected an asset with %s", name, weights ? "weights (WGHT), no ROWS" : "ROWS");
    CHECK(rt_gpu_mismatch(f.m) == 0, "%s at rest: %g", name, rt_gpu_mismatch(f.m));
    const romrt_real push[3] = {0, 1, 1};
    CHECK(romrt_add_vertex_force(f.m, romrt_shown_count(f.m) - 1, push, NULL) == ROMRT_OK, "push");
    for (int k = 0; k < steps; k++) CHECK(romrt_step(f.m, &rerr) == ROMRT_OK, "%s", rerr.message);
    double d = rt_gpu_mismatch(f.m);
    printf("# %s (r = %d, %d shown): |X + U q - positions| %.2e of the motion (tol %.0e)\n", name,
           (int)romrt_reduced_size(f.m), (int)romrt_shown_count(f.m), d, GPU_TOL);
    CHECK(d >= 0 && d < GPU_TOL, "%s: %g", name, d);
    rt_fixture_close(&f);
}

TEST(rest_positions_and_rows_give_the_positions) { gpu_check("modes cantilever, rows", cantilever, 0, 20); }
TEST(skinning_weights_give_dense_rows) { gpu_check("skinning block, weights", skinned, 1, 20); }

/* The clock through a saved state: t = 7200 + 1/3 s survives romrt_set_state / romrt_get_state
 * (in float as a pair of floats, ~48 bits), and the state reads back bit for bit. */
TEST(the_state_keeps_the_double_clock)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture f;
    CHECK_OK(rt_fixture_open(&f, cantilever, ASSET_REAL, &err, &rerr));
    int ns = romrt_state_size(f.m);
    romrt_real *s = calloc((size_t)ns, sizeof *s), *back = calloc((size_t)ns, sizeof *back);
    CHECK(s && back && romrt_get_state(f.m, s, ns, NULL) == ROMRT_OK, "get_state");
    double want = 7200.0 + 1.0 / 3.0;
    s[0] = (romrt_real)want;
    s[1] = (romrt_real)(want - (double)s[0]);
    CHECK(romrt_set_state(f.m, s, ns, NULL) == ROMRT_OK, "set_state");
    CHECK(fabs(romrt_time(f.m) - want) < 1e-9, "clock %.12f after setting %.12f", romrt_time(f.m), want);
    CHECK(romrt_step(f.m, &rerr) == ROMRT_OK, "%s", rerr.message);
    double after = want + (double)romrt_time_step(f.m);
    CHECK(fabs(romrt_time(f.m) - after) < 1e-9, "clock %.12f a step later, want %.12f", romrt_time(f.m), after);
    CHECK(romrt_get_state(f.m, s, ns, NULL) == ROMRT_OK && romrt_set_state(f.m, s, ns, NULL) == ROMRT_OK &&
              romrt_get_state(f.m, back, ns, NULL) == ROMRT_OK && memcmp(s, back, sizeof *s * (size_t)ns) == 0,
          "a saved state does not read back the same");
    romrt_reset(f.m, NULL);
    CHECK(romrt_time(f.m) == 0, "reset: clock %g", romrt_time(f.m));
    free(s), free(back);
    rt_fixture_close(&f);
}

/* One step from rest at clock t0, the shown positions into x. */
static int step_from(romrt_model *m, double t0, romrt_real *state, int ns, romrt_real *x, int n)
{
    romrt_reset(m, NULL);
    if (romrt_get_state(m, state, ns, NULL) != ROMRT_OK) return -1;
    state[0] = (romrt_real)t0;
    state[1] = (romrt_real)(t0 - (double)state[0]);
    if (romrt_set_state(m, state, ns, NULL) != ROMRT_OK || romrt_step(m, NULL) != ROMRT_OK) return -1;
    return romrt_positions(m, x, 3 * (size_t)n, 3, NULL) == ROMRT_OK ? 0 : -1;
}

/* The twist's pin 1800 whole periods in (two hours: 7200 s at 90 degrees a second, to the asset's
 * rounding of that rate) is where it is at 0 s: a step from rest then takes the step of the first
 * second to round-off. The clock a float running sum of 0.01 s would show after 720,000 steps
 * (7130.85 s, measured) puts the pin 69 s, a quarter turn, elsewhere; even one float rounding of
 * the clock near 7200 s (0.2 ms) is seen. */
TEST(time_driven_pins_follow_the_clock_two_hours_in)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture f;
    CHECK_OK(rt_fixture_open(&f, twisting, ASSET_REAL, &err, &rerr));
    int n = romrt_shown_count(f.m), ns = romrt_state_size(f.m);
    romrt_real *s = calloc((size_t)ns, sizeof *s), *a = calloc((size_t)3 * n, sizeof *a), *b = calloc((size_t)3 * n, sizeof *b);
    romrt_real *X = calloc((size_t)3 * n, sizeof *X);
    CHECK(s && a && b && X && romrt_rest_positions(f.m, X, 3 * (size_t)n, 3, NULL) == ROMRT_OK, "setup");
    double h = (double)romrt_time_step(f.m), off[2], motion = 0;
    const double T = 1800 * 2 * 3.14159265358979323846 / (double)(romrt_real)(3.14159265358979323846 / 2);
    const double late[2] = {T, T + (double)(float)(T + h) - (T + h)};
    CHECK(step_from(f.m, 0, s, ns, a, n) == 0, "step from 0 s");
    for (int i = 0; i < 3 * n; i++) motion = fmax(motion, fabs((double)a[i] - X[i]));
    for (int c = 0; c < 2; c++) {
        CHECK(step_from(f.m, late[c], s, ns, b, n) == 0, "step from %.6f s", late[c]);
        off[c] = 0;
        for (int i = 0; i < 3 * n; i++) off[c] = fmax(off[c], fabs((double)a[i] - b[i]));
        off[c] /= motion;
    }
    printf("# a step at %.9f s against one at 0 s: %.2e of the step's motion %.2e m; with the clock off by a float "
           "rounding (%.2e s): %.2e\n", T, off[0], motion, late[1] - late[0], off[1]);
    CHECK(motion > 1e-4, "the twist moved nothing (%g m)", motion);
#ifdef ROMRT_DOUBLE
    CHECK(off[0] < 1e-9, "two hours in, the pin is off by %g of the step", off[0]);
#else
    CHECK(off[0] < 1e-4, "two hours in, the pin is off by %g of the step", off[0]);
#endif
    CHECK(off[1] > 10 * off[0] && off[1] > 1e-4, "a clock off by %g s went unseen (%g)", late[1] - late[0], off[1]);
    free(s), free(a), free(b), free(X);
    rt_fixture_close(&f);
}

TEST(version_matches_the_header)
{
    CHECK(romrt_version() == ROMRT_VERSION_NUMBER, "library %d, header %d", romrt_version(), ROMRT_VERSION_NUMBER);
    CHECK(ROMRT_VERSION_NUMBER == ROMRT_VERSION_MAJOR * 10000 + ROMRT_VERSION_MINOR * 100 + ROMRT_VERSION_PATCH,
          "the number");
}

int main(void)
{
    RUN(short_buffers_are_refused_and_left_alone);
    RUN(rest_positions_and_rows_give_the_positions);
    RUN(skinning_weights_give_dense_rows);
    RUN(the_state_keeps_the_double_clock);
    RUN(time_driven_pins_follow_the_clock_two_hours_in);
    RUN(version_matches_the_header);
    return test_finish();
}
