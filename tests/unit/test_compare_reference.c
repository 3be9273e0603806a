/* romkit compare against a refined full-order reference (scene "reference": {"refine": k}): the
 * reference runs on the scene's mesh refined k times, its size is reported, every error is taken at
 * the scene mesh's vertices (the refined mesh's first ones), and the reduced methods still run on
 * the scene's mesh. Small meshes: the whole file runs in a few seconds. The converged reference of
 * the FreeForm beam (Table 1) is bench/beam_reference.sh. */
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

/* A coarse FreeForm beam (5 x 1 x 1 m, 10 x 2 x 2 cells, 240 tets) sagging under gravity for 0.3 s;
 * mesh_extra goes into its mesh object, root_extra at the top level. */
static char beam_text[2048];
static const char *beam(const char *mesh_extra, const char *root_extra)
{
    snprintf(beam_text, sizeof beam_text,
             "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [5, 1, 1], \"cells\": [10, 2, 2]}%s},"
             " \"material\": {\"model\": \"neohookean\", \"young\": 5e6, \"poisson\": 0.45, \"density\": 1000},"
             " \"fixed\": [{\"box\": [[-1, -1, -1], [0.5, 2, 2]]}]}],"
             " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": 0.01, \"duration\": 0.3},"
             " \"rom\": [{\"basis\": \"modes\", \"size\": 8}, {\"basis\": \"skinning\", \"size\": 4}]%s}",
             mesh_extra, root_extra);
    return beam_text;
}

typedef struct {
    int nv;        /* vertices kept: the first `per_object` of each object, in order */
    int ndof, T;
    int per_object;
    const int *first;  /* the run's object_first_vertex */
    int nobjects;
    double *x;     /* 3 nv x (T + 1) */
} first_vertices;

static int keep_first(void *ctx, int step, rk_fom *fom, double seconds, rk_error *err)
{
    first_vertices *f = ctx;
    for (int k = 0; k < f->nobjects; k++)
        memcpy(f->x + (size_t)f->ndof * step + 3 * (size_t)k * f->per_object, fom->x + 3 * (size_t)f->first[k],
               sizeof(double) * 3 * f->per_object);
    return 0;
}

/* The scene run at full order, keeping the first per_object vertices of each object in every frame. */
static int run_first(const char *json, int per_object, first_vertices *f, rk_error *err)
{
    rk_scene scene;
    rk_scene_sim sim;
    if (rk_scene_parse(json, "test.json", &scene, err)) return -1;
    if (rk_scene_build(&scene, &sim, err)) {
        rk_scene_free(&scene);
        return -1;
    }
    f->per_object = per_object;
    f->nobjects = scene.nobjects;
    f->first = sim.object_first_vertex;
    f->nv = per_object * scene.nobjects;
    f->ndof = 3 * f->nv;
    f->T = sim.steps;
    f->x = calloc((size_t)f->ndof * (f->T + 1), sizeof(double));
    int rc = f->x ? rk_scene_fom_run(&sim, NULL, "test run", keep_first, f, NULL, err) : -1;
    rk_scene_sim_free(&sim);
    rk_scene_free(&scene);
    return rc;
}

/* util's normalized MSE between two such runs, over the frames after the start. */
static double nmse_between(const first_vertices *a, const first_vertices *b)
{
    rk_run_error e;
    rk_run_error_init(&e, a->x, a->nv);
    for (int s = 1; s <= a->T; s++) rk_run_error_add(&e, a->x + (size_t)a->ndof * s, b->x + (size_t)b->ndof * s);
    return rk_normalized_mse(&e);
}

/* Refine 1 against refine 0: the reference is 8 times the tets, its size is reported, the full-order
 * run on the scene's mesh gets its own error against it, and each method's error changes (the
 * 240-tet beam is far stiffer than the 1920-tet one). That error is the one util's normalized MSE
 * gives between the scene's run and a run of the scene with mesh.refine 1 at its first vertices:
 * the refined mesh numbers the scene mesh's vertices first, and the errors are taken there. */
TEST(refined_reference_is_measured_at_the_scene_vertices)
{
    rk_error err;
    rk_compare_result r0, r1;
    CHECK_OK(compare_text(beam("", ""), &r0, &err));
    CHECK_OK(compare_text(beam("", ", \"reference\": {\"refine\": 1}"), &r1, &err));
    printf("# refine 0: %d vertices, %d tets; refine 1: reference %d vertices, %d tets, %.3g s/step; scene mesh "
           "nMSE %.3e against it\n", r0.reference_vertices, r0.reference_tets, r1.reference_vertices,
           r1.reference_tets, r1.reference_seconds_per_step, r1.fom_normalized_mse);
    CHECK(r0.reference_refine == 0 && r0.reference_tets == r0.tets && r0.reference_vertices == r0.vertices &&
          r0.fom_normalized_mse == 0, "refine 0: reference %d / %d tets, nMSE %g", r0.reference_tets, r0.tets,
          r0.fom_normalized_mse);
    CHECK(r1.reference_refine == 1 && r1.tets == 240 && r1.reference_tets == 8 * 240 && r1.vertices == 99 &&
          r1.reference_vertices == 21 * 5 * 5, "refine 1: %d -> %d tets, %d -> %d vertices", r1.tets,
          r1.reference_tets, r1.vertices, r1.reference_vertices);
    CHECK(r1.steps == r0.steps && r1.reference_seconds_per_step > 0, "steps %d / %d", r1.steps, r0.steps);
    for (int k = 0; k < r1.nmethods; k++) {
        const rk_compare_method *a = &r0.methods[k], *b = &r1.methods[k];
        printf("# %-12s nMSE %.4e against refine 0, %.4e against refine 1; online %.3e / %.3e\n", a->name,
               a->normalized_mse, b->normalized_mse, a->relative_online_error, b->relative_online_error);
        CHECK(!a->failure[0] && !b->failure[0], "%s failed: %s %s", a->name, a->failure, b->failure);
        /* the reduced model itself is the same: it runs on the scene's mesh */
        CHECK(a->r == b->r && a->cubature_points == b->cubature_points, "%s: r %d / %d", a->name, a->r, b->r);
        CHECK(fabs(a->normalized_mse - b->normalized_mse) > 0.1 * a->normalized_mse, "%s: nMSE %g and %g",
              a->name, a->normalized_mse, b->normalized_mse);
        CHECK(isfinite(b->relative_online_error) && b->relative_online_error != a->relative_online_error,
              "%s: online %g and %g", a->name, a->relative_online_error, b->relative_online_error);
    }
    /* the same number by hand: the scene's run and the mesh.refine 1 run at the first 99 vertices */
    first_vertices coarse = {0}, fine = {0};
    CHECK_OK(run_first(beam("", ""), 99, &coarse, &err));
    CHECK_OK(run_first(beam(", \"refine\": 1", ""), 99, &fine, &err));
    double nmse = nmse_between(&coarse, &fine);
    printf("# by hand: nMSE %.6e, compare %.6e\n", nmse, r1.fom_normalized_mse);
    CHECK(nmse > 1e-6 && fabs(nmse - r1.fom_normalized_mse) <= 1e-12 * nmse, "by hand %.12g, compare %.12g", nmse,
          r1.fom_normalized_mse);
    /* the reference's frames kept in the result (romkit compare --reference-frames writes them): the
     * refined run's at the scene's vertices with a refined reference, the scene's own run without */
    double d0 = 0, d1 = 0, moved = 0;
    for (size_t i = 0; i < (size_t)coarse.ndof * (coarse.T + 1); i++) {
        d0 = fmax(d0, fabs(r0.reference_x[i] - coarse.x[i]));
        d1 = fmax(d1, fabs(r1.reference_x[i] - fine.x[i]));
        moved = fmax(moved, fabs(fine.x[i] - coarse.x[i]));
    }
    printf("# reference frames: refine 0 %.3g m from the scene's run, refine 1 %.3g m from the refined run "
           "(the two runs %.3g m apart)\n", d0, d1, moved);
    CHECK(r1.steps == coarse.T && r1.vertices == coarse.nv && d0 <= 1e-9 && d1 <= 1e-9 && moved > 1e-3,
          "reference frames: %g, %g m off (runs %g m apart)", d0, d1, moved);
    free(coarse.x);
    free(fine.x);
    rk_compare_result_free(&r0);
    rk_compare_result_free(&r1);
}

/* Two objects: the refined scene numbers each object's vertices after the previous object's refined
 * ones, so the second object's scene vertices sit further down; the errors still pair them up. */
TEST(each_object_is_measured_at_its_own_vertices)
{
    const char *fmt =
        "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [1, 0.2, 0.2], \"cells\": [4, 1, 1]}%s},"
        " \"material\": {\"model\": \"neohookean\", \"young\": 2e6, \"poisson\": 0.4, \"density\": 1000},"
        " \"fixed\": [{\"box\": [[-1, -1, -1], [0.01, 1, 1]]}]},"
        " {\"mesh\": {\"box\": {\"size\": [1, 0.2, 0.2], \"cells\": [4, 1, 1]}, \"translate\": [0, 0, 1]%s},"
        " \"material\": {\"model\": \"neohookean\", \"young\": 5e5, \"poisson\": 0.4, \"density\": 1000},"
        " \"fixed\": [{\"box\": [[-1, -1, 0.9], [0.01, 1, 2]]}]}],"
        " \"gravity\": [0, -9.81, 0], \"time\": {\"step\": 0.01, \"duration\": 0.2},"
        " \"rom\": [{\"basis\": \"modes\", \"size\": 6}]%s}";
    char with_ref[2048], coarse_text[2048], fine_text[2048];
    snprintf(with_ref, sizeof with_ref, fmt, "", "", ", \"reference\": {\"refine\": 1}");
    snprintf(coarse_text, sizeof coarse_text, fmt, "", "", "");
    snprintf(fine_text, sizeof fine_text, fmt, ", \"refine\": 1", ", \"refine\": 1", "");
    rk_error err;
    rk_compare_result r;
    CHECK_OK(compare_text(with_ref, &r, &err));
    first_vertices coarse = {0}, fine = {0};
    CHECK_OK(run_first(coarse_text, 20, &coarse, &err));
    CHECK_OK(run_first(fine_text, 20, &fine, &err));
    double nmse = nmse_between(&coarse, &fine);
    printf("# two objects: %d -> %d vertices; scene mesh nMSE %.6e, by hand %.6e; modes-6 %.3e\n", r.vertices,
           r.reference_vertices, r.fom_normalized_mse, nmse, r.methods[0].normalized_mse);
    CHECK(r.vertices == 40 && r.reference_vertices == 2 * 81, "%d and %d vertices", r.vertices, r.reference_vertices);
    CHECK(nmse > 1e-6 && fabs(nmse - r.fom_normalized_mse) <= 1e-12 * nmse, "by hand %.12g, compare %.12g", nmse,
          r.fom_normalized_mse);
    CHECK(!r.methods[0].failure[0], "modes-6: %s", r.methods[0].failure);
    free(coarse.x);
    free(fine.x);
    rk_compare_result_free(&r);
}

/* A linear-elastic bar with nu = 0, clamped at one end and pulled 0.1 m at the other, solved
 * statically: a uniform stretch, which linear tets reproduce exactly on any mesh. Refinement
 * changes nothing but round-off, so a method's error against the refined reference is the one
 * against the scene's own run. */
TEST(refinement_changes_nothing_where_the_mesh_is_exact)
{
    const char *fmt =
        "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [2, 1, 1], \"cells\": [4, 2, 2]}},"
        " \"material\": {\"model\": \"linear\", \"young\": 1e6, \"poisson\": 0, \"density\": 1000},"
        " \"fixed\": [{\"box\": [[-1, -1, -1], [0.01, 2, 2]]}],"
        " \"moving\": [{\"box\": [[1.99, -1, -1], [3, 2, 2]], \"translate\": {\"velocity\": [0.1, 0, 0]}}]}],"
        " \"gravity\": [0, 0, 0], \"time\": {\"step\": 0.01, \"duration\": 1, \"static\": true},"
        " \"rom\": [{\"basis\": \"modes\", \"size\": 4}]%s}";
    char a[1024], b[1024];
    snprintf(a, sizeof a, fmt, "");
    snprintf(b, sizeof b, fmt, ", \"reference\": {\"refine\": 2}");
    rk_error err;
    rk_compare_result r0, r2;
    CHECK_OK(compare_text(a, &r0, &err));
    CHECK_OK(compare_text(b, &r2, &err));
    const rk_compare_method *m0 = &r0.methods[0], *m2 = &r2.methods[0];
    printf("# stretch: reference %d tets (refine %d); scene mesh nMSE %.3e against it; modes-4 nMSE %.6e against "
           "refine 0, %.6e against refine 2\n", r2.reference_tets, r2.reference_refine, r2.fom_normalized_mse,
           m0->normalized_mse, m2->normalized_mse);
    CHECK(r2.reference_tets == 64 * r0.tets && r2.steps == 1, "%d tets, %d steps", r2.reference_tets, r2.steps);
    CHECK(!m0->failure[0] && !m2->failure[0], "failed: %s %s", m0->failure, m2->failure);
    CHECK(r2.fom_normalized_mse < 1e-16, "the exact stretch moved by %g (Newton stops at 1e-5 of the diagonal)", r2.fom_normalized_mse);
    CHECK(m0->normalized_mse > 1e-8, "modes-4 nMSE %g: too small to tell", m0->normalized_mse);
    CHECK(fabs(m0->normalized_mse - m2->normalized_mse) <= 1e-6 * m0->normalized_mse, "modes-4 nMSE %.12g / %.12g",
          m0->normalized_mse, m2->normalized_mse);
    rk_compare_result_free(&r0);
    rk_compare_result_free(&r2);
}

/* Nonsense values fail the parse with the JSON path and what is wrong; too many levels say the tet
 * count they would make. */
TEST(bad_reference_values_name_the_path)
{
    static const struct {
        const char *root, *mesh, *want;
    } bad[] = {
        {", \"reference\": {\"refine\": -1}", "", "got -1"},
        {", \"reference\": {\"refine\": 1.5}", "", "whole number"},
        {", \"reference\": {\"refine\": \"2\"}", "", "must be a number"},
        {", \"reference\": {}", "", "names neither"},
        {", \"reference\": {\"order\": 3}", "", "reference.order: must be 1 (linear tets) or 2"},
        {", \"reference\": {\"order\": 1}", "", "names neither"},
        {", \"reference\": {\"refine\": 1, \"cells\": 2}", "", "cells"},
        {", \"reference\": 2", "", "must be an object"},
        /* 240 tets x 8^5 = 7,864,320 tets, but 5 levels */
        {", \"reference\": {\"refine\": 5}", "", "7864320 tets"},
        /* on top of mesh.refine 4: the same count, and the message names the object's own levels */
        {", \"reference\": {\"refine\": 1}", ", \"refine\": 4", "mesh.refine 4) into 7864320 tets"},
        {", \"reference\": {\"refine\": 1e9}", "", "into "},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        rk_error err = {{0}};
        rk_scene scene;
        int rc = rk_scene_parse(beam(bad[i].mesh, bad[i].root), "beam.json", &scene, &err);
        printf("# %s%s -> %s\n", bad[i].root + 2, bad[i].mesh, err.msg);
        CHECK(rc != 0, "%s was taken", bad[i].root);
        CHECK(strstr(err.msg, "beam.json: reference") && strstr(err.msg, bad[i].want), "%s: message: %s",
              bad[i].root, err.msg);
    }
    rk_error err;
    rk_scene scene;
    CHECK_OK(rk_scene_parse(beam("", ", \"reference\": {\"refine\": 0}"), "beam.json", &scene, &err));
    CHECK(scene.reference_refine == 0, "refine %d", scene.reference_refine);
    rk_scene_free(&scene);
    CHECK_OK(rk_scene_parse(beam("", ", \"reference\": {\"order\": 2}"), "beam.json", &scene, &err));
    CHECK(scene.reference_refine == 0 && scene.reference_order == 2, "refine %d, order %d", scene.reference_refine,
          scene.reference_order);
    rk_scene_free(&scene);
    CHECK_OK(rk_scene_parse(beam("", ", \"reference\": {\"refine\": 3}"), "beam.json", &scene, &err));
    CHECK(scene.reference_refine == 3, "refine %d", scene.reference_refine);
    rk_scene_free(&scene);
}

int main(void)
{
    RUN(refined_reference_is_measured_at_the_scene_vertices);
    RUN(each_object_is_measured_at_its_own_vertices);
    RUN(refinement_changes_nothing_where_the_mesh_is_exact);
    RUN(bad_reference_values_name_the_path);
    return test_finish();
}
