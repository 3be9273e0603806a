/* romkit run --stress (run_stress.h). */
#include "run_stress.h"

#include <stdlib.h>
#include <string.h>

#include "fem/fem.h"

int run_stress_open(run_stress *o, const char *path, long frames, const run_scene *S, const romrt_model *m,
                    rk_error *err)
{
    memset(o, 0, sizeof *o);
    int n = o->n = S->shown;
    o->model = calloc((size_t)n + 1, sizeof(rk_material_model));
    o->mu = calloc((size_t)n + 1, sizeof(double));
    o->lambda = calloc((size_t)n + 1, sizeof(double));
    o->sigma = calloc((size_t)n + 1, sizeof(double));
    o->F = calloc(9 * (size_t)n + 1, sizeof(romrt_real));
    if (!o->model || !o->mu || !o->lambda || !o->sigma || !o->F) return rk_fail(err, "--stress: out of memory");
    romrt_error rerr;
    if (romrt_deformation_gradients(m, o->F, 9 * (size_t)n, &rerr) != ROMRT_OK) { /* a mesh: its tets */
        free(o->F);
        o->F = NULL;
        int nv = S->sim.fem.nv;
        if (S->sim.fem.nt == 0 || n != nv)
            return rk_fail(err, "--stress: the asset shows %d of the scene's %d vertices and stores no deformation "
                           "gradients (GRAD, a point cloud's): a mesh's stresses come from its tets, so bake it with "
                           "rom.asset.show \"all\" (or take romkit fom --stress's)", n, nv);
        o->S = S;
        o->x = calloc(3 * (size_t)nv + 1, sizeof(double));
        o->sigma_all = calloc((size_t)nv + 1, sizeof(double));
        if (!o->x || !o->sigma_all) return rk_fail(err, "--stress: out of memory");
    }
    for (int i = 0; i < n && o->F; i++) { /* each point's material, as the bake took it (tags and regions) */
        int v = (int)S->source[i];
        rk_material mat = rk_scene_point_material(&S->scene, &S->sim, run_scene_object_of(S, v), v);
        o->model[i] = mat.model;
        rk_lame(mat.young, mat.poisson, &o->mu[i], &o->lambda[i]);
    }
    long shape[2] = {frames, n};
    if (rk_npy_stream_open(&o->out, path, 2, shape, err)) return -1;
    o->open = 1;
    return 0;
}

int run_stress_frame(run_stress *o, const romrt_model *m, long k, const romrt_real *xyz, rk_error *err)
{
    romrt_error rerr;
    if (!o->F) { /* a mesh: every vertex shown, each tet's stress as romkit fom --stress takes it */
        for (int i = 0; i < o->n; i++)
            for (int a = 0; a < 3; a++) o->x[3 * (size_t)o->S->source[i] + a] = (double)xyz[3 * i + a];
        if (rk_fem_principal_stress(&o->S->sim.fem, o->x, o->sigma_all, err)) return -1;
        for (int i = 0; i < o->n; i++) o->sigma[i] = o->sigma_all[o->S->source[i]];
        rk_npy_stream_append(&o->out, o->sigma, (size_t)o->n);
        return 0;
    }
    if (romrt_deformation_gradients(m, o->F, 9 * (size_t)o->n, &rerr) != ROMRT_OK)
        return rk_fail(err, "--stress: frame %ld: %s", k, rerr.message);
    for (int i = 0; i < o->n; i++) {
        double F[9], s[9];
        for (int a = 0; a < 9; a++) F[a] = (double)o->F[9 * (size_t)i + a];
        rk_cauchy_stress(o->model[i], o->mu[i], o->lambda[i], F, s);
        o->sigma[i] = rk_largest_principal(s);
    }
    rk_npy_stream_append(&o->out, o->sigma, (size_t)o->n);
    return 0;
}

int run_stress_commit(run_stress *o, rk_error *err)
{
    if (!o->open) return 0;
    o->open = 0;
    return rk_npy_stream_commit(&o->out, err);
}

void run_stress_close(run_stress *o)
{
    if (o->open) rk_npy_stream_abort(&o->out);
    free(o->model), free(o->mu), free(o->lambda), free(o->sigma), free(o->F), free(o->x), free(o->sigma_all);
    memset(o, 0, sizeof *o);
}
