/* The adaptive simulator's full-space residual in the reports (method_adaptive_subspace.h): per
 * step, its summary, and the line on stderr when a run ended steps above its tolerance (rk_adaptive_own_tolerance). */
#include "pipeline/method_adaptive_subspace.h"

#include <math.h>

void rk_adaptive_residual_add(rk_adaptive_subspace_measures *m, int s, int T, double r)
{
    int stride = (T + RK_ADAPTIVE_RESIDUAL_VALUES - 1) / RK_ADAPTIVE_RESIDUAL_VALUES;
    if (stride < 1) stride = 1;
    int k = s / stride;
    if (k >= RK_ADAPTIVE_RESIDUAL_VALUES) return;
    m->residual_stride = stride;
    if (k >= m->residual_count) {
        m->residual_count = k + 1;
        m->residual_per_step[k] = (float)r;
    } else if (r > m->residual_per_step[k]) {
        m->residual_per_step[k] = (float)r;
    }
}

void rk_adaptive_residual_record(rk_adaptive_subspace_measures *m, const rk_adaptive *ad)
{
    const rk_adaptive_stats *s = &ad->stats;
    m->steps_full = (int)s->steps_full;
    m->residual = ad->opt.residual;
    m->residual_tolerance = ad->tolerance;
    m->residual_max = s->residual_max;
    m->residual_mean = s->steps ? s->residual_sum / s->steps : 0;
    m->residual_over = (int)s->residual_over;
    m->residual_rounds = (int)s->residual_rounds;
    m->residual_nodes_added = (int)s->residual_nodes_added;
}

void rk_adaptive_residual_report(cJSON *j, const rk_adaptive_subspace_measures *m)
{
    if (!m->residual) return;
    cJSON *r = cJSON_AddObjectToObject(j, "residual");
    cJSON_AddNumberToObject(r, "tolerance", m->residual_tolerance);
    cJSON_AddNumberToObject(r, "max", m->residual_max);
    cJSON_AddNumberToObject(r, "mean", m->residual_mean);
    cJSON_AddNumberToObject(r, "steps_over_tolerance", m->residual_over);
    cJSON_AddNumberToObject(r, "enrichment_rounds", m->residual_rounds);
    cJSON_AddNumberToObject(r, "vertices_added", m->residual_nodes_added);
    cJSON_AddNumberToObject(r, "steps_per_value", m->residual_stride);
    cJSON *a = cJSON_AddArrayToObject(r, "per_step");
    for (int k = 0; k < m->residual_count; k++) cJSON_AddItemToArray(a, cJSON_CreateNumber(m->residual_per_step[k]));
}

void rk_adaptive_residual_warn(FILE *f, const char *name, const rk_adaptive_subspace_measures *m, int steps)
{
    if (!m->residual || m->residual_over == 0) return;
    fprintf(f, "warning: %s: the full-space residual |d|_inf/h ended %d of %d steps above its tolerance "
            "%.3g m/s (largest %.3g m/s, after %d enrichment rounds for it): its answer may miss its accuracy target "
            "(more residual_rounds or a lower eps_g_nodal enrich more)\n",
            name, m->residual_over, steps, m->residual_tolerance, m->residual_max, m->residual_rounds);
}
