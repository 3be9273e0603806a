/* An adaptive subspace entry beside full order (method_adaptive_subspace.c's compare): the free run
 * from the scene's start, and the realigned run that starts each step from the reference's state. */
#include "pipeline/method_adaptive_subspace.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void record_model(rk_compare_method *m, const rk_adaptive *ad, int nv)
{
    const rk_adaptive_stats *s = &ad->stats;
    rk_adaptive_subspace_measures *am = rk_method_measures(m, &rk_method_adaptive_subspace);
    m->r = ad->impl ? ad->modes : 0;
    am->mean_modes = s->steps ? s->sum_modes / s->steps : 0;
    am->mean_nodes = s->steps ? s->sum_nodes / s->steps : 0;
    am->enriched_share = am->mean_nodes / nv;
    am->max_modes = s->max_modes;
    am->max_nodes = s->max_nodes;
    am->subdomains = ad->opt.subdomains;
    am->pcg_per_solve = s->solves ? (double)s->pcg_iterations / s->solves : 0;
    am->newton_per_step = s->steps ? (double)s->newton_iterations / s->steps : 0;
    m->newton_iterations = s->newton_iterations;
    m->unconverged_steps = ad->fom.stats.unconverged_steps;
    double total = s->seconds_total > 0 ? s->seconds_total : 1;
    am->share_potential = s->seconds_potential / total;
    am->share_oracle = s->seconds_oracle / total;
    am->share_hessian = s->seconds_hessian / total;
    am->share_system = s->seconds_system / total;
    am->share_pcg = (s->seconds_pcg - s->seconds_system) / total; /* the PCG's own, the rows built counted apart */
    am->share_line_search = s->seconds_line_search / total;
    rk_adaptive_residual_record(am, ad);
}

int rk_adaptive_subspace_compare(rk_compare_ctx *c, const rk_rom_entry *e, rk_compare_method *m, rk_error *err);

/* Its candidate basis trains on the entry's training set (or the scene's run); it runs as many
 * steps as the scene's own run. */
int rk_adaptive_subspace_compare(rk_compare_ctx *c, const rk_rom_entry *e, rk_compare_method *m, rk_error *err)
{
    const rk_scene *scene = c->scene;
    const rk_scene_sim *sim = c->sim;
    const rk_fom_frames *ref = c->ref;
    const double *D;
    int T;
    if (rk_compare_training(c, e, &D, &T, m, err)) return -1;
    T = c->fom->T;
    int ndof = ref->ndof, rc = -1;
    rk_adaptive ad = {0};
    double *secs = rk_calloc((size_t)T + 1, sizeof(double), err);
    if (!secs || rk_scene_adaptive_init(scene, sim, e, D, T, &ad, &m->seconds_basis, err)) goto out;
    m->size = e->basis.size;
    rk_run_error er;
    rk_run_error_init(&er, sim->mesh.X, ndof / 3);
    m->contact_min_distance = INFINITY;
    for (int s = 0; s < T; s++) {
        double t0 = rk_now();
        if (rk_adaptive_step(&ad, err)) goto out;
        secs[s] = rk_now() - t0;
        int crossings;
        double d;
        if (rk_fom_contact_measure(&ad.fom, &crossings, &d, err)) goto out;
        m->contact_min_distance = fmin(m->contact_min_distance, d);
        if (crossings > m->contact_intersections) m->contact_intersections = crossings;
        rk_run_error_add(&er, ad.fom.x, ref->x + (size_t)ndof * (s + 1));
        if (ad.opt.residual)
            rk_adaptive_residual_add(rk_method_measures(m, &rk_method_adaptive_subspace), s, T, ad.stats.residual_last);
    }
    rk_compare_record_errors(m, &er);
    m->seconds_per_step = rk_median(secs, T);
    record_model(m, &ad, sim->mesh.nv);
    rk_adaptive_residual_warn(stderr, m->name, rk_method_measures(m, &rk_method_adaptive_subspace), T);
    /* realigned: the same simulator (its model as the free run left it) from each reference state */
    rk_run_error_init(&er, sim->mesh.X, ndof / 3);
    for (int s = 0; s < T; s++) {
        const double *xp = s > 0 ? ref->x + (size_t)ndof * (s - 1) : NULL, *vp = s > 0 ? ref->v + (size_t)ndof * (s - 1) : NULL;
        rk_fom_set_state(&ad.fom, ref->x + (size_t)ndof * s, ref->v + (size_t)ndof * s, xp, vp, s * sim->options.h);
        if (rk_adaptive_step(&ad, err)) goto out;
        rk_run_error_add(&er, ad.fom.x, ref->x + (size_t)ndof * (s + 1));
    }
    m->relative_online_error = rk_relative_online_error(&er);
    rc = 0;
out:
    rk_adaptive_free(&ad);
    free(secs);
    return rc;
}
