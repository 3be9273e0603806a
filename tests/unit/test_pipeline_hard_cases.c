/* Numerical stability on hard cases: each must run to the end with finite states, and where
 * the physics says so, without inverted elements or vertices behind a plane. */
#include "scene_run.h"

#define NEO "\"model\": \"neohookean\""

/* Runs `steps` steps; fails the calling test on error or non-finite state. */
#define RUN_STEPS(r, steps)                                                                         \
    for (int s_ = 0; s_ < (steps); s_++) {                                                          \
        CHECK(rk_fom_step(&(r).fom, &err) == 0, "step %d: %s", s_, err.msg);                        \
        CHECK(scene_run_finite(&(r)), "non-finite state after step %d", s_);                       \
    }

TEST(paper_beam_bend_runs_clean)
{
    rk_error err;
    scene_run r;
    /* The freeform paper's beam (Sec. 4): 5 x 1 x 1 m, E 5e6, nu 0.45, rho 1000, left 0.5 m fixed. */
    CHECK_OK(scene_run_open(&r,
        "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [5, 1, 1], \"cells\": [20, 4, 4]}},"
        " \"material\": {" NEO ", \"young\": 5e6, \"poisson\": 0.45, \"density\": 1000},"
        " \"fixed\": [{\"box\": [[-1, -1, -1], [0.5, 2, 2]]}]}],"
        " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": 0.01, \"duration\": 1.0}}", &err));
    RUN_STEPS(r, r.sim.steps);
    double min_J;
    int inv = rk_fem_inverted(&r.sim.fem, r.fom.x, &min_J);
    double tip = 0;
    for (int v = 0; v < r.sim.mesh.nv; v++) tip = fmin(tip, r.fom.x[3 * v + 1] - r.sim.mesh.X[3 * v + 1]);
    printf("# bend: %d steps, tip sag %.3f m, min det F %.3f, %ld Newton iterations\n", r.sim.steps, -tip, min_J,
           r.fom.stats.newton_iterations);
    scene_run_close(&r);
    CHECK(inv == 0, "%d inverted elements at the end", inv);
    CHECK(tip < -0.05, "the beam should sag visibly under gravity (tip moved %.3g m)", tip);
}

TEST(paper_beam_twist_720_degrees_runs_clean)
{
    rk_error err;
    scene_run r;
    CHECK_OK(scene_run_open(&r,
        "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [5, 1, 1], \"cells\": [20, 4, 4]}},"
        " \"material\": {" NEO ", \"young\": 5e6, \"poisson\": 0.45, \"density\": 1000},"
        " \"fixed\": [{\"box\": [[-1, -1, -1], [0, 2, 2]]}],"
        " \"moving\": [{\"box\": [[5, -1, -1], [6, 2, 2]],"
        "   \"twist\": {\"axis\": [1, 0, 0], \"center\": [5, 0.5, 0.5], \"degrees_per_second\": 360}}]}],"
        " \"time\": {\"step\": 0.01, \"duration\": 2.0}}", &err));
    RUN_STEPS(r, r.sim.steps);
    double min_J;
    int inv = rk_fem_inverted(&r.sim.fem, r.fom.x, &min_J);
    printf("# twist 720 deg: %d steps, min det F %.3f, %ld Newton iterations\n", r.sim.steps, min_J,
           r.fom.stats.newton_iterations);
    scene_run_close(&r);
    CHECK(inv == 0, "%d inverted elements at the end", inv);
}

TEST(nearly_incompressible_nu_0499)
{
    rk_error err;
    scene_run r;
    CHECK_OK(scene_run_open(&r,
        "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [2, 0.4, 0.4], \"cells\": [10, 2, 2]}},"
        " \"material\": {" NEO ", \"young\": 1e6, \"poisson\": 0.499, \"density\": 1000},"
        " \"fixed\": [{\"box\": [[-1, -1, -1], [0, 1, 1]]}]}],"
        " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": 0.01, \"duration\": 0.5}}", &err));
    RUN_STEPS(r, r.sim.steps);
    int inv = rk_fem_inverted(&r.sim.fem, r.fom.x, NULL);
    scene_run_close(&r);
    CHECK(inv == 0, "%d inverted elements", inv);
}

TEST(youngs_modulus_from_1e5_to_1e9_in_one_object)
{
    rk_error err;
    scene_run r;
    CHECK_OK(scene_run_open(&r,
        "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [5, 0.5, 0.5], \"cells\": [20, 2, 2]}},"
        " \"material\": {" NEO ", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000},"
        " \"regions\": [{\"box\": [[1, -1, -1], [2, 1, 1]], \"material\": {\"young\": 1e6}},"
        "               {\"box\": [[2, -1, -1], [3, 1, 1]], \"material\": {\"young\": 1e7}},"
        "               {\"box\": [[3, -1, -1], [4, 1, 1]], \"material\": {\"young\": 1e8}},"
        "               {\"box\": [[4, -1, -1], [5, 1, 1]], \"material\": {\"young\": 1e9}}],"
        " \"fixed\": [{\"box\": [[-1, -1, -1], [0, 1, 1]]}]}],"
        " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": 0.01, \"duration\": 0.5}}", &err));
    double lo = INFINITY, hi = 0;
    for (int t = 0; t < r.sim.mesh.nt; t++) {
        lo = fmin(lo, r.sim.materials[t].young);
        hi = fmax(hi, r.sim.materials[t].young);
    }
    RUN_STEPS(r, r.sim.steps);
    int inv = rk_fem_inverted(&r.sim.fem, r.fom.x, NULL);
    scene_run_close(&r);
    CHECK(lo == 1e5 && hi == 1e9, "regions should give E from 1e5 to 1e9, got %g to %g", lo, hi);
    CHECK(inv == 0, "%d inverted elements", inv);
}

/* The same twisting bar at h = 1e-4 s and h = 0.1 s. */
TEST(time_steps_from_1e4_to_0p1_seconds)
{
    const double steps_h[] = {1e-4, 1e-3, 1e-2, 1e-1};
    for (int k = 0; k < 4; k++) {
        rk_error err;
        scene_run r;
        char json[1024];
        snprintf(json, sizeof json,
                 "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [2, 0.5, 0.5], \"cells\": [8, 2, 2]}},"
                 " \"material\": {" NEO ", \"young\": 1e6, \"poisson\": 0.45, \"density\": 1000},"
                 " \"fixed\": [{\"box\": [[-1, -1, -1], [0, 1, 1]]}]}],"
                 " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": %g, \"duration\": %g}}",
                 steps_h[k], 20 * steps_h[k]);
        CHECK_OK(scene_run_open(&r, json, &err));
        RUN_STEPS(r, r.sim.steps);
        int inv = rk_fem_inverted(&r.sim.fem, r.fom.x, NULL);
        scene_run_close(&r);
        CHECK(inv == 0, "h = %g: %d inverted elements", steps_h[k], inv);
    }
}

/* 10,000 steps of a damped cantilever: still finite, and it has come to rest. */
TEST(ten_thousand_steps)
{
    rk_error err;
    scene_run r;
    CHECK_OK(scene_run_open(&r,
        "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1, 0.2, 0.2], \"cells\": [4, 1, 1]}},"
        " \"material\": {" NEO ", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1000},"
        " \"fixed\": [{\"box\": [[-1, -1, -1], [0, 1, 1]]}]}],"
        " \"gravity\": [0, -9.81, 0], \"damping\": {\"mass\": 0.5},"
        " \"time\": {\"step\": 0.01, \"duration\": 100}}", &err));
    CHECK(r.sim.steps == 10000, "steps %d", r.sim.steps);
    RUN_STEPS(r, r.sim.steps);
    double ke = rk_fom_kinetic_energy(&r.fom);
    scene_run_close(&r);
    CHECK(ke < 1e-8, "kinetic energy %g after 100 s of damped motion", ke);
}

/* A box dropped onto a ground plane: no vertex ever reaches the plane, and it comes to rest on it. */
TEST(drop_onto_ground_plane)
{
    rk_error err;
    scene_run r;
    CHECK_OK(scene_run_open(&r,
        "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.5, 0.5, 0.5], \"cells\": [3, 3, 3]}, \"translate\": [0, 0.5, 0]},"
        " \"material\": {" NEO ", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000}}],"
        " \"gravity\": [0, -9.81, 0], \"damping\": {\"mass\": 1.0},"
        " \"obstacles\": [{\"plane\": {\"point\": [0, 0, 0], \"normal\": [0, 1, 0]}}],"
        " \"time\": {\"step\": 0.01, \"duration\": 2.0}}", &err));
    double lowest = INFINITY;
    for (int s = 0; s < r.sim.steps; s++) {
        CHECK(rk_fom_step(&r.fom, &err) == 0, "step %d: %s", s, err.msg);
        for (int v = 0; v < r.sim.mesh.nv; v++) lowest = fmin(lowest, r.fom.x[3 * v + 1]);
        CHECK(lowest > 0, "vertex below the plane at step %d (y = %g)", s, lowest);
    }
    double ke = rk_fom_kinetic_energy(&r.fom);
    int inv = rk_fem_inverted(&r.sim.fem, r.fom.x, NULL);
    scene_run_close(&r);
    printf("# drop: lowest vertex height %.3g m, final kinetic energy %.3g J\n", lowest, ke);
    CHECK(lowest < 0.01, "the box should reach the ground (lowest %g m)", lowest);
    CHECK(ke < 1e-3, "the box should come to rest, kinetic energy %g J", ke);
    CHECK(inv == 0, "%d inverted elements", inv);
}

/* Stable Neo-Hookean recovers from inverted elements (Smith et al. 2018; Eq. 16 of the freeform
 * paper is defined for det F <= 0). Two starts: the box mirrored through its mid-plane (every
 * element inverted) and every vertex scrambled to a random point inside the box. At the end no
 * element is inverted and the elastic energy is back near zero (the rest shape, up to rotation). */
static void recover_from(int scramble, int *inverted_at_start, int *inverted_at_end, double *energy_ratio,
                         rk_error *err, int *ok)
{
    scene_run r;
    *ok = 0;
    if (scene_run_open(&r,
        "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1, 1, 1], \"cells\": [3, 3, 3]}},"
        " \"material\": {" NEO ", \"young\": 1e5, \"poisson\": 0.3, \"density\": 1000}}],"
        " \"damping\": {\"mass\": 5}, \"time\": {\"step\": 0.01, \"duration\": 3}}", err))
        return;
    int n = 3 * r.sim.mesh.nv;
    double *x0 = malloc(sizeof(double) * (size_t)n);
    unsigned seed = 12345;
    for (int i = 0; i < n; i++) {
        seed = seed * 1103515245u + 12345u;
        double u = (double)((seed >> 8) & 0xffff) / 65535.0;
        x0[i] = scramble ? u : (i % 3 == 0 ? 1.0 - r.sim.mesh.X[i] : r.sim.mesh.X[i]);
    }
    r.sim.options.position0 = x0;
    rk_fom_free(&r.fom);
    if (rk_fom_init(&r.fom, &r.sim.fem, &r.sim.options, err)) {
        free(x0);
        r.ready = 0;
        return;
    }
    *inverted_at_start = rk_fem_inverted(&r.sim.fem, r.fom.x, NULL);
    double e0 = rk_fem_energy(&r.sim.fem, r.fom.x);
    free(x0);
    for (int s = 0; s < r.sim.steps; s++)
        if (rk_fom_step(&r.fom, err) || !scene_run_finite(&r)) {
            scene_run_close(&r);
            return;
        }
    *inverted_at_end = rk_fem_inverted(&r.sim.fem, r.fom.x, NULL);
    *energy_ratio = rk_fem_energy(&r.sim.fem, r.fom.x) / e0;
    scene_run_close(&r);
    *ok = 1;
}

TEST(inverted_start_recovers_the_rest_shape)
{
    for (int scramble = 0; scramble < 2; scramble++) {
        rk_error err;
        int inv0 = 0, inv1 = -1, ok;
        double ratio = 1;
        recover_from(scramble, &inv0, &inv1, &ratio, &err, &ok);
        CHECK(ok, "%s start: %s", scramble ? "scrambled" : "mirrored", err.msg);
        printf("# %s start: %d of 162 elements inverted at the start, %d at the end; energy %.2e of the start's\n",
               scramble ? "scrambled" : "mirrored", inv0, inv1, ratio);
        CHECK(inv0 > (scramble ? 20 : 161), "the start should have inverted elements (%d)", inv0);
        CHECK(inv1 == 0, "%d elements still inverted", inv1);
        CHECK(ratio < 1e-6, "elastic energy only fell to %.3g of its start", ratio);
    }
}

/* Scene-level selections that select nothing, and obstacles the object starts behind. */
TEST(empty_selection_and_bad_start_are_named)
{
    rk_error err;
    scene_run r;
    CHECK(scene_run_open(&r,
        "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1, 1, 1], \"cells\": [1, 1, 1]}},"
        " \"material\": {" NEO ", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000},"
        " \"fixed\": [{\"box\": [[5, 5, 5], [6, 6, 6]]}]}]}", &err) != 0, "empty selection accepted");
    CHECK(strstr(err.msg, "objects[0].fixed[0].box selects no vertex"), "message: %s", err.msg);
    CHECK(scene_run_open(&r,
        "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1, 1, 1], \"cells\": [1, 1, 1]}},"
        " \"material\": {" NEO ", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000}}],"
        " \"obstacles\": [{\"plane\": {\"point\": [0, 0.5, 0], \"normal\": [0, 1, 0]}}]}", &err) != 0,
          "object starting through a plane accepted");
    CHECK(strstr(err.msg, "obstacles[0]") && strstr(err.msg, "behind the plane"), "message: %s", err.msg);
    CHECK(scene_run_open(&r,
        "{\"objects\": [{\"mesh\": {\"file\": \"/nonexistent/mesh.msh\"},"
        " \"material\": {" NEO ", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000}}]}", &err) != 0,
          "missing mesh accepted");
    CHECK(strstr(err.msg, "/nonexistent/mesh.msh"), "message: %s", err.msg);
}

int main(void)
{
    RUN(paper_beam_bend_runs_clean);
    RUN(paper_beam_twist_720_degrees_runs_clean);
    RUN(nearly_incompressible_nu_0499);
    RUN(youngs_modulus_from_1e5_to_1e9_in_one_object);
    RUN(time_steps_from_1e4_to_0p1_seconds);
    RUN(ten_thousand_steps);
    RUN(drop_onto_ground_plane);
    RUN(inverted_start_recovers_the_rest_shape);
    RUN(empty_selection_and_bad_start_are_named);
    return test_finish();
}
