/* precompute/compare: the full-order model and every reduced method a scene lists (reduced models,
 * and Koopman operators for entries with a koopman section), run side by side on the scene, with
 * the error metrics of util/util.h: normalized MSE, max error and relative error of a free run
 * against every frame of the reference, and the total relative online error of a run that starts
 * each step from the reference's state at t - 1 projected onto the subspace (Grassmann paper, Sec.
 * 5.1: per-step realignment, so drift does not dominate). The reference is the full-order run on
 * the scene's mesh, or with "reference": {"refine": k} the full-order run on that mesh refined k
 * times, taken at the scene mesh's vertices (a converged reference: FreeForm paper, Table 1).
 *
 * Timing: the median wall time of one step (reconstruction of the vertices not counted: a runtime
 * only rebuilds the vertices it shows). A Koopman method steps in its real eigen-coordinates, as
 * the runtime does; its online error starts each step from the full-order state lifted. */
#ifndef RK_COMPARE_H
#define RK_COMPARE_H

#include "pipeline/pipeline.h"

typedef struct {
    char name[96];
    int koopman;                   /* a Koopman operator: r is its rank, size its observables */
    double max_abs_eigenvalue;     /* Koopman: after the clamp, if any */
    rk_basis_type type;
    int size;                      /* rom.size as built: columns, or weights m for skinning */
    int r;                         /* reduced coordinates */
    int cubature_points;           /* 0: exact */
    double cubature_error;
    double normalized_mse, normalized_max_error, max_error_m, relative_error, relative_online_error; /* util/util.h */
    double fit_normalized_mse;     /* the basis fitting residual (FreeForm Eq. 36, Table 6): every reference frame
                                    * fitted by the subspace in least squares, normalized MSE; NAN where the
                                    * method has no fixed linear basis (Koopman, adaptive) */
    double seconds_per_step, speedup;
    double seconds_basis, seconds_cubature, seconds_training_run; /* the last: 0 unless the basis needed frames */
    double seconds_fit;            /* Koopman: the DMD fit */
    long newton_iterations, unconverged_steps;
    double contact_min_distance;   /* over the free run's frames (INFINITY without contact) */
    int contact_intersections;     /* the most exact crossings in a frame (0) */
    int realign_clipped;           /* online error: steps whose projected start lay beyond contact
                                    * (the realignment stopped short where CCD did) */
    /* method adaptive_subspace (adaptive = 1): the free run's model sizes at each step's end
     * (active columns, enriched vertices and their share of the mesh), Schur PCG iterations per
     * solve, Newton iterations per step, and the shares of its time (adaptive.h's stats) */
    int adaptive;
    double mean_modes, mean_nodes, enriched_share, pcg_per_solve, newton_per_step;
    int max_modes, max_nodes, subdomains;
    double share_potential, share_oracle, share_hessian, share_system, share_pcg, share_line_search;
    /* method adaptive_linear (alrom = 1): the share of the free run's steps whose basis blended
     * the history (the rest used the decoder's alone: the history did not span r directions yet) */
    int alrom;
    double history_share;
    int training_frames;           /* the full-order frames its data-driven parts trained on */
    double reference_nmse;
    char reference_source[96];
    char basis_reason[256], cubature_reason[256];
    char failure[1024];            /* empty when it ran; else why it did not (the error message) */
} rk_compare_method;

typedef struct {
    int vertices, tets, steps;
    double bbox_diagonal;
    double fom_seconds_per_step, fom_seconds_total;
    long fom_newton_iterations;
    int has_contact;
    double fom_min_distance;       /* over the full-order frames */
    int fom_intersections;         /* the most exact crossings in a frame (0) */
    /* What every error is measured against (scene "reference": {"refine": k}): the full-order run
     * with every object's mesh refined k more times, taken at the scene mesh's vertices (the
     * refined mesh's first ones: rk_scene_build_reference). The reduced methods still run, and
     * train, on the scene's mesh; speed-ups are over the full-order run on it. k = 0: the
     * reference is that run itself (sizes and seconds its own, the fom_* errors 0). */
    int reference_refine, reference_vertices, reference_tets;
    double reference_seconds_per_step, reference_seconds_total;
    long reference_newton_iterations;
    double reference_min_distance; /* contact over the reference's frames, on its own surface */
    int reference_intersections;
    /* The full-order run on the scene's mesh against the reference (its discretization error;
     * util/util.h's metrics over every frame, as the methods'). */
    double fom_normalized_mse, fom_normalized_max_error, fom_max_error_m, fom_relative_error;
    int nmethods;
    rk_compare_method *methods;
} rk_compare_result;

/* Runs it all. Fails on a bad scene or a failing full-order run; a reduced method that fails
 * (a basis it cannot build, NaN) is recorded in its failure field and the others still run. */
int rk_compare_scene(const rk_scene *scene, rk_compare_result *out, rk_error *err);
void rk_compare_result_free(rk_compare_result *r);

#endif
