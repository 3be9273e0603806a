/* Reduced models under contact: every basis type dropped at speed onto a plane and obstacles must
 * run to the end (each step starts from a valid state and CCD filters every Newton step, as at
 * full order), with no exact crossing and a positive distance in every frame, free and realigned
 * (the online error's realignment stops short of a projection that lies behind an obstacle).
 * The octopus case is the one that failed with "not finite at Newton iteration 0". */
#include "compare/compare.h"
#include "testlib.h"

static int compare_text(const char *json, rk_compare_result *res, rk_error *err)
{
    rk_scene scene;
    if (rk_scene_parse(json, "test.json", &scene, err)) return -1;
    int rc = rk_compare_scene(&scene, res, err);
    rk_scene_free(&scene);
    return rc;
}

static void check_methods(const char *what, const rk_compare_result *res, int expected)
{
    printf("# %s: full order closest %.3g m, %d crossings\n", what, res->fom_min_distance, res->fom_intersections);
    for (int k = 0; k < res->nmethods; k++) {
        const rk_compare_method *m = &res->methods[k];
        printf("# %s %-22s r %3d  nMSE %.3e  online %.3e  closest %.3g m  crossings %d  realignments cut short %d  %s\n",
               what, m->name, m->r, m->normalized_mse, m->relative_online_error, m->contact_min_distance,
               m->contact_intersections, m->realign_clipped, m->failure);
    }
    CHECK(res->nmethods == expected, "%d methods, expected %d", res->nmethods, expected);
    CHECK(res->has_contact && res->fom_intersections == 0 && res->fom_min_distance > 0,
          "full order: %d crossings, closest %g", res->fom_intersections, res->fom_min_distance);
    for (int k = 0; k < res->nmethods; k++) {
        const rk_compare_method *m = &res->methods[k];
        CHECK(!m->failure[0], "%s failed: %s", m->name, m->failure);
        CHECK(isfinite(m->normalized_mse) && isfinite(m->relative_online_error), "%s: errors not finite", m->name);
        CHECK(m->contact_intersections == 0, "%s: %d crossings in a frame", m->name, m->contact_intersections);
        CHECK(m->contact_min_distance > 0 && m->contact_min_distance < 1e-2,
              "%s: closest approach %g m (it should reach the obstacles, never touch them)", m->name,
              m->contact_min_distance);
    }
}

TEST(octopus_dropped_at_1_m_per_s_onto_a_plane)
{
    rk_error err;
    rk_compare_result res;
    CHECK_OK(compare_text(
        "{\"objects\": [{\"mesh\": {\"file\": \"tests/data/meshes/octopus-low.mesh\"},"
        "  \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000},"
        "  \"velocity\": [0, -1, 0]}],"
        " \"gravity\": [0, -9.81, 0],"
        " \"obstacles\": [{\"plane\": {\"point\": [0, -0.33, 0], \"normal\": [0, 1, 0]}}],"
        " \"time\": {\"step\": 0.01, \"duration\": 0.2},"
        " \"rom\": [{\"basis\": \"pod\", \"size\": 16}, {\"basis\": \"skinning\", \"size\": 8}]}", &res, &err));
    check_methods("octopus", &res, 2);
    /* POD of this very run reproduces it closely, contact included */
    CHECK(res.nmethods == 2 && res.methods[0].normalized_mse < 1e-4, "pod-16 nMSE %g", res.methods[0].normalized_mse);
    rk_compare_result_free(&res);
}

TEST(every_basis_type_dropped_at_2_m_per_s_onto_a_plane_a_sphere_and_a_box)
{
    rk_error err;
    rk_compare_result res;
    /* a soft slab falling at 2 m/s: one corner lands on a sphere, the other on a box, then the
     * middle on the ground plane */
    CHECK_OK(compare_text(
        "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.6, 0.1, 0.3], \"cells\": [6, 1, 3]}, \"translate\": [0, 0.12, 0]},"
        "  \"material\": {\"model\": \"neohookean\", \"young\": 2e5, \"poisson\": 0.4, \"density\": 1000},"
        "  \"velocity\": [0, -2, 0]}],"
        " \"gravity\": [0, -9.81, 0],"
        " \"obstacles\": [{\"plane\": {\"point\": [0, 0, 0], \"normal\": [0, 1, 0]}},"
        "   {\"sphere\": {\"center\": [0.05, 0.0, 0.15], \"radius\": 0.1}},"
        "   {\"box\": {\"min\": [0.45, -0.1, 0.05], \"max\": [0.65, 0.08, 0.25]}}],"
        " \"time\": {\"step\": 0.01, \"duration\": 0.2},"
        " \"rom\": [{\"basis\": \"modes\", \"size\": 12}, {\"basis\": \"modal_derivatives\", \"size\": 10},"
        "   {\"basis\": \"skinning\", \"size\": 6}, {\"basis\": \"rkpm_skinning\", \"size\": 6},"
        "   {\"basis\": \"pod\", \"size\": 12}]}", &res, &err));
    check_methods("slab", &res, 5);
    rk_compare_result_free(&res);
}

int main(void)
{
    RUN(octopus_dropped_at_1_m_per_s_onto_a_plane);
    RUN(every_basis_type_dropped_at_2_m_per_s_onto_a_plane_a_sphere_and_a_box);
    return test_finish();
}
