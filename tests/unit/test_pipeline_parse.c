/* Scene files: good ones parse into what they say; each bad one gives one clear message that
 * names the file and the JSON path of the problem. */
#include "testlib.h"
#include "pipeline/method_koopman.h"

#define BEAM_OBJECT                                                                         \
    "\"mesh\": {\"box\": {\"size\": [5, 1, 1], \"cells\": [10, 2, 2]}},"                  \
    "\"material\": {\"model\": \"neohookean\", \"young\": 5e6, \"poisson\": 0.45, \"density\": 1000}"

TEST(parses_the_design_example)
{
    rk_error err;
    rk_scene s;
    const char *text =
        "{\"objects\": [{" BEAM_OBJECT ","
        "  \"regions\": [{\"box\": [[2.5, -1, -1], [6, 2, 2]], \"material\": {\"young\": 1e9}}],"
        "  \"fixed\": [{\"box\": [[-1, -1, -1], [0.5, 2, 2]]}],"
        "  \"moving\": [{\"box\": [[4.5, -1, -1], [6, 2, 2]], \"twist\": {\"axis\": [2, 0, 0], \"degrees_per_second\": 720}}],"
        "  \"velocity\": [1, 0, 0]}],"
        " \"gravity\": [0, -9.81, 0],"
        " \"obstacles\": [{\"plane\": {\"point\": [0, -2, 0], \"normal\": [0, 2, 0]}}],"
        " \"time\": {\"step\": 0.01, \"duration\": 1.0, \"integrator\": \"bdf2\", \"static\": false},"
        " \"rom\": {\"basis\": \"rkpm_skinning\", \"size\": 16}}";
    CHECK_OK(rk_scene_parse(text, "dir/scene.json", &s, &err));
    CHECK(s.nobjects == 1, "objects %d", s.nobjects);
    const rk_scene_object *o = &s.objects[0];
    CHECK(o->shape == RK_SHAPE_BOX && o->box_cells[0] == 10, "box");
    CHECK(o->material.model == RK_MAT_NEOHOOKEAN && o->material.young == 5e6, "material");
    CHECK(o->nregions == 1 && o->regions[0].material.young == 1e9 && o->regions[0].material.poisson == 0.45,
          "region must override young and inherit the rest");
    CHECK(o->nmotions == 2 && o->motions[0].kind == RK_MOTION_FIXED && o->motions[1].kind == RK_MOTION_TWIST,
          "motions");
    CHECK_CLOSE(o->motions[1].axis[0], 1.0, 1e-15);
    CHECK_CLOSE(o->motions[1].rate, 4 * M_PI, 1e-12);
    CHECK(s.nobstacles == 1 && s.obstacles[0].shape.kind == RK_OBSTACLE_PLANE && s.obstacles[0].shape.normal[1] == 1.0,
          "plane normal must be normalized");
    CHECK(s.integrator == RK_BDF2 && s.h == 0.01, "time");
    CHECK(s.nentries == 1 && s.entries[0].basis.type == RK_BASIS_RKPM_SKINNING && s.entries[0].basis.size == 16 &&
              strcmp(s.entries[0].name, "rkpm_skinning-16") == 0 && !s.entries[0].cubature && !rk_koopman_of(&s.entries[0]),
          "rom entry parsed: %d entries", s.nentries);
    rk_scene_free(&s);
}

/* Nested balls make the layers of a sphere (the freeform paper's Fig. 7): outermost first, the
 * last region holding a place gives it its material; a place outside every ball keeps the
 * object's. */
TEST(ball_regions_layer_a_sphere)
{
    rk_error err;
    rk_scene s;
    const char *text =
        "{\"objects\": [{" BEAM_OBJECT ", \"regions\": ["
        " {\"ball\": {\"center\": [1, 0, 0], \"radius\": 0.4}, \"material\": {\"young\": 1e5}},"
        " {\"ball\": {\"center\": [1, 0, 0], \"radius\": 0.2}, \"material\": {\"young\": 1e7}}]}]}";
    CHECK_OK(rk_scene_parse(text, "layers.json", &s, &err));
    const double at[4][3] = {{1, 0, 0}, {1.3, 0, 0}, {1, 0, -0.39}, {1, 0.41, 0}}, young[4] = {1e7, 1e5, 1e5, 5e6};
    for (int k = 0; k < 4; k++) {
        rk_material m = rk_scene_material_at(&s.objects[0], at[k]);
        CHECK(m.young == young[k] && m.poisson == 0.45, "place %d: young %g, poisson %g", k, m.young, m.poisson);
    }
    rk_scene_free(&s);
}

TEST(resolves_files_against_the_scene_folder)
{
    rk_error err;
    rk_scene s;
    const char *text = "{\"objects\": [{\"mesh\": {\"file\": \"meshes/a.msh\"},"
                       " \"material\": {\"model\": \"linear\", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1000}}]}";
    CHECK_OK(rk_scene_parse(text, "/data/scenes/s.json", &s, &err));
    CHECK(strcmp(s.objects[0].file, "/data/scenes/meshes/a.msh") == 0, "file %s", s.objects[0].file);
    rk_scene_free(&s);
}

/* Each bad scene must fail with a message containing every listed fragment. */
static const struct {
    const char *name, *text, *expect1, *expect2;
} bad_scenes[] = {
    {"region with box and ball", "{\"objects\": [{" BEAM_OBJECT ", \"regions\": [{\"box\": [[0, 0, 0], [1, 1, 1]],"
     " \"ball\": {\"center\": [0, 0, 0], \"radius\": 1}, \"material\": {\"young\": 1e6}}]}]}",
     "objects[0].regions[0]", "more than one of box, tag and ball"},
    {"ball of no radius", "{\"objects\": [{" BEAM_OBJECT ", \"regions\": [{\"ball\": {\"center\": [0, 0, 0],"
     " \"radius\": 0}, \"material\": {\"young\": 1e6}}]}]}",
     "objects[0].regions[0].ball", "radius must be positive"},
    {"unknown top key", "{\"objects\": [{" BEAM_OBJECT "}], \"gravty\": [0, -9.81, 0]}", "unknown key 'gravty'", "s.json"},
    {"unknown material key", "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1,1,1], \"cells\": [1,1,1]}},"
     " \"material\": {\"model\": \"linear\", \"yung\": 1e6, \"poisson\": 0.3, \"density\": 1}}]}",
     "objects[0].material", "unknown key 'yung'"},
    {"negative density", "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1,1,1], \"cells\": [1,1,1]}},"
     " \"material\": {\"model\": \"linear\", \"young\": 1e6, \"poisson\": 0.3, \"density\": -5}}]}",
     "objects[0].material.density", "positive"},
    {"poisson 0.5", "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1,1,1], \"cells\": [1,1,1]}},"
     " \"material\": {\"model\": \"linear\", \"young\": 1e6, \"poisson\": 0.5, \"density\": 1}}]}",
     "objects[0].material.poisson", "(-1, 0.5)"},
    {"unknown model", "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1,1,1], \"cells\": [1,1,1]}},"
     " \"material\": {\"model\": \"rubber\", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1}}]}",
     "objects[0].material.model", "'rubber'"},
    {"invalid json", "{\"objects\": [\n  {\"mesh\": ,}]}", "s.json:2:", "invalid JSON"},
    {"no objects", "{\"objects\": []}", "objects", "non-empty"},
    {"two mesh sources", "{\"objects\": [{\"mesh\": {\"file\": \"a.msh\", \"box\": {\"size\": [1,1,1], \"cells\": [1,1,1]}},"
     " \"material\": {\"model\": \"linear\", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1}}]}",
     "objects[0].mesh", "exactly one"},
    {"negative step", "{\"objects\": [{" BEAM_OBJECT "}], \"time\": {\"step\": -0.01}}", "time.step", "positive"},
    {"bad integrator", "{\"objects\": [{" BEAM_OBJECT "}], \"time\": {\"integrator\": \"rk4\"}}", "time.integrator", "'rk4'"},
    {"box min above max", "{\"objects\": [{" BEAM_OBJECT ", \"fixed\": [{\"box\": [[1, 0, 0], [0, 1, 1]]}]}]}",
     "objects[0].fixed[0].box", "min exceeds max"},
    {"twist without axis", "{\"objects\": [{" BEAM_OBJECT ", \"moving\": [{\"box\": [[0,0,0],[1,1,1]], \"twist\": {\"degrees_per_second\": 1}}]}]}",
     "objects[0].moving[0].twist.axis", "missing"},
    {"gravity wrong length", "{\"objects\": [{" BEAM_OBJECT "}], \"gravity\": [0, -9.81]}", "gravity", "3 numbers"},
    {"negative refine", "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1,1,1], \"cells\": [1,1,1]}, \"refine\": -1},"
     " \"material\": {\"model\": \"linear\", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1}}]}",
     "objects[0].mesh", "refine must be a whole number from 0 to 4, got -1"},
    {"refine 5", "{\"objects\": [{\"mesh\": {\"file\": \"a.msh\", \"refine\": 5},"
     " \"material\": {\"model\": \"linear\", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1}}]}",
     "objects[0].mesh", "from 0 to 4, got 5"},
    {"fractional refine", "{\"objects\": [{\"mesh\": {\"file\": \"a.msh\", \"refine\": 1.5},"
     " \"material\": {\"model\": \"linear\", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1}}]}",
     "objects[0].mesh", "refine must be a whole number"},
    {"refined point cloud", "{\"objects\": [{\"mesh\": {\"points\": \"a.ply\", \"refine\": 1},"
     " \"material\": {\"model\": \"linear\", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1}}]}",
     "objects[0].mesh", "not to a point cloud"},
    {"zero plane normal", "{\"objects\": [{" BEAM_OBJECT "}], \"obstacles\": [{\"plane\": {\"point\": [0,0,0], \"normal\": [0,0,0]}}]}",
     "obstacles[0].plane", "zero"},
    {"mesh-free modes", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"basis\": \"modes\", \"size\": 4, \"mesh_free\": true}}",
     "rom.mesh_free", "needs basis rkpm_skinning"},
    {"unknown sampling", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"basis\": \"rkpm_skinning\", \"size\": 4,"
     " \"mesh_free\": {\"sampling\": \"sobol\"}}}", "rom.mesh_free", "sampling must be grid, random or cloud"},
    {"negative volume", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"basis\": \"rkpm_skinning\", \"size\": 4,"
     " \"mesh_free\": {\"volume\": -1}}}", "rom.mesh_free", "volume (m^3) must be positive"},
    {"too few points", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"basis\": \"rkpm_skinning\", \"size\": 4,"
     " \"mesh_free\": {\"points\": 2}}}", "rom.mesh_free", "points"},
    {"adaptive threshold zero", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"method\": \"adaptive_subspace\", \"size\": 4,"
     " \"eps_g_nodal\": 0}}", "rom", "eps_g_nodal must be a positive number"},
    {"adaptive negative downdating", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"method\": \"adaptive_subspace\", \"size\": 4,"
     " \"eps_d\": -1}}", "rom", "eps_d must be a positive number"},
    {"adaptive hessian", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"method\": \"adaptive_subspace\", \"size\": 4,"
     " \"hessian\": \"lbfgs\"}}", "rom", "hessian must be \"bfgs\" or \"exact\""},
    {"adaptive without size", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"method\": \"adaptive_subspace\"}}",
     "rom", "needs size"},
    {"adaptive with cubature", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"method\": \"adaptive_subspace\", \"size\": 4,"
     " \"cubature\": {}}}", "rom", "no cubature"},
    {"adaptive key on a fixed basis", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"basis\": \"modes\", \"size\": 4,"
     " \"subdomains\": 8}}", "rom", "subdomains is a key of method adaptive_subspace"},
    {"adaptive fractional subdomains", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"method\": \"adaptive_subspace\", \"size\": 4,"
     " \"subdomains\": 2.5}}", "rom", "subdomains"},
    {"adaptive threshold units", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"method\": \"adaptive_subspace\", \"size\": 4,"
     " \"eps_g_units\": \"strain\"}}", "rom", "eps_g_units must be \"tolerance\""},
    {"adaptive negative residual rounds", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"method\": \"adaptive_subspace\", \"size\": 4,"
     " \"residual_rounds\": -1}}", "rom", "residual_rounds"},
    {"adaptive full fraction over 1", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"method\": \"adaptive_subspace\", \"size\": 4,"
     " \"full_fraction\": 1.5}}", "rom", "full_fraction"},
    {"adaptive residual not a bool", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"method\": \"adaptive_subspace\", \"size\": 4,"
     " \"residual\": 2}}", "rom", "residual"},
    {"adaptive linear lambda", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"method\": \"adaptive_linear\", \"size\": 4,"
     " \"lambda\": 2}}", "rom", "lambda must be in [0, 1]"},
    {"adaptive linear decoder", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"method\": \"adaptive_linear\", \"size\": 4,"
     " \"decoder\": \"vae\"}}", "rom", "decoder must be \"quadratic\", \"quadratic_pod\" or \"crom\""},
    {"crom options without crom", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"method\": \"adaptive_linear\", \"size\": 4,"
     " \"crom\": {\"epochs\": 3}}}", "rom.crom", "is for decoder"},
    {"empty training list", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"method\": \"adaptive_linear\", \"size\": 4,"
     " \"training\": []}}", "rom.training", "1 to 32"},
    {"training for modes", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"basis\": \"modes\", \"size\": 4,"
     " \"training\": [\"a.json\"]}}", "rom.training", "basis pod or method adaptive_linear"},
    {"adaptive linear basis", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"method\": \"adaptive_linear\", \"size\": 4,"
     " \"basis\": \"pod\"}}", "rom", "no basis"},
    {"adaptive linear without size", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"method\": \"adaptive_linear\"}}",
     "rom", "needs size"},
    {"history on a fixed basis", "{\"objects\": [{" BEAM_OBJECT "}], \"rom\": {\"basis\": \"modes\", \"size\": 4,"
     " \"history\": 8}}", "rom", "history is a key of method adaptive_linear"},
    {"proxy voxel on a mesh", "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1,1,1], \"cells\": [1,1,1]}, \"proxy_voxel\": 0.1},"
     " \"material\": {\"model\": \"linear\", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1}}]}",
     "objects[0].mesh", "only with points"},
    {"proxy on a mesh", "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1,1,1], \"cells\": [1,1,1]}, \"proxy\": \"march\"},"
     " \"material\": {\"model\": \"linear\", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1}}]}",
     "objects[0].mesh", "only with points"},
    {"unknown proxy", "{\"objects\": [{\"mesh\": {\"points\": \"a.ply\", \"proxy\": \"spheres\"},"
     " \"material\": {\"model\": \"linear\", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1}}]}",
     "objects[0].mesh", "\"march\" (the default) or \"voxels\""},
};

TEST(bad_scenes_give_one_clear_message)
{
    for (size_t i = 0; i < sizeof bad_scenes / sizeof bad_scenes[0]; i++) {
        rk_error err = {{0}};
        rk_scene s;
        int rc = rk_scene_parse(bad_scenes[i].text, "s.json", &s, &err);
        CHECK(rc != 0, "'%s' was accepted", bad_scenes[i].name);
        CHECK(strstr(err.msg, bad_scenes[i].expect1) && strstr(err.msg, bad_scenes[i].expect2),
              "'%s': message \"%s\" lacks \"%s\" or \"%s\"", bad_scenes[i].name, err.msg, bad_scenes[i].expect1,
              bad_scenes[i].expect2);
        CHECK(strchr(err.msg, '\n') == NULL, "'%s': message spans lines", bad_scenes[i].name);
    }
}

/* mesh.refine: the object's tets split into 8, the vertices selected afterwards; a count above
 * the cap is refused when the mesh is built, naming the object's mesh. */
TEST(refine_key_splits_the_tets)
{
    rk_error err;
    rk_scene s;
    rk_scene_sim sim;
    const char *text = "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [2, 1, 1], \"cells\": [2, 1, 1]}, \"refine\": 2},"
                       " \"material\": {\"model\": \"linear\", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1000},"
                       " \"fixed\": [{\"box\": [[-1, -1, -1], [0.01, 2, 2]]}]}]}";
    CHECK_OK(rk_scene_parse(text, "r.json", &s, &err));
    CHECK(s.objects[0].refine == 2, "refine %d", s.objects[0].refine);
    int rc = rk_scene_build(&s, &sim, &err);
    rk_scene_free(&s);
    CHECK(rc == 0, "build: %s", err.msg);
    /* 12 tets -> 768; the x = 0 face of 1 x 1 m at spacing 1/4 has 25 vertices */
    int nt = sim.mesh.nt, fixed = sim.options.nprescribed ? sim.options.prescribed[0].count : -1;
    rk_scene_sim_free(&sim);
    CHECK(nt == 12 * 64, "%d tets", nt);
    CHECK(fixed == 25, "%d fixed vertices", fixed);
    const char *big = "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1, 1, 1], \"cells\": [12, 12, 6]}, \"refine\": 4},"
                      " \"material\": {\"model\": \"linear\", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1000}}]}";
    CHECK_OK(rk_scene_parse(big, "big.json", &s, &err));
    rc = rk_scene_build(&s, &sim, &err);
    rk_scene_free(&s);
    CHECK(rc != 0, "21 million tets were built");
    CHECK(strstr(err.msg, "big.json: objects[0].mesh: refine: 4 levels would turn 5184 tets into 21233664"),
          "message: %s", err.msg);
}

TEST(missing_scene_file_is_named)
{
    rk_error err;
    rk_scene s;
    CHECK(rk_scene_load("/nonexistent/scene.json", &s, &err) != 0, "accepted");
    CHECK(strstr(err.msg, "/nonexistent/scene.json") != NULL, "message: %s", err.msg);
}

int main(void)
{
    RUN(parses_the_design_example);
    RUN(resolves_files_against_the_scene_folder);
    RUN(bad_scenes_give_one_clear_message);
    RUN(ball_regions_layer_a_sphere);
    RUN(refine_key_splits_the_tets);
    RUN(missing_scene_file_is_named);
    return test_finish();
}
