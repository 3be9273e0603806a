/* precompute/plan: the job graph of each kind of entry (which steps, what each passes on and waits
 * for), and that the files between the steps are exact (a basis and a cubature written and read
 * back bit for bit), which the byte-identical asset rests on. */
#include "testlib.h"

#include <stdint.h>

#include "pipeline/method_fixed.h"
#include "plan/plan.h"

static const char *SCENE =
    "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1, 0.2, 0.2], \"cells\": [4, 1, 1]}},"
    "  \"material\": {\"model\": \"neohookean\", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1000},"
    "  \"fixed\": [{\"box\": [[-1, -1, -1], [0.01, 1, 1]]}]}],"
    " \"time\": {\"step\": 0.01, \"duration\": 0.1},"
    " \"rom\": [{\"basis\": \"modes\", \"size\": 4, \"cubature\": {\"tolerance\": 0.05}},"
    "         {\"basis\": \"pod\", \"size\": 3, \"training\": [\"a.json\", {\"snapshots\": \"s.npy\"}]},"
    "         {\"basis\": \"modes\", \"size\": 4},"
    "         {\"basis\": \"skinning\", \"size\": 2},"
    "         {\"basis\": \"modes\", \"size\": 4, \"koopman\": {\"rank\": 4, \"trajectories\": [{}, {\"load_scale\": 2}]}}]}";

static rk_plan plan;

static int make_plan(int k, rk_error *err)
{
    rk_scene s;
    const rk_rom_entry *e;
    if (rk_scene_parse(SCENE, "/data/bake/scene.json", &s, err)) return -1;
    int rc = rk_scene_entry(&s, k, &e, err) || rk_plan_make(&s, e, "/data/bake/scene.json", 3, &plan, err);
    rk_scene_free(&s);
    return rc ? -1 : 0;
}

/* Whether step k's arguments hold a, b one after the other. */
static int has_args(int k, const char *a, const char *b)
{
    const rk_plan_step *s = &plan.steps[k];
    for (int i = 0; i + 1 < s->nargs; i++)
        if (!strcmp(s->args[i], a) && (!b || !strcmp(s->args[i + 1], b))) return 1;
    return 0;
}

static int waits_for(int k, int j)
{
    for (int i = 0; i < plan.steps[k].nafter; i++)
        if (plan.steps[k].after[i] == j) return 1;
    return 0;
}

TEST(own_run_basis_cubature_bake)
{
    rk_error err = {{0}};
    CHECK_OK(make_plan(0, &err));
    CHECK(plan.split && plan.nsteps == 4 && plan.ntrain == 1, "split %d, %d steps, %d training", plan.split,
          plan.nsteps, plan.ntrain);
    CHECK(!strcmp(plan.steps[0].id, "train-0") && has_args(0, "fom", "/data/bake/scene.json") &&
              has_args(0, "--snapshots", "train-0.npy"), "train-0: %s %s", plan.steps[0].id, plan.steps[0].args[0]);
    /* a modes basis trains on nothing: no wait for the run */
    CHECK(!strcmp(plan.steps[1].id, "basis") && plan.steps[1].nafter == 0 && !has_args(1, "--training", NULL),
          "basis waits for %d steps", plan.steps[1].nafter);
    CHECK(!strcmp(plan.steps[2].id, "cubature") && waits_for(2, 0) && waits_for(2, 1) &&
              has_args(2, "--training", "train-0.npy") && has_args(2, "--basis", "basis.npy"), "cubature step");
    CHECK(!strcmp(plan.steps[3].id, "bake") && waits_for(3, 1) && waits_for(3, 2) && !waits_for(3, 0) &&
              has_args(3, "--cubature", "cubature.json") && has_args(3, "-o", "asset.rombin"), "bake step");
    CHECK(plan.threads == 3, "threads %d", plan.threads);
}

TEST(training_list_scene_runs_and_snapshot_files)
{
    rk_error err = {{0}};
    CHECK_OK(make_plan(1, &err));
    /* the scene item is a run; the snapshot item is an input as it is */
    CHECK(plan.ntrain == 1 && has_args(0, "fom", "/data/bake/a.json"), "%d training steps", plan.ntrain);
    CHECK(!strcmp(plan.steps[1].id, "basis") && has_args(1, "--training-run", "train-0.npy") &&
              has_args(1, "--training-run", "/data/bake/s.npy") && waits_for(1, 0), "basis step");
    int listed = 0;
    for (int i = 0; i < plan.steps[1].ninputs; i++) listed |= !strcmp(plan.steps[1].inputs[i], "/data/bake/s.npy");
    CHECK(listed, "the snapshot file is not an input of the basis step");
    CHECK(plan.nsteps == 3 && !strcmp(plan.steps[2].id, "bake"), "no cubature step: %d steps", plan.nsteps);
}

TEST(nothing_trains_no_training_step)
{
    rk_error err = {{0}};
    CHECK_OK(make_plan(2, &err));
    CHECK(plan.ntrain == 0 && plan.nsteps == 2 && !strcmp(plan.steps[0].id, "basis"), "%d steps", plan.nsteps);
}

TEST(skinning_is_one_build_step)
{
    rk_error err = {{0}};
    CHECK_OK(make_plan(3, &err));
    CHECK(!plan.split && plan.nsteps == 1 && has_args(0, "build", "/data/bake/scene.json") && !has_args(0, "--basis", NULL),
          "split %d, %d steps", plan.split, plan.nsteps);
    CHECK(strstr(plan.whole_reason, "skinning") != NULL, "reason: %s", plan.whole_reason);
}

TEST(koopman_trajectories_are_steps)
{
    rk_error err = {{0}};
    CHECK_OK(make_plan(4, &err));
    CHECK(!plan.split && plan.ntrain == 2 && plan.nsteps == 3, "split %d, %d training, %d steps", plan.split,
          plan.ntrain, plan.nsteps);
    CHECK(has_args(1, "--trajectory", "1") && has_args(1, "--entry", "4"), "trajectory-1 step");
    CHECK(has_args(2, "--trajectory-run", "trajectory-0.npy") && has_args(2, "--trajectory-run", "trajectory-1.npy") &&
              waits_for(2, 0) && waits_for(2, 1), "bake step");
}

TEST(a_path_make_cannot_name_is_refused)
{
    rk_error err = {{0}};
    rk_scene s;
    const rk_rom_entry *e;
    CHECK_OK(rk_scene_parse(SCENE, "/data/my bake/scene.json", &s, &err));
    CHECK_OK(rk_scene_entry(&s, 0, &e, &err));
    int rc = rk_plan_make(&s, e, "/data/my bake/scene.json", 1, &plan, &err);
    rk_scene_free(&s);
    CHECK(rc != 0 && strstr(err.msg, "' '") != NULL, "rc %d: %s", rc, err.msg);
}

/* doubles whose shortest decimal form needs 17 digits, subnormals, extremes */
static double awkward(int i)
{
    uint64_t x = 0x9E3779B97F4A7C15ull * (uint64_t)(i + 1);
    double v = (double)(x >> 11) / 9007199254740992.0; /* [0, 1) with every bit used */
    switch (i % 5) {
    case 0: return 0.1 + v * 0.2;
    case 1: return v * 1e-308;
    case 2: return 4.9406564584124654e-324 * (double)(i + 1);
    case 3: return v * 1.7e308;
    default: return 1.0 / 3.0 + v;
    }
}

TEST(cubature_file_is_exact)
{
    rk_error err = {{0}};
    rk_scene_rom R;
    memset(&R, 0, sizeof R);
    int n = 40;
    R.cubature_set.count = n;
    R.cubature_set.index = calloc(n, sizeof(int));
    R.cubature_set.weight = calloc(n, sizeof(double));
    for (int i = 0; i < n; i++) {
        R.cubature_set.index[i] = 3 * i + 1;
        R.cubature_set.weight[i] = awkward(i) + (i % 5 == 2 ? 0 : 1e-300);
    }
    R.cubature_set.relative_error = awkward(7);
    R.cubature_set.reached = 1;
    R.cubature_set.greedy_count = 44;
    R.cubature_poses = 120;
    char path[] = "/tmp/test_plan_graph_XXXXXX";
    int fd = mkstemp(path);
    close(fd);
    rk_cubature_set back;
    int poses = 0;
    int rc = rk_scene_cubature_write(path, &R, &err) || rk_scene_cubature_read(path, &back, &poses, &err);
    unlink(path);
    CHECK(rc == 0, "%s", err.msg);
    int same = back.count == n && poses == 120 && back.reached && back.greedy_count == 44 &&
               memcmp(&back.relative_error, &R.cubature_set.relative_error, sizeof(double)) == 0;
    for (int i = 0; same && i < n; i++)
        same = back.index[i] == R.cubature_set.index[i] &&
               memcmp(&back.weight[i], &R.cubature_set.weight[i], sizeof(double)) == 0;
    rk_cubature_set_free(&back);
    rk_cubature_set_free(&R.cubature_set);
    CHECK(same, "the cubature read back differs from the one written");
}

TEST(basis_file_is_exact)
{
    rk_error err = {{0}};
    int n = 7, r = 3;
    double T[7 * 3 * 3], *U;
    for (int i = 0; i < 3 * n * r; i++) T[i] = awkward(i) * (i % 2 ? -1 : 1);
    long shape[3] = {n, 3, r};
    char path[] = "/tmp/test_plan_graph_XXXXXX";
    int fd = mkstemp(path);
    close(fd);
    rk_basis b;
    int rc = rk_npy_write(path, T, 3, shape, &err) || rk_scene_basis_read(path, RK_BASIS_POD, &b, &err);
    unlink(path);
    CHECK(rc == 0, "%s", err.msg);
    U = b.U;
    int same = b.n == n && b.r == r && b.type == RK_BASIS_POD;
    /* row (vertex i, coordinate c) and column j of the file is U[j * 3n + 3i + c] */
    for (int i = 0; same && i < 3 * n; i++)
        for (int j = 0; same && j < r; j++) same = memcmp(&U[(size_t)j * 3 * n + i], &T[i * r + j], sizeof(double)) == 0;
    rk_basis_free(&b);
    CHECK(same, "the basis read back differs from the file's");
}

int main(void)
{
    RUN(own_run_basis_cubature_bake);
    RUN(training_list_scene_runs_and_snapshot_files);
    RUN(nothing_trains_no_training_step);
    RUN(skinning_is_one_build_step);
    RUN(koopman_trajectories_are_steps);
    RUN(a_path_make_cannot_name_is_refused);
    RUN(cubature_file_is_exact);
    RUN(basis_file_is_exact);
    return test_finish();
}
