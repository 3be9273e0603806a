/* RKPM skinning eigenmodes, mesh-free (freeform paper Sec. 3.2 and 7.1): kernels on farthest
 * samples of the integration points, the weight-space eigenproblem H_w c = lambda M c (Eq. 15)
 * with H_w from Prop. 1 and M from Eq. 14, weights W^j(X) = sum_k phi_k(X) c_k^j (Eq. 6). With a
 * clamp the phi_k are masked (rkpm_clamp.c) before anything is assembled, so Eq. 15 is solved in
 * the masked space and every weight vanishes on the fixed region. With a moving region too
 * (rk_basis_rkpm_skinning_lifted) the mask covers both, and the lifting field of rkpm_lift.c is the
 * last weight. */
#include "basis/basis.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/util.h"

/* The kernels' mean radius: the clamp mask's unit. */
static double mean_radius(const rk_rkpm *k)
{
    double s = 0;
    for (int c = 0; c < k->K; c++) s += k->radius[c];
    return s / k->K;
}

/* The clamped eigenproblem: kernels whose masked mass vanishes (all their support inside the fixed
 * region, M_kk below 1e-12 of the largest) are left out (their rows would make the pencil
 * singular) and get nodal value 0. */
static int clamped_eigs(const rk_sparse *H, const rk_sparse *M, int m, double *values, double *C, int *nzero,
                        rk_error *err)
{
    int K = H->n, kept = 0, rc = -1;
    double top = 0;
    for (int c = 0; c < K; c++) top = fmax(top, M->val[M->colptr[c + 1] - 1]); /* (the diagonal ends a column) */
    int *keep = rk_calloc((size_t)K, sizeof(int), err);
    if (!keep) return -1;
    for (int c = 0; c < K; c++) keep[c] = M->val[M->colptr[c + 1] - 1] > 1e-12 * top ? kept++ : -1;
    rc = rk_weight_eigs_restricted(H, M, keep, kept, m, 1, values, C, nzero, err);
    free(keep);
    return rc;
}

/* The mask's region: the fixed points, and with a lift the moving ones too (NULL: no mask). */
static unsigned char *held_points(const unsigned char *fixed, const unsigned char *moving, int n, rk_error *err)
{
    unsigned char *held = rk_calloc((size_t)n, 1, err);
    for (int i = 0; held && i < n; i++) held[i] = (fixed && fixed[i]) || moving[i];
    return held;
}

static int skinning(const rk_rkpm_points *pts, const double *coef, int kernels, int m, const double *Xeval, int n,
                    const unsigned char *fixed, const unsigned char *moving, const int *tets, int nt, rk_basis *b,
                    rk_rkpm_timing *timing, rk_error *err)
{
    memset(b, 0, sizeof *b);
    rk_rkpm_timing tm = {0};
    rk_sparse H = {0}, M = {0};
    rk_lift lift = {0};
    unsigned char *held = moving ? held_points(fixed, moving, n, err) : NULL;
    int H_lift = moving != NULL; /* the lifting handle after the m + 1 eigen-weights */
    int *chosen = rk_calloc((size_t)(kernels > 0 ? kernels : 1), sizeof(int), err);
    double *centers = rk_calloc(3 * (size_t)(kernels > 0 ? kernels : 1), sizeof(double), err);
    b->rkpm = rk_calloc(1, sizeof *b->rkpm, err);
    int rc = -1, have_rkpm = 0;
    if (!chosen || !centers || !b->rkpm || (moving && !held)) goto out;
    if (moving && !tets) {
        rk_fail(err, "a moving region held exactly (clamp \"lifted\") needs the mesh's tets");
        goto out;
    }
    double t = rk_now();
    if (rk_fps(pts->X, pts->n, kernels, chosen, err)) goto out;
    for (int k = 0; k < kernels; k++) memcpy(centers + 3 * k, pts->X + 3 * (size_t)chosen[k], 3 * sizeof(double));
    tm.fps = rk_now() - t;
    t = rk_now();
    if (rk_rkpm_init(b->rkpm, centers, kernels, err)) goto out;
    have_rkpm = 1;
    if ((held || fixed) &&
        rk_rkpm_set_clamp(b->rkpm, Xeval, n, held ? held : fixed, tets, nt, RK_RKPM_CLAMP_RISE * mean_radius(b->rkpm), err))
        goto out;
    if (moving && (rk_lift_init(&lift, Xeval, n, fixed, moving, tets, nt, err) ||
                   rk_rkpm_set_lift(b->rkpm, &lift, m + 1, err)))
        goto out;
    tm.kernels = rk_now() - t;
    t = rk_now();
    int damped_integration = 0;
    if (rk_rkpm_assemble(b->rkpm, pts->X, pts->weight, coef, pts->n, &H, &M, &damped_integration, err)) goto out;
    tm.assemble = rk_now() - t;
    t = rk_now();
    b->type = RK_BASIS_RKPM_SKINNING;
    b->n = n;
    b->nvalues = m + 1;
    b->m = m + 1 + H_lift;
    b->r = 12 * b->m;
    b->lift_handle = H_lift ? b->m : 0;
    b->values = rk_calloc((size_t)m + 1, sizeof(double), err);
    b->C = rk_calloc((size_t)kernels * b->m, sizeof(double), err); /* (the lift's nodal values stay 0) */
    b->W = rk_calloc((size_t)n * b->m, sizeof(double), err);
    b->U = rk_calloc(3 * (size_t)n * b->r, sizeof(double), err);
    if (!b->values || !b->C || !b->W || !b->U) goto out;
    if (b->rkpm->clamp.n > 0 ? clamped_eigs(&H, &M, m, b->values, b->C, &b->nzero, err)
                             : rk_weight_eigs(&H, &M, m, 0, b->values, b->C, &b->nzero, err))
        goto out;
    tm.eigs = rk_now() - t;
    t = rk_now();
    if (rk_rkpm_interpolate(b->rkpm, Xeval, n, b->C, b->m, b->W, NULL, &b->damped_points, err)) goto out;
    b->damped_points += damped_integration;
    rk_skinning_to_U(b->W, n, b->m, Xeval, b->U);
    tm.evaluate = rk_now() - t;
    rc = 0;
out:
    if (rc) {
        rk_error_prefix(err, "RKPM skinning eigenmodes");
        if (!have_rkpm) { free(b->rkpm); b->rkpm = NULL; }
        rk_basis_free(b);
    }
    if (timing) *timing = tm;
    rk_sparse_free(&H);
    rk_sparse_free(&M);
    free(chosen);
    free(centers);
    free(held);
    rk_lift_free(&lift);
    return rc;
}

int rk_basis_rkpm_skinning(const rk_rkpm_points *pts, const double *coef, int kernels, int m,
                           const double *Xeval, int n, const unsigned char *fixed, const int *tets, int nt,
                           rk_basis *b, rk_rkpm_timing *timing, rk_error *err)
{
    return skinning(pts, coef, kernels, m, Xeval, n, fixed, NULL, tets, nt, b, timing, err);
}

int rk_basis_rkpm_skinning_lifted(const rk_rkpm_points *pts, const double *coef, int kernels, int m,
                                  const double *Xeval, int n, const unsigned char *fixed, const unsigned char *moving,
                                  const int *tets, int nt, rk_basis *b, rk_rkpm_timing *timing, rk_error *err)
{
    if (!moving) return rk_fail(err, "RKPM skinning with a lift: no moving region given");
    return skinning(pts, coef, kernels, m, Xeval, n, fixed, moving, tets, nt, b, timing, err);
}
