/* Method fixed beside full order (method_fixed.c's compare): the reduced model built on the scene's
 * mesh (trained on the entry's training set or the scene's run), its free run (errors against
 * every reference frame, the median step time), its realigned run (each step from the reference's
 * state, projected: Grassmann paper Sec. 5.1) and its basis's fitting residual. */
#include "pipeline/method_fixed.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/util.h"

int rk_fixed_compare(rk_compare_ctx *c, const rk_rom_entry *e, rk_compare_method *m, rk_error *err);

/* The free run: errors against every full-order frame and the median step time. */
static int run_free(const rk_scene_sim *sim, rk_scene_rom *R, const rk_fom_frames *F, const rk_sparse *M,
                    rk_compare_method *out, rk_error *err)
{
    int r = R->basis.r, ndof = F->ndof;
    double *q0 = rk_calloc((size_t)r, sizeof(double), err), *v0 = rk_calloc((size_t)r, sizeof(double), err);
    double *x = rk_calloc((size_t)ndof, sizeof(double), err), *secs = rk_calloc((size_t)F->T + 1, sizeof(double), err);
    int rc = -1;
    rk_rom rom = {0};
    if (!q0 || !v0 || !x || !secs) goto out;
    if (rk_rom_project(&R->model, M, R->basis.U, ndof, sim->mesh.X, F->x, q0, err) ||
        rk_rom_project(&R->model, M, R->basis.U, ndof, NULL, F->v, v0, err) ||
        rk_rom_init(&rom, &R->model, q0, v0, err))
        goto out;
    rk_run_error e;
    rk_run_error_init(&e, sim->mesh.X, ndof / 3);
    out->contact_min_distance = INFINITY;
    for (int s = 0; s < F->T; s++) {
        double t0 = rk_now();
        if (rk_rom_step(&rom, err)) goto out;
        secs[s] = rk_now() - t0;
        int crossings;
        double d;
        if (rk_rom_contact_measure(&rom, &crossings, &d, err)) goto out;
        out->contact_min_distance = fmin(out->contact_min_distance, d);
        if (crossings > out->contact_intersections) out->contact_intersections = crossings;
        rk_rom_positions(R->basis.U, ndof, r, sim->mesh.X, rom.q, x);
        rk_run_error_add(&e, x, F->x + (size_t)ndof * (s + 1));
    }
    rk_compare_record_errors(out, &e);
    out->seconds_per_step = rk_median(secs, F->T);
    out->newton_iterations = rom.stats.newton_iterations;
    out->unconverged_steps = rom.stats.unconverged_steps;
    rc = 0;
out:
    rk_rom_free(&rom);
    free(q0);
    free(v0);
    free(x);
    free(secs);
    return rc;
}

/* Each step from the full-order state before it, projected (Grassmann paper Sec. 5.1). */
static int run_realigned(const rk_scene_sim *sim, rk_scene_rom *R, const rk_fom_frames *F, const rk_sparse *M,
                         rk_compare_method *out, rk_error *err)
{
    int r = R->basis.r, ndof = F->ndof;
    double *q = rk_calloc((size_t)r, sizeof(double), err), *v = rk_calloc((size_t)r, sizeof(double), err);
    double *x = rk_calloc((size_t)ndof, sizeof(double), err);
    int rc = -1;
    rk_rom rom = {0};
    if (!q || !v || !x || rk_rom_init(&rom, &R->model, NULL, NULL, err)) goto out;
    rk_run_error e;
    rk_run_error_init(&e, sim->mesh.X, ndof / 3);
    for (int s = 0; s < F->T; s++) {
        if (rk_rom_project(&R->model, M, R->basis.U, ndof, sim->mesh.X, F->x + (size_t)ndof * s, q, err) ||
            rk_rom_project(&R->model, M, R->basis.U, ndof, NULL, F->v + (size_t)ndof * s, v, err))
            goto out;
        double reached;
        if (rk_rom_realign(&rom, q, v, s * sim->options.h, &reached, err) || rk_rom_step(&rom, err)) goto out;
        out->realign_clipped += reached < 1;
        rk_rom_positions(R->basis.U, ndof, r, sim->mesh.X, rom.q, x);
        rk_run_error_add(&e, x, F->x + (size_t)ndof * (s + 1));
    }
    out->relative_online_error = rk_relative_online_error(&e);
    rc = 0;
out:
    rk_rom_free(&rom);
    free(q);
    free(v);
    free(x);
    return rc;
}

int rk_fixed_compare(rk_compare_ctx *c, const rk_rom_entry *e, rk_compare_method *m, rk_error *err)
{
    const double *D;
    int T;
    rk_scene_rom R;
    if (rk_compare_training(c, e, &D, &T, m, err) || rk_scene_rom_build(c->scene, c->sim, e, D, T, &R, err)) return -1;
    m->r = R.basis.r;
    m->size = R.basis.W ? R.basis.m - 1 - (R.basis.lift_handle != 0) : R.basis.r; /* (m: not the lift) */
    m->cubature_points = R.cubature_points;
    m->cubature_error = R.cubature_error;
    m->seconds_basis = R.seconds_basis;
    m->seconds_cubature = R.seconds_cubature;
    m->seconds_training_run = R.basis_info.fom_frames ? c->fom_seconds_total : 0;
    memcpy(m->basis_reason, R.basis_reason, sizeof m->basis_reason);
    memcpy(m->cubature_reason, R.cubature_reason, sizeof m->cubature_reason);
    memcpy(m->volume_warning, R.volume_warning, sizeof m->volume_warning);
    const rk_fom_frames *ref = c->ref;
    int rc = run_free(c->sim, &R, ref, c->M, m, err) || run_realigned(c->sim, &R, ref, c->M, m, err) ||
                     rk_compare_basis_fit(R.basis.U, ref->ndof, R.basis.r, c->sim->mesh.X, ref, m, err)
                 ? -1
                 : 0;
    rk_scene_rom_free(&R);
    return rc;
}
