/* precompute/pipeline: method adaptive_linear (grassmann.h): its keys, the decoder and simulator
 * on the built scene (alrom.c), its bake (bake_alrom.c) and its table entry
 * (method_adaptive_linear.c). */
#ifndef RK_PIPELINE_METHOD_ADAPTIVE_LINEAR_H
#define RK_PIPELINE_METHOD_ADAPTIVE_LINEAR_H

#include "pipeline/method.h"
#include "grassmann/grassmann.h"

/* The method's keys: size is r; history (m, 20), lambda (0.2), decoder ("quadratic": linear modes
 * and their modal derivatives, no training; "quadratic_pod": the training frames' POD modes and a
 * quadratic term fitted to them (rk_quadratic_fit); "crom": trained on the scene's full-order
 * frames with the options of the "crom" key). */
typedef struct {
    rk_alrom_options opt;
    int crom;                        /* decoder "crom" */
    int quadratic_pod;               /* decoder "quadratic_pod" */
    rk_crom_options crom_opt;
} rk_adaptive_linear_entry;

/* What romkit compare measures of it: the share of the free run's steps whose basis blended the
 * history (the rest used the decoder's alone: the history did not span r directions yet). */
typedef struct {
    double history_share;
} rk_adaptive_linear_measures;

extern const rk_method rk_method_adaptive_linear;
/* Entry e's options, or NULL when it is another method. */
const rk_adaptive_linear_entry *rk_adaptive_linear_of(const rk_rom_entry *e);

/* ---- an adaptive linear ROM entry (alrom.c, bake_alrom.c) ---- */

/* The quadratic-manifold decoder's parts for entry e, both column-major and the caller's to free:
 * Phi (3 nv x r) and Psi (3 nv x r(r+1)/2). Decoder "quadratic": Phi its r linear modes with the
 * fixed vertices held, Psi their modal derivatives (the pairs of rigid modes zero); decoder
 * "quadratic_pod": Phi the POD modes of the frames (3 nv x T displacements, needed), Psi the
 * quadratic term fitted to them. */
int rk_scene_quadratic_parts(const rk_scene_sim *sim, const rk_rom_entry *e, const double *frames, int T,
                             double **Phi, double **Psi, rk_error *err);

/* Entry e (method adaptive_linear) on the built scene: its decoder into *dec (a quadratic manifold
 * from the entry's size r linear modes with the fixed vertices held and their modal derivatives,
 * or a CROM trained on frames: the scene's full-order displacements, 3 nv x T, run here when NULL)
 * and rk_alrom_init under the scene's options (dec must outlive s; free both). *seconds_decoder (may
 * be NULL): the decoder's build time. */
int rk_scene_alrom_init(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e, const double *frames,
                        int T, rk_alrom *s, rk_decoder *dec, double *seconds_decoder, rk_error *err);
/* With rom.cubature: the elements and weights (multiplying each element's energy) of a cubature
 * trained for the moving basis (issue 33, rk_cubature_train_moving): up to rom.cubature.poses
 * frames evenly spaced over the entry's (3 nv x T displacements), each with the decoder's basis
 * dg/dp at its code p = e(u) (the prescribed rows zero), to rom.cubature.tolerance, with the fit's
 * error on held-out frames in *fit. Why the decoder's basis: the step's basis is the Grassmann
 * point between it and the history basis, and along a motion the decoder fits, the history's
 * secant D P^T (P P^T)^-1 is the decoder's Jacobian to first order. None (count 0) without
 * rom.cubature. malloc'd. */
int rk_scene_alrom_cubature(const rk_scene_sim *sim, const rk_rom_entry *e, const rk_decoder *dec, const double *frames,
                            int T, int **element, double **weight, int *count, rk_moving_fit *fit, rk_error *err);
/* The decoder alone (rk_scene_alrom_init's first half). */
int rk_scene_alrom_decoder(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e, const double *frames,
                           int T, rk_decoder *dec, rk_error *err);

/* rk_scene_bake of an adaptive_linear entry (bake_alrom.c): the decoder's asset (quadratic, fitted
 * quadratic or CROM) with the chunks the runtime's adaptive step reads (formats/ROMBIN.md).
 * training_runs (n of them, or NULL): the training list's items from files, as
 * rk_scene_training_set_from reads them (romkit plan's training steps). */
int rk_scene_bake_alrom(const rk_scene *scene, const rk_rom_entry *e, const rk_asset_options *ao,
                        const char *const *training_runs, int n, rk_baked *out, rk_error *err);

#endif
