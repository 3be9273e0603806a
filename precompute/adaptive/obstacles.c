/* The scene's moving obstacles in the adaptive step (adaptive_impl.h): over a step their vertices
 * go on straight lines to where they are due, and their progress s is one more Newton unknown
 * beside x, pulled to 1 (contact.h, rk_obstacle_way: the reduced simulator's way, pull and rounds,
 * precompute/rom/obstacle_solve.c). The contact terms depend on s through the obstacle points
 * alone: the full-order potential gives their gradient (rk_fom_view's og) and each pair's block
 * with them as degrees of freedom, whence d/ds = og . D, d2/ds2 = D.B D and d2/dx ds = B D.
 *
 * Eq. 19's system bordered by s: [H b; b^T c] [d; d_s] = -[g; g_s], with H's solve the Schur
 * complement's (system.c) restricted to the running model's span P (d = P z): its inverse
 * S = P (P^T H P)^-1 P^T is symmetric, so d_s = -(g_s - b.S g) / (c - b.S b) and
 * d = -S g - d_s S b minimise the bordered quadratic over P and s exactly. Two Schur solves per
 * iteration, to a tighter tolerance (below); the modal coordinates of d (the secant's s,
 * downdating) combine the same way. */
#include "adaptive/adaptive_impl.h"

#include <math.h>
#include <string.h>

/* The bordered solves' PCG tolerance (relative residual): their right-hand sides are dominated by
 * the barrier's entries at the contact (d2/dx ds reached 1e11 against the body's inertia of 1e2
 * on a bar lifted by a box), and the default 1e-5 left the body's soft response to the obstacle,
 * moving it out of the way as a whole, unsolved: the obstacle pressed the body to gaps of 1e-14 m
 * and Newton stalled. 1e-10 cut the full-space residual after the solve 30-fold there. */
#define RK_ADAPTIVE_BORDER_PCG_TOL 1e-10

double rk_adaptive_obstacle_terms(rk_adaptive *ad, const double *y, double *g, int hessian, double *magnitude)
{
    rk_adaptive_impl *im = ad->impl;
    int n = im->n;
    double s = y[n], gs = 0, hss = 0;
    double E = rk_obstacle_way_pull(im->way, s, g ? &gs : NULL, hessian ? &hss : NULL);
    if (magnitude) *magnitude += fabs(E);
    if (g) {
        rk_fom_view v;
        rk_fom_view_get(&ad->fom, &v);
        gs += rk_obstacle_way_gradient(im->way, v.og);
        g[n] = gs;
    }
    if (hessian) {
        memset(im->hxs, 0, sizeof(double) * (size_t)n);
        double BD[12];
        for (int b = 0; b < im->view.nblocks; b++) {
            const rk_contact_block *blk = &im->view.blocks[b];
            if (!rk_obstacle_way_block(im->way, blk->id, blk->np, blk->H, BD, &hss)) continue;
            for (int p = 0; p < blk->np; p++)
                for (int k = 0; k < 3 && blk->id[p] >= 0; k++) im->hxs[3 * blk->id[p] + k] += BD[3 * p + k];
        }
        for (int i = 0; i < n; i++)
            if (im->view.prescribed[i]) im->hxs[i] = 0;
        im->hss = hss;
    }
    return E;
}

int rk_adaptive_solve_bordered(rk_adaptive *ad, const rk_fom_terms *T, const double *g, double *d, rk_error *err)
{
    rk_adaptive_impl *im = ad->impl;
    int n = im->n, a = im->a;
    double tol = ad->opt.pcg_tol;
    ad->opt.pcg_tol = fmin(tol, RK_ADAPTIVE_BORDER_PCG_TOL);
    int bad = rk_adaptive_solve(ad, T, im->hxs, im->sx, err); /* sx = -S b */
    if (!bad) {
        memcpy(im->dq_b, im->dq, sizeof(double) * (size_t)a); /* its modal part */
        bad = rk_adaptive_solve(ad, T, g, d, err);             /* d = -S g */
    }
    ad->opt.pcg_tol = tol;
    if (bad) return -1;
    double bSb = 0, bSg = 0;
    for (int i = 0; i < n; i++) {
        bSb -= im->hxs[i] * im->sx[i];
        bSg -= im->hxs[i] * d[i];
    }
    double schur = im->hss - bSb;
    /* c - b.S b > 0 for a positive definite bordered matrix; the pull alone (w > 0) where round-off
     * says otherwise */
    double ds = schur > 0 ? -(g[n] - bSg) / schur : -g[n] / im->hss;
    for (int i = 0; i < n; i++) d[i] += ds * im->sx[i];
    for (int j = 0; j < a; j++) im->dq[j] += ds * im->dq_b[j];
    d[n] = ds;
    return 0;
}
