/* rk_compare_report (compare.h): a comparison as romkit compare's report. Each method's own keys
 * come from its report operation (method.h). */
#include "compare/compare.h"

#include <math.h>

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
    if (m->volume_warning[0]) cJSON_AddStringToObject(j, "volume_warning", m->volume_warning);
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

cJSON *rk_compare_report(const rk_compare_result *res, double seconds)
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
    cJSON_AddNumberToObject(ref, "order", res->reference_order);
    cJSON_AddNumberToObject(ref, "vertices", res->reference_vertices);
    cJSON_AddNumberToObject(ref, "tets", res->reference_tets);
    cJSON_AddNumberToObject(ref, "measured_vertices", res->vertices);
    cJSON_AddNumberToObject(ref, "seconds_per_step", res->reference_seconds_per_step);
    cJSON_AddNumberToObject(ref, "seconds_total", res->reference_seconds_total);
    cJSON_AddNumberToObject(ref, "newton_iterations", (double)res->reference_newton_iterations);
    if (res->reference_warning[0]) cJSON_AddStringToObject(ref, "warning", res->reference_warning);
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
    if (res->reference_refine > 0 || res->reference_order == 2) { /* the scene mesh's run against the reference */
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

