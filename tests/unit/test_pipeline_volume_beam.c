/* rom.volume "projected" on the FreeForm beam (meshfree_beam.h): the projected volume's static sag
 * at nu = 0.45 beside the pointwise volume's, per pressure space. */
#include "meshfree_beam.h"
#include "testlib.h"

/* rom.volume "projected" (cubature.h, "the projected volume"; pipeline/volume.c) against the
 * pointwise volume that locks, m = 16, nu = 0.45, the Dirichlet clamp (the default), one row per
 * pressure space, beside the converged solid (quadratic tets: 0.1220 m, 95.7% of beam theory,
 * docs/results/p2_beam.md). The richer the space, the more volume patterns it holds and the stiffer
 * the beam: the pointwise volume (one pressure a point) locks far below the solid; the weights times
 * (1, x, y, z) hold nearly as many patterns and lock nearly as much; the weights (the object's
 * eigen-weights without the clamp: pipeline/volume.c says why) land within 3% of the solid; the
 * constant leaves the deviatoric part alone, a nu = 0 material of the same mu (far too soft). No
 * space leaves a zero-energy mode: the deviatoric energy, which keeps its lambda-free Psi(mu, 0) at
 * every point, holds every non-rigid motion, and the clamp the rigid ones (the smallest eigenvalues
 * of K(0) + A, printed, stay those of the pointwise model's order). At nu = 0 (lambda = 0) the
 * projected model is the pointwise one, bit for bit. */
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
    const double solid = 0.1220; /* bench_p2_beam: Richardson on P2 levels 0-2 */
    CHECK(tip[0] < 0.9 * solid, "pointwise: tip %g not locked below the solid's %g", tip[0], solid);
    CHECK(tip[0] < tip[2] && tip[2] < 0.95 * solid, "weights_affine: tip %g, pointwise %g: expected to lock nearly alike",
          tip[2], tip[0]);
    CHECK(fabs(tip[1] / solid - 1) < 0.03, "weights: tip %g, %.1f%% of the solid's %g", tip[1], 100 * tip[1] / solid, solid);
    CHECK(tip[3] > tip[1] && tip[3] > 1.1 * exact, "constant: tip %g not past weights' %g and beam theory's %g (too soft)",
          tip[3], tip[1], exact);
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
