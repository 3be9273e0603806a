/* rom.clamp "lifted" in the runtime (LIFT, ROMBIN 1.11; issue 37): the FreeForm beam's turned end
 * held by its lifting handle, whose 12 coordinates the runtime sets from the baked motion each step
 * and leaves out of Newton, as the reduced simulator does (precompute/rom/model.c, set_lift). The
 * 180-degree twist of test_pipeline_lifted_twist (5 x 1 x 1 m, 10 x 2 x 2 mesh, mesh-free RKPM
 * skinning m = 6, 0.5 s) baked and stepped 50 times:
 *   - the runtime follows the reduced simulator on the same model to PARITY_TOL relative (double:
 *     round-off; float: its precision);
 *   - every shown vertex of the turned end is on its path R(t) X + s(t), and the fixed end's do
 *     not move (the path to 1e-9 m in double: the lifted coordinates are set, not solved for; a
 *     Newton that moved them would miss it by its tolerance);
 *   - what cannot give way to a lifted group is refused: a collider (ROMRT_E_UNSUPPORTED naming
 *     LIFT), and a LIFT that names no handle (ROMRT_E_MODEL naming LIFT). */
#include "runtime_fixture.h"
#include "asset_patch.h"

#ifdef ROMRT_DOUBLE
#define PARITY_TOL 1e-9
#define PATH_TOL 1e-9
#define ASSET_REAL ROMBIN_REAL_F64
#else
#define PARITY_TOL 1e-4
#define PATH_TOL 2e-5
#define ASSET_REAL ROMBIN_REAL_F32
#endif

#define TWIST                                                                                                     \
    "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [5, 1, 1], \"cells\": [10, 2, 2]}},"                      \
    " \"material\": {\"model\": \"neohookean\", \"young\": 5e6, \"poisson\": 0.45, \"density\": 1000},"        \
    " \"fixed\": [{\"box\": [[-1, -1, -1], [0.01, 2, 2]]}],"                                                   \
    " \"moving\": [{\"box\": [[4.99, -1, -1], [6, 2, 2]], \"twist\": {\"axis\": [1, 0, 0], \"center\": [5, 0.5, 0.5],"\
    " \"degrees_per_second\": 360}}]}],"                                                                       \
    " \"gravity\": [0, 0, 0], \"time\": {\"step\": 0.01, \"duration\": 0.5, \"integrator\": \"backward_euler\"},"  \
    " \"rom\": {\"basis\": \"rkpm_skinning\", \"size\": 6, \"kernels\": 200, \"mesh_free\": {\"points\": 2000},"  \
    " \"clamp\": \"lifted\"}}"

TEST(the_runtime_holds_the_lifted_end_on_its_path_as_the_reduced_simulator)
{
    rk_error err = {{0}};
    romrt_error rerr;
    rt_fixture f;
    rk_rom s;
    CHECK_OK(rt_fixture_open(&f, TWIST, ASSET_REAL, &err, &rerr));
    int n = romrt_shown_count(f.m), nv = f.sim.mesh.nv, moving = -1, fixed_group = -1;
    for (int g = 0; g < f.sim.options.nprescribed; g++)
        if (f.sim.options.prescribed[g].kind != RK_MOTION_FIXED) moving = g;
        else fixed_group = g;
    char *group = calloc((size_t)nv, 1); /* 1: turned end, 2: fixed end */
    double *ref = calloc(3 * (size_t)n, sizeof(double));
    romrt_real *xyz = calloc(3 * (size_t)n, sizeof(romrt_real));
    double rel = 0, scale = 0, path = 0, clamp = 0;
    int on_path = 0, rc = moving >= 0 && fixed_group >= 0 && group && ref && xyz ? 0 : -1;
    for (int k = 0; !rc && k < f.sim.options.prescribed[moving].count; k++) group[f.sim.options.prescribed[moving].verts[k]] = 1;
    for (int k = 0; !rc && k < f.sim.options.prescribed[fixed_group].count; k++)
        group[f.sim.options.prescribed[fixed_group].verts[k]] = 2;
    /* the reduced simulator's iterates are the fresh mode's (the default may keep Newton's matrix) */
    if (!rc && romrt_set_hessian_reuse(f.m, 1, &rerr) != ROMRT_OK) rc = rk_fail(&err, "%s", rerr.message);
    if (!rc) rc = rk_rom_init(&s, &f.R.model, NULL, f.v0, &err);
    for (int step = 0; !rc && step < 50; step++) {
        if (rk_rom_step(&s, &err)) {
            rc = -1;
            break;
        }
        if (romrt_step(f.m, &rerr) != ROMRT_OK) {
            rc = rk_fail(&err, "runtime, step %d: %s", step, rerr.message);
            break;
        }
        rt_fixture_reference(&f, s.q, ref);
        romrt_positions(f.m, xyz, 3 * (size_t)n, 3, NULL);
        double R[9], shift[3];
        rk_prescribed_transform(&f.sim.options.prescribed[moving], s.t, R, shift);
        for (int i = 0; i < n; i++) {
            int v = (int)f.vmap[i];
            const double *X = &f.sim.mesh.X[3 * v];
            double miss = 0, moved = 0;
            for (int a = 0; a < 3; a++) {
                double x = (double)xyz[3 * i + a], target = R[3 * a] * X[0] + R[3 * a + 1] * X[1] + R[3 * a + 2] * X[2] + shift[a];
                rel = fmax(rel, fabs(x - ref[3 * i + a]));
                scale = fmax(scale, fabs(ref[3 * i + a] - X[a]));
                miss += (x - target) * (x - target);
                moved += (x - X[a]) * (x - X[a]);
            }
            if (group[v] == 1) path = fmax(path, sqrt(miss)), on_path++;
            if (group[v] == 2) clamp = fmax(clamp, sqrt(moved));
        }
    }
    rel /= scale > 0 ? scale : 1;
    printf("# lifted twist, 50 steps: runtime against the reduced simulator %.3g relative (tol %g); turned end off "
           "its path %.3g m over %d vertex frames, fixed end moved %.3g m (largest displacement %.3g m)\n",
           rel, (double)PARITY_TOL, path, on_path, clamp, scale);
    /* an app collider cannot be given way to */
    romrt_collider c;
    memset(&c, 0, sizeof c);
    c.kind = ROMRT_COLLIDER_SPHERE;
    c.position[0] = 2.5, c.position[1] = 3, c.position[2] = 0.5;
    c.rotation[0] = c.rotation[4] = c.rotation[8] = 1;
    c.radius = (romrt_real)0.1;
    romrt_status cs = romrt_set_collider(f.m, 0, &c, &rerr);
    int takes = romrt_takes_colliders(f.m);
    if (!rc) rk_rom_free(&s);
    /* LIFT naming no handle: its column moved to 6, inside r but not a handle's first */
    double bad_col = 6;
    float bad_col_f = 6;
    int damaged_refused = 0;
    char damaged_msg[256] = "";
    if (!rc) {
        unsigned char *copy = malloc(f.bytes);
        size_t need = 0;
        memcpy(copy, f.asset, f.bytes);
        size_t at = (size_t)ROMBIN_PIN_PARAMS * (ASSET_REAL == ROMBIN_REAL_F64 ? 8 : 4);
        if (ASSET_REAL == ROMBIN_REAL_F64) asset_patch_chunk(copy, ROMBIN_LIFT, at, &bad_col, 8);
        else asset_patch_chunk(copy, ROMBIN_LIFT, at, &bad_col_f, 4);
        void *arena = NULL;
        romrt_model *dm = NULL;
        romrt_status ds = romrt_arena_size(copy, f.bytes, &need, &rerr);
        if (ds == ROMRT_OK && (arena = aligned_alloc(16, (need + 15) / 16 * 16)) != NULL)
            ds = romrt_open(copy, f.bytes, arena, need, &dm, &rerr);
        damaged_refused = ds == ROMRT_E_MODEL && strcmp(rerr.chunk, ROMBIN_LIFT) == 0;
        free(arena);
        snprintf(damaged_msg, sizeof damaged_msg, "%s: %s", rerr.chunk, rerr.message);
        free(copy);
    }
    free(group);
    free(ref);
    free(xyz);
    rt_fixture_close(&f);
    CHECK(rc == 0, "%s", err.msg);
    CHECK(on_path > 0, "no shown vertex of the turned end");
    CHECK(rel <= PARITY_TOL, "runtime and reduced simulator %g apart (relative)", rel);
    CHECK(path <= PATH_TOL, "the turned end is %g m off its path", path);
    CHECK(clamp <= PATH_TOL, "the fixed end moved %g m", clamp);
    CHECK(scale > 0.3, "the beam hardly moved (%g m): the twist did not run", scale);
    CHECK(cs == ROMRT_E_UNSUPPORTED && !takes, "a collider on a lifted asset: status %d, takes %d", (int)cs, takes);
    CHECK(damaged_refused, "a LIFT naming no handle was not refused by name: %s", damaged_msg);
}

int main(void)
{
    RUN(the_runtime_holds_the_lifted_end_on_its_path_as_the_reduced_simulator);
    return test_finish();
}
