/* Private to precompute/compare: the full-order run every method is measured against, and what
 * the reduced-model and Koopman methods share. */
#ifndef RK_COMPARE_IMPL_H
#define RK_COMPARE_IMPL_H

#include "compare/compare.h"
#include "util/util.h"

typedef struct {
    int ndof, T;
    const int *map;  /* NULL: every vertex of the run; else the run's vertex kept as vertex i (ndof / 3) */
    double *x, *v;   /* ndof x (T + 1): the start, then after every step */
    double *step_seconds;
    double min_distance;   /* contact over the frames: closest surfaces (m), most crossings */
    int intersections;
} fom_run;

/* A free run's errors (util/util.h) into m: normalized MSE, max error, relative error. */
void rk_compare_record_errors(rk_compare_method *m, const rk_run_error *e);
/* The method did not run: why, and its numbers NAN. */
void rk_compare_record_failure(rk_compare_method *m, const rk_error *err);

/* m->fit_normalized_mse (basis_fit.c): each frame of ref after the start fitted by X + U q in
 * least squares over the vertices (FreeForm Eq. 36), measured as a free run is. */
int rk_compare_basis_fit(const double *U, int ndof, int r, const double *X, const fom_run *ref, rk_compare_method *m,
                         rk_error *err);

/* Entry `index` with a koopman section (koopman_method.c): fitted on the full-order run F (D: its
 * displacement frames) and any other trajectories it lists, then run free and realigned as the
 * reduced models are, against the reference `ref` (F itself, or the refined run at sim's vertices). */
int rk_compare_koopman(const rk_scene *scene, const rk_scene_sim *sim, const fom_run *F, const fom_run *ref,
                       const double *D, const rk_rom_entry *e, rk_compare_method *m, rk_error *err);

/* Entry e with method adaptive_subspace: its free run against ref (error, time, model sizes) and
 * its realigned run (online error), each step from ref's state before it. */
int rk_compare_adaptive(const rk_scene *scene, const rk_scene_sim *sim, const fom_run *ref, const double *D, int T,
                        const rk_rom_entry *e, rk_compare_method *m, rk_error *err);

/* Entry e with method adaptive_linear: its free run against ref and its realigned run. */
/* Whether two entries list the same training runs (the same files, in the same order). */
int rk_compare_same_training(const rk_rom_entry *a, const rk_rom_entry *b);

/* The decoder last built, kept for the next entry that would build the same one. */
typedef struct {
    const rk_rom_entry *from;   /* NULL: none */
    rk_decoder dec;
    double seconds;             /* its build (training) time */
    int ncub, *cub_element;     /* the entry's cubature (rom.cubature), or none */
    double *cub_weight;
} rk_compare_decoder_cache;
void rk_compare_decoder_cache_free(rk_compare_decoder_cache *c);
int rk_compare_alrom(const rk_scene *scene, const rk_scene_sim *sim, const fom_run *ref, const double *D, int T,
                     const rk_rom_entry *e, rk_compare_method *m, rk_compare_decoder_cache *cache, rk_error *err);

#endif
