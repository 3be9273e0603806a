/* rk_compare_scene (compare.h): one full-order run (and, with a refined reference, a second on the
 * refined mesh, kept at the scene mesh's vertices), then each entry through its method's compare
 * operation (method.h): free (error over the whole run, time per step) and realigned every step
 * (online error), both against the reference. */
#include "compare/compare.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/util.h"


/* The state after step `step` (0: the start) into F, at F's vertices (through F->map, if any). */
static void keep_state(rk_fom_frames *F, int step, const double *xs, const double *vs, double seconds)
{
    double *x = F->x + (size_t)F->ndof * step, *v = F->v + (size_t)F->ndof * step;
    if (F->layout) {
        rk_scene_layout_apply(F->layout, xs, x);
        for (int i = 0; i < F->ndof / 3; i++) { /* velocities interpolated alike (no offset) */
            double *vi = v + 3 * (size_t)i;
            vi[0] = vi[1] = vi[2] = 0;
            for (int a = 0; a < 4; a++) {
                double w = F->layout->weight[4 * (size_t)i + a];
                const double *vs_a = vs + 3 * (size_t)F->layout->vertex[4 * (size_t)i + a];
                for (int d = 0; d < 3; d++) vi[d] += w * vs_a[d];
            }
        }
    } else if (F->map) {
        for (int i = 0; i < F->ndof / 3; i++) {
            memcpy(x + 3 * (size_t)i, xs + 3 * (size_t)F->map[i], 3 * sizeof(double));
            memcpy(v + 3 * (size_t)i, vs + 3 * (size_t)F->map[i], 3 * sizeof(double));
        }
    } else {
        memcpy(x, xs, sizeof(double) * F->ndof);
        memcpy(v, vs, sizeof(double) * F->ndof);
    }
    if (step > 0) F->step_seconds[step - 1] = seconds;
}

static int keep_frame(void *ctx, int step, rk_fom *fom, double seconds, rk_error *err)
{
    rk_fom_frames *F = ctx;
    int crossings;
    double d;
    if (rk_fom_contact_measure(fom, &crossings, &d, err)) return -1;
    F->min_distance = fmin(F->min_distance, d);
    F->intersections = crossings > F->intersections ? crossings : F->intersections;
    keep_state(F, step, fom->x, fom->v, seconds);
    return 0;
}

typedef struct {
    rk_fom_frames *F;
    const char *label;
} p2_progress;

/* A P2 run's frame (the mesh's vertices are its first nodes, so F's map applies as it is). */
static int keep_p2_frame(void *ctx, int step, const double *x, const double *v, double seconds, rk_error *err)
{
    p2_progress *p = ctx;
    keep_state(p->F, step, x, v, seconds);
    if (step > 0) rk_progress(p->label, step, p->F->T);
    return 0;
}

/* The built scene's full-order run into F on linear (order 1) or quadratic tets (order 2), keeping
 * nv vertices: all of them (map NULL) or those map lists. */
static int run_frames(const rk_scene_sim *sim, int order, const int *map, int nv, const char *label, rk_fom_frames *F,
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
    int rc;
    if (order == 2) {
        if (sim->cloud_points > 0) return rk_fail(err, "%s: reference.order 2 with a point cloud: its full-order body is linear tets (its voxels' Kuhn split), with no quadratic version yet", label);
        p2_progress p = {F, label};
        rc = rk_p2_fom_run(&sim->fem, &sim->options, keep_p2_frame, &p, stats, err);
        rk_progress_done(label);
        if (rc) rk_error_prefix(err, "%s", label);
    } else {
        rc = rk_scene_fom_run(sim, NULL, label, keep_frame, F, stats, err);
    }
    F->map = NULL; /* it pointed into the caller's map, kept only while running */
    F->layout = NULL;
    return rc;
}

/* The scene's full-order run into F at sim's vertices: on sim itself, or for a scene with point
 * clouds on its full-order build (each cloud's body, rk_scene_build_full_order), taken back to
 * sim's vertices (the cloud's points at their barycentric coordinates, its contact surface's
 * vertices as they are) through the layout. */
static int run_fom(const rk_scene *scene, const rk_scene_sim *sim, rk_fom_frames *F, rk_compare_result *out,
                   rk_error *err)
{
    rk_fom_stats stats;
    rk_scene_sim body;
    const rk_scene_sim *run = sim;
    if (sim->cloud_points) {
        if (rk_scene_build_full_order(scene, &body, err)) return -1;
        if (body.layout.nv != sim->mesh.nv) {
            rk_scene_sim_free(&body);
            return rk_fail(err, "%s: the full-order build has %d scene vertices, the scene %d", scene->path,
                           body.layout.nv, sim->mesh.nv);
        }
        run = &body;
        F->layout = &body.layout;
        out->tets = body.mesh.nt; /* the bodies' (the scene's clouds have none of their own) */
    }
    int rc = run_frames(run, 1, NULL, sim->mesh.nv, "full-order run", F, &stats, err);
    if (run != sim) rk_scene_sim_free(&body);
    if (rc) return -1;
    out->fom_seconds_total = stats.seconds_total;
    out->fom_newton_iterations = stats.newton_iterations;
    out->fom_seconds_per_step = rk_median(F->step_seconds, F->T);
    out->has_contact = sim->options.nobstacles > 0 || sim->options.nobjects > 1 || sim->options.contact.self;
    out->fom_min_distance = F->min_distance;
    out->fom_intersections = F->intersections;
    return 0;
}

static void rk_fom_frames_free(rk_fom_frames *F)
{
    free(F->x);
    free(F->v);
    free(F->step_seconds);
}

/* The reference without refinement: the scene's full-order run F itself. */
static void reference_is_fom(rk_compare_result *out)
{
    out->reference_refine = 0;
    out->reference_order = 1;
    out->reference_vertices = out->vertices;
    out->reference_tets = out->tets;
    out->reference_seconds_per_step = out->fom_seconds_per_step;
    out->reference_seconds_total = out->fom_seconds_total;
    out->reference_newton_iterations = out->fom_newton_iterations;
    out->reference_min_distance = out->fom_min_distance;
    out->reference_intersections = out->fom_intersections;
    out->fom_normalized_mse = out->fom_normalized_max_error = out->fom_max_error_m = out->fom_relative_error = 0;
}

/* The scene refined scene->reference_refine more times (or as it is), run at full order on the
 * reference's tets (linear, or quadratic for "order": 2) into R (kept at sim's vertices), and the
 * scene's own run F measured against it. The refined model is freed before returning: only R's
 * frames stay. */
static int run_reference(const rk_scene *scene, const rk_scene_sim *sim, const rk_fom_frames *F, rk_fom_frames *R,
                         rk_compare_result *out, rk_error *err)
{
    rk_scene_sim fine;
    int *map = NULL, k = scene->reference_refine, order = scene->reference_order == 2 ? 2 : 1;
    const rk_scene_sim *ref = sim;
    if (k > 0) {
        if (rk_scene_build_reference(scene, sim, k, &fine, &map, err)) return -1;
        ref = &fine;
    }
    out->reference_refine = k;
    out->reference_order = order;
    out->reference_vertices = ref->mesh.nv;
    out->reference_tets = ref->mesh.nt;
    char label[128];
    snprintf(label, sizeof label, "reference run (refine %d: %d %s tets)", k, ref->mesh.nt,
             order == 2 ? "quadratic" : "linear");
    rk_fom_stats stats;
    int rc = run_frames(ref, order, map, sim->mesh.nv, label, R, &stats, err);
    if (k > 0) {
        free(map);
        rk_scene_sim_free(&fine);
    }
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

/* The P1 reference's locking (compare.h, reference_warning): the largest Poisson ratio over the
 * scene's elements, nu = lambda / (2 (lambda + mu)). The 0.4 bound: the FreeForm beam's P1 run
 * (1,920 tets) at nu = 0.45 is 0.0079 nMSE from a P2 run where a projected-volume m = 4 model is
 * 0.0012 (tests/data/demo_small.json, docs/methods.md), and the golden cantilever at 0.4 (P1 1.6e-3
 * from its P2 run, a projected skinning-2 model 2.1e-4); the same bound as the pointwise volume's
 * warning (pipeline/volume.c). */
static void reference_locking(const rk_scene_sim *sim, rk_compare_result *out)
{
    double nu = 0;
    for (int e = 0; e < sim->fem.nt; e++)
        if (sim->fem.lambda[e] + sim->fem.mu[e] > 0)
            nu = fmax(nu, sim->fem.lambda[e] / (2 * (sim->fem.lambda[e] + sim->fem.mu[e])));
    out->reference_poisson = nu;
    out->reference_warning[0] = 0;
    if (nu >= 0.4 && out->reference_order != 2)
        snprintf(out->reference_warning, sizeof out->reference_warning,
                 "Poisson's ratio %.3g: the reference runs on linear tets, which lock in bending as nu nears 1/2, so a "
                 "reduced model that does not lock (volume \"projected\") measures worse against it than one that "
                 "does; set the scene's \"reference\": {\"order\": 2} (quadratic tets) to measure against the "
                 "converged solid", nu);
}

/* Entry e through its method's compare operation: built on the scene's mesh (trained on the
 * scene's run or the entry's training set) and measured against the reference. */
static void run_method(rk_compare_ctx *c, const rk_rom_entry *e, rk_compare_method *m, const rk_compare_result *res)
{
    rk_error err;
    memset(m, 0, sizeof *m);
    m->method = e->method;
    m->cubature_error = NAN;
    m->fit_normalized_mse = NAN;
    memcpy(m->name, e->name, sizeof m->name);
    m->type = e->basis.type;
    snprintf(m->basis_name, sizeof m->basis_name, "%s", rk_basis_type_name(e->basis.type));
    m->reference_nmse = e->reference_nmse;
    memcpy(m->reference_source, e->reference_source, sizeof m->reference_source);
    if (e->method->compare(c, e, m, &err)) rk_compare_record_failure(m, &err);
    else m->speedup = res->fom_seconds_per_step / m->seconds_per_step;
}

int rk_compare_scene(const rk_scene *scene, rk_compare_result *out, rk_error *err)
{
    memset(out, 0, sizeof *out);
    int n = scene->nentries;
    if (n == 0) return rk_fail(err, "%s: no \"rom\" section: nothing to compare with the full-order model", scene->path);
    rk_scene_sim sim;
    if (rk_scene_build(scene, &sim, err)) return -1;
    rk_fom_frames F = {0}, R = {0};
    const rk_fom_frames *ref = &F;
    rk_sparse M = {0};
    double *D = NULL;
    int rc = -1;
    out->vertices = sim.mesh.nv;
    out->tets = sim.mesh.nt;
    out->bbox_diagonal = rk_points_diagonal(sim.mesh.X, sim.mesh.nv);
    if (run_fom(scene, &sim, &F, out, err)) goto done;
    out->steps = F.T;
    reference_is_fom(out);
    if (scene->reference_refine > 0 || scene->reference_order == 2) {
        if (run_reference(scene, &sim, &F, &R, out, err)) goto done;
        ref = &R;
    }
    reference_locking(&sim, out);
    /* Displacement frames, as the bases train on them. */
    D = rk_calloc((size_t)F.ndof * F.T, sizeof(double), err);
    if (!D || rk_sparse_alloc_pattern(&sim.fem, &M, err)) goto done;
    rk_fem_add_mass(&sim.fem, sim.options.lumped_mass, 1.0, &M);
    /* a cloud's points weigh outside any element (rk_fem_init_points): without them the realigned
     * runs projected a cloud's full-order state with a zero mass */
    rk_fem_add_point_mass(&sim.fem, 1.0, &M);
    for (int s = 0; s < F.T; s++)
        for (int i = 0; i < F.ndof; i++) D[(size_t)F.ndof * s + i] = F.x[(size_t)F.ndof * (s + 1) + i] - sim.mesh.X[i];
    out->methods = rk_calloc((size_t)n, sizeof *out->methods, err);
    if (!out->methods) goto done;
    out->nmethods = n;
    /* each method's own cache, kept from entry to entry (a sweep of one method trains once) */
    void *caches[64] = {0};
    if (rk_method_count() > 64) {
        rk_fail(err, "%d methods registered, at most 64", rk_method_count());
        goto done;
    }
    rk_compare_ctx ctx = {.scene = scene, .sim = &sim, .fom = &F, .ref = ref, .D = D, .M = &M,
                          .fom_seconds_total = out->fom_seconds_total};
    for (int k = 0; k < n; k++) {
        const rk_rom_entry *e = &scene->entries[k];
        int i = 0;
        while (rk_method_at(i) != e->method) i++;
        ctx.cache = &caches[i];
        run_method(&ctx, e, &out->methods[k], out);
    }
    free(ctx.training_D);
    for (int i = 0; i < rk_method_count(); i++)
        if (caches[i] && rk_method_at(i)->compare_free) rk_method_at(i)->compare_free(caches[i]);
    /* the reference's frames go to the result (romkit compare --reference-frames): handed over, not
     * copied, since a refined reference's frames are the largest thing a compare holds */
    rk_fom_frames *kept = ref == &R ? &R : &F;
    out->reference_x = kept->x;
    kept->x = NULL;
    rc = 0;
done:
    free(D);
    rk_sparse_free(&M);
    rk_fom_frames_free(&F);
    rk_fom_frames_free(&R);
    rk_scene_sim_free(&sim);
    return rc;
}

void rk_compare_result_free(rk_compare_result *r)
{
    free(r->methods);
    free(r->reference_x);
    memset(r, 0, sizeof *r);
}
