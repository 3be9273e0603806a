/* An adaptive linear ROM entry beside full order (compare_impl.h, rk_compare_alrom): the free run
 * from the scene's start and the realigned run that starts each step from the reference's state
 * (the paper's Sec. 5.1: total relative online error with per-step realignment). */
#include "compare/compare_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Whether entries a and b build the same decoder from the same data. */
static int same_decoder(const rk_rom_entry *a, const rk_rom_entry *b)
{
    if (a->crom != b->crom || a->quadratic_pod != b->quadratic_pod || a->basis.size != b->basis.size) return 0;
    if (a->cubature != b->cubature || (a->cubature && memcmp(&a->cub, &b->cub, sizeof a->cub))) return 0;
    if (a->crom && memcmp(&a->crom_opt, &b->crom_opt, sizeof a->crom_opt)) return 0;
    return rk_compare_same_training(a, b);
}

void rk_compare_decoder_cache_free(rk_compare_decoder_cache *c)
{
    rk_decoder_free(&c->dec);
    free(c->cub_element);
    free(c->cub_weight);
    c->cub_element = NULL;
    c->cub_weight = NULL;
    c->ncub = 0;
    c->from = NULL;
}

int rk_compare_alrom(const rk_scene *scene, const rk_scene_sim *sim, const fom_run *ref, const double *D, int T,
                     const rk_rom_entry *e, rk_compare_method *m, rk_compare_decoder_cache *cache, rk_error *err)
{
    int ndof = ref->ndof, rc = -1, steps = ref->T; /* T: the training frames in D; steps: the run's */
    rk_alrom s = {0};
    double *secs = rk_calloc((size_t)steps + 1, sizeof(double), err);
    if (!secs) goto out;
    if (!cache->from || !same_decoder(cache->from, e)) { /* a sweep of m or lambda trains one decoder */
        rk_compare_decoder_cache_free(cache);
        double t0 = rk_now();
        if (rk_scene_alrom_decoder(scene, sim, e, D, T, &cache->dec, err) ||
            rk_scene_alrom_cubature(scene, sim, e, D, T, &cache->cub_element, &cache->cub_weight, &cache->ncub, err))
            goto out;
        cache->from = e;
        cache->seconds = rk_now() - t0;
    }
    m->seconds_basis = cache->seconds;
    const rk_decoder *dec = &cache->dec;
    rk_alrom_options o = e->alrom;
    o.ncub = cache->ncub;
    o.cub_element = cache->cub_element;
    o.cub_weight = cache->cub_weight;
    m->cubature_points = cache->ncub;
    if (rk_alrom_init(&s, &sim->fem, &sim->options, dec, &o, err)) {
        rk_error_prefix(err, "%s", e->path);
        goto out;
    }
    m->alrom = 1;
    m->size = m->r = e->basis.size;
    snprintf(m->basis_reason, sizeof m->basis_reason, "decoder %s, r %d, m %d, lambda %g%s",
             e->crom ? "crom" : e->quadratic_pod ? "quadratic_pod" : "quadratic", e->basis.size, e->alrom.history,
             e->alrom.lambda, e->crom || e->quadratic_pod ? ", trained on the entry's frames" : "");
    rk_run_error er;
    rk_run_error_init(&er, sim->mesh.X, ndof / 3);
    m->contact_min_distance = INFINITY;
    for (int t = 0; t < steps; t++) {
        double t0 = rk_now();
        if (rk_alrom_step(&s, err)) goto out;
        secs[t] = rk_now() - t0;
        int crossings;
        double d;
        if (rk_fom_contact_measure(&s.fom, &crossings, &d, err)) goto out;
        m->contact_min_distance = fmin(m->contact_min_distance, d);
        if (crossings > m->contact_intersections) m->contact_intersections = crossings;
        rk_run_error_add(&er, s.fom.x, ref->x + (size_t)ndof * (t + 1));
    }
    rk_compare_record_errors(m, &er);
    m->seconds_per_step = rk_median(secs, steps);
    m->newton_iterations = s.stats.newton_iterations;
    m->unconverged_steps = s.fom.stats.unconverged_steps;
    m->history_share = s.stats.steps ? (double)s.stats.history_used / s.stats.steps : 0;
    /* realigned: a fresh simulator (the same decoder) from each reference state (its history then
     * holds them) */
    rk_alrom_free(&s);
    if (rk_alrom_init(&s, &sim->fem, &sim->options, dec, &o, err)) goto out;
    rk_run_error_init(&er, sim->mesh.X, ndof / 3);
    for (int t = 0; t < steps; t++) {
        const double *xp = t > 0 ? ref->x + (size_t)ndof * (t - 1) : NULL, *vp = t > 0 ? ref->v + (size_t)ndof * (t - 1) : NULL;
        rk_alrom_set_state(&s, ref->x + (size_t)ndof * t, ref->v + (size_t)ndof * t, xp, vp, t * sim->options.h);
        if (rk_alrom_step(&s, err)) goto out;
        rk_run_error_add(&er, s.fom.x, ref->x + (size_t)ndof * (t + 1));
    }
    m->relative_online_error = rk_relative_online_error(&er);
    rc = 0;
out:
    rk_alrom_free(&s);
    free(secs);
    return rc;
}
