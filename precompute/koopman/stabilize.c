/* The stable refit of a DMD fit (fit.c's default when the data does not grow): whether the
 * training data gains energy, and the eigenvalues refitted under |lambda| <= 1 with the modes held. */
#include "koopman/koopman_impl.h"

#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The mechanical energy (times 2 h^2, unit masses) at frame t of a trajectory (1 <= t - 1, t < frames):
 * |delta_t|^2 + u_t^T K u_t - 2 h^2 a . u_t, delta_t = u_t - u_{t-1}, the last term the constant
 * load's potential (a body released under gravity loses energy as it sags: without that term it
 * would count as gaining it), with u^T K u measured from the data's own
 * acceleration: for M u'' + C u' + K u = M a (backward Euler, as the full order steps), unit
 * masses, h^2 K u_t = -(delta_t - delta_{t-1} - a h^2) - h C v_t, the damping term dropped
 * (a dissipation, small beside the stiffness at these steps). u about its unloaded rest. */
static double frame_energy(const rk_koopman_trajectory *tr, int d, int t, double h)
{
    const double *u0 = tr->u + (size_t)d * (t - 2), *u1 = u0 + d, *u2 = u1 + d;
    double e = 0;
    for (int i = 0; i < d; i++) {
        double v1 = u1[i] - u0[i], v2 = u2[i] - u1[i], a = tr->accel ? tr->accel[i] * h * h : 0;
        e += v2 * v2 - u2[i] * (v2 - v1 - a) - 2 * a * u2[i]; /* kinetic, elastic, the load's potential */
    }
    return e;
}

/* Whether the training data grows: the trajectories' mechanical energy at their last frame,
 * summed, above that at their first (frame_energy; frame 2, the first with an acceleration
 * behind it). A passive body (elastic, damped, under loads that do not change) cannot gain
 * energy, so a fit of such data that leaves the unit circle is an artefact of the truncation, and
 * the default refits it (stabilize); data that gains energy keeps its growth. Not the norm of the
 * state [u; beta delta] the fit sees: that norm is not conserved by an undamped oscillation (on
 * slow chains it rose by 45% over a damped run), the energy is. A body released from rest under a
 * load loses the load's potential as it sags: passive, so refitted where its fit leaves the circle. */
int rk_koopman_data_grows(const rk_koopman_trajectory *traj, int ntraj, int d, double h)
{
    double first = 0, last = 0;
    for (int k = 0; k < ntraj; k++) {
        first += frame_energy(traj + k, d, 2, h);
        last += frame_energy(traj + k, d, traj[k].frames - 1, h);
    }
    return last > first;
}

/* q = 1/2 (theta - theta_0)^T G (theta - theta_0), half the misfit a refit adds (stabilize); diff and
 * Gd (n each) get theta - theta_0 and G (theta - theta_0). */
static double excess(int n, const double *G, const double *theta, const double *theta0, double *diff, double *Gd)
{
    for (int i = 0; i < n; i++) diff[i] = theta[i] - theta0[i];
    cblas_dsymv(CblasColMajor, CblasUpper, n, 1.0, G, n, diff, 1, 0.0, Gd, 1);
    return 0.5 * cblas_ddot(n, diff, 1, Gd, 1);
}

/* The stability-constrained refit of the eigenvalues. Truncation (U_r of the SVD) can give K' an
 * eigenvalue outside the unit circle though the data never grows: K' = U_r^T X' V_r S_r^-1 is the
 * least-squares operator of the reduced pairs (Z' ~ K Z, Z = U_r^T X, Z' = U_r^T X'), and what
 * the dropped directions did to the kept ones is absorbed into it as if it were dynamics. The
 * refit keeps the fitted modes W and re-solves the eigenvalue blocks B (K = W B W^-1) for the same
 * objective, min |Z' - W B W^-1 Z|_F^2, subject to |lambda| <= 1 for every block.
 *
 * Why jointly, not mode by mode: in modal coordinates Y = W^-1 Z, Y' = W^-1 Z', the Galerkin
 * eigenvalues are each mode's own least-squares fit (the residual Z' - K' Z is orthogonal to
 * Z's rows, so (Y' - Lambda Y) Y^T = 0, row by row lambda_j = <y'_j, y_j> / |y_j|^2), and per mode
 * sum_t |y'_t - lambda y_t|^2 = |y|^2 |lambda - lambda_j|^2 + const is isotropic in lambda, so
 * its minimiser on the disc is the radial projection: that is exactly the clamp. But the
 * objective the fit minimises is in z, not y: |W (Y' - B Y)|_F, and W is not orthogonal, so the
 * modes' errors add up through W^T W and the cheapest stable B moves the other blocks too.
 * With W held, W B Y is linear in B's parameters theta (lambda for a real block, (a, b) for a
 * pair's [[a, b], [-b, a]], F_p = W E_p Y), so the objective is the quadratic
 *   |Z' - W B Y|^2 = |Z' - K' Z|^2 + (theta - theta_0)^T G (theta - theta_0),
 *   G_pq = <W E_p Y, W E_q Y> = <E_p, (W^T W) E_q (Y Y^T)>,
 * theta_0 the Galerkin eigenvalues (its unconstrained minimiser, by the orthogonality above), and
 * the feasible set is a product of discs and intervals: a convex problem with one minimiser,
 * solved here by a log-barrier interior point method (Newton steps on r x r systems; Y Y^T =
 * W^-1 S_r^2 W^-T needs no pass over the data). The minimiser is strictly inside the constraint
 * where it is not on it, and the barrier's last iterate lies inside by a duality gap of
 * 1e-12 of the objective, so every returned |lambda| < 1. Not done: moving the modes W themselves
 * (a non-convex problem; the stable-DMD literature's constrained K), so a refit costs more
 * residual than the best stable operator of rank r would. */
int rk_koopman_stabilize(rk_koopman *k, const double *Z, int M, double *work, rk_error *err)
{
    int r = k->r, np = r, rc = -1;
    /* parameter p of each index: a real block's lambda at j, a pair's a at j and b at j + 1 */
    double *A = rk_calloc((size_t)r * r, sizeof(double), err), *C = rk_calloc((size_t)r * r, sizeof(double), err);
    double *G = rk_calloc((size_t)np * np, sizeof(double), err), *H = rk_calloc((size_t)np * np, sizeof(double), err);
    double *v = rk_calloc((size_t)np * 7, sizeof(double), err);
    if (!A || !C || !G || !H || !v) goto done;
    double *theta0 = v, *theta = v + np, *g = v + 2 * np, *step = v + 3 * np, *dq = v + 4 * np, *trial = v + 5 * np,
           *cand = v + 6 * np;
    /* A = W^T W, C = Y Y^T = W^-1 (Z Z^T) W^-T */
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, r, r, r, 1.0, k->W, r, k->W, r, 0.0, A, r);
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, r, M, r, 1.0, k->Winv, r, Z, r, 0.0, work, r);
    cblas_dsyrk(CblasColMajor, CblasUpper, CblasNoTrans, r, M, 1.0, work, r, 0.0, C, r);
    for (int i = 0; i < r; i++)
        for (int j = 0; j < i; j++) C[i + (size_t)r * j] = C[j + (size_t)r * i];
    /* E_p as (row, col, sign) entries: a real block e_j e_j^T; a pair's a: e_j e_j^T + e_j1 e_j1^T,
     * its b: e_j e_j1^T - e_j1 e_j^T (B[j][j+1] = b, B[j+1][j] = -b, koopman.h) */
    int ent[2][2][2];
    double sgn[2][2];
    for (int p = 0; p < np; p++)
        for (int q = 0; q < np; q++) {
            int ne[2] = {0, 0};
            for (int w = 0; w < 2; w++) {
                int x = w ? q : p, j = k->block[x] == 0 ? x - 1 : x;
                if (k->block[x] == 1) {
                    ent[w][0][0] = ent[w][0][1] = j, sgn[w][0] = 1, ne[w] = 1;
                } else if (k->block[x] == 2) { /* a */
                    ent[w][0][0] = ent[w][0][1] = j, ent[w][1][0] = ent[w][1][1] = j + 1;
                    sgn[w][0] = sgn[w][1] = 1, ne[w] = 2;
                } else { /* b */
                    ent[w][0][0] = j, ent[w][0][1] = j + 1, ent[w][1][0] = j + 1, ent[w][1][1] = j;
                    sgn[w][0] = 1, sgn[w][1] = -1, ne[w] = 2;
                }
            }
            double s = 0; /* <e_i e_k^T, A e_m e_n^T C> = A[i][m] C[n][k] */
            for (int e = 0; e < ne[0]; e++)
                for (int f = 0; f < ne[1]; f++)
                    s += sgn[0][e] * sgn[1][f] * A[ent[0][e][0] + (size_t)r * ent[1][f][0]] *
                         C[ent[1][f][1] + (size_t)r * ent[0][e][1]];
            G[p + (size_t)np * q] = s;
        }
    /* theta_0 and a strictly feasible start (each block inside the circle by 1e-3) */
    int nb = 0;
    for (int j = 0; j < r; j++) theta0[j] = k->block[j] == 0 ? k->lambda_im[j - 1] : k->lambda_re[j];
    for (int j = 0; j < r; j++) {
        if (!k->block[j]) continue;
        nb++;
        double m = k->block[j] == 2 ? hypot(theta0[j], theta0[j + 1]) : fabs(theta0[j]);
        double f = m < 1 - 1e-3 ? 1 : (1 - 1e-3) / m;
        theta[j] = theta0[j] * f;
        if (k->block[j] == 2) theta[j + 1] = theta0[j + 1] * f;
    }
    double q0 = excess(np, G, theta, theta0, trial, dq);
    double t = q0 > 0 ? nb / q0 : 1, gap_goal = 1e-12 * q0;
    for (int outer = 0; outer < 60 && nb / t > gap_goal; outer++, t *= 10) {
        for (int it = 0; it < 100; it++) {
            /* phi = t q - sum_b log(1 - |theta_b|^2): gradient g, Hessian H */
            excess(np, G, theta, theta0, trial, dq); /* dq = G (theta - theta_0) */
            for (int p = 0; p < np; p++) g[p] = t * dq[p];
            for (int p = 0; p < np; p++)
                for (int i = 0; i < np; i++) H[i + (size_t)np * p] = t * G[i + (size_t)np * p];
            for (int j = 0; j < r; j++) {
                if (!k->block[j]) continue;
                int w = k->block[j];
                double s = theta[j] * theta[j] + (w == 2 ? theta[j + 1] * theta[j + 1] : 0), den = 1 - s;
                for (int a = 0; a < w; a++) {
                    g[j + a] += 2 * theta[j + a] / den;
                    for (int b = 0; b < w; b++)
                        H[j + a + (size_t)np * (j + b)] +=
                            (a == b ? 2 / den : 0) + 4 * theta[j + a] * theta[j + b] / (den * den);
                }
            }
            /* Newton step: H step = -g, H scaled to unit diagonal first (G's scales span the data's) */
            for (int p = 0; p < np; p++) dq[p] = 1 / sqrt(H[p + (size_t)np * p]);
            for (int p = 0; p < np; p++) {
                step[p] = -g[p] * dq[p];
                for (int i = 0; i < np; i++) H[i + (size_t)np * p] *= dq[i] * dq[p];
            }
            if (LAPACKE_dposv(LAPACK_COL_MAJOR, 'U', np, 1, H, np, step, np) != 0) break; /* keep theta */
            for (int p = 0; p < np; p++) step[p] *= dq[p];
            double decrement = -cblas_ddot(np, g, 1, step, 1);
            if (!(decrement > 0)) break;
            /* the largest step that stays inside every disc, then backtracking on phi */
            double alpha = 1, phi0 = t * excess(np, G, theta, theta0, trial, dq);
            for (int j = 0; j < r; j++)
                if (k->block[j]) {
                    double s = theta[j] * theta[j] + (k->block[j] == 2 ? theta[j + 1] * theta[j + 1] : 0);
                    phi0 -= log(1 - s);
                }
            for (int tries = 0; tries < 60; tries++, alpha *= 0.5) {
                double bar = 0;
                int inside = 1;
                for (int p = 0; p < np; p++) cand[p] = theta[p] + alpha * step[p];
                for (int j = 0; j < r && inside; j++)
                    if (k->block[j]) {
                        double s = cand[j] * cand[j] + (k->block[j] == 2 ? cand[j + 1] * cand[j + 1] : 0);
                        inside = s < 1;
                        bar -= inside ? log(1 - s) : 0;
                    }
                if (!inside) continue;
                if (t * excess(np, G, cand, theta0, trial, dq) + bar <= phi0 - 0.25 * alpha * decrement) {
                    memcpy(theta, cand, sizeof(double) * np);
                    break;
                }
            }
            if (decrement < 1e-10) break;
        }
    }
    /* the refitted eigenvalues, K = W B W^-1 */
    double shift = 0, top = 0;
    for (int j = 0; j < r; j++) {
        double re, im;
        if (k->block[j] == 1) re = theta[j], im = 0;
        else if (k->block[j] == 2) re = theta[j], im = theta[j + 1];
        else re = theta[j - 1], im = -theta[j];
        top = fmax(top, hypot(k->lambda_re[j], k->lambda_im[j]));
        k->stabilized += hypot(k->lambda_re[j], k->lambda_im[j]) > 1;
        shift = fmax(shift, hypot(re - k->lambda_re[j], im - k->lambda_im[j]));
        k->lambda_re[j] = re, k->lambda_im[j] = im;
    }
    k->stabilize_shift = shift;
    k->stabilize_top = top;
    rk_koopman_compose(k, A);
    rc = 0;
done:
    free(A);
    free(C);
    free(G);
    free(H);
    free(v);
    return rc;
}
