/* The files a split bake's step reads (stage_inputs.h). */
#include "stage_inputs.h"

#include <stdlib.h>
#include <string.h>

#include "args.h"

int tool_stage_args(const char *cmd, int *argc, char **argv, tool_stage *s)
{
    int n = cli_take_all(cmd, argc, argv, "--training-run", s->runs, RK_MAX_TRAINING);
    if (n < 0) return -1;
    s->nruns = n;
    n = cli_take_all(cmd, argc, argv, "--trajectory-run", s->traj, RK_KOOPMAN_MAX_TRAJECTORIES);
    if (n < 0) return -1;
    s->ntraj = n;
    return 0;
}

/* Whether entry e's basis can come from a file: U alone (no weights, kernels or parts), on the
 * mesh (not mesh-free), of a fixed-basis entry. */
static int takes_basis(const rk_scene *scene, const rk_rom_entry *e, rk_error *err)
{
    rk_basis_type t = e->basis.type;
    if (e->method != &rk_method_fixed)
        return rk_fail(err, "--basis/--cubature: %s (%s) is a %s entry; only fixed-basis entries are baked from parts",
                       e->path, e->name, e->method->name);
    if ((t != RK_BASIS_MODES && t != RK_BASIS_MODAL_DERIVATIVES && t != RK_BASIS_POD) || rk_scene_mesh_free(scene, e))
        return rk_fail(err, "--basis/--cubature: %s (%s) has a %s%s basis; only modes, modal_derivatives and pod "
                       "bases on the mesh are taken from files", e->path, e->name, rk_basis_type_name(t),
                       rk_scene_mesh_free(scene, e) ? " mesh-free" : "");
    return 0;
}

int tool_stage_load(tool_stage *s, const rk_scene *scene, const rk_rom_entry *e, rk_bake_request *req, rk_error *err)
{
    if (s->nruns && s->nruns != e->ntraining)
        return rk_fail(err, "--training-run given %d times; %s lists %d training runs", s->nruns, e->path, e->ntraining);
    if (s->nruns && s->training)
        return rk_fail(err, "--training (the scene's own run) and --training-run (the training list's) both given");
    if ((s->basis || s->cubature) && takes_basis(scene, e, err)) return -1;
    if (s->ntraj && !rk_koopman_of(e))
        return rk_fail(err, "--trajectory-run: %s (%s) has no koopman section, no trajectories", e->path, e->name);
    if (s->cubature && !e->cubature)
        return rk_fail(err, "--cubature %s: %s has no rom.cubature (it integrates exactly)", s->cubature, e->path);
    if (s->training) {
        int ndim;
        if (rk_npy_read(s->training, &s->snapshots, &ndim, req->snapshot_shape, err))
            return rk_error_prefix(err, "--training");
        req->snapshots = s->snapshots;
        req->snapshot_dims = ndim;
    }
    req->training_runs = s->runs;
    req->ntraining_runs = s->nruns;
    req->trajectory_runs = s->traj;
    req->ntrajectory_runs = s->ntraj;
    if (s->basis) {
        if (rk_scene_basis_read(s->basis, e->basis.type, &s->b, err)) return rk_error_prefix(err, "--basis");
        s->have_basis = 1;
        req->basis = &s->b;
    }
    if (s->cubature) {
        if (rk_scene_cubature_read(s->cubature, &s->c, &req->cubature_poses, err))
            return rk_error_prefix(err, "--cubature");
        s->have_cubature = 1;
        req->cubature = &s->c;
    }
    return 0;
}

void tool_stage_free(tool_stage *s)
{
    free(s->snapshots);
    s->snapshots = NULL;
    if (s->have_basis) rk_basis_free(&s->b);
    if (s->have_cubature) rk_cubature_set_free(&s->c);
    s->have_basis = s->have_cubature = 0;
}
