/* precompute/pipeline: a built scene's full-order run measured (rk_scene_fom_measure) and the
 * report romkit fom writes of it (rk_fom_report): counts, the timings of the parts, the Newton
 * iterations against their factorization, the mesh's checks, the final state and, with contact,
 * what contact came to and cost. The command only parses arguments, writes files and prints. */
#ifndef RK_PIPELINE_FOM_REPORT_H
#define RK_PIPELINE_FOM_REPORT_H

#include <stdio.h>

#include "pipeline/pipeline.h"

/* A timing over the run's Newton iterations: the median, the fastest and the slowest. */
typedef struct {
    double median, min, max;
} rk_iteration_stat;

typedef struct {
    int steps;                     /* 1 for a static solve */
    int contact;                   /* contact is measured: obstacles, several objects or self-contact */
    rk_fom_stats stats;            /* the run's (rk_scene_fom_run) */
    rk_iteration_stat iteration, factorization; /* per Newton iteration: its seconds, its factorization's */
    int max_inverted;              /* the most inverted elements in a frame */
    /* the final state */
    double time, min_det_F, max_displacement, kinetic_energy, elastic_energy;
    int inverted;
    /* contact (when measured): the frames' exact crossings and closest surfaces (the one tally
     * every report's contact.* keys come from), the contact stage's counters at the end */
    rk_contact_tally tally;
    rk_contact_stats contact_stats;
    double *x;                     /* the final positions, 3 nv (malloc'd: rk_fom_measure_free) */
} rk_fom_measure;

/* The scene's full-order run (as rk_scene_fom_run runs it, with progress under "full-order run"),
 * measured frame by frame; frame (may be NULL) is called too, after each frame is measured
 * (snapshots, frame files). */
int rk_scene_fom_measure(const rk_scene_sim *sim, rk_frame_fn frame, void *ctx, rk_fom_measure *out, rk_error *err);
void rk_fom_measure_free(rk_fom_measure *m);

/* The report (DESIGN.md's fom keys): vertices, tets, steps, h, integrator, seconds_per_step,
 * newton_iterations, unconverged_steps, seconds.*, shares.*, factorization_share, newton.*,
 * threads, mesh.*, final.*, max_inverted_elements and, with contact, contact.*. seconds_total: the
 * command's wall time. */
cJSON *rk_fom_report(const rk_scene_sim *sim, const rk_fom_measure *m, double seconds_total);

/* Says on f that who's run (full order, a method of romkit compare) left unconverged of its steps
 * short of the Newton tolerance: a run whose answer may be off must say so beside the report's
 * unconverged_steps. Nothing when unconverged is 0. */
void rk_unconverged_warn(FILE *f, const char *who, long unconverged, long steps);

#endif
