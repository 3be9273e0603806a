/* precompute/pipeline: the Koopman method, an entry with a "koopman" section: its options (the
 * method's own block of the entry), the scene's training runs, the fit and the bake (koopman.c,
 * method_koopman.c). With a cubature the entry also bakes a fixed-basis reduced model beside the
 * operator. */
#ifndef RK_PIPELINE_METHOD_KOOPMAN_H
#define RK_PIPELINE_METHOD_KOOPMAN_H

#include "pipeline/method.h"
#include "koopman/koopman.h"

/* rom[i].koopman: one training run of the scene with what it names changed. */
typedef struct {
    int has_gravity, has_velocity;
    double gravity[3], velocity[3];
    double load_scale;               /* 1: as the scene says */
} rk_koopman_variation;

#define RK_KOOPMAN_MAX_TRAJECTORIES 32

/* rom[i].koopman: {"rank": 24 | "energy": 0.999999, "clamp": true, "project": true,
 *                  "trajectories": [{"gravity": [0, -9.81, 0], "velocity": [0, 0, 1], "load_scale": 1}, ...]}
 * No trajectory listed: the scene as written, once. */
typedef struct {
    rk_koopman_options fit;          /* h comes from the scene's time step */
    int project;                     /* fit on the entry's basis coordinates (default 0: full displacements) */
    int ntraj;
    rk_koopman_variation traj[RK_KOOPMAN_MAX_TRAJECTORIES];
} rk_koopman_entry;

/* What romkit compare measures of it beside the shared numbers. */
typedef struct {
    double max_abs_eigenvalue;     /* after the clamp, if any */
} rk_koopman_measures;

extern const rk_method rk_method_koopman;
/* Entry e's Koopman options, or NULL when it has no koopman section. */
const rk_koopman_entry *rk_koopman_of(const rk_rom_entry *e);

/* ---- an entry's Koopman operator (koopman.c) ---- */

/* The forcing as an acceleration of every degree of freedom (3 nv values): gravity plus each load
 * (force, N, 3 nv or NULL) over its vertex's lumped mass: what a trajectory runs under and what an
 * asset steps along, as impulses (Eq. 19). */
void rk_koopman_scene_accel(const rk_scene_sim *sim, const double gravity[3], const double *force, double *accel);
/* accel (3 nv) += the chambers' load as a constant acceleration, the pressure held from t = 0
 * (the neural DMD's family members, rk_family): u_1 / h^2, u_1 the displacement one full-order
 * step from rest under the pressure alone takes (implicit Euler: about (M + h D + h^2 K)^-1 h^2
 * A(X_0) C, the follower force included). Not A(X_0) C over the lumped mass: that impulse sits
 * on the chamber walls alone and is ~10^3 times the motion of a step (the walls' stiffness over
 * their mass, times h^2), outside every mode a fit can learn, so the fitted model misses it
 * wholesale (measured: rollout errors of 10^6 %). u_1 is the same push as the motion it starts:
 * the impulse Eq. 19 adds then lies among the states the model is fitted on, and the operator's
 * forcing term learns the rest of the response (the follower load's change with the
 * deformation included, for that pressure; romkit control, which varies the pressure, takes
 * chambers as inputs instead). Fails on a chamber that follows a schedule (keys) or a static
 * scene. No pressure: accel unchanged. */
int rk_koopman_scene_pressure_accel(const rk_scene_sim *sim, double *accel, rk_error *err);
/* The frame before a start at rest positions moving at vel (3 nv, or NULL: at rest): u_{-1} = -h v. */
void rk_koopman_frame_before(const rk_scene_sim *sim, const double *vel, double *u_prev);

/* A trajectory of the built scene's full-order run, as the fit takes it (owning its arrays):
 * displacement frames u_{-1} = -h v_0, u_0 = 0, then one per step, so that X_0 = [0; h v_0]
 * starts it; accel: gravity plus each load over its vertex's lumped mass. */
typedef struct {
    rk_koopman_trajectory t;
    double *u, *accel;
} rk_koopman_run;
/* The scene run again with what v changes (v NULL: as written). */
int rk_koopman_scene_run(const rk_scene_sim *sim, const rk_koopman_variation *v, rk_koopman_run *out, rk_error *err);
/* The same trajectory from the scene's full-order run already done: frames (3 nv x T) are the
 * displacements after each of its T steps (rk_scene_training_frames). */
int rk_koopman_scene_run_frames(const rk_scene_sim *sim, const double *frames, int T, rk_koopman_run *out,
                                rk_error *err);
/* The same trajectory from a file: the positions romkit fom --entry K --trajectory I --snapshots
 * wrote for it ((steps + 1) x nv x 3 float64, a job of its own: romkit plan), bit for bit the run. */
int rk_koopman_scene_run_file(const rk_scene_sim *sim, const rk_koopman_variation *v, const char *file,
                              rk_koopman_run *out, rk_error *err);
/* The built scene changed to run as trajectory v runs (gravity, every load times load_scale, the
 * initial velocities; its own arrays, freed with sim): what romkit fom --trajectory runs. */
int rk_koopman_scene_vary(rk_scene_sim *sim, const rk_koopman_variation *v, rk_error *err);
void rk_koopman_run_free(rk_koopman_run *r);

typedef struct {
    int trajectories, frames;        /* runs and frames in all */
    double seconds_fom, seconds_fit;
    int projected;                   /* observables are basis coordinates (d = basis columns) */
    int reused;                      /* the given frames (the scene as written) were a trajectory */
    rk_basis_type basis_type;        /* when projected: the basis and its build time */
    int basis_columns;
    double seconds_basis;
} rk_koopman_scene_info;

/* Runs every trajectory of ko and fits the operator on their (projected) displacements. basis:
 * the entry's basis when ko->project, else NULL. frames (may be NULL): the scene's own run,
 * already done, used for each trajectory that changes nothing. */
int rk_koopman_scene_fit(const rk_scene_sim *sim, const rk_koopman_entry *ko, const rk_basis *basis,
                         const double *frames, int T, rk_koopman *k, rk_koopman_scene_info *info, rk_error *err);
/* The same with trajectory i read from files[i] (rk_koopman_scene_run_file; files NULL: run here;
 * an entry listing no trajectory has one, the scene as written). */
int rk_koopman_scene_fit_from(const rk_scene_sim *sim, const rk_koopman_entry *ko, const rk_basis *basis,
                              const double *frames, int T, const char *const *files, rk_koopman *k,
                              rk_koopman_scene_info *info, rk_error *err);

/* An entry's Koopman operator and what baking it needs: the scene's constant acceleration, the
 * start (where the training runs start: X_0 = [0; h v_0]) and the boundary to show. */
typedef struct {
    rk_koopman k;
    rk_koopman_scene_info info;
    double *accel, *u0, *u_prev;
    int *tris, ntris;                /* the boundary (source numbers) */
    rk_koopman_geometry geometry;    /* points into the arrays above */
} rk_scene_koopman;

/* Entry e end to end: the basis when it asks for a projection, the training runs, the fit and the
 * asset geometry. frames (3 nv x T, may be NULL): the scene's own full-order run, already done;
 * when NULL and something needs it, it is run here. */
int rk_scene_koopman_build(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e,
                           const double *frames, int T, rk_scene_koopman *out, rk_error *err);
/* The same with the trajectories from files (rk_koopman_scene_fit_from; NULL: run here). */
int rk_scene_koopman_build_from(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e,
                                const double *frames, int T, const char *const *files, rk_scene_koopman *out,
                                rk_error *err);
void rk_scene_koopman_free(rk_scene_koopman *p);
/* What an asset of the built scene shows and steps along: the boundary, the scene's forcing, the
 * start (p's accel, u0, u_prev, tris and geometry; its operator k left alone, freed with p). */
int rk_scene_koopman_geometry(const rk_scene_sim *sim, rk_scene_koopman *p, rk_error *err);
/* The report's "koopman" object: rank, max_abs_eigenvalue, eigenvalues [[re, im], ...],
 * residuals, clamped, data_grows, stabilized, stabilize_shift, max_abs_eigenvalue_before_refit,
 * step_residual [Galerkin, returned], singular values, observables, h. */
cJSON *rk_koopman_report(const rk_koopman *k);

/* A Koopman operator k over geometry g baked alone (romkit dmd's outside snapshots, and a Koopman
 * entry without cubature): the asset, its report's "koopman" and "asset" objects, the summary. */
int rk_bake_koopman(const rk_koopman *k, const rk_koopman_geometry *g, const rk_asset_options *ao, const char *info,
                    rk_baked *out, rk_error *err);

#endif
