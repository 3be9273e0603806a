/* precompute/pipeline: forces on named groups that make a Koopman model follow a target (control.c). */
#ifndef RK_PIPELINE_CONTROL_H
#define RK_PIPELINE_CONTROL_H

#include "pipeline/method_koopman.h"

/* ---- following a target trajectory with forces on named groups (control.c) ---- */

/* One controlled input: a force along one axis on one of the entry's named vertex groups
 * (rom.asset.groups), spread over the group's vertices by mass (a uniform acceleration), C newtons
 * in all; or (chamber[0] set) the pressure of the scene's chamber of that name, C pascals, whose
 * force A(X) C follows the deformed walls (fom.h, rk_chamber; Sec. 7.3). */
typedef struct {
    int group;                       /* index into e->asset.groups (forces) */
    int axis;                        /* 0, 1, 2: x, y, z (forces) */
    char chamber[RK_CHAMBER_NAME];   /* a pressure input: the chamber's name ("" for a force) */
} rk_control_input;

#define RK_CONTROL_MAX_INPUTS 64

typedef struct {
    int ninputs;
    rk_control_input input[RK_CONTROL_MAX_INPUTS];
    int nfollow;                     /* groups whose vertices follow the target; 0: the inputs' groups */
    int follow[RK_ASSET_MAX_GROUPS];
    double train_force;              /* N held during each input's training run; 0: the group's weight */
    double train_pressure;           /* Pa behind each pressure input's training run (> 0 when there is one) */
    int horizon;                     /* rk_koopman_track's H (>= 1) */
    int nonnegative;
    double regularize;               /* rho of rk_lstsq_tikhonov (>= 0; 0: plain least squares) */
} rk_control_options;

typedef struct {
    int T, inputs, trajectories, rank, follow_values;
    double *C;                       /* inputs x (T - 1), column-major, N */
    double *u_model;                 /* 3 nv x T: the Koopman model under C (displacements) */
    double *u_fom;                   /* 3 nv x T: the full-order model under C */
    double seconds_training, seconds_fit, seconds_solve, seconds_fom;
    double max_abs_eigenvalue;
} rk_control_result;

/* Entry e's Koopman operator (rom.koopman, unprojected) trained on the entry's trajectories and one
 * run per input holding train_force (a pressure input: the force of train_pressure on the chamber's
 * rest walls, held, so that the fit's forcing is the run's own), then the inputs that make the
 * followed vertices track target (a pressure input's field A(X) re-evaluated at the predicted state,
 * 5 times a frame, the paper's iteration)
 * (3 nv x T displacements from the rest positions, frame 0 the scene's start; the scene's time
 * step between frames) by rk_koopman_track, and the full-order run under those inputs
 * (rk_fom_set_force and rk_fom_set_pressure each step: the pressures as follower loads). */
int rk_scene_control(const rk_scene_sim *sim, const rk_rom_entry *e, const rk_control_options *o,
                     const double *target, int T, rk_control_result *out, rk_error *err);
void rk_control_result_free(rk_control_result *r);

/* The size errors are measured against: the largest |u_t| over the target's T frames (3 nv = n3
 * values each, displacements from rest); 0 for a target that never moves. */
double rk_control_target_scale(const double *target, int n3, int T);
/* romkit control's report: vertices, frames, horizon, regularize, inputs[] (group, axis),
 * followed_values, koopman.*, error.* (per frame |u_a - u_b| in % of rk_control_target_scale:
 * fom_vs_target, model_vs_target, model_vs_fom, each with max_percent, frames_under_2_percent,
 * frames_under_6_percent, per_frame_percent) and seconds.*. max_percent (may be NULL) gets the three
 * maxima. */
cJSON *rk_control_report(const rk_rom_entry *e, const rk_control_options *o, const rk_control_result *r,
                         const double *target, int n3, double max_percent[3]);

#endif
