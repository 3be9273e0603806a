/* The reduced velocity a baked model starts with (the VEL0 chunk): the scene's initial velocities
 * projected onto the basis exactly as romkit compare projects the full-order run's first frame
 * (rom_compare.c), so that the runtime's free run and compare's start from the same state. */
#include "pipeline/method_fixed.h"

#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/util.h"

/* Least squares over the points (a point cloud has no mass matrix): QR of a copy of U. */
static int project_unweighted(const double *U, int ndof, int r, const double *v, double *q, rk_error *err)
{
    double *A = rk_calloc((size_t)ndof * r, sizeof(double), err), *b = rk_calloc((size_t)ndof, sizeof(double), err);
    int rc = -1;
    if (A && b) {
        memcpy(A, U, sizeof(double) * (size_t)ndof * r);
        memcpy(b, v, sizeof(double) * (size_t)ndof);
        lapack_int info = LAPACKE_dgels(LAPACK_COL_MAJOR, 'N', ndof, r, 1, A, ndof, b, ndof);
        if (info) rk_fail(err, "initial velocity: the basis's least squares failed (LAPACK info %d)", (int)info);
        else {
            memcpy(q, b, sizeof(double) * r);
            rc = 0;
        }
    }
    free(A);
    free(b);
    return rc;
}

/* |a|^2 in M's norm (M NULL: the Euclidean one); Ma is scratch of a's length. */
static double norm2(const rk_sparse *M, const double *a, double *Ma, int n)
{
    if (!M) return cblas_ddot(n, a, 1, a, 1);
    rk_sparse_mul(M, a, Ma);
    return cblas_ddot(n, a, 1, Ma, 1);
}

int rk_scene_rom_velocity0(const rk_scene_sim *sim, const rk_scene_rom *R, double **v0, double *residual, rk_error *err)
{
    int ndof = 3 * sim->mesh.nv, r = R->basis.r, moving = 0;
    const double *v = sim->options.velocity0;
    *v0 = NULL;
    *residual = 0;
    for (int i = 0; v && i < ndof; i++) moving |= v[i] != 0;
    if (!moving) return 0;
    rk_sparse M = {0};
    int have_mass = sim->fem.nt > 0;
    double *q = rk_calloc((size_t)r, sizeof(double), err), *d = rk_calloc((size_t)ndof, sizeof(double), err);
    double *Md = rk_calloc((size_t)ndof, sizeof(double), err);
    int rc = -1;
    if (!q || !d || !Md) goto out;
    if (have_mass) {
        if (rk_sparse_alloc_pattern(&sim->fem, &M, err)) goto out;
        rk_fem_add_mass(&sim->fem, sim->options.lumped_mass, 1.0, &M);
        /* a cloud's points beside the meshes weigh too (else its velocity projected to nothing) */
        rk_fem_add_point_mass(&sim->fem, 1.0, &M);
        if (rk_rom_project(&R->model, &M, R->basis.U, ndof, NULL, v, q, err)) goto out;
    } else if (project_unweighted(R->basis.U, ndof, r, v, q, err))
        goto out;
    /* what the basis holds of the motion: a skinning basis holds a translation exactly, a POD
     * trained on other motions may not */
    memcpy(d, v, sizeof(double) * ndof);
    cblas_dgemv(CblasColMajor, CblasNoTrans, ndof, r, -1.0, R->basis.U, ndof, q, 1, 1.0, d, 1);
    const rk_sparse *W = have_mass ? &M : NULL;
    *residual = sqrt(norm2(W, d, Md, ndof) / norm2(W, v, Md, ndof));
    *v0 = q;
    q = NULL;
    rc = 0;
out:
    rk_sparse_free(&M);
    free(q);
    free(d);
    free(Md);
    return rc;
}
