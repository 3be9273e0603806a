/* rom.volume "projected" on the FreeForm beam (meshfree_beam.h): the projected volume's static sag
 * at nu = 0.45 beside the pointwise volume's, per pressure space. */
#include "meshfree_beam.h"
#include "testlib.h"

/* rom.volume "projected" (cubature.h, "the projected volume"; pipeline/volume.c) against the
 * pointwise volume that locks, m = 16, nu = 0.45, one row per pressure space: the skinning weights
 * (the default space) take back part of the sag the pointwise volume holds; the weights times
 * (1, x, y, z) constrain nearly as many volume patterns as the points do and lock as they do;
 * the constant leaves the deviatoric part alone, which at nu = 0.45 (lambda = 9 mu) is too soft
 * (past beam theory). No space leaves a zero-energy mode: the deviatoric energy, which keeps its
 * lambda-free Psi(mu, 0) at every point, holds every non-rigid motion, and the clamp the rigid ones
 * (the smallest eigenvalues of K(0) + A, printed, stay those of the pointwise model's order). At
 * nu = 0 (lambda = 0) the projected model is the pointwise one, bit for bit. */
TEST(the_projected_volume_by_pressure_space)
{
    rk_error err;
    static const char *const names[] = {"pointwise", "weights", "weights_affine", "constant"};
    static const char *const keys[] = {"\"volume\": \"pointwise\"", "\"volume\": \"projected\"",
                                       "\"volume\": \"projected\", \"pressure\": \"weights_affine\"",
                                       "\"volume\": \"projected\", \"pressure\": \"constant\""};
    double tip[4], exact = timoshenko_tip(0.45);
    int ok;
    for (int k = 0; k < 4; k++) {
        double eig[3];
        tip[k] = model_tip_keys(0.45, 16, 0, keys[k], NULL, eig, &err, &ok);
        CHECK(ok, "%s: %s", names[k], err.msg);
        if (!ok) return;
        printf("# nu = 0.45, m = 16, volume %-15s tip %.5f m, %6.2f%% of beam theory; K(0) + A's smallest eigenvalues "
               "%.3g %.3g %.3g\n", names[k], tip[k], 100 * tip[k] / exact, eig[0], eig[1], eig[2]);
        CHECK(eig[0] > 0, "%s: a zero or negative stiffness %.3g", names[k], eig[0]);
    }
    CHECK(tip[1] > 1.1 * tip[0], "weights: tip %g not 10%% past the pointwise %g", tip[1], tip[0]);
    CHECK(tip[1] < exact, "weights: tip %g past beam theory's %g", tip[1], exact);
    CHECK(fabs(tip[2] - tip[0]) < 0.05 * tip[0], "weights_affine: tip %g, pointwise %g: expected to lock alike", tip[2], tip[0]);
    CHECK(tip[3] > 1.1 * exact, "constant: tip %g not past beam theory's %g (too soft)", tip[3], exact);
    double t0 = model_tip_keys(0, 16, 0, keys[0], NULL, NULL, &err, &ok), t1 = ok ? model_tip_keys(0, 16, 0, keys[1], NULL, NULL, &err, &ok) : 0;
    CHECK(ok && t0 == t1, "nu = 0: projected %.17g, pointwise %.17g (%s)", t1, t0, ok ? "" : err.msg);
    printf("# nu = 0, m = 16: tip %.5f m pointwise and projected (%.2f%% of beam theory's %.5f)\n", t0,
           100 * t0 / timoshenko_tip(0), timoshenko_tip(0));
    rk_scene scene;
    CHECK(rk_scene_parse("{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1, 1, 1], \"cells\": [1, 1, 1]}},"
                         " \"material\": {\"model\": \"linear\", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1000}}],"
                         " \"rom\": {\"basis\": \"modes\", \"size\": 4, \"volume\": \"projected\", \"pressure\": \"cubic\"}}",
                         "bad.json", &scene, &err) != 0 &&
              strstr(err.msg, "pressure must be \"weights\", \"constant\" or \"weights_affine\", got \"cubic\""),
          "accepted or wrong message: %s", err.msg);
    CHECK(rk_scene_parse("{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1, 1, 1], \"cells\": [1, 1, 1]}},"
                         " \"material\": {\"model\": \"linear\", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1000}}],"
                         " \"rom\": {\"basis\": \"modes\", \"size\": 4, \"volume\": \"pointwise\", \"pressure\": \"constant\"}}",
                         "bad.json", &scene, &err) != 0 &&
              strstr(err.msg, "pressure needs volume \"projected\""),
          "accepted or wrong message: %s", err.msg);
}

int main(void)
{
    RUN(the_projected_volume_by_pressure_space);
    return test_finish();
}
