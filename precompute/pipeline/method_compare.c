/* What every method's compare operation shares (method.h): the training set, kept from entry to
 * entry, and how a run's errors or its failure are recorded. */
#include "pipeline/method.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int rk_compare_same_training(const rk_rom_entry *a, const rk_rom_entry *b)
{
    if (a->ntraining != b->ntraining) return 0;
    for (int k = 0; k < a->ntraining; k++)
        if (a->training[k].snapshots != b->training[k].snapshots || strcmp(a->training[k].file, b->training[k].file))
            return 0;
    return 1;
}

/* A scene usually gives every data-driven method the same list: it is run once. */
int rk_compare_training(rk_compare_ctx *c, const rk_rom_entry *e, const double **D, int *T, rk_compare_method *m,
                        rk_error *err)
{
    *D = c->D;
    *T = c->fom->T;
    if (e->ntraining) {
        if (!c->training_from || !rk_compare_same_training(c->training_from, e)) {
            free(c->training_D);
            c->training_D = NULL;
            c->training_from = NULL;
            if (rk_scene_training_set(c->scene, c->sim, e, &c->training_D, &c->training_T, err)) return -1;
            c->training_from = e;
        }
        *D = c->training_D;
        *T = c->training_T;
    }
    m->training_frames = *T;
    return 0;
}

void rk_compare_record_errors(rk_compare_method *m, const rk_run_error *e)
{
    m->normalized_mse = rk_normalized_mse(e);
    m->normalized_max_error = rk_normalized_max_error(e);
    m->max_error_m = e->max_dist;
    m->relative_error = rk_relative_error(e);
}

void rk_compare_record_failure(rk_compare_method *m, const rk_error *err)
{
    snprintf(m->failure, sizeof m->failure, "%s", err->msg);
    m->normalized_mse = m->normalized_max_error = m->max_error_m = m->relative_error = m->relative_online_error = NAN;
    m->fit_normalized_mse = NAN;
    m->seconds_per_step = m->speedup = NAN;
}
