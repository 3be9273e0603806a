/* romkit compare SCENE.json [--report R.json] [--quiet]: the full-order model and every reduced
 * method the scene's rom section lists, side by side (precompute/rom/compare.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "commands.h"
#include "compare/compare.h"
#include "pipeline/pipeline.h"
#include "util/util.h"

static void compare_usage(FILE *f)
{
    fprintf(f, "usage: romkit compare SCENE.json [--report R.json] [--quiet]\n"
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
               "                    the reference (reference.refine, .vertices, .tets, .seconds_per_step)\n"
               "  --quiet           no progress line on stderr\n\n"
               "example:\n"
               "  romkit compare examples/scenes/cantilever_small.json --report compare.json\n");
}

static void add_number(cJSON *o, const char *key, double v)
{
    if (isfinite(v)) cJSON_AddNumberToObject(o, key, v);
    else cJSON_AddNullToObject(o, key);
}

static cJSON *method_json(const rk_compare_method *m)
{
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "name", m->name);
    cJSON_AddStringToObject(j, "kind", m->method->kind);
    cJSON_AddNumberToObject(j, "training_frames", m->training_frames);
    if (m->failure[0]) {
        cJSON_AddStringToObject(j, "failure", m->failure);
        return j;
    }
    cJSON *b = cJSON_AddObjectToObject(j, "basis");
    cJSON_AddStringToObject(b, "type", m->basis_name);
    cJSON_AddNumberToObject(b, "size", m->size);
    cJSON_AddNumberToObject(b, "columns", m->r);
    cJSON_AddStringToObject(b, "bound_by", m->basis_reason);
    if (m->method->report) m->method->report(m, j); /* the method's own keys */
    cJSON *c = cJSON_AddObjectToObject(j, "cubature");
    cJSON_AddNumberToObject(c, "elements", m->cubature_points);
    add_number(c, "relative_error", m->cubature_error);
    cJSON_AddStringToObject(c, "bound_by", m->cubature_reason);
    add_number(j, "normalized_mse", m->normalized_mse);
    add_number(j, "normalized_max_error", m->normalized_max_error);
    add_number(j, "max_error", m->max_error_m);
    add_number(j, "relative_error", m->relative_error);
    add_number(j, "relative_online_error", m->relative_online_error);
    add_number(j, "fit_normalized_mse", m->fit_normalized_mse);
    add_number(j, "seconds_per_step", m->seconds_per_step);
    add_number(j, "speedup", m->speedup);
    cJSON *s = cJSON_AddObjectToObject(j, "seconds");
    cJSON_AddNumberToObject(s, "basis", m->seconds_basis);
    cJSON_AddNumberToObject(s, "cubature", m->seconds_cubature);
    cJSON_AddNumberToObject(s, "training_run", m->seconds_training_run);
    cJSON_AddNumberToObject(s, "fit", m->seconds_fit);
    cJSON_AddNumberToObject(s, "precompute",
                            m->seconds_basis + m->seconds_cubature + m->seconds_training_run + m->seconds_fit);
    cJSON_AddNumberToObject(j, "newton_iterations", (double)m->newton_iterations);
    cJSON_AddNumberToObject(j, "unconverged_steps", (double)m->unconverged_steps);
    cJSON_AddNumberToObject(j, "realign_clipped", m->realign_clipped);
    if (isfinite(m->reference_nmse)) {
        cJSON *ref = cJSON_AddObjectToObject(j, "reference");
        cJSON_AddNumberToObject(ref, "normalized_mse", m->reference_nmse);
        cJSON_AddStringToObject(ref, "source", m->reference_source);
    }
    return j;
}

static cJSON *make_report(const rk_compare_result *res, double seconds)
{
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "vertices", res->vertices);
    cJSON_AddNumberToObject(root, "tets", res->tets);
    cJSON_AddNumberToObject(root, "steps", res->steps);
    cJSON_AddNumberToObject(root, "bbox_diagonal", res->bbox_diagonal);
    cJSON *fom = cJSON_AddObjectToObject(root, "fom");
    cJSON_AddNumberToObject(fom, "seconds_per_step", res->fom_seconds_per_step);
    cJSON_AddNumberToObject(fom, "seconds_total", res->fom_seconds_total);
    cJSON_AddNumberToObject(fom, "newton_iterations", (double)res->fom_newton_iterations);
    /* What every error is measured against: refine 0 is the full-order run above. */
    cJSON *ref = cJSON_AddObjectToObject(root, "reference");
    cJSON_AddNumberToObject(ref, "refine", res->reference_refine);
    cJSON_AddNumberToObject(ref, "vertices", res->reference_vertices);
    cJSON_AddNumberToObject(ref, "tets", res->reference_tets);
    cJSON_AddNumberToObject(ref, "measured_vertices", res->vertices);
    cJSON_AddNumberToObject(ref, "seconds_per_step", res->reference_seconds_per_step);
    cJSON_AddNumberToObject(ref, "seconds_total", res->reference_seconds_total);
    cJSON_AddNumberToObject(ref, "newton_iterations", (double)res->reference_newton_iterations);
    if (res->has_contact) {
        cJSON *c = cJSON_AddObjectToObject(ref, "contact");
        add_number(c, "min_distance", res->reference_min_distance);
        cJSON_AddNumberToObject(c, "intersections", res->reference_intersections);
    }
    cJSON *methods = cJSON_AddArrayToObject(root, "methods");
    cJSON *f = cJSON_CreateObject();
    cJSON_AddStringToObject(f, "name", "fom");
    cJSON_AddNumberToObject(f, "seconds_per_step", res->fom_seconds_per_step);
    cJSON_AddNumberToObject(f, "normalized_mse", res->fom_normalized_mse);
    if (res->reference_refine > 0) { /* the scene mesh's run against the refined one */
        cJSON_AddNumberToObject(f, "normalized_max_error", res->fom_normalized_max_error);
        cJSON_AddNumberToObject(f, "max_error", res->fom_max_error_m);
        cJSON_AddNullToObject(f, "relative_online_error"); /* not measured: it would restart the run each step */
    } else {
        cJSON_AddNumberToObject(f, "relative_online_error", 0);
    }
    cJSON_AddNumberToObject(f, "relative_error", res->fom_relative_error);
    cJSON_AddItemToArray(methods, f);
    for (int k = 0; k < res->nmethods; k++) {
        const rk_compare_method *m = &res->methods[k];
        cJSON *j = method_json(m);
        if (res->has_contact && m->method->measures_contact && !m->failure[0]) {
            cJSON *c = cJSON_AddObjectToObject(j, "contact");
            add_number(c, "min_distance", m->contact_min_distance);
            cJSON_AddNumberToObject(c, "intersections", m->contact_intersections);
        }
        cJSON_AddItemToArray(methods, j);
    }
    if (res->has_contact) { /* the full-order run's */
        cJSON *c = cJSON_AddObjectToObject(root, "contact");
        add_number(c, "min_distance", res->fom_min_distance);
        cJSON_AddNumberToObject(c, "intersections", res->fom_intersections);
    }
    cJSON *s = cJSON_AddObjectToObject(root, "seconds");
    cJSON_AddNumberToObject(s, "total", seconds);
    return root;
}

static void print_table(const char *path, const rk_compare_result *res)
{
    printf("%s: %d vertices, %d tets, %d steps; full order %.4g s/step\n", path, res->vertices, res->tets, res->steps,
           res->fom_seconds_per_step);
    if (res->reference_refine > 0)
        printf("reference: refine %d, %d vertices, %d tets, full order %.4g s/step (%.4g s); errors at the %d vertices "
               "above; full order on the %d tets: nMSE %.3g, max err %.3g\n", res->reference_refine,
               res->reference_vertices, res->reference_tets, res->reference_seconds_per_step,
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
    }
}

int cmd_compare(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (is_help(argv[i])) {
            compare_usage(stdout);
            return 0;
        }
    const char *scene_path, *report_out = NULL;
    int quiet = 0;
    const cli_option opts[] = {{"--report", &report_out, NULL}, {"--quiet", NULL, &quiet}, {NULL, NULL, NULL}};
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
    cJSON *report = make_report(&res, rk_now() - t0);
    int wrote = !report_out || rk_json_write_file(report_out, report, &err) == 0;
    cJSON_Delete(report);
    if (!wrote) goto done;
    print_table(scene_path, &res);
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
