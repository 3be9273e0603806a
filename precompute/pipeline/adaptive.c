/* An adaptive subspace entry on the built scene (method_adaptive_subspace.h, rk_scene_adaptive_init): its candidate
 * basis, how the oracle groups its columns, and the simulator under the scene's own options. */
#include "pipeline/method_adaptive_subspace.h"
#include "pipeline/method_fixed.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Reorders a joined skinning basis's 12-column blocks: part k's first weight to block k, the rest
 * after them in their order (the oracle adds blocks by their measures, not their order). */
static int first_blocks_first(rk_basis *b, rk_error *err)
{
    size_t rows = 3 * (size_t)b->n, block = 12 * rows;
    int H = b->m, at = b->nparts;
    double *U = rk_calloc((size_t)b->r * rows, sizeof(double), err);
    if (!U) return -1;
    for (int h = 0; h < H; h++) {
        int to = -1;
        for (int k = 0; k < b->nparts; k++)
            if (b->part_handle[k] == h) to = k;
        if (to < 0) to = at++;
        memcpy(U + block * (size_t)to, b->U + block * (size_t)h, sizeof(double) * block);
    }
    free(b->U);
    b->U = U;
    return 0;
}

int rk_scene_adaptive_init(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e,
                           const double *frames, int T, rk_adaptive *ad, double *seconds_basis, rk_error *err)
{
    if (sim->cloud_points) return rk_fail(err, "%s: method adaptive_subspace needs tetrahedral meshes, not point clouds", e->path);
    double t0 = rk_now();
    rk_basis basis;
    rk_scene_basis_info info;
    memset(&info, 0, sizeof info);
    if (rk_scene_basis(scene, sim, &e->basis, frames, T, &basis, &info, err)) {
        rk_scene_basis_info_free(&info);
        return rk_error_prefix(err, "%s: the candidate basis", e->path);
    }
    rk_scene_basis_info_free(&info);
    if (seconds_basis) *seconds_basis = rk_now() - t0;
    const rk_adaptive_subspace_entry *own = rk_adaptive_subspace_of(e);
    if (!own) return rk_fail(err, "%s is not method adaptive_subspace", e->path);
    rk_adaptive_options o = own->opt;
    int skinning = basis.W != NULL;
    o.block = skinning ? 12 : 1; /* a skinning weight's 12 affine columns are one candidate (Sec. 3.5) */
    int initial = own->initial_size;
    if (!initial) initial = skinning ? 12 * (basis.nparts ? basis.nparts : 1) : basis.nzero > 0 ? basis.nzero : 1;
    /* Several objects: each object's first weight's block first, so the initial blocks move every
     * object (with only the first object's the others had no column until the oracle enriched
     * them, even in free flight). */
    if (skinning && basis.nparts > 1 && first_blocks_first(&basis, err)) {
        rk_basis_free(&basis);
        return rk_error_prefix(err, "%s", e->path);
    }
    int rc = 0;
    if (initial % o.block || initial > basis.r)
        rc = rk_fail(err, "%s: initial_size must be a multiple of %d up to the %d candidate columns, got %d", e->path,
                     o.block, basis.r, initial);
    o.initial_blocks = initial / o.block;
    if (!rc && rk_adaptive_init(ad, &sim->fem, &sim->options, basis.U, basis.r, &o, err))
        rc = rk_error_prefix(err, "%s", e->path);
    rk_basis_free(&basis);
    return rc;
}

/* romkit adaptive's report (method_adaptive_subspace.h). */
cJSON *rk_adaptive_report(const rk_scene_sim *sim, const rk_adaptive *ad, const double *secs, int steps,
                          const rk_contact_tally *contact, const rk_adaptive_subspace_measures *residual)
{
    const rk_adaptive_stats *s = &ad->stats;
    cJSON *r = cJSON_CreateObject();
    cJSON_AddNumberToObject(r, "vertices", sim->mesh.nv);
    cJSON_AddNumberToObject(r, "tets", sim->mesh.nt);
    cJSON_AddNumberToObject(r, "steps", steps);
    cJSON_AddNumberToObject(r, "threads", rk_threads());
    double *t = malloc(sizeof(double) * (size_t)(steps > 0 ? steps : 1));
    if (t) memcpy(t, secs, sizeof(double) * (size_t)steps);
    cJSON_AddNumberToObject(r, "seconds_per_step", t && steps > 0 ? rk_median(t, steps) : 0);
    free(t);
    cJSON_AddNumberToObject(r, "newton_iterations", (double)s->newton_iterations);
    cJSON_AddNumberToObject(r, "unconverged_steps", (double)ad->fom.stats.unconverged_steps);
    cJSON *a = cJSON_AddObjectToObject(r, "adaptive");
    cJSON_AddNumberToObject(a, "mean_modes", s->steps ? s->sum_modes / s->steps : 0);
    cJSON_AddNumberToObject(a, "max_modes", s->max_modes);
    cJSON_AddNumberToObject(a, "steps_full", (double)s->steps_full);
    cJSON_AddNumberToObject(a, "mean_enriched_vertices", s->steps ? s->sum_nodes / s->steps : 0);
    cJSON_AddNumberToObject(a, "max_enriched_vertices", s->max_nodes);
    cJSON_AddNumberToObject(a, "subdomains", ad->opt.subdomains);
    cJSON_AddNumberToObject(a, "pcg_iterations_per_solve", s->solves ? (double)s->pcg_iterations / s->solves : 0);
    cJSON_AddNumberToObject(a, "modes_added", (double)s->oracle_modes_added);
    cJSON_AddNumberToObject(a, "vertices_added", (double)s->oracle_nodes_added);
    cJSON_AddNumberToObject(a, "modes_downdated", (double)s->modes_downdated);
    cJSON_AddNumberToObject(a, "vertices_downdated", (double)s->nodes_downdated);
    cJSON_AddNumberToObject(a, "bfgs_updates", (double)s->bfgs_updates);
    cJSON_AddNumberToObject(a, "bfgs_skipped", (double)s->bfgs_skipped);
    if (residual) rk_adaptive_residual_report(a, residual);
    cJSON *sec = cJSON_AddObjectToObject(r, "seconds");
    cJSON_AddNumberToObject(sec, "simulate", s->seconds_total);
    cJSON_AddNumberToObject(sec, "potential", s->seconds_potential);
    cJSON_AddNumberToObject(sec, "oracle", s->seconds_oracle);
    cJSON_AddNumberToObject(sec, "subspace_hessian", s->seconds_hessian);
    cJSON_AddNumberToObject(sec, "enriched_rows", s->seconds_system);
    cJSON_AddNumberToObject(sec, "pcg", s->seconds_pcg - s->seconds_system);
    cJSON_AddNumberToObject(sec, "line_search", s->seconds_line_search);
    cJSON_AddNumberToObject(sec, "residual_check", s->seconds_residual);
    if (contact) rk_contact_tally_report(cJSON_AddObjectToObject(r, "contact"), contact);
    return r;
}
