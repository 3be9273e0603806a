/* The runtime's colliders (romrt_set_collider) against the reduced simulator's (rk_rom_set_collider)
 * on the same baked model and the same app moves: a sphere swept into a hanging block, a capsule
 * and a turned box, a block sliding on a plane with friction. Positions agree to PARITY_TOL
 * relative (double runtime, test_runtime_colliders_double) or float's tolerance; no collision
 * vertex is ever inside a collider; bad colliders are refused with a status and change nothing;
 * an asset baked without collision vertices refuses colliders.
 * On an asset with a collision surface (here a far sphere obstacle gives it one) the spheres,
 * capsules and boxes go through the exact obstacle path in both (runtime/shape_collider.c, and
 * the reduced simulator's contact model, precompute/rom/collider_obstacles.c): the same three
 * scripts, with friction, agree as closely (PARITY_TOL), and in double a sphere the block holds
 * back near its fixed top (24 steps short of its pose) too. */
#include "runtime_fixture.h"
#include "rom/rom.h"

#ifdef ROMRT_DOUBLE
#define PARITY_TOL 1e-8
#define ASSET_REAL ROMBIN_REAL_F64
#else
#define PARITY_TOL 2e-3
#define ASSET_REAL ROMBIN_REAL_F32
#endif

#define HANGING(asset)                                                                                 \
    "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.2, 0.6, 0.2], \"cells\": [2, 6, 2]}},"           \
    "  \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000}," \
    "  \"fixed\": [{\"box\": [[-1, 0.599, -1], [1, 1, 1]]}]}],"                                         \
    " \"gravity\": [0, -9.81, 0], \"damping\": {\"mass\": 0.5},"                                         \
    " \"time\": {\"step\": 0.01, \"duration\": 0.1},"                                                    \
    " \"rom\": {\"basis\": \"modes\", \"size\": 12, \"asset\": " asset "}}"

/* The hanging block with a collision surface (the asset's OBHD: a sphere obstacle far away) and
 * friction: the app's shapes there are on the exact obstacle path. */
#define SURFACE_HANGING                                                                                \
    "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.2, 0.6, 0.2], \"cells\": [2, 6, 2]}},"           \
    "  \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000}," \
    "  \"fixed\": [{\"box\": [[-1, 0.599, -1], [1, 1, 1]]}]}],"                                         \
    " \"gravity\": [0, -9.81, 0], \"damping\": {\"mass\": 0.5},"                                         \
    " \"obstacles\": [{\"sphere\": {\"center\": [3, 3, 3], \"radius\": 0.05}}],"                         \
    " \"contact\": {\"friction\": 0.3}, \"time\": {\"step\": 0.01, \"duration\": 0.1},"                \
    " \"rom\": {\"basis\": \"modes\", \"size\": 12}}"

/* The app's collider in both forms. */
typedef struct {
    rk_collider rom;
    romrt_collider rt;
} both_collider;

static both_collider make_collider(int kind, const double position[3], const double R[9], double radius,
                                   double half_length, const double half[3])
{
    both_collider c;
    memset(&c, 0, sizeof c);
    c.rom.kind = (rk_collider_kind)kind;
    c.rt.kind = (romrt_collider_kind)kind;
    for (int i = 0; i < 3; i++) c.rom.shape[i] = position[i], c.rt.position[i] = (romrt_real)position[i];
    for (int i = 0; i < 9; i++) c.rom.shape[3 + i] = R[i], c.rt.rotation[i] = (romrt_real)R[i];
    c.rom.shape[12] = radius, c.rt.radius = (romrt_real)radius;
    c.rom.shape[13] = half_length, c.rt.half_length = (romrt_real)half_length;
    for (int i = 0; i < 3; i++) c.rom.shape[14 + i] = half ? half[i] : 0, c.rt.half_extents[i] = (romrt_real)(half ? half[i] : 0);
    return c;
}

static const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};

/* A script of app moves: collider `slot` set to script(step) before each step. */
typedef both_collider (*script_fn)(int step, int *slot);

typedef struct {
    double rel, pushed, least;   /* trajectory difference, mean x displacement, least collider distance */
    int behind;
    int exact;                   /* the reduced simulator's collider is on the exact obstacle path */
    long rom_iterations, rt_iterations;
} run_result;

static int run_script(rt_fixture *f, int steps, script_fn script, run_result *out, rk_error *err)
{
    rk_rom s;
    romrt_error rerr;
    int n = romrt_shown_count(f->m), rc = 0;
    double *ref = calloc((size_t)3 * n, sizeof(double)), scale = 0, x0 = 0, x1 = 0;
    romrt_real *xyz = calloc((size_t)3 * n, sizeof(romrt_real));
    memset(out, 0, sizeof *out);
    out->least = INFINITY;
    /* the reduced simulator's iterates are the fresh mode's (the default may keep Newton's matrix) */
    if (romrt_set_hessian_reuse(f->m, 1, &rerr) != ROMRT_OK) return rk_fail(err, "%s", rerr.message);
    if (rk_rom_init(&s, &f->R.model, NULL, f->v0, err)) return -1;
    for (int i = 0; i < n; i++) x0 += f->sim.mesh.X[3 * (int)f->vmap[i]] / n;
    for (int k = 0; k < steps && !rc; k++) {
        int slot;
        both_collider c = script(k, &slot);
        if (rk_rom_set_collider(&s, slot, &c.rom, err) || rk_rom_step(&s, err)) rc = -1;
        else if (romrt_set_collider(f->m, slot, &c.rt, &rerr) != ROMRT_OK || romrt_step(f->m, &rerr) != ROMRT_OK)
            rc = rk_fail(err, "runtime, step %d: %s", k, rerr.message);
        if (rc) break;
        romrt_step_info info;
        info.size = sizeof info;
        romrt_last_step(f->m, &info, NULL);
        out->behind += info.colliders_behind;
        out->rt_iterations += info.newton_iterations;
        rt_fixture_reference(f, s.q, ref);
        romrt_positions(f->m, xyz, 3 * (size_t)n, 3, NULL);
        x1 = 0;
        for (int i = 0; i < 3 * n; i++) {
            out->rel = fmax(out->rel, fabs((double)xyz[i] - ref[i]));
            scale = fmax(scale, fabs(ref[i] - f->sim.mesh.X[3 * (int)f->vmap[i / 3] + i % 3]));
        }
        for (int i = 0; i < n; i++) {
            x1 += xyz[3 * i] / n;
            /* the runtime's shown vertices against where its collider is now (its own precision) */
            double p[3] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
            out->least = fmin(out->least, rk_collider_distance(c.rom.kind, s.colliders[slot].now, p, NULL, NULL));
        }
    }
    out->rel /= scale;
    out->pushed = x1 - x0;
    out->rom_iterations = s.stats.newton_iterations;
    for (int k = 0; k < RK_MAX_COLLIDERS; k++) out->exact |= s.colliders[k].active && s.colliders[k].exact;
    rk_rom_free(&s);
    free(ref);
    free(xyz);
    return rc;
}

/* A sphere 1 cm a step from beside the block into where it hangs. */
static both_collider sweeping_sphere(int step, int *slot)
{
    double p[3] = {fmin(-0.15 + 0.01 * step, 0.1), 0.15, 0.1};
    *slot = 3;
    return make_collider(ROMRT_COLLIDER_SPHERE, p, I3, 0.1, 0, NULL);
}

#ifdef ROMRT_DOUBLE
/* A sphere driven 1 cm a step into the block near its fixed top, where it cannot give way: the
 * sphere stops short of the app's pose (behind) and goes on when it can. */
static both_collider pinning_sphere(int step, int *slot)
{
    double p[3] = {fmin(-0.12 + 0.01 * step, 0.02), 0.52, 0.1};
    *slot = 5;
    return make_collider(ROMRT_COLLIDER_SPHERE, p, I3, 0.1, 0, NULL);
}
#endif

/* A capsule along z swept in from beside, turning about y as it comes. */
static both_collider turning_capsule(int step, int *slot)
{
    double a = 0.02 * step, R[9] = {cos(a), 0, sin(a), 0, 1, 0, -sin(a), 0, cos(a)};
    double base[9] = {0, 0, -1, 0, 1, 0, 1, 0, 0}, Rz[9]; /* local x along world z, then turned */
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) Rz[3 * i + j] = R[3 * i] * base[j] + R[3 * i + 1] * base[3 + j] + R[3 * i + 2] * base[6 + j];
    double p[3] = {fmin(-0.1 + 0.008 * step, 0.06), 0.1, 0.1};
    *slot = 0;
    return make_collider(ROMRT_COLLIDER_CAPSULE, p, Rz, 0.05, 0.2, NULL);
}

#define CHECK_RUN(label, json, steps, script, min_push) CHECK_PATH(label, json, steps, script, min_push, 0)
/* want_exact: whether the reduced simulator's collider is to be an obstacle of its contact model */
#define CHECK_PATH(label, json, steps, script, min_push, want_exact)                                          \
    do {                                                                                                  \
        rk_error err = {{0}};                                                                             \
        romrt_error rerr;                                                                                 \
        rt_fixture f;                                                                                     \
        run_result res;                                                                                   \
        CHECK_OK(rt_fixture_open(&f, json, ASSET_REAL, &err, &rerr));                                     \
        int rc = run_script(&f, steps, script, &res, &err);                                               \
        printf("# %s: relative difference %.3g (tol %g), pushed %.3f m, closest shown vertex %.3g m, "     \
               "%d steps behind, Newton iterations %ld (reduced) %ld (runtime)\n",                         \
               label, res.rel, (double)PARITY_TOL, res.pushed, res.least, res.behind, res.rom_iterations,  \
               res.rt_iterations);                                                                        \
        rt_fixture_close(&f);                                                                             \
        CHECK(rc == 0, "%s", err.msg);                                                                    \
        CHECK(res.rel <= PARITY_TOL, "relative difference %.3g above %g", res.rel, (double)PARITY_TOL);   \
        CHECK(res.least > 0, "a shown vertex is inside the collider (%g)", res.least);                   \
        CHECK(res.pushed > (min_push), "the block moved only %g m", res.pushed);                          \
        CHECK(res.exact == (want_exact), "the reduced simulator's collider is%s on the exact path", res.exact ? "" : " not"); \
    } while (0)

TEST(an_app_moved_sphere_pushes_a_hanging_block_as_the_reduced_simulator)
{
    CHECK_RUN("sphere", HANGING("{\"colliders\": \"vertices\"}"), 30, sweeping_sphere, 0.05);
}

TEST(a_turning_capsule_pushes_a_hanging_block_as_the_reduced_simulator)
{
    CHECK_RUN("capsule", HANGING("{\"colliders\": \"vertices\"}"), 30, turning_capsule, 0.02);
}

/* A block on a plane, pushed along by a box sliding on the plane behind it, with friction. */
static both_collider sliding_box(int step, int *slot)
{
    double p[3] = {-0.25 + 0.005 * step, 0.05, 0.1}, half[3] = {0.1, 0.05, 0.1};
    *slot = 7;
    return make_collider(ROMRT_COLLIDER_BOX, p, I3, 0, 0, half);
}

TEST(a_box_pushes_a_block_along_a_plane_with_friction_as_the_reduced_simulator)
{
    CHECK_RUN("box and friction",
              "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.2, 0.1, 0.2], \"cells\": [2, 1, 2]}, \"translate\": [0, 0.0005, 0]},"
              "  \"material\": {\"model\": \"neohookean\", \"young\": 1e6, \"poisson\": 0.4, \"density\": 1000}}],"
              " \"gravity\": [0, -9.81, 0], \"obstacles\": [{\"plane\": {\"point\": [0, 0, 0], \"normal\": [0, 1, 0]}}],"
              " \"contact\": {\"dhat\": 1e-3, \"friction\": 0.4}, \"time\": {\"step\": 0.01, \"duration\": 0.1},"
              " \"rom\": {\"basis\": \"modes\", \"size\": 12, \"asset\": {\"colliders\": \"vertices\"}}}",
              40, sliding_box, 0.03);
}

/* On the default asset (rom.asset.colliders true) a model with no surface of its own, with no
 * obstacle at all or planes only, holds its surface for the app's shapes: both take the exact path. */
TEST(on_the_default_asset_the_shapes_collide_exactly_as_the_reduced_simulator)
{
    CHECK_PATH("sphere, no obstacle, default asset", HANGING("{}"), 30, sweeping_sphere, 0.05, 1);
    CHECK_PATH("box and friction, planes only, default asset",
              "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.2, 0.1, 0.2], \"cells\": [2, 1, 2]}, \"translate\": [0, 0.0005, 0]},"
              "  \"material\": {\"model\": \"neohookean\", \"young\": 1e6, \"poisson\": 0.4, \"density\": 1000}}],"
              " \"gravity\": [0, -9.81, 0], \"obstacles\": [{\"plane\": {\"point\": [0, 0, 0], \"normal\": [0, 1, 0]}}],"
              " \"contact\": {\"dhat\": 1e-3, \"friction\": 0.4}, \"time\": {\"step\": 0.01, \"duration\": 0.1},"
              " \"rom\": {\"basis\": \"modes\", \"size\": 12}}",
              40, sliding_box, 0.03, 1);
}

TEST(on_a_collision_surface_the_shapes_collide_exactly_as_the_reduced_simulator)
{
    CHECK_PATH("sphere, exact path", SURFACE_HANGING, 30, sweeping_sphere, 0.05, 1);
    CHECK_PATH("capsule, exact path", SURFACE_HANGING, 30, turning_capsule, 0.02, 1);
#ifdef ROMRT_DOUBLE
    /* held back (the obstacle part way to its pose between steps): in double only, where it is
     * 1.3e-13; the float runtime's arrival tolerance is float's floor (runtime/step.c,
     * arrival_tol), so where the sphere stops short differs, 5.5e-3 relative */
    CHECK_PATH("sphere held back, exact path", SURFACE_HANGING, 30, pinning_sphere, 0.0, 1);
#endif
    CHECK_PATH("box and friction, exact path",
              "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.2, 0.1, 0.2], \"cells\": [2, 1, 2]}, \"translate\": [0, 0.0005, 0]},"
              "  \"material\": {\"model\": \"neohookean\", \"young\": 1e6, \"poisson\": 0.4, \"density\": 1000}}],"
              " \"gravity\": [0, -9.81, 0], \"obstacles\": [{\"plane\": {\"point\": [0, 0, 0], \"normal\": [0, 1, 0]}},"
              "  {\"sphere\": {\"center\": [3, 3, 3], \"radius\": 0.05}}],"
              " \"contact\": {\"dhat\": 1e-3, \"friction\": 0.4}, \"time\": {\"step\": 0.01, \"duration\": 0.1},"
              " \"rom\": {\"basis\": \"modes\", \"size\": 12}}",
              40, sliding_box, 0.03, 1);
}

TEST(bad_colliders_are_refused_with_a_status_and_change_nothing)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture f;
    CHECK_OK(rt_fixture_open(&f, HANGING("{\"colliders\": \"vertices\"}"), ASSET_REAL, &err, &rerr));
    double p[3] = {0.5, 0.3, 0.1};
    both_collider c = make_collider(ROMRT_COLLIDER_SPHERE, p, I3, 0.05, 0, NULL);
    CHECK(romrt_takes_colliders(f.m), "the asset takes no colliders");
    c.rt.radius = -1;
    CHECK(romrt_set_collider(f.m, 0, &c.rt, &rerr) == ROMRT_E_ARGUMENT, "a negative radius passed");
    c.rt.radius = (romrt_real)0.05;
    c.rt.position[1] = (romrt_real)NAN;
    CHECK(romrt_set_collider(f.m, 0, &c.rt, &rerr) == ROMRT_E_ARGUMENT, "a NaN position passed");
    c.rt.position[1] = (romrt_real)0.3;
    c.rt.rotation[0] = 2;
    CHECK(romrt_set_collider(f.m, 0, &c.rt, &rerr) == ROMRT_E_ARGUMENT, "a scaled rotation passed");
    c.rt.rotation[0] = 1;
    romrt_limits lim;
    lim.size = sizeof lim;
    CHECK(romrt_get_limits(&lim, NULL) == ROMRT_OK && lim.collider_slots == 8, "collider slots %zu", lim.collider_slots);
    CHECK(romrt_set_collider(f.m, lim.collider_slots, &c.rt, &rerr) == ROMRT_E_ARGUMENT, "a slot past the end passed");
    CHECK(romrt_set_collider(f.m, (size_t)-1, &c.rt, &rerr) == ROMRT_E_ARGUMENT, "slot -1 passed");
    c.rt.position[0] = 0; /* through the block's side */
    CHECK(romrt_set_collider(f.m, 0, &c.rt, &rerr) == ROMRT_E_ARGUMENT, "a sphere through the block passed");
    printf("# refused: %s\n", rerr.message);
    /* nothing changed: the model steps exactly as one that never saw them */
    rt_fixture g;
    CHECK_OK(rt_fixture_open(&g, HANGING("{\"colliders\": \"vertices\"}"), ASSET_REAL, &err, &rerr));
    int n = romrt_shown_count(f.m);
    romrt_real *a = calloc((size_t)3 * n, sizeof(romrt_real)), *b = calloc((size_t)3 * n, sizeof(romrt_real));
    for (int k = 0; k < 5; k++) romrt_step(f.m, &rerr), romrt_step(g.m, &rerr);
    romrt_positions(f.m, a, 3 * (size_t)n, 3, NULL);
    romrt_positions(g.m, b, 3 * (size_t)n, 3, NULL);
    CHECK(memcmp(a, b, sizeof(romrt_real) * 3 * n) == 0, "refused colliders changed the steps");
    free(a);
    free(b);
    rt_fixture_close(&g);
    rt_fixture_close(&f);
    /* without collision vertices in the asset */
    CHECK_OK(rt_fixture_open(&f, HANGING("{\"colliders\": false}"), ASSET_REAL, &err, &rerr));
    c.rt.position[0] = (romrt_real)0.5;
    CHECK(!romrt_takes_colliders(f.m) && romrt_set_collider(f.m, 0, &c.rt, &rerr) == ROMRT_E_UNSUPPORTED,
          "an asset without CVTX took a collider");
    rt_fixture_close(&f);
}

int main(void)
{
    RUN(an_app_moved_sphere_pushes_a_hanging_block_as_the_reduced_simulator);
    RUN(a_turning_capsule_pushes_a_hanging_block_as_the_reduced_simulator);
    RUN(a_box_pushes_a_block_along_a_plane_with_friction_as_the_reduced_simulator);
    RUN(on_the_default_asset_the_shapes_collide_exactly_as_the_reduced_simulator);
    RUN(on_a_collision_surface_the_shapes_collide_exactly_as_the_reduced_simulator);
    RUN(bad_colliders_are_refused_with_a_status_and_change_nothing);
    return test_finish();
}
