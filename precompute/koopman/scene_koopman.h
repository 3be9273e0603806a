/* precompute/koopman, scene side: a Koopman operator learned from full-order runs romkit does of
 * the scene itself (its `rom.koopman` section), optionally on the coordinates of the scene's
 * reduced basis (a POD basis first, Sec. 4.1).
 *
 *   "koopman": {"rank": 24 | "energy": 0.999999, "clamp": true, "project": true,
 *               "trajectories": [{"gravity": [0, -9.81, 0], "velocity": [0, 0, 1], "load_scale": 1}, ...]}
 *
 * Each trajectory is the scene run again with what it names changed (gravity, the initial
 * velocity of every object, the loads scaled); none listed: the scene as written, once. */
#ifndef RK_SCENE_KOOPMAN_H
#define RK_SCENE_KOOPMAN_H

#include <cjson/cJSON.h>

#include "basis/scene_basis.h"
#include "koopman/koopman.h"
#include "scene/scene.h"

#define RK_KOOPMAN_MAX_TRAJECTORIES 32

typedef struct {
    int has_gravity, has_velocity;
    double gravity[3], velocity[3];
    double load_scale;               /* 1: as the scene says */
} rk_koopman_variation;

typedef struct {
    rk_koopman_options fit;
    int project;                     /* fit on the rom basis's coordinates (default 0: full displacements) */
    int ntraj;                       /* 0: the scene once */
    rk_koopman_variation traj[RK_KOOPMAN_MAX_TRAJECTORIES];
} rk_koopman_scene_options;

/* Whether rom entry `index` has a koopman section. */
int rk_koopman_scene_present(const cJSON *rom, int index);
/* Reads rom[index].koopman (h comes from the scene's time step). */
int rk_koopman_scene_options_parse(const cJSON *rom, int index, const char *file, double h,
                                   rk_koopman_scene_options *o, rk_error *err);

/* The forcing as an acceleration of every degree of freedom (3 nv values): gravity plus each load
 * (force, N, 3 nv or NULL) over its vertex's lumped mass: what a trajectory runs under and what an
 * asset steps along, as impulses (Eq. 19). */
void rk_koopman_scene_accel(const rk_scene_sim *sim, const double gravity[3], const double *force, double *accel);
/* The frame before a start at rest positions moving at vel (3 nv, or NULL: at rest): u_{-1} = -h v. */
void rk_koopman_frame_before(const rk_scene_sim *sim, const double *vel, double *u_prev);

/* A trajectory of the built scene's full-order run, as the fit takes it (owning its arrays):
 * displacement frames u_{-1} = -h v_0, u_0 = 0, then one per step, so that X_0 = [0; h v_0]
 * starts it; accel: gravity plus each load over its vertex's lumped mass. */
typedef struct {
    rk_koopman_trajectory t;
    double *u, *accel;
} rk_koopman_run;
int rk_koopman_scene_run(const rk_scene_sim *sim, const rk_koopman_variation *v, rk_koopman_run *out, rk_error *err);
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

/* The same trajectory from the scene's full-order run already done: frames (3 nv x T,
 * column-major) are the displacements after each of its T steps (rk_scene_training_frames). */
int rk_koopman_scene_run_frames(const rk_scene_sim *sim, const double *frames, int T, rk_koopman_run *out,
                                rk_error *err);

/* Runs every trajectory of o and fits the operator on their (projected) displacements. basis:
 * the rom's basis when o->project, else NULL. frames (may be NULL): the scene's own run, already
 * done, used for each trajectory that changes nothing. */
int rk_koopman_scene_fit(const rk_scene_sim *sim, const rk_koopman_scene_options *o, const rk_basis *basis,
                         const double *frames, int T, rk_koopman *k, rk_koopman_scene_info *info, rk_error *err);

/* Entry `index` of the scene's rom section end to end: its koopman options (h from the scene), the
 * entry's basis when it asks for a projection (bo: the entry's basis keys), and the fit. frames
 * (3 nv x T, may be NULL): the scene's own full-order run, already done; when NULL and something
 * needs it, it is run here. */
int rk_koopman_scene_build(const rk_scene *scene, const rk_scene_sim *sim, int index, const rk_basis_options *bo,
                           const double *frames, int T, rk_koopman *k, rk_koopman_scene_info *info, rk_error *err);

#endif
