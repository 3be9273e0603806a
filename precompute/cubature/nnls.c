/* Non-negative least squares on the normal equations: Lawson & Hanson 1974, "Solving Least
 * Squares Problems", Ch. 23, algorithm NNLS, with A^T A and A^T b in place of A and b.
 *
 * The indices are split into a passive set P (free, w_P > 0) and an active set Z (held at 0).
 * Outer loop (L&H steps 2-6): the dual d = A^T (b - A w) = atb - gram w is the negative gradient
 * of the objective; if no d_j in Z is positive the KKT conditions hold and w is optimal,
 * otherwise the j with the largest d_j moves to P. Inner loop (L&H steps 7-11): solve the
 * unconstrained problem on P, gram_PP z = atb_P (Cholesky, LAPACK dposv); if z > 0 accept it,
 * else walk from w towards z until the first passive weight hits 0, move it (and any other that
 * reached 0) to Z, and solve again. Each inner pass shrinks P, so it ends.
 *
 * Normal equations square the condition number; the caller (greedy.c) keeps P small (at most
 * as many points as rows, because L&H keeps the passive columns independent), which is where
 * that is affordable. In floating point, L&H's guarantee that the entering index gets z_j > 0
 * can fail, and so can the Cholesky factorization when the entering column is (numerically) in
 * the span of the passive ones. Both cases mean the index does not help: it goes back to Z with
 * weight 0, w returns to where it was before the index entered, and the index is barred from
 * entering again until some other index has entered successfully (which changes the duals). */
#include "cubature/cubature.h"

#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A dual below this, relative to the size of the terms it is computed from, is rounding. */
#define RK_NNLS_DUAL_TOL 1e-12

typedef struct {
    int k;
    const double *gram, *atb;
    double *w;
    unsigned char *passive; /* passive[j]: j is in P (w_j > 0 between outer iterations) */
    unsigned char *barred;  /* barred[j]: j failed to enter since the last successful entry */
    int *list;              /* the passive indices, ascending */
    double *gpp;            /* gram_PP, packed */
    double *z;              /* the subproblem solution, by position in list */
    double *w_save;         /* w before the current entry, to undo a failed one */
    double *gw;             /* gram w */
} nnls_ws;

static void ws_free(nnls_ws *s)
{
    free(s->passive); free(s->barred); free(s->list); free(s->gpp); free(s->z); free(s->w_save);
    free(s->gw);
}

static int ws_alloc(nnls_ws *s, int k, const double *gram, const double *atb, double *w, rk_error *err)
{
    memset(s, 0, sizeof *s);
    s->k = k; s->gram = gram; s->atb = atb; s->w = w;
    s->passive = rk_calloc((size_t)k, 1, err);
    s->barred = rk_calloc((size_t)k, 1, err);
    s->list = rk_calloc((size_t)k, sizeof(int), err);
    s->gpp = rk_calloc((size_t)k * k, sizeof(double), err);
    s->z = rk_calloc((size_t)k, sizeof(double), err);
    s->w_save = rk_calloc((size_t)k, sizeof(double), err);
    s->gw = rk_calloc((size_t)k, sizeof(double), err);
    if (s->passive && s->barred && s->list && s->gpp && s->z && s->w_save && s->gw) return 0;
    ws_free(s);
    return -1;
}

static int check_finite(int k, const double *gram, const double *atb, const double *w, rk_error *err)
{
    for (size_t i = 0; i < (size_t)k * k; i++)
        if (!isfinite(gram[i]))
            return rk_fail(err, "NNLS: Gram matrix entry (%zu, %zu) is not finite", i % (size_t)k, i / (size_t)k);
    for (int j = 0; j < k; j++) {
        if (!isfinite(atb[j])) return rk_fail(err, "NNLS: right-hand side entry %d is not finite", j);
        if (!isfinite(w[j])) return rk_fail(err, "NNLS: starting weight %d is not finite", j);
    }
    return 0;
}

/* Solves gram_PP z = atb_P. Returns the size of P, or -1 when gram_PP is not numerically
 * positive definite (dpotrf found a non-positive pivot). */
static int solve_passive(nnls_ws *s)
{
    int np = 0;
    for (int j = 0; j < s->k; j++)
        if (s->passive[j]) s->list[np++] = j;
    for (int b = 0; b < np; b++) {
        for (int a = 0; a < np; a++)
            s->gpp[(size_t)b * np + a] = s->gram[(size_t)s->list[b] * s->k + s->list[a]];
        s->z[b] = s->atb[s->list[b]];
    }
    if (np == 0) return 0;
    return LAPACKE_dposv(LAPACK_COL_MAJOR, 'L', np, 1, s->gpp, np, s->z, np) == 0 ? np : -1;
}

/* L&H steps 8-11: w moves towards z until the first passive weight reaches 0; that one (and
 * any other at 0) goes to Z. Called only when some z is <= 0. */
static void step_towards(nnls_ws *s, int np)
{
    double alpha = 1.0;
    int first = -1;
    for (int i = 0; i < np; i++) {
        if (s->z[i] > 0) continue;
        double wq = s->w[s->list[i]], gap = wq - s->z[i];
        double a = gap > 0 ? wq / gap : 0.0;
        if (first < 0 || a < alpha) { alpha = a; first = s->list[i]; }
    }
    for (int i = 0; i < np; i++) {
        int q = s->list[i];
        s->w[q] += alpha * (s->z[i] - s->w[q]);
    }
    /* Exactly 0 for the blocking index, so P shrinks even when alpha rounds. */
    s->w[first] = 0;
    for (int i = 0; i < np; i++) {
        int q = s->list[i];
        if (s->w[q] <= 0) { s->w[q] = 0; s->passive[q] = 0; }
    }
}

/* The inner loop from a feasible w (w_P > 0, except the entering index at 0). Returns 0 with
 * w = z > 0 on P, or -1 when the entering index does not help (singular block, or z_entering
 * <= 0 on the first solve) or a later block is singular. */
static int descend(nnls_ws *s, int entering)
{
    for (;;) {
        int np = solve_passive(s);
        if (np < 0) return -1;
        int all_positive = 1;
        for (int i = 0; i < np; i++) {
            if (s->list[i] == entering && !(s->z[i] > 0)) return -1;
            if (!(s->z[i] > 0)) all_positive = 0;
        }
        entering = -1;
        if (all_positive) {
            for (int i = 0; i < np; i++) s->w[s->list[i]] = s->z[i];
            return 0;
        }
        step_towards(s, np);
    }
}

/* L&H steps 2-5: the index in Z (not barred) with the largest dual above the rounding level,
 * or -1 when w satisfies the KKT conditions. The level is relative to the largest term in
 * atb - gram w, so the test does not depend on how A and b are scaled. */
static int entering_index(const nnls_ws *s)
{
    int k = s->k, best = -1;
    double scale = 0, best_dual = 0;
    cblas_dsymv(CblasColMajor, CblasLower, k, 1.0, s->gram, k, s->w, 1, 0.0, s->gw, 1);
    for (int j = 0; j < k; j++) {
        double dual = s->atb[j] - s->gw[j];
        scale = fmax(scale, fmax(fabs(s->atb[j]), fabs(s->gw[j])));
        if (!s->passive[j] && !s->barred[j] && dual > best_dual) { best_dual = dual; best = j; }
    }
    return best_dual > RK_NNLS_DUAL_TOL * scale ? best : -1;
}

/* Warm start: P = {w_j > 0}, then the inner loop makes w the solution on (a subset of) P. If
 * that block is singular the start is useless, and the solve starts from w = 0 instead. */
static void warm_start(nnls_ws *s)
{
    int any = 0;
    for (int j = 0; j < s->k; j++) {
        if (s->w[j] > 0) s->passive[j] = any = 1;
        else s->w[j] = 0;
    }
    if (any && descend(s, -1) != 0) {
        memset(s->w, 0, sizeof(double) * s->k);
        memset(s->passive, 0, s->k);
    }
}

/* One outer iteration with entering index j. Returns 0 when j entered, -1 when it was refused
 * (w and P are as before, j is barred). */
static int enter(nnls_ws *s, int j)
{
    memcpy(s->w_save, s->w, sizeof(double) * s->k);
    s->passive[j] = 1;
    if (descend(s, j) == 0) {
        memset(s->barred, 0, s->k);
        return 0;
    }
    memcpy(s->w, s->w_save, sizeof(double) * s->k);
    for (int q = 0; q < s->k; q++) s->passive[q] = s->w[q] > 0;
    s->barred[j] = 1;
    return -1;
}

int rk_nnls_normal(int k, const double *gram, const double *atb, double *w, int max_iter, rk_error *err)
{
    if (k < 0) return rk_fail(err, "NNLS: %d unknowns", k);
    if (k == 0) return 0;
    if (check_finite(k, gram, atb, w, err)) return -1;
    nnls_ws s;
    if (ws_alloc(&s, k, gram, atb, w, err)) return -1;
    if (max_iter <= 0) max_iter = 3 * k;
    warm_start(&s);
    /* Only successful entries count: refusals are bounded by k between two of them. */
    for (int iter = 0; iter < max_iter;) {
        int j = entering_index(&s);
        if (j < 0) break;
        if (enter(&s, j) == 0) iter++;
    }
    ws_free(&s);
    return 0;
}
