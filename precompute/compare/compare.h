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

#include "pipeline/method.h"

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
    int reference_order;           /* 1: linear tets; 2: quadratic ("order": 2, rk_p2_fom_run), its
                                    * vertices and tets those of the mesh it puts nodes on */
    /* A linear-tet reference of a nearly incompressible scene (the largest element Poisson ratio
     * reference_poisson >= 0.4) locks in bending as the pointwise volume does, so a reduced model
     * that does not lock (rom.volume "projected", the skinning bases' default) measures worse
     * against it than one that does (issue 37): reference_warning then says so and names
     * "reference": {"order": 2}; empty otherwise. */
    double reference_poisson;
    char reference_warning[320];
    double reference_seconds_per_step, reference_seconds_total;
    long reference_newton_iterations;
    double reference_min_distance; /* contact over the reference's frames, on its own surface */
    int reference_intersections;
    /* The full-order run on the scene's mesh against the reference (its discretization error;
     * util/util.h's metrics over every frame, as the methods'). */
    double fom_normalized_mse, fom_normalized_max_error, fom_max_error_m, fom_relative_error;
    /* The reference's positions at the scene mesh's vertices, every frame from the start:
     * (steps + 1) x vertices x 3, as bench/bench_reference.c writes a level's frames, so a
     * reference run inside compare (hours at 15,360 quadratic tets) can be measured against
     * other levels without running it again (romkit compare --reference-frames). */
    double *reference_x;
    int nmethods;
    rk_compare_method *methods;
} rk_compare_result;

/* Runs it all. Fails on a bad scene or a failing full-order run; a reduced method that fails
 * (a basis it cannot build, NaN) is recorded in its failure field and the others still run. */
int rk_compare_scene(const rk_scene *scene, rk_compare_result *out, rk_error *err);
void rk_compare_result_free(rk_compare_result *r);
/* The report romkit compare writes (report.c): sizes, the full-order and reference runs, methods[]
 * (the fom row first, then each method: name, kind, basis.*, cubature.*, the errors, seconds.*,
 * its own keys, contact.* where measured, or its failure) and seconds.total (the caller's). */
cJSON *rk_compare_report(const rk_compare_result *res, double seconds);

#endif
