/* An adaptive linear ROM entry beside full order (method_adaptive_linear.c's compare): the free run
 * from the scene's start and the realigned run that starts each step from the reference's state
 * (the paper's Sec. 5.1: total relative online error with per-step realignment). */
#include "pipeline/method_adaptive_linear.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Whether entries a and b build the same decoder from the same data. */
/* The decoder last built, kept for the next entry that would build the same one. */
typedef struct {
    const rk_rom_entry *from;   /* NULL: none */
    rk_decoder dec;
    double seconds;             /* its build (training) time */
    int ncub, *cub_element;     /* the entry's cubature (rom.cubature), or none */
    double *cub_weight;
    rk_moving_fit fit;          /* its training */
} decoder_cache;

static int same_decoder(const rk_rom_entry *ea, const rk_rom_entry *eb)
{
    const rk_adaptive_linear_entry *a = rk_adaptive_linear_of(ea), *b = rk_adaptive_linear_of(eb);
    if (a->crom != b->crom || a->quadratic_pod != b->quadratic_pod || ea->basis.size != eb->basis.size) return 0;
    if (ea->cubature != eb->cubature || (ea->cubature && memcmp(&ea->cub, &eb->cub, sizeof ea->cub))) return 0;
    if (a->crom && memcmp(&a->crom_opt, &b->crom_opt, sizeof a->crom_opt)) return 0;
    return rk_compare_same_training(ea, eb);
}

static void cache_clear(decoder_cache *c)
{
    rk_decoder_free(&c->dec);
    free(c->cub_element);
    free(c->cub_weight);
    c->cub_element = NULL;
    c->cub_weight = NULL;
    c->ncub = 0;
    c->from = NULL;
}

int rk_adaptive_linear_compare(rk_compare_ctx *c, const rk_rom_entry *e, rk_compare_method *m, rk_error *err);
void rk_adaptive_linear_compare_free(void *cache);

void rk_adaptive_linear_compare_free(void *cache)
{
    if (!cache) return;
    cache_clear(cache);
    free(cache);
}

/* Its decoder (and cubature) trains on the entry's training set or the scene's run; the decoder
 * is kept in the method's cache for the next entry that would build the same one. */
int rk_adaptive_linear_compare(rk_compare_ctx *c, const rk_rom_entry *e, rk_compare_method *m, rk_error *err)
{
    const rk_scene *scene = c->scene;
    const rk_scene_sim *sim = c->sim;
    const rk_fom_frames *ref = c->ref;
    const rk_adaptive_linear_entry *own = rk_adaptive_linear_of(e);
    const double *D;
    int T;
    if (rk_compare_training(c, e, &D, &T, m, err)) return -1;
    if (!*c->cache && !(*c->cache = rk_calloc(1, sizeof(decoder_cache), err))) return -1;
    decoder_cache *cache = *c->cache;
    int ndof = ref->ndof, rc = -1, steps = ref->T; /* T: the training frames in D; steps: the run's */
    rk_alrom s = {0};
    double *secs = rk_calloc((size_t)steps + 1, sizeof(double), err);
    if (!secs) goto out;
    if (!cache->from || !same_decoder(cache->from, e)) { /* a sweep of m or lambda trains one decoder */
        cache_clear(cache);
        double t0 = rk_now();
        if (rk_scene_alrom_decoder(scene, sim, e, D, T, &cache->dec, err) ||
            rk_scene_alrom_cubature(sim, e, &cache->dec, D, T, &cache->cub_element, &cache->cub_weight, &cache->ncub,
                                    &cache->fit, err))
            goto out;
        cache->from = e;
        cache->seconds = rk_now() - t0;
    }
    m->seconds_basis = cache->seconds;
    const rk_decoder *dec = &cache->dec;
    rk_alrom_options o = own->opt;
    o.ncub = cache->ncub;
    o.cub_element = cache->cub_element;
    o.cub_weight = cache->cub_weight;
    m->cubature_points = cache->ncub;
    if (cache->ncub) {
        m->cubature_error = cache->fit.train_error;
        snprintf(m->cubature_reason, sizeof m->cubature_reason, "trained for the moving basis on %d frames, held-out "
                 "error %.4g on %d", cache->fit.poses, cache->fit.heldout_error, cache->fit.heldout_poses);
    }
    if (rk_alrom_init(&s, &sim->fem, &sim->options, dec, &o, err)) {
        rk_error_prefix(err, "%s", e->path);
        goto out;
    }
    snprintf(m->basis_name, sizeof m->basis_name, "decoder"); /* its basis is the decoder's Jacobian */
    m->size = m->r = e->basis.size;
    snprintf(m->basis_reason, sizeof m->basis_reason, "decoder %s, r %d, m %d, lambda %g, cadence %d%s",
             own->crom ? "crom" : own->quadratic_pod ? "quadratic_pod" : "quadratic", e->basis.size, own->opt.history,
             own->opt.lambda, own->opt.cadence, own->crom || own->quadratic_pod ? ", trained on the entry's frames" : "");
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
    if (o.cadence > 1) { /* the mean: a median over a cadence's steps would be a held step's alone */
        double sum = 0;
        for (int t = 0; t < steps; t++) sum += secs[t];
        m->seconds_per_step = steps ? sum / steps : 0;
    } else
        m->seconds_per_step = rk_median(secs, steps);
    m->newton_iterations = s.stats.newton_iterations;
    m->unconverged_steps = s.fom.stats.unconverged_steps;
    rk_adaptive_linear_measures *lm = rk_method_measures(m, &rk_method_adaptive_linear);
    lm->history_share = s.stats.steps ? (double)s.stats.history_used / s.stats.steps : 0;
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
