/* rk_compare_scene (compare.h): one full-order run (and, with a refined reference, a second on the
 * refined mesh, kept at the scene mesh's vertices), then each reduced method twice: free (error
 * over the whole run, time per step) and realigned every step (online error), both against the
 * reference. */
#include "compare/compare_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/util.h"


static int keep_frame(void *ctx, int step, rk_fom *fom, double seconds, rk_error *err)
{
    fom_run *F = ctx;
    int crossings;
    double d;
    if (rk_fom_contact_measure(fom, &crossings, &d, err)) return -1;
    F->min_distance = fmin(F->min_distance, d);
    F->intersections = crossings > F->intersections ? crossings : F->intersections;
    double *x = F->x + (size_t)F->ndof * step, *v = F->v + (size_t)F->ndof * step;
    if (F->map) {
        for (int i = 0; i < F->ndof / 3; i++) {
            memcpy(x + 3 * (size_t)i, fom->x + 3 * (size_t)F->map[i], 3 * sizeof(double));
            memcpy(v + 3 * (size_t)i, fom->v + 3 * (size_t)F->map[i], 3 * sizeof(double));
        }
    } else {
        memcpy(x, fom->x, sizeof(double) * F->ndof);
        memcpy(v, fom->v, sizeof(double) * F->ndof);
    }
    if (step > 0) F->step_seconds[step - 1] = seconds;
    return 0;
}

/* The built scene's full-order run into F, keeping nv vertices: all of them (map NULL) or those map
 * lists. */
static int run_frames(const rk_scene_sim *sim, const int *map, int nv, const char *label, fom_run *F,
                      rk_fom_stats *stats, rk_error *err)
{
    F->ndof = 3 * nv;
    F->map = map;
    F->min_distance = INFINITY;
    F->T = sim->options.is_static ? 1 : sim->steps;
    F->x = rk_calloc((size_t)F->ndof * (F->T + 1), sizeof(double), err);
    F->v = rk_calloc((size_t)F->ndof * (F->T + 1), sizeof(double), err);
    F->step_seconds = rk_calloc((size_t)F->T + 1, sizeof(double), err);
    if (!F->x || !F->v || !F->step_seconds) return -1;
    int rc = rk_scene_fom_run(sim, NULL, label, keep_frame, F, stats, err);
    F->map = NULL; /* it pointed into the caller's map, kept only while running */
    return rc;
}

static int run_fom(const rk_scene_sim *sim, fom_run *F, rk_compare_result *out, rk_error *err)
{
    rk_fom_stats stats;
    if (run_frames(sim, NULL, sim->mesh.nv, "full-order run", F, &stats, err)) return -1;
    out->fom_seconds_total = stats.seconds_total;
    out->fom_newton_iterations = stats.newton_iterations;
    out->fom_seconds_per_step = rk_median(F->step_seconds, F->T);
    out->has_contact = sim->options.nobstacles > 0 || sim->options.nobjects > 1 || sim->options.contact.self;
    out->fom_min_distance = F->min_distance;
    out->fom_intersections = F->intersections;
    return 0;
}

static void fom_run_free(fom_run *F)
{
    free(F->x);
    free(F->v);
    free(F->step_seconds);
}

/* The reference without refinement: the scene's full-order run F itself. */
static void reference_is_fom(rk_compare_result *out)
{
    out->reference_refine = 0;
    out->reference_vertices = out->vertices;
    out->reference_tets = out->tets;
    out->reference_seconds_per_step = out->fom_seconds_per_step;
    out->reference_seconds_total = out->fom_seconds_total;
    out->reference_newton_iterations = out->fom_newton_iterations;
    out->reference_min_distance = out->fom_min_distance;
    out->reference_intersections = out->fom_intersections;
    out->fom_normalized_mse = out->fom_normalized_max_error = out->fom_max_error_m = out->fom_relative_error = 0;
}

/* The scene refined scene->reference_refine more times, run at full order into R (kept at sim's
 * vertices), and the scene's own run F measured against it. The refined model is freed before
 * returning: only R's frames stay. */
static int run_reference(const rk_scene *scene, const rk_scene_sim *sim, const fom_run *F, fom_run *R,
                         rk_compare_result *out, rk_error *err)
{
    rk_scene_sim fine;
    int *map = NULL, k = scene->reference_refine;
    if (rk_scene_build_reference(scene, sim, k, &fine, &map, err)) return -1;
    out->reference_refine = k;
    out->reference_vertices = fine.mesh.nv;
    out->reference_tets = fine.mesh.nt;
    char label[128];
    snprintf(label, sizeof label, "reference run (refine %d: %d tets)", k, fine.mesh.nt);
    rk_fom_stats stats;
    int rc = run_frames(&fine, map, sim->mesh.nv, label, R, &stats, err);
    free(map);
    rk_scene_sim_free(&fine);
    if (rc) return -1;
    if (R->T != F->T) return rk_fail(err, "reference run: %d frames, the scene's run %d", R->T, F->T);
    out->reference_seconds_total = stats.seconds_total;
    out->reference_newton_iterations = stats.newton_iterations;
    out->reference_seconds_per_step = rk_median(R->step_seconds, R->T);
    out->reference_min_distance = R->min_distance;
    out->reference_intersections = R->intersections;
    rk_run_error e;
    rk_run_error_init(&e, sim->mesh.X, sim->mesh.nv);
    for (int s = 1; s <= F->T; s++) rk_run_error_add(&e, F->x + (size_t)F->ndof * s, R->x + (size_t)R->ndof * s);
    out->fom_normalized_mse = rk_normalized_mse(&e);
    out->fom_normalized_max_error = rk_normalized_max_error(&e);
    out->fom_max_error_m = e.max_dist;
    out->fom_relative_error = rk_relative_error(&e);
    return 0;
}

/* The free run: errors against every full-order frame and the median step time. */
static int run_free(const rk_scene_sim *sim, rk_scene_rom *R, const fom_run *F, const rk_sparse *M,
                    rk_compare_method *out, rk_error *err)
{
    int r = R->basis.r, ndof = F->ndof;
    double *q0 = rk_calloc((size_t)r, sizeof(double), err), *v0 = rk_calloc((size_t)r, sizeof(double), err);
    double *x = rk_calloc((size_t)ndof, sizeof(double), err), *secs = rk_calloc((size_t)F->T + 1, sizeof(double), err);
    int rc = -1;
    rk_rom rom = {0};
    if (!q0 || !v0 || !x || !secs) goto out;
    if (rk_rom_project(&R->model, M, R->basis.U, ndof, sim->mesh.X, F->x, q0, err) ||
        rk_rom_project(&R->model, M, R->basis.U, ndof, NULL, F->v, v0, err) ||
        rk_rom_init(&rom, &R->model, q0, v0, err))
        goto out;
    rk_run_error e;
    rk_run_error_init(&e, sim->mesh.X, ndof / 3);
    out->contact_min_distance = INFINITY;
    for (int s = 0; s < F->T; s++) {
        double t0 = rk_now();
        if (rk_rom_step(&rom, err)) goto out;
        secs[s] = rk_now() - t0;
        int crossings;
        double d;
        if (rk_rom_contact_measure(&rom, &crossings, &d, err)) goto out;
        out->contact_min_distance = fmin(out->contact_min_distance, d);
        if (crossings > out->contact_intersections) out->contact_intersections = crossings;
        rk_rom_positions(R->basis.U, ndof, r, sim->mesh.X, rom.q, x);
        rk_run_error_add(&e, x, F->x + (size_t)ndof * (s + 1));
    }
    rk_compare_record_errors(out, &e);
    out->seconds_per_step = rk_median(secs, F->T);
    out->newton_iterations = rom.stats.newton_iterations;
    out->unconverged_steps = rom.stats.unconverged_steps;
    rc = 0;
out:
    rk_rom_free(&rom);
    free(q0);
    free(v0);
    free(x);
    free(secs);
    return rc;
}

/* Each step from the full-order state before it, projected (Grassmann paper Sec. 5.1). */
static int run_realigned(const rk_scene_sim *sim, rk_scene_rom *R, const fom_run *F, const rk_sparse *M,
                         rk_compare_method *out, rk_error *err)
{
    int r = R->basis.r, ndof = F->ndof;
    double *q = rk_calloc((size_t)r, sizeof(double), err), *v = rk_calloc((size_t)r, sizeof(double), err);
    double *x = rk_calloc((size_t)ndof, sizeof(double), err);
    int rc = -1;
    rk_rom rom = {0};
    if (!q || !v || !x || rk_rom_init(&rom, &R->model, NULL, NULL, err)) goto out;
    rk_run_error e;
    rk_run_error_init(&e, sim->mesh.X, ndof / 3);
    for (int s = 0; s < F->T; s++) {
        if (rk_rom_project(&R->model, M, R->basis.U, ndof, sim->mesh.X, F->x + (size_t)ndof * s, q, err) ||
            rk_rom_project(&R->model, M, R->basis.U, ndof, NULL, F->v + (size_t)ndof * s, v, err))
            goto out;
        double reached;
        if (rk_rom_realign(&rom, q, v, s * sim->options.h, &reached, err) || rk_rom_step(&rom, err)) goto out;
        out->realign_clipped += reached < 1;
        rk_rom_positions(R->basis.U, ndof, r, sim->mesh.X, rom.q, x);
        rk_run_error_add(&e, x, F->x + (size_t)ndof * (s + 1));
    }
    out->relative_online_error = rk_relative_online_error(&e);
    rc = 0;
out:
    rk_rom_free(&rom);
    free(q);
    free(v);
    free(x);
    return rc;
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

/* The training set last built, kept for the next entry that lists the same runs (a scene usually
 * gives every data-driven method the same list). */
typedef struct {
    const rk_rom_entry *from;   /* the entry whose list it is; NULL: none */
    double *D;
    int T;
    rk_compare_decoder_cache decoder;
} training_cache;

int rk_compare_same_training(const rk_rom_entry *a, const rk_rom_entry *b)
{
    if (a->ntraining != b->ntraining) return 0;
    for (int k = 0; k < a->ntraining; k++)
        if (a->training[k].snapshots != b->training[k].snapshots || strcmp(a->training[k].file, b->training[k].file))
            return 0;
    return 1;
}

/* Entry e built on the scene's mesh (trained on F, displacements D, or its own training set) and
 * measured against ref. */
static void run_method(const rk_scene *scene, const rk_scene_sim *sim, const fom_run *F, const fom_run *ref,
                       const double *D, const rk_sparse *M, const rk_rom_entry *e, rk_compare_method *m,
                       const rk_compare_result *res, training_cache *cache)
{
    rk_error err;
    rk_scene_rom R;
    memset(m, 0, sizeof *m);
    m->cubature_error = NAN;
    m->fit_normalized_mse = NAN;
    memcpy(m->name, e->name, sizeof m->name);
    m->type = e->basis.type;
    m->reference_nmse = e->reference_nmse;
    memcpy(m->reference_source, e->reference_source, sizeof m->reference_source);
    if (e->koopman) {
        if (rk_compare_koopman(scene, sim, F, ref, D, e, m, &err)) rk_compare_record_failure(m, &err);
        else m->speedup = res->fom_seconds_per_step / m->seconds_per_step;
        return;
    }
    /* what trains on full-order runs: the entry's training set when it lists one, else this run */
    int Tt = F->T;
    if (e->ntraining) {
        if (!cache->from || !rk_compare_same_training(cache->from, e)) {
            free(cache->D);
            cache->from = NULL;
            if (rk_scene_training_set(scene, sim, e, &cache->D, &cache->T, &err)) {
                rk_compare_record_failure(m, &err);
                return;
            }
            cache->from = e;
        }
        D = cache->D;
        Tt = cache->T;
    }
    m->training_frames = Tt;
    if (e->method == RK_METHOD_ADAPTIVE_LINEAR) {
        if (rk_compare_alrom(scene, sim, ref, D, Tt, e, m, &cache->decoder, &err)) rk_compare_record_failure(m, &err);
        else m->speedup = res->fom_seconds_per_step / m->seconds_per_step;
        return;
    }
    if (e->method == RK_METHOD_ADAPTIVE_SUBSPACE) {
        if (rk_compare_adaptive(scene, sim, ref, D, F->T, e, m, &err)) rk_compare_record_failure(m, &err);
        else m->speedup = res->fom_seconds_per_step / m->seconds_per_step;
        return;
    }
    if (rk_scene_rom_build(scene, sim, e, D, Tt, &R, &err)) {
        rk_compare_record_failure(m, &err);
        return;
    }
    m->r = R.basis.r;
    m->size = R.basis.W ? R.basis.m - 1 : R.basis.r;
    m->cubature_points = R.cubature_points;
    m->cubature_error = R.cubature_error;
    m->seconds_basis = R.seconds_basis;
    m->seconds_cubature = R.seconds_cubature;
    m->seconds_training_run = R.basis_info.fom_frames ? res->fom_seconds_total : 0;
    memcpy(m->basis_reason, R.basis_reason, sizeof m->basis_reason);
    memcpy(m->cubature_reason, R.cubature_reason, sizeof m->cubature_reason);
    if (run_free(sim, &R, ref, M, m, &err) || run_realigned(sim, &R, ref, M, m, &err) ||
        rk_compare_basis_fit(R.basis.U, ref->ndof, R.basis.r, sim->mesh.X, ref, m, &err))
        rk_compare_record_failure(m, &err);
    else m->speedup = res->fom_seconds_per_step / m->seconds_per_step;
    rk_scene_rom_free(&R);
}

int rk_compare_scene(const rk_scene *scene, rk_compare_result *out, rk_error *err)
{
    memset(out, 0, sizeof *out);
    int n = scene->nentries;
    if (n == 0) return rk_fail(err, "%s: no \"rom\" section: nothing to compare with the full-order model", scene->path);
    rk_scene_sim sim;
    if (rk_scene_build(scene, &sim, err)) return -1;
    fom_run F = {0}, R = {0};
    const fom_run *ref = &F;
    rk_sparse M = {0};
    double *D = NULL;
    int rc = -1;
    out->vertices = sim.mesh.nv;
    out->tets = sim.mesh.nt;
    out->bbox_diagonal = rk_points_diagonal(sim.mesh.X, sim.mesh.nv);
    if (run_fom(&sim, &F, out, err)) goto done;
    out->steps = F.T;
    reference_is_fom(out);
    if (scene->reference_refine > 0) {
        if (run_reference(scene, &sim, &F, &R, out, err)) goto done;
        ref = &R;
    }
    /* Displacement frames, as the bases train on them. */
    D = rk_calloc((size_t)F.ndof * F.T, sizeof(double), err);
    if (!D || rk_sparse_alloc_pattern(&sim.fem, &M, err)) goto done;
    rk_fem_add_mass(&sim.fem, sim.options.lumped_mass, 1.0, &M);
    for (int s = 0; s < F.T; s++)
        for (int i = 0; i < F.ndof; i++) D[(size_t)F.ndof * s + i] = F.x[(size_t)F.ndof * (s + 1) + i] - sim.mesh.X[i];
    out->methods = rk_calloc((size_t)n, sizeof *out->methods, err);
    if (!out->methods) goto done;
    out->nmethods = n;
    training_cache cache = {0};
    for (int k = 0; k < n; k++) {
        run_method(scene, &sim, &F, ref, D, &M, &scene->entries[k], &out->methods[k], out, &cache);
    }
    free(cache.D);
    rk_compare_decoder_cache_free(&cache.decoder);
    rc = 0;
done:
    free(D);
    rk_sparse_free(&M);
    fom_run_free(&F);
    fom_run_free(&R);
    rk_scene_sim_free(&sim);
    return rc;
}

void rk_compare_result_free(rk_compare_result *r)
{
    free(r->methods);
    memset(r, 0, sizeof *r);
}
