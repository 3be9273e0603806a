/* The skinning bases' default volume (issue 37; parse_rom.c parse_volume): a FreeForm beam model
 * built with no "volume" key does not lock. */
#include "meshfree_beam.h"
#include "testlib.h"

/* The mesh-free rkpm_skinning beam (meshfree_beam.h, the Dirichlet clamp) built with no volume key,
 * static sag under a tenth of gravity. At nu = 0.45 against the converged solid (quadratic tets,
 * Richardson: 0.1220 m, docs/results/p2_beam.md): m = 9 and 16 within 5% (the projected volume on
 * the weights: 96.1% and 98.0%, docs/results/volume_sag.md; the pointwise volume, the default
 * before, 76.5% and 85.3%, so this fails on it). m = 6 is not asserted: no pressure space of
 * eigen-weights lands within 5% there (docs/results/volume_sag.md says why). At nu = 0 (lambda = 0
 * leaves the projection empty) m = 9 within 5% of Timoshenko (99.2%; that it is the pointwise
 * model bit for bit, test_pipeline_volume_beam asserts). */
TEST(a_default_skinning_beam_does_not_lock)
{
    rk_error err;
    int ok;
    const double solid = 0.1220;
    const int ms[2] = {9, 16};
    for (int k = 0; k < 2; k++) {
        double tip = model_tip_keys(0.45, ms[k], 0, NULL, NULL, NULL, &err, &ok);
        CHECK(ok, "nu = 0.45, m = %d: %s", ms[k], err.msg);
        if (!ok) return;
        printf("# nu = 0.45, m = %2d, default volume: tip %.5f m, %.2f%% of the solid's %.4f\n", ms[k], tip,
               100 * tip / solid, solid);
        CHECK(fabs(tip / solid - 1) < 0.05, "nu = 0.45, m = %d: tip %g, %.1f%% of the solid's %g (locks or too soft)",
              ms[k], tip, 100 * tip / solid, solid);
    }
    double t0 = model_tip_keys(0, 9, 0, NULL, NULL, NULL, &err, &ok), exact = timoshenko_tip(0);
    CHECK(ok, "nu = 0: %s", err.msg);
    if (!ok) return;
    printf("# nu = 0, m = 9, default volume: tip %.5f m, %.2f%% of Timoshenko's %.5f\n", t0, 100 * t0 / exact, exact);
    CHECK(fabs(t0 / exact - 1) < 0.05, "nu = 0, m = 9: tip %g, %.1f%% of Timoshenko's %g", t0, 100 * t0 / exact, exact);
}

int main(void)
{
    RUN(a_default_skinning_beam_does_not_lock);
    return test_finish();
}
