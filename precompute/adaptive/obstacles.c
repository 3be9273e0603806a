/* The scene's moving obstacles in the adaptive step (adaptive_impl.h): over a step their vertices
 * go on straight lines to where they are due, and each moving obstacle's progress s_k is one more
 * Newton unknown beside x, pulled to 1 (contact.h, rk_obstacle_way: the reduced simulator's way, pull and rounds,
 * precompute/rom/obstacle_solve.c). The contact terms depend on s through the obstacle points
 * alone: the full-order potential gives their gradient (rk_fom_view's og) and each pair's block
 * with them as degrees of freedom, whence d/ds = og . D, d2/ds2 = D.B D and d2/dx ds = B D.
 *
 * Eq. 19's system bordered by s (k of them): [H B; B^T C] [d; d_s] = -[g; g_s], with H's solve the
 * Schur complement's (system.c) restricted to the running model's span P (d = P z): its inverse
 * S = P (P^T H P)^-1 P^T is symmetric, so (C - B^T S B) d_s = -(g_s - B^T S g) (k x k, by
 * Cholesky; one obstacle: a division) and d = -S g - S B d_s minimise the bordered quadratic over P
 * and s exactly. k + 1 Schur solves per iteration, to a tighter tolerance (below); the modal
 * coordinates of d (the secant's s, downdating) combine the same way. */
#include "adaptive/adaptive_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The bordered solves' PCG tolerance (relative residual): their right-hand sides are dominated by
 * the barrier's entries at the contact (d2/dx ds reached 1e11 against the body's inertia of 1e2
 * on a bar lifted by a box), and the default 1e-5 left the body's soft response to the obstacle,
 * moving it out of the way as a whole, unsolved: the obstacle pressed the body to gaps of 1e-14 m
 * and Newton stalled. 1e-10 cut the full-space residual after the solve 30-fold there. */
#define RK_ADAPTIVE_BORDER_PCG_TOL 1e-10

int rk_adaptive_progress_room(rk_adaptive_impl *im, int k, rk_error *err)
{
    if (k <= im->kcap) return 0;
    size_t n = (size_t)im->n, kk = (size_t)k;
    double *work = realloc(im->newton_work, sizeof(double) * (RK_NEWTON_WORK(n + kk) + 1));
    if (work) im->newton_work = work;
    double *y = realloc(im->y, sizeof(double) * (n + kk + 1));
    if (y) im->y = y;
    char *py = realloc(im->prescribed_y, n + kk + 1);
    if (py) im->prescribed_y = py;
    double *hxs = realloc(im->hxs, sizeof(double) * (n * kk + 1));
    if (hxs) im->hxs = hxs;
    double *sx = realloc(im->sx, sizeof(double) * (n * kk + 1));
    if (sx) im->sx = sx;
    double *dq_b = realloc(im->dq_b, sizeof(double) * ((size_t)im->r * kk + 1));
    if (dq_b) im->dq_b = dq_b;
    double *hss = realloc(im->hss, sizeof(double) * (kk * kk + 1));
    if (hss) im->hss = hss;
    if (!work || !y || !py || !hxs || !sx || !dq_b || !hss)
        return rk_fail(err, "out of memory for %d moving obstacles' progress", k);
    memset(im->prescribed_y + n, 0, kk); /* the progress is free */
    im->kcap = k;
    return 0;
}

double rk_adaptive_obstacle_terms(rk_adaptive *ad, const double *y, double *g, int hessian, double *magnitude)
{
    rk_adaptive_impl *im = ad->impl;
    int n = im->n, k = im->way->n;
    if (g) memset(g + n, 0, sizeof(double) * (size_t)k);
    if (hessian) memset(im->hss, 0, sizeof(double) * (size_t)k * k);
    double E = rk_obstacle_way_pull(im->way, y + n, g ? g + n : NULL, hessian ? im->hss : NULL, k);
    if (magnitude) *magnitude += fabs(E);
    if (g) {
        rk_fom_view v;
        rk_fom_view_get(&ad->fom, &v);
        rk_obstacle_way_gradient(im->way, v.og, g + n);
    }
    if (hessian) {
        memset(im->hxs, 0, sizeof(double) * (size_t)n * k);
        double BD[48];
        int units[4];
        for (int b = 0; b < im->view.nblocks; b++) {
            const rk_contact_block *blk = &im->view.blocks[b];
            int nu = rk_obstacle_way_block(im->way, blk->id, blk->np, blk->H, units, BD, im->hss, k);
            for (int j = 0; j < nu; j++) {
                double *hxs = im->hxs + (size_t)n * units[j];
                for (int p = 0; p < blk->np; p++)
                    for (int c = 0; c < 3 && blk->id[p] >= 0; c++) hxs[3 * blk->id[p] + c] += BD[12 * j + 3 * p + c];
            }
        }
        for (int j = 0; j < k; j++)
            for (int i = 0; i < n; i++)
                if (im->view.prescribed[i]) im->hxs[(size_t)n * j + i] = 0;
    }
    return E;
}

/* M x = b for the k x k symmetric M (column-major) by Cholesky, in place (b into x): 0, or -1 when
 * M is not positive definite. */
static int small_cholesky(double *M, int k, double *b)
{
    for (int j = 0; j < k; j++) {
        for (int l = 0; l < j; l++) M[j + k * j] -= M[j + k * l] * M[j + k * l];
        if (!(M[j + k * j] > 0)) return -1;
        M[j + k * j] = sqrt(M[j + k * j]);
        for (int i = j + 1; i < k; i++) {
            for (int l = 0; l < j; l++) M[i + k * j] -= M[i + k * l] * M[j + k * l];
            M[i + k * j] /= M[j + k * j];
        }
    }
    for (int i = 0; i < k; i++) { /* L z = b, then L^T x = z */
        for (int l = 0; l < i; l++) b[i] -= M[i + k * l] * b[l];
        b[i] /= M[i + k * i];
    }
    for (int i = k - 1; i >= 0; i--) {
        for (int l = i + 1; l < k; l++) b[i] -= M[l + k * i] * b[l];
        b[i] /= M[i + k * i];
    }
    return 0;
}

int rk_adaptive_solve_bordered(rk_adaptive *ad, const rk_fom_terms *T, const double *g, double *d, rk_error *err)
{
    rk_adaptive_impl *im = ad->impl;
    int n = im->n, a = im->a, r = im->r, k = im->way->n;
    double tol = ad->opt.pcg_tol;
    ad->opt.pcg_tol = fmin(tol, RK_ADAPTIVE_BORDER_PCG_TOL);
    int bad = 0;
    for (int u = 0; u < k && !bad; u++) { /* sx_u = -S b_u, and its modal part */
        bad = rk_adaptive_solve(ad, T, im->hxs + (size_t)n * u, im->sx + (size_t)n * u, err);
        if (!bad) memcpy(im->dq_b + (size_t)r * u, im->dq, sizeof(double) * (size_t)a);
    }
    if (!bad) bad = rk_adaptive_solve(ad, T, g, d, err); /* d = -S g */
    ad->opt.pcg_tol = tol;
    if (bad) return -1;
    if (k == 1) { /* (the one obstacle's case, as before there were several) */
        double bSb = 0, bSg = 0;
        for (int i = 0; i < n; i++) {
            bSb -= im->hxs[i] * im->sx[i];
            bSg -= im->hxs[i] * d[i];
        }
        double schur = im->hss[0] - bSb;
        /* c - b.S b > 0 for a positive definite bordered matrix; the pull alone (w > 0) where
         * round-off says otherwise */
        d[n] = schur > 0 ? -(g[n] - bSg) / schur : -g[n] / im->hss[0];
    } else { /* (C - B^T S B) d_s = -(g_s - B^T S g), k x k, in d[n..] */
        double *M = rk_calloc((size_t)k * k, sizeof(double), err);
        if (!M) return -1;
        for (int u = 0; u < k; u++) {
            const double *bu = im->hxs + (size_t)n * u;
            double bSg = 0;
            for (int i = 0; i < n; i++) bSg -= bu[i] * d[i];
            d[n + u] = -(g[n + u] - bSg);
            for (int v = 0; v < k; v++) {
                const double *sv = im->sx + (size_t)n * v;
                double bSb = 0;
                for (int i = 0; i < n; i++) bSb -= bu[i] * sv[i];
                M[u + (size_t)k * v] = im->hss[u + (size_t)k * v] - bSb;
            }
        }
        if (small_cholesky(M, k, d + n)) /* the pulls alone where round-off says it is not PD */
            for (int u = 0; u < k; u++) d[n + u] = -g[n + u] / im->hss[u + (size_t)k * u];
        free(M);
    }
    for (int u = 0; u < k; u++) {
        double ds = d[n + u];
        for (int i = 0; i < n; i++) d[i] += ds * im->sx[(size_t)n * u + i];
        for (int j = 0; j < a; j++) im->dq[j] += ds * im->dq_b[(size_t)r * u + j];
    }
    return 0;
}
