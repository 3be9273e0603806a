/* precompute/pipeline: method adaptive_subspace (adaptive.h): its keys, the simulator on the built
 * scene (adaptive.c) and its table entry (method_adaptive_subspace.c). It has no runtime asset. */
#ifndef RK_PIPELINE_METHOD_ADAPTIVE_SUBSPACE_H
#define RK_PIPELINE_METHOD_ADAPTIVE_SUBSPACE_H

#include "pipeline/method.h"
#include "adaptive/adaptive.h"

/* The method's keys: eps_g_modal, eps_g_nodal, eps_e (in units of the Newton tolerance, adaptive.h;
 * "eps_g_units": "paper" for the paper's, whose defaults 0.5, 0.5, 1e-4 then apply), eps_d,
 * subdomains, initial_size (columns active from the start: default one block, or the rigid modes
 * of a modes basis), downdate, modal, nodal, hessian ("bfgs" or "exact"), pcg_tol, residual and
 * residual_rounds (the full-space residual's check, adaptive.h), full_fraction (the enriched share at
 * which full order finishes a step, adaptive.h). The entry's basis is the candidate basis (block: 12
 * columns per skinning weight, else 1). */
typedef struct {
    rk_adaptive_options opt;
    int initial_size;                /* 0: the default above */
} rk_adaptive_subspace_entry;

/* What romkit compare measures of it: the free run's model sizes at each step's end (active
 * columns, enriched vertices and their share of the mesh), Schur PCG iterations per solve, Newton
 * iterations per step, and the shares of its time (adaptive.h's stats). */
/* The free run's full-space residual |d_full|_inf / h at each step's end (adaptive.h, opt.residual):
 * its values in at most RK_ADAPTIVE_RESIDUAL_VALUES, each the largest over residual_stride steps. */
#define RK_ADAPTIVE_RESIDUAL_VALUES 72
typedef struct {
    double mean_modes, mean_nodes, enriched_share, pcg_per_solve, newton_per_step;
    int max_modes, max_nodes, subdomains;
    int steps_full;                  /* steps finished by full order (opt.full_fraction) */
    double share_potential, share_oracle, share_hessian, share_system, share_pcg, share_line_search;
    int residual;                    /* 0: not computed (opt.residual off) */
    double residual_tolerance, residual_max, residual_mean;
    int residual_over, residual_rounds, residual_nodes_added;
    int residual_count, residual_stride;
    float residual_per_step[RK_ADAPTIVE_RESIDUAL_VALUES];
} rk_adaptive_subspace_measures;

/* Steps' residual r (step s of T, from 0) into m's per-step values (the largest of each stride). */
void rk_adaptive_residual_add(rk_adaptive_subspace_measures *m, int s, int T, double r);

extern const rk_method rk_method_adaptive_subspace;
/* Entry e's options, or NULL when it is another method. */
const rk_adaptive_subspace_entry *rk_adaptive_subspace_of(const rk_rom_entry *e);

/* ---- an adaptive subspace entry (adaptive.c) ---- */

/* Entry e (method adaptive_subspace) on the built scene: its candidate basis built as rk_scene_basis
 * builds it (frames as there), grouped in blocks (a skinning weight's 12 columns, else single
 * columns), the initial columns (initial_size, or one block, or a modes basis's rigid modes), and
 * rk_adaptive_init under the scene's options. *seconds_basis (may be NULL): the basis's time. */
int rk_scene_adaptive_init(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e,
                           const double *frames, int T, rk_adaptive *ad, double *seconds_basis, rk_error *err);

/* romkit adaptive's report of a run of ad on sim: vertices, tets, steps, seconds_per_step (the
 * median of secs, steps values), newton_iterations, unconverged_steps, adaptive.* (model sizes,
 * oracle and BFGS counts), seconds.* (the parts), when contact is not NULL, contact.*
 * (rk_contact_tally_report), and when residual is not NULL, adaptive.residual.*
 * (rk_adaptive_residual_report). */
cJSON *rk_adaptive_report(const rk_scene_sim *sim, const rk_adaptive *ad, const double *secs, int steps,
                          const rk_contact_tally *contact, const rk_adaptive_subspace_measures *residual);
/* The residual's keys (the compare report's and romkit adaptive's "residual" object): tolerance,
 * max, mean, steps_over_tolerance, enrichment_rounds, vertices_added, per_step, steps_per_value. */
void rk_adaptive_residual_report(cJSON *j, const rk_adaptive_subspace_measures *m);
/* Says on f (stderr) that entry name ended steps above the Newton tolerance, when it did. */
void rk_adaptive_residual_warn(FILE *f, const char *name, const rk_adaptive_subspace_measures *m, int steps);
/* m's residual fields from ad's stats (the per-step values added apart). */
void rk_adaptive_residual_record(rk_adaptive_subspace_measures *m, const rk_adaptive *ad);

#endif
