/* rk_koopman_fit: snapshot pairs, truncated SVD, the reduced operator (Eq. 13), its eigenvalues
 * and real eigenvector form, and each mode's residual on the data. */
#include "koopman/koopman_impl.h"

#include <cblas.h>
#include <float.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void rk_koopman_default_options(rk_koopman_options *o)
{
    memset(o, 0, sizeof *o);
    o->energy = 0.999999;
    o->h = 0.01;
}

void rk_koopman_free(rk_koopman *k)
{
    free(k->U);
    free(k->K);
    free(k->lambda_re);
    free(k->lambda_im);
    free(k->residual);
    free(k->W);
    free(k->Winv);
    free(k->block);
    free(k->singular);
    free(k->P_in);
    free(k->P_out);
    memset(k, 0, sizeof *k);
}

/* X and X' (2d x M each, column-major) from the trajectories; a known acceleration enters each
 * state's velocity part as the impulse a h^2 (Eq. 19). */
static int snapshot_pairs(const rk_koopman_trajectory *traj, int ntraj, int d, double h, int disp_only, double **X,
                          double **Y, int *M, rk_error *err)
{
    int m = 0, n2 = 2 * d;
    for (int k = 0; k < ntraj; k++) {
        if (traj[k].frames < 3)
            return rk_fail(err, "trajectory %d has %d frames; a state needs two and its successor a third", k,
                           traj[k].frames);
        for (size_t i = 0; i < (size_t)d * traj[k].frames; i++)
            if (!isfinite(traj[k].u[i]))
                return rk_fail(err, "trajectory %d: value %zu (frame %zu) is not finite", k, i, i / (size_t)d);
        for (int i = 0; traj[k].accel && i < d; i++)
            if (!isfinite(traj[k].accel[i]))
                return rk_fail(err, "trajectory %d: acceleration %d is not finite", k, i);
        m += traj[k].frames - 2;
    }
    *X = rk_calloc((size_t)n2 * m, sizeof(double), err);
    *Y = rk_calloc((size_t)n2 * m, sizeof(double), err);
    if (!*X || !*Y) return -1;
    int c = 0;
    for (int k = 0; k < ntraj; k++)
        for (int t = 1; t + 1 < traj[k].frames; t++, c++) {
            const double *up = traj[k].u + (size_t)d * (t - 1), *u = up + d, *un = u + d, *a = traj[k].accel;
            double *x = *X + (size_t)n2 * c, *y = *Y + (size_t)n2 * c;
            for (int i = 0; i < d; i++) {
                double impulse = a ? a[i] * h * h : 0;
                if (disp_only) { /* options.displacement_only: X_t = u_t, the impulse on u itself */
                    x[i] = u[i] + impulse;
                    y[i] = un[i];
                    continue; /* velocity rows stay zero */
                }
                x[i] = u[i];
                x[d + i] = u[i] - up[i] + impulse;
                y[i] = un[i];
                y[d + i] = un[i] - u[i];
            }
        }
    *M = m;
    return 0;
}

/* Balances the two blocks of the state before the SVD (rows 0..d-1 displacements u, rows d..2d-1
 * velocities delta = u - u_prev, in X and X' alike): the velocity rows are multiplied by
 * beta = |U|_F / |Delta|_F, so both blocks carry equal energy. delta is about omega h times u, so
 * unscaled, the SVD's energy truncation saw the velocity block as noise and dropped directions
 * only it carries, and the Galerkin operator U_r^T K U_r (Eq. 13) of what was left could leave the
 * unit circle though the data's dynamics do not. Any D = diag(I, beta I) leaves the dynamics'
 * eigenvalues as they are (D K D^-1 is similar to K): the fit works on D X, D X', and beta is kept
 * (k->vscale) so that lifting, forcing and reading back undo it. The energies are those of the
 * successors X', which hold the recorded motion only: X's velocity rows also carry the impulses
 * a h^2 (Eq. 19), which are inputs, not motion (a body held still under gravity has delta = 0 and
 * keeps beta = 1, as does any data with an all-zero block). *noise: choose_rank's floor. */
static double balance_blocks(double *X, double *Y, int d, int M, int balance, double *noise)
{
    double eu = 0, ev = 0;
    for (int c = 0; c < M; c++)
        for (int i = 0; i < d; i++) {
            double u = Y[(size_t)2 * d * c + i], v = Y[(size_t)2 * d * c + d + i];
            eu += u * u, ev += v * v;
        }
    double beta = balance && eu > 0 && ev > 0 ? sqrt(eu / ev) : 1;
    *noise = DBL_EPSILON * sqrt(eu + beta * beta * (4 * eu + ev)); /* choose_rank's |E|_F */
    if (beta != 1)
        for (int c = 0; c < M; c++) {
            cblas_dscal(d, beta, X + (size_t)2 * d * c + d, 1);
            cblas_dscal(d, beta, Y + (size_t)2 * d * c + d, 1);
        }
    return beta;
}

/* The rank: o->rank, or the smallest r for which each block, displacements and (scaled)
 * velocities, keeps o->energy of its own energy in the rank-r approximation U_r S_r V_r^T (block
 * b keeps sum_{i<r} sigma_i^2 |U_b(:, i)|^2), so that neither block's directions are dropped as
 * the other's noise; never above the numerical rank, the count of singular values above the
 * data's rounding noise. The data holds u to double precision and delta = u - u_prev is formed
 * from it, so entry by entry the noise is eps |u| in the displacement rows and about
 * beta eps (|u| + |u_prev|) in the scaled velocity rows (plus beta eps |delta|: an impulse a h^2
 * enters there too); a perturbation E of that size moves every singular value by at most
 * |E|_2 <= |E|_F (Weyl), so singular values below
 * |E|_F = eps sqrt(|U|_F^2 + beta^2 (4 |U|_F^2 + |Delta|_F^2)) are not told apart from zero. (A
 * fixed ratio to sigma_0 refused exactly linear data whose smallest directions were well above
 * the noise.) U: the 2d x ns left singular vectors. */
static int choose_rank(const double *s, const double *U, int d, int ns, double noise, const rk_koopman_options *o,
                       int *r, rk_error *err)
{
    int numerical = 0;
    while (numerical < ns && s[numerical] > noise) numerical++;
    if (numerical == 0) return rk_fail(err, "the snapshot data is all zero: nothing moves");
    if (o->rank > 0) {
        if (o->rank > numerical)
            return rk_fail(err, "rank %d is above the data's numerical rank %d (repeated or too few frames?): "
                           "ask for at most %d, or add trajectories", o->rank, numerical, numerical);
        *r = o->rank;
        return 0;
    }
    double total[2] = {0, 0}, kept[2] = {0, 0};
    for (int i = 0; i < numerical; i++)
        for (int b = 0; b < 2; b++) {
            double n = cblas_dnrm2(d, U + (size_t)2 * d * i + (size_t)d * b, 1);
            total[b] += s[i] * s[i] * n * n;
        }
    *r = 0;
    while (*r < numerical && (kept[0] < o->energy * total[0] || kept[1] < o->energy * total[1])) {
        for (int b = 0; b < 2; b++) {
            double n = cblas_dnrm2(d, U + (size_t)2 * d * *r + (size_t)d * b, 1);
            kept[b] += s[*r] * s[*r] * n * n;
        }
        (*r)++;
    }
    return 0;
}

/* The residual of each mode on the data as k->lambda holds it: |Ys phi - lambda U phi| / |phi| with
 * phi = x + i y (U orthonormal: |U phi| = |phi|; Ys = X' V_r S_r^-1 precomputed, 2d x r). */
static int residuals(rk_koopman *k, const double *Ys, int n2, rk_error *err)
{
    int r = k->r;
    double *a = rk_calloc((size_t)n2 * 4, sizeof(double), err);
    if (!a) return -1;
    double *Yx = a, *Yy = a + n2, *Ux = a + 2 * (size_t)n2, *Uy = a + 3 * (size_t)n2;
    for (int j = 0; j < r; j++) {
        int pair = k->block[j] != 1;
        const double *x = k->W + (size_t)r * (k->block[j] == 0 ? j - 1 : j);
        const double *y = pair ? x + r : NULL;
        double sign = k->block[j] == 0 ? -1 : 1; /* the pair's second: the conjugate, x - i y */
        cblas_dgemv(CblasColMajor, CblasNoTrans, n2, r, 1.0, Ys, n2, x, 1, 0.0, Yx, 1);
        cblas_dgemv(CblasColMajor, CblasNoTrans, n2, r, 1.0, k->U, n2, x, 1, 0.0, Ux, 1);
        memset(Yy, 0, sizeof(double) * n2);
        memset(Uy, 0, sizeof(double) * n2);
        if (y) {
            cblas_dgemv(CblasColMajor, CblasNoTrans, n2, r, sign, Ys, n2, y, 1, 0.0, Yy, 1);
            cblas_dgemv(CblasColMajor, CblasNoTrans, n2, r, sign, k->U, n2, y, 1, 0.0, Uy, 1);
        }
        double lr = k->lambda_re[j], li = k->lambda_im[j], num = 0, den = 0;
        for (int i = 0; i < n2; i++) {
            double re = Yx[i] - (lr * Ux[i] - li * Uy[i]), im = Yy[i] - (lr * Uy[i] + li * Ux[i]);
            num += re * re + im * im;
            den += Ux[i] * Ux[i] + Uy[i] * Uy[i];
        }
        k->residual[j] = den > 0 ? sqrt(num / den) : INFINITY;
    }
    free(a);
    return 0;
}

/* Real eigenvector form of K (r x r): W, block, eigenvalues, W^-1. */
static int eigen(rk_koopman *k, rk_error *err)
{
    int r = k->r;
    double *A = rk_calloc((size_t)r * r, sizeof(double), err), *vl = NULL;
    if (!A) return -1;
    memcpy(A, k->K, sizeof(double) * r * r);
    int info = LAPACKE_dgeev(LAPACK_COL_MAJOR, 'N', 'V', r, A, r, k->lambda_re, k->lambda_im, vl, 1, k->W, r);
    free(A);
    if (info != 0) return rk_fail(err, "the eigen-decomposition of K' failed (LAPACK dgeev info %d)", info);
    for (int j = 0; j < r; j++)
        k->block[j] = k->lambda_im[j] != 0 ? (j + 1 < r && k->lambda_im[j] > 0 ? 2 : 0) : 1;
    /* W^-1 by LU */
    int *piv = rk_calloc((size_t)r, sizeof(int), err);
    if (!piv) return -1;
    memcpy(k->Winv, k->W, sizeof(double) * r * r);
    info = LAPACKE_dgetrf(LAPACK_COL_MAJOR, r, r, k->Winv, r, piv);
    if (!info) info = LAPACKE_dgetri(LAPACK_COL_MAJOR, r, k->Winv, r, piv);
    free(piv);
    if (info != 0)
        return rk_fail(err, "K' is not diagonalizable in double precision (its eigenvector matrix is singular, "
                       "LAPACK info %d): lower the rank", info);
    return 0;
}

/* |X' - U_r K Z|_F / |X'|_F over the M (scaled) pairs, Z = U_r^T X = S_r V_r^T (r x M), X' in Y
 * (2d x M); work: r x M and 2d x M. */
static double step_residual(const rk_koopman *k, const double *Y, const double *Z, int M, double *wr, double *wn)
{
    int r = k->r, n2 = 2 * k->d;
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, r, M, r, 1.0, k->K, r, Z, r, 0.0, wr, r);
    memcpy(wn, Y, sizeof(double) * (size_t)n2 * M);
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n2, M, r, -1.0, k->U, n2, wr, r, 1.0, wn, n2);
    double y = cblas_dnrm2(n2 * M, Y, 1);
    return y > 0 ? cblas_dnrm2(n2 * M, wn, 1) / y : 0;
}

/* K = W B W^-1 from the eigenvalues as k->lambda holds them (after a refit or the clamp, so that K,
 * the blocks and the one-step residual describe one operator); work: r x r. */
void rk_koopman_compose(rk_koopman *k, double *work)
{
    int r = k->r;
    double *A = work;
    memcpy(A, k->Winv, sizeof(double) * r * r); /* B W^-1, row block by row block */
    for (int j = 0; j < r; j++) {
        if (k->block[j] == 1) {
            cblas_dscal(r, k->lambda_re[j], A + j, r);
        } else if (k->block[j] == 2) {
            double a = k->lambda_re[j], b = k->lambda_im[j];
            for (int c = 0; c < r; c++) {
                double x = k->Winv[j + (size_t)r * c], y = k->Winv[j + 1 + (size_t)r * c];
                A[j + (size_t)r * c] = a * x + b * y;
                A[j + 1 + (size_t)r * c] = -b * x + a * y;
            }
        }
    }
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, r, r, r, 1.0, k->W, r, A, r, 0.0, k->K, r);
}

int rk_koopman_fit(const rk_koopman_trajectory *traj, int ntraj, int d, const rk_koopman_options *o, rk_koopman *k,
                   rk_error *err)
{
    memset(k, 0, sizeof *k);
    if (ntraj < 1 || d < 1) return rk_fail(err, "Koopman fit: no trajectories (%d) or no observables (%d)", ntraj, d);
    if (!(o->h > 0)) return rk_fail(err, "Koopman fit: the time step must be positive, got %g", o->h);
    if (o->rank < 0 || (o->rank == 0 && !(o->energy > 0 && o->energy <= 1)))
        return rk_fail(err, "Koopman fit: rank must be >= 1, or energy in (0, 1]");
    double *X = NULL, *Y = NULL, *Vt = NULL, *Ys = NULL, *Z = NULL;
    int M = 0, n2 = 2 * d, rc = -1;
    double noise = 0;
    if (snapshot_pairs(traj, ntraj, d, o->h, o->displacement_only, &X, &Y, &M, err)) goto done;
    k->displacement_only = o->displacement_only;
    k->vscale = balance_blocks(X, Y, d, M, !o->unbalanced, &noise);
    k->data_grows = rk_koopman_data_grows(traj, ntraj, d, o->h);
    int ns = n2 < M ? n2 : M;
    double *Uall = rk_calloc((size_t)n2 * ns, sizeof(double), err);
    k->singular = rk_calloc((size_t)ns, sizeof(double), err);
    Vt = rk_calloc((size_t)ns * M, sizeof(double), err);
    if (!Uall || !k->singular || !Vt) {
        free(Uall);
        goto done;
    }
    /* Y is needed intact; the SVD overwrites a copy of X (X itself is no longer needed after). */
    int info = LAPACKE_dgesdd(LAPACK_COL_MAJOR, 'S', n2, M, X, n2, k->singular, Uall, n2, Vt, ns);
    if (info != 0) {
        free(Uall);
        rk_fail(err, "SVD of the %d x %d snapshot matrix failed (LAPACK dgesdd info %d)", n2, M, info);
        goto done;
    }
    k->nsingular = ns;
    if (choose_rank(k->singular, Uall, d, ns, noise, o, &k->r, err)) {
        free(Uall);
        goto done;
    }
    int r = k->r;
    k->d = k->n = d;
    k->h = o->h;
    k->U = Uall; /* the first r columns are U_r (column-major, leading dimension n2) */
    k->K = rk_calloc((size_t)r * r, sizeof(double), err);
    Ys = rk_calloc((size_t)n2 * r, sizeof(double), err);
    k->lambda_re = rk_calloc((size_t)r, sizeof(double), err);
    k->lambda_im = rk_calloc((size_t)r, sizeof(double), err);
    k->residual = rk_calloc((size_t)r, sizeof(double), err);
    k->W = rk_calloc((size_t)r * r, sizeof(double), err);
    k->Winv = rk_calloc((size_t)r * r, sizeof(double), err);
    k->block = rk_calloc((size_t)r, sizeof(int), err);
    if (!k->K || !Ys || !k->lambda_re || !k->lambda_im || !k->residual || !k->W || !k->Winv || !k->block) goto done;
    /* Ys = X' V_r S_r^-1 (Vt's first r rows are V_r^T), then K' = U_r^T Ys (Eq. 13). */
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, n2, r, M, 1.0, Y, n2, Vt, ns, 0.0, Ys, n2);
    for (int j = 0; j < r; j++) cblas_dscal(n2, 1.0 / k->singular[j], Ys + (size_t)n2 * j, 1);
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, r, r, n2, 1.0, k->U, n2, Ys, n2, 0.0, k->K, r);
    if (eigen(k, err) || residuals(k, Ys, n2, err)) goto done;
    /* Z = U_r^T X = S_r V_r^T (r x M) for the one-step residuals and the refit; X's memory (the SVD
     * overwrote it) is their 2d x M work space */
    Z = rk_calloc((size_t)r * M * 2, sizeof(double), err);
    if (!Z) goto done;
    for (int c = 0; c < M; c++)
        for (int i = 0; i < r; i++) Z[i + (size_t)r * c] = k->singular[i] * Vt[i + (size_t)ns * c];
    k->step_residual[0] = k->step_residual[1] = step_residual(k, Y, Z, M, Z + (size_t)r * M, X);
    /* The default: a fit that leaves the unit circle on data that does not grow is refitted under
     * |lambda| <= 1 (stabilize); growing data keeps its growth unless the clamp is asked. A fit
     * already inside is never touched (the full-rank recovery of exactly linear data included),
     * nor one outside by round-off only (a body standing still: lambda = 1 + 2e-16; a refit would
     * put it inside by the barrier's gap, 2e-9, which stops a model that should stay put). */
    if (rk_max_abs_eigenvalue(k->lambda_re, k->lambda_im, r) > 1 + 64 * DBL_EPSILON &&
        (o->stabilize > 0 || (o->stabilize == 0 && !k->data_grows))) {
        if (rk_koopman_stabilize(k, Z, M, Z + (size_t)r * M, err) || residuals(k, Ys, n2, err)) goto done;
        k->step_residual[1] = step_residual(k, Y, Z, M, Z + (size_t)r * M, X);
    }
    if (o->clamp)
        for (int j = 0; j < r; j++) {
            double m = hypot(k->lambda_re[j], k->lambda_im[j]);
            if (m > 1) {
                k->lambda_re[j] /= m;
                k->lambda_im[j] /= m;
                k->clamped++;
            }
        }
    if (k->clamped) {
        double *w = rk_calloc((size_t)r * r, sizeof(double), err);
        if (!w) goto done;
        rk_koopman_compose(k, w);
        free(w);
        k->step_residual[1] = step_residual(k, Y, Z, M, Z + (size_t)r * M, X);
    }
    rc = 0;
done:
    free(X);
    free(Y);
    free(Vt);
    free(Ys);
    free(Z);
    if (rc) {
        rk_koopman_free(k);
        return rk_error_prefix(err, "Koopman fit");
    }
    return 0;
}

int rk_koopman_fit_projected(const rk_koopman_trajectory *traj, int ntraj, int n, const double *P_in,
                             const double *P_out, int d, const rk_koopman_options *o, rk_koopman *k, rk_error *err)
{
    memset(k, 0, sizeof *k);
    if (ntraj < 1 || n < 1 || d < 1 || d > n)
        return rk_fail(err, "Koopman fit: %d trajectories of %d values projected to %d observables", ntraj, n, d);
    rk_koopman_trajectory *proj = rk_calloc((size_t)ntraj, sizeof *proj, err);
    if (!proj) return -1;
    int rc = -1;
    for (int t = 0; t < ntraj; t++) {
        if (traj[t].frames < 1) {
            rk_fail(err, "Koopman fit: trajectory %d has %d frames", t, traj[t].frames);
            goto done;
        }
        double *u = rk_calloc((size_t)d * traj[t].frames + d, sizeof(double), err);
        if (!u) goto done;
        proj[t].u = u;
        proj[t].frames = traj[t].frames;
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, d, traj[t].frames, n, 1.0, P_in, d, traj[t].u, n, 0.0,
                    u, d);
        if (traj[t].accel) {
            cblas_dgemv(CblasColMajor, CblasNoTrans, d, n, 1.0, P_in, d, traj[t].accel, 1, 0.0, u + (size_t)d * traj[t].frames, 1);
            proj[t].accel = u + (size_t)d * traj[t].frames;
        }
    }
    if (rk_koopman_fit(proj, ntraj, d, o, k, err)) goto done;
    k->n = n;
    k->P_in = rk_calloc((size_t)d * n, sizeof(double), err);
    k->P_out = rk_calloc((size_t)d * n, sizeof(double), err);
    if (!k->P_in || !k->P_out) {
        rk_koopman_free(k);
        goto done;
    }
    memcpy(k->P_in, P_in, sizeof(double) * d * n);
    memcpy(k->P_out, P_out, sizeof(double) * d * n);
    rc = 0;
done:
    for (int t = 0; t < ntraj; t++) free((void *)proj[t].u);
    free(proj);
    return rc;
}
