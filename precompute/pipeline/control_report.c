/* romkit control's report (control.h, rk_control_report): the inputs, the Koopman operator and
 * the per-frame errors (util/metrics' rk_frame_error) of the full-order run and the model against
 * the target and each other. */
#include "pipeline/control.h"

#include <math.h>

/* Per-frame |a_t - b_t| over every vertex (rk_frame_error), in % of scale. */
static cJSON *frame_errors(const double *a, const double *b, int n3, int T, double scale, double *max_out)
{
    cJSON *o = cJSON_CreateObject(), *per = cJSON_CreateArray();
    double mx = 0;
    int under2 = 0, under6 = 0;
    for (int t = 0; t < T; t++) {
        double e = 100 * rk_frame_error(a + (size_t)n3 * t, b + (size_t)n3 * t, n3 / 3) / scale;
        mx = fmax(mx, e);
        under2 += e < 2, under6 += e < 6;
        cJSON_AddItemToArray(per, cJSON_CreateNumber(e));
    }
    cJSON_AddNumberToObject(o, "max_percent", mx);
    cJSON_AddNumberToObject(o, "frames_under_2_percent", under2);
    cJSON_AddNumberToObject(o, "frames_under_6_percent", under6);
    cJSON_AddItemToObject(o, "per_frame_percent", per);
    *max_out = mx;
    return o;
}

double rk_control_target_scale(const double *target, int n3, int T)
{
    double scale = 0;
    for (int t = 0; t < T; t++) scale = fmax(scale, rk_frame_error(target + (size_t)n3 * t, NULL, n3 / 3));
    return scale;
}

cJSON *rk_control_report(const rk_rom_entry *e, const rk_control_options *o, const rk_control_result *r,
                         const double *target, int n3, double max_percent[3])
{
    double scale = rk_control_target_scale(target, n3, r->T), local[3];
    double *mx = max_percent ? max_percent : local;
    cJSON *rep = cJSON_CreateObject(), *in = cJSON_AddArrayToObject(rep, "inputs");
    cJSON_AddNumberToObject(rep, "vertices", n3 / 3);
    cJSON_AddNumberToObject(rep, "frames", r->T);
    cJSON_AddNumberToObject(rep, "horizon", o->horizon);
    cJSON_AddNumberToObject(rep, "regularize", o->regularize);
    for (int j = 0; j < o->ninputs; j++) {
        cJSON *x = cJSON_CreateObject();
        if (o->input[j].chamber[0]) {
            cJSON_AddStringToObject(x, "chamber", o->input[j].chamber); /* a pressure (Pa) */
        } else {
            cJSON_AddStringToObject(x, "group", e->asset.groups[o->input[j].group].name);
            cJSON_AddStringToObject(x, "axis", (const char *[]){"x", "y", "z"}[o->input[j].axis]);
        }
        cJSON_AddItemToArray(in, x);
    }
    cJSON_AddNumberToObject(rep, "followed_values", r->follow_values);
    cJSON *k = cJSON_AddObjectToObject(rep, "koopman");
    cJSON_AddNumberToObject(k, "rank", r->rank);
    cJSON_AddNumberToObject(k, "max_abs_eigenvalue", r->max_abs_eigenvalue);
    cJSON_AddNumberToObject(k, "trajectories", r->trajectories);
    cJSON *er = cJSON_AddObjectToObject(rep, "error");
    cJSON_AddStringToObject(er, "definition", "per frame |u_a - u_b| over every vertex, in % of the target's largest "
                            "such norm over the frames (displacements from rest)");
    cJSON_AddNumberToObject(er, "target_max_displacement", scale);
    cJSON_AddItemToObject(er, "fom_vs_target", frame_errors(r->u_fom, target, n3, r->T, scale, &mx[0]));
    cJSON_AddItemToObject(er, "model_vs_target", frame_errors(r->u_model, target, n3, r->T, scale, &mx[1]));
    cJSON_AddItemToObject(er, "model_vs_fom", frame_errors(r->u_model, r->u_fom, n3, r->T, scale, &mx[2]));
    cJSON *s = cJSON_AddObjectToObject(rep, "seconds");
    cJSON_AddNumberToObject(s, "training", r->seconds_training);
    cJSON_AddNumberToObject(s, "fit", r->seconds_fit);
    cJSON_AddNumberToObject(s, "solve", r->seconds_solve);
    cJSON_AddNumberToObject(s, "solve_per_frame", r->seconds_solve / (r->T - 1));
    cJSON_AddNumberToObject(s, "fom", r->seconds_fom);
    return rep;
}

