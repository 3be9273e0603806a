/* precompute/pipeline: method adaptive_subspace (adaptive.h): its keys, the simulator on the built
 * scene (adaptive.c) and its table entry (method_adaptive_subspace.c). It has no runtime asset. */
#ifndef RK_PIPELINE_METHOD_ADAPTIVE_SUBSPACE_H
#define RK_PIPELINE_METHOD_ADAPTIVE_SUBSPACE_H

#include "pipeline/method.h"
#include "adaptive/adaptive.h"

/* The method's keys: eps_g_modal, eps_g_nodal, eps_e, eps_d, subdomains, initial_size (columns
 * active from the start: default one block, or the rigid modes of a modes basis), downdate, modal,
 * nodal, hessian ("bfgs" or "exact"), pcg_tol. The entry's basis is the candidate basis (block: 12
 * columns per skinning weight, else 1). */
typedef struct {
    rk_adaptive_options opt;
    int initial_size;                /* 0: the default above */
} rk_adaptive_subspace_entry;

/* What romkit compare measures of it: the free run's model sizes at each step's end (active
 * columns, enriched vertices and their share of the mesh), Schur PCG iterations per solve, Newton
 * iterations per step, and the shares of its time (adaptive.h's stats). */
typedef struct {
    double mean_modes, mean_nodes, enriched_share, pcg_per_solve, newton_per_step;
    int max_modes, max_nodes, subdomains;
    double share_potential, share_oracle, share_hessian, share_system, share_pcg, share_line_search;
} rk_adaptive_subspace_measures;

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
 * oracle and BFGS counts), seconds.* (the parts) and, when contact is not NULL, contact.*
 * (rk_contact_tally_report). */
cJSON *rk_adaptive_report(const rk_scene_sim *sim, const rk_adaptive *ad, const double *secs, int steps,
                          const rk_contact_tally *contact);

#endif
