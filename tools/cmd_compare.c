/* romkit compare SCENE.json [--report R.json] [--quiet]: the full-order model and every reduced
 * method the scene's rom section lists, side by side (precompute/compare/compare.h: the run and its
 * report; this file parses the options, writes the report and prints the table). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "commands.h"
#include "compare/compare.h"
#include "pipeline/fom_report.h"
#include "pipeline/pipeline.h"
#include "util/util.h"

static void compare_usage(FILE *f)
{
    fprintf(f, "usage: romkit compare SCENE.json [--report R.json] [--reference-frames R.npy] [--quiet]\n"
               "  runs the scene at full order, then every entry of its rom section (a list or one\n"
               "  object) as a reduced model, and prints error against time for each:\n"
               "  normalized MSE and max error (over all frames, by the bounding-box diagonal), total\n"
               "  relative online error (each step realigned to the full-order state), the basis fitting\n"
               "  residual (each reference frame fitted by the subspace in least squares: what any run in\n"
               "  it could reach; FreeForm Eq. 36), median seconds per step, speed-up over full order,\n"
               "  precompute seconds. Exit 1 if any method fails.\n"
               "  The errors are against the full-order run on the scene's mesh, or with the scene key\n"
               "  \"reference\": {\"refine\": k} against a full-order run on that mesh refined k times\n"
               "  (1:8 each), taken at the scene mesh's vertices; the methods still run on the scene's\n"
               "  mesh, and the fom row then gives the scene mesh's own error against the reference.\n"
               "  --report R.json   the same per method (methods[]), plus the full-order timings and\n"
               "                    the reference (reference.refine, .vertices, .tets, .seconds_per_step;\n"
               "                    .warning where linear tets lock: Poisson's ratio >= 0.4 without\n"
               "                    \"reference\": {\"order\": 2}, also said on stderr)\n"
               "  --reference-frames R.npy  the reference's positions at the scene mesh's vertices,\n"
               "                    every frame from the start ((steps + 1) x n x 3 float64, as\n"
               "                    bench_reference writes a level's): to measure a costly reference\n"
               "                    against another level without running it again\n"
               "  --quiet           no progress line on stderr\n\n"
               "example:\n"
               "  romkit compare examples/scenes/cantilever_small.json --report compare.json\n");
}

static void print_table(const char *path, const rk_compare_result *res)
{
    printf("%s: %d vertices, %d tets, %d steps; full order %.4g s/step\n", path, res->vertices, res->tets, res->steps,
           res->fom_seconds_per_step);
    if (res->reference_refine > 0 || res->reference_order == 2)
        printf("reference: refine %d, %d vertices, %d %s tets, full order %.4g s/step (%.4g s); errors at the %d vertices "
               "above; full order on the %d tets: nMSE %.3g, max err %.3g\n", res->reference_refine,
               res->reference_vertices, res->reference_tets, res->reference_order == 2 ? "quadratic" : "linear", res->reference_seconds_per_step,
               res->reference_seconds_total, res->vertices, res->tets, res->fom_normalized_mse,
               res->fom_normalized_max_error);
    printf("%-28s %5s %6s %10s %10s %10s %10s %10s %10s %9s %9s\n", "method", "r", "cub", "nMSE", "paper", "max err",
           "online", "basis fit", "s/step", "speed-up", "precomp s");
    for (int k = 0; k < res->nmethods; k++) {
        const rk_compare_method *m = &res->methods[k];
        if (m->failure[0]) {
            printf("%-28s FAILED: %s\n", m->name, m->failure);
            continue;
        }
        char paper[32] = "-";
        if (isfinite(m->reference_nmse)) snprintf(paper, sizeof paper, "%.3g", m->reference_nmse);
        char cub[16] = "exact";
        if (m->method->table_cubature) snprintf(cub, sizeof cub, "%s", m->method->table_cubature);
        else if (m->cubature_points) snprintf(cub, sizeof cub, "%d", m->cubature_points);
        char fit[32] = "-"; /* no fixed linear basis (Koopman, adaptive): no fit */
        if (isfinite(m->fit_normalized_mse)) snprintf(fit, sizeof fit, "%.3g", m->fit_normalized_mse);
        printf("%-28s %5d %6s %10.3g %10s %10.3g %10.3g %10s %10.3g %9.1f %9.3g\n", m->name, m->r, cub,
               m->normalized_mse, paper, m->normalized_max_error, m->relative_online_error, fit,
               m->seconds_per_step, m->speedup,
               m->seconds_basis + m->seconds_cubature + m->seconds_training_run + m->seconds_fit);
    }
    for (int k = 0; k < res->nmethods; k++) {
        const rk_compare_method *m = &res->methods[k];
        if (m->failure[0]) continue;
        if (m->method->print) m->method->print(m, stdout);
        else printf("  %s: basis %s; cubature %s\n", m->name, m->basis_reason, m->cubature_reason);
        if (m->volume_warning[0]) printf("  warning: %s: %s\n", m->name, m->volume_warning);
    }
}

int cmd_compare(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (is_help(argv[i])) {
            compare_usage(stdout);
            return 0;
        }
    const char *scene_path, *report_out = NULL, *frames_out = NULL;
    int quiet = 0;
    const cli_option opts[] = {{"--report", &report_out, NULL}, {"--reference-frames", &frames_out, NULL},
                               {"--quiet", NULL, &quiet}, {NULL, NULL, NULL}};
    if (cli_parse("compare", argc, argv, opts, &scene_path, "scene file")) {
        compare_usage(stderr);
        return 2;
    }
    rk_progress_set_quiet(quiet);
    double t0 = rk_now();
    rk_error err = {{0}};
    rk_scene scene;
    rk_compare_result res = {0};
    int rc = 1;
    if (rk_scene_load(scene_path, &scene, &err)) goto done;
    if (rk_compare_scene(&scene, &res, &err)) {
        rk_scene_free(&scene);
        goto done;
    }
    rk_scene_free(&scene);
    cJSON *report = rk_compare_report(&res, rk_now() - t0);
    int wrote = !report_out || rk_json_write_file(report_out, report, &err) == 0;
    cJSON_Delete(report);
    if (!wrote) goto done;
    if (frames_out) {
        const long shape[3] = {res.steps + 1, res.vertices, 3};
        if (rk_npy_write(frames_out, res.reference_x, 3, shape, &err)) goto done;
    }
    print_table(scene_path, &res);
    if (res.reference_warning[0]) fprintf(stderr, "romkit compare: warning: %s\n", res.reference_warning);
    for (int k = 0; k < res.nmethods; k++)
        if (!res.methods[k].failure[0])
            rk_unconverged_warn(stderr, res.methods[k].name, res.methods[k].unconverged_steps, res.steps);
    rc = 0;
    for (int k = 0; k < res.nmethods; k++)
        if (res.methods[k].failure[0]) {
            fprintf(stderr, "romkit compare: %s failed: %s\n", res.methods[k].name, res.methods[k].failure);
            rc = 1;
        }
    rk_compare_result_free(&res);
    return rc;
done:
    fprintf(stderr, "romkit compare: %s\n", err.msg);
    rk_compare_result_free(&res);
    return rc;
}
