/* rom.clamp "lifted" (issue 37, rkpm_lift.c): a moving prescribed region held exactly by a
 * lifting handle instead of the penalty. A small twist of the FreeForm beam (5 x 1 x 1 m, the left
 * end fixed, the right end turned at 360 deg/s, the table's Neo-Hookean material, a coarse 10 x 2 x 2
 * mesh and 0.5 s so it runs in about 3 s of CPU), mesh-free RKPM skinning m = 6, against full order on the
 * same mesh:
 *   - lifted: every vertex of the turned end is on its prescribed path, R(t) X + s(t), to 1e-9 m in
 *     every frame, and the fixed end does not move; the penalty (clamp "dirichlet", pin_stiffness
 *     1e4) misses the path by more than that (so the check can fail);
 *   - the lifted run is closer to full order than the penalty run at the same m (the penalty takes
 *     freedom from the subspace to hold the end; docs/methods.md's twist section has the table);
 *   - what it cannot represent is refused by name: clamp "lifted" on a mesh skinning basis, and
 *     contact (the lifted coordinates cannot give way). The runtime steps its asset (LIFT):
 *     test_runtime_lifted. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "testlib.h"

#include "pipeline/pipeline.h"
#include "pipeline/method_fixed.h"

#define SCENE_HEAD                                                                                              \
    "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [5, 1, 1], \"cells\": [10, 2, 2]}},"                      \
    " \"material\": {\"model\": \"neohookean\", \"young\": 5e6, \"poisson\": 0.45, \"density\": 1000},"        \
    " \"fixed\": [{\"box\": [[-1, -1, -1], [0.01, 2, 2]]}],"                                                   \
    " \"moving\": [{\"box\": [[4.99, -1, -1], [6, 2, 2]], \"twist\": {\"axis\": [1, 0, 0], \"center\": [5, 0.5, 0.5],"\
    " \"degrees_per_second\": 360}}]}],"                                                                       \
    " \"gravity\": [0, 0, 0], \"time\": {\"step\": 0.01, \"duration\": 0.5, \"integrator\": \"backward_euler\"},"

static const char *scene_json =
    SCENE_HEAD " \"rom\": [{\"basis\": \"rkpm_skinning\", \"size\": 6, \"kernels\": 200, \"mesh_free\": {\"points\": 2000},"
               " \"clamp\": \"lifted\"},"
               " {\"basis\": \"rkpm_skinning\", \"size\": 6, \"kernels\": 200, \"mesh_free\": {\"points\": 2000}}]}";

typedef struct {
    double path_miss;  /* largest distance of a turned-end vertex from its prescribed place, any frame */
    double clamp_move; /* largest displacement of a fixed vertex, any frame */
    double error;      /* sum over frames and vertices of |x - x_full|^2, over frames x vertices x diag^2 */
} run_result;

/* Entry e of the scene run for T steps against the full-order displacement frames D (3 nv x T). */
static int run_entry(const rk_scene *scene, const rk_scene_sim *sim, int e, const double *D, int T, run_result *out,
                     rk_error *err)
{
    rk_scene_rom R;
    rk_rom rom = {0};
    if (rk_scene_rom_build(scene, sim, &scene->entries[e], NULL, 0, &R, err)) return -1;
    int nv = sim->mesh.nv, rc = -1, moving = -1;
    for (int g = 0; g < sim->options.nprescribed; g++)
        if (sim->options.prescribed[g].kind != RK_MOTION_FIXED) moving = g;
    unsigned char *fixed = rk_scene_fixed_vertices(sim, err);
    double *x = calloc(3 * (size_t)nv, sizeof *x), diag = rk_points_diagonal(sim->mesh.X, nv);
    memset(out, 0, sizeof *out);
    if (!fixed || !x || moving < 0 || rk_rom_init(&rom, &R.model, NULL, NULL, err)) goto out;
    const rk_prescribed *p = &sim->options.prescribed[moving];
    for (int t = 0; t < T; t++) {
        if (rk_rom_step(&rom, err)) goto out;
        rk_rom_positions(R.basis.U, 3 * nv, R.basis.r, sim->mesh.X, rom.q, x);
        double Rm[9], s[3];
        rk_prescribed_transform(p, rom.t, Rm, s);
        for (int k = 0; k < p->count; k++) {
            int v = p->verts[k];
            const double *X = &sim->mesh.X[3 * v];
            double d2 = 0;
            for (int a = 0; a < 3; a++) {
                double target = Rm[3 * a] * X[0] + Rm[3 * a + 1] * X[1] + Rm[3 * a + 2] * X[2] + s[a];
                d2 += (x[3 * v + a] - target) * (x[3 * v + a] - target);
            }
            out->path_miss = fmax(out->path_miss, sqrt(d2));
        }
        for (int v = 0; v < nv; v++) {
            double d2 = 0, f2 = 0;
            for (int a = 0; a < 3; a++) {
                double u = x[3 * v + a] - sim->mesh.X[3 * v + a], du = u - D[3 * (size_t)nv * t + 3 * v + a];
                d2 += u * u;
                f2 += du * du;
            }
            if (fixed[v]) out->clamp_move = fmax(out->clamp_move, sqrt(d2));
            out->error += f2;
        }
    }
    out->error /= (double)T * nv * diag * diag;
    rc = 0;
out:
    rk_rom_free(&rom);
    rk_scene_rom_free(&R);
    free(fixed);
    free(x);
    return rc;
}

TEST(the_lifted_end_follows_its_path_and_beats_the_penalty)
{
    rk_error err;
    rk_scene scene;
    rk_scene_sim sim;
    CHECK_OK(rk_scene_parse(scene_json, "twist.json", &scene, &err));
    if (rk_scene_build(&scene, &sim, &err)) {
        rk_scene_free(&scene);
        CHECK(0, "%s", err.msg);
    }
    double *D = NULL;
    int T = 0;
    run_result lifted, penalty;
    int ok = !rk_scene_training_frames(&sim, &D, &T, &err) && T == 50 && !run_entry(&scene, &sim, 0, D, T, &lifted, &err) &&
             !run_entry(&scene, &sim, 1, D, T, &penalty, &err);
    free(D);
    rk_scene_sim_free(&sim);
    rk_scene_free(&scene);
    CHECK(ok, "T = %d: %s", T, err.msg);
    printf("# 180 deg twist, m = 6: lifted: end off its path %.2e m, clamp moves %.2e m, error %.3e\n", lifted.path_miss,
           lifted.clamp_move, lifted.error);
    printf("# penalty 1e4: end off its path %.2e m, clamp moves %.2e m, error %.3e (lifted / penalty %.3f)\n",
           penalty.path_miss, penalty.clamp_move, penalty.error, lifted.error / penalty.error);
    CHECK(lifted.path_miss <= 1e-9, "the lifted end is %g m off its path", lifted.path_miss);
    CHECK(lifted.clamp_move <= 1e-12, "the clamp moves %g m", lifted.clamp_move);
    CHECK(penalty.clamp_move <= 1e-12, "the penalty row's clamp moves %g m", penalty.clamp_move);
    CHECK(penalty.path_miss > 1e-6, "the penalty holds the end to %g m: this check cannot tell them apart",
          penalty.path_miss);
    CHECK(lifted.error < penalty.error, "lifted error %g, not below the penalty's %g", lifted.error, penalty.error);
}

TEST(what_a_lifted_model_cannot_be_is_refused)
{
    rk_error err;
    rk_scene scene;
    CHECK(rk_scene_parse(SCENE_HEAD " \"rom\": {\"basis\": \"skinning\", \"size\": 4, \"clamp\": \"lifted\"}}", "mesh.json",
                         &scene, &err) != 0 &&
              strstr(err.msg, "clamp \"lifted\" is for basis rkpm_skinning only"),
          "accepted or wrong message: %s", err.msg);
    CHECK(rk_scene_parse(SCENE_HEAD " \"rom\": {\"basis\": \"rkpm_skinning\", \"size\": 4, \"clamp\": \"pinned\"}}",
                         "bad.json", &scene, &err) != 0 &&
              strstr(err.msg, "\"lifted\""),
          "accepted or wrong message: %s", err.msg);
    /* contact the lifted coordinates would have to give way to: refused by name */
    CHECK_OK(rk_scene_parse(SCENE_HEAD " \"obstacles\": [{\"plane\": {\"point\": [0, -1, 0], \"normal\": [0, 1, 0]}}],"
                                       " \"rom\": {\"basis\": \"rkpm_skinning\", \"size\": 3, \"kernels\": 100,"
                                       " \"mesh_free\": {\"points\": 1000}, \"clamp\": \"lifted\"}}",
                            "contact.json", &scene, &err));
    rk_scene_sim sim;
    rk_scene_rom R;
    int built = !rk_scene_build(&scene, &sim, &err);
    int refused = built && rk_scene_rom_build(&scene, &sim, &scene.entries[0], NULL, 0, &R, &err) != 0;
    if (built && !refused) rk_scene_rom_free(&R);
    if (built) rk_scene_sim_free(&sim);
    rk_scene_free(&scene);
    CHECK(built, "%s", err.msg);
    CHECK(refused && strstr(err.msg, "with contact"), "built or wrong message: %s", err.msg);
}

int main(void)
{
    RUN(the_lifted_end_follows_its_path_and_beats_the_penalty);
    RUN(what_a_lifted_model_cannot_be_is_refused);
    return test_finish();
}
