/* Greedy cubature point selection: An, Kim & James 2008, "Optimizing cubature for efficient
 * integration of subspace deformations", Sec. 4. The residual r = b - A_S w starts at b; every
 * iteration scores a random subset of the unselected candidates by how well their column points
 * along r, (a_c . r) / |a_c|, adds the best one, and re-fits all weights with non-negative least
 * squares (nnls.c), warm-started from the previous weights so that usually a single NNLS outer
 * iteration is needed. Points whose weight the re-fit sets to 0 leave the set and become
 * candidates again.
 *
 * The selected columns are kept (rows x count), so the residual is b - A_S w computed from them
 * exactly, not |b|^2 - 2 w^T A^T b + w^T G w, which would lose half the digits to cancellation
 * near a good fit. The Gram matrix A_S^T A_S grows by one row and column per pick (the new
 * column against the stored ones) and shrinks when points are dropped.
 *
 * Stopping: the tolerance, max_points, no candidate with a positive score (b is outside the cone
 * of what is left), or an iteration that does not lower the error (the numerical floor of the
 * normal equations has been reached; that pick is undone, so the result is the best set seen). */
#include "cubature/cubature.h"

#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "util/util.h"

/* A candidate whose column makes a cosine below this with the residual does not point along it:
 * the dot product's rounding error is of this order. */
#define RK_GREEDY_SCORE_FLOOR 1e-13
/* An iteration must lower the relative error by at least this fraction to count as progress. */
#define RK_GREEDY_MIN_GAIN 1e-12
/* A column this small against the target is zero to rounding: it would need a weight of 1e12 to
 * move the fit, and its cosine with the residual is noise. Elements whose vertices are all held
 * have such columns (the basis vanishes there up to rounding, 1e-27 against 0.08 on the
 * armadillo's bend), and scoring one by its cosine picked it and ended the greedy at 3 points. */
#define RK_GREEDY_NORM_FLOOR 1e-12

typedef struct {
    const rk_cubature_problem *p;
    int rows, max_points, cap, count;
    double *cols;            /* rows x cap: the selected columns (slot count: the one on trial) */
    int *idx;                /* cap: their candidate indices */
    double *w, *w_trial;     /* cap: weights, and the re-fit of the trial set */
    double *gram;            /* cap x cap (leading dimension cap): A_S^T A_S */
    double *gram_packed;     /* (count + 1)^2: the trial Gram matrix as rk_nnls_normal takes it */
    double *atb;             /* cap: A_S^T b */
    double *r, *r_trial;     /* rows: residuals */
    double *col, *best_col;  /* rows: the candidate being scored, the best one so far */
    int *pool, npool;        /* unselected candidates with a non-zero column */
    int *pos;                /* candidates: position in pool, or -1 */
    int *draw;               /* candidates: the subset scored this iteration */
    uint64_t rng;            /* the subset draws (util/util.h) */
    double bnorm;
} greedy;

static int check_problem(const rk_cubature_problem *p, rk_error *err)
{
    if (p->rows < 1 || p->candidates < 1)
        return rk_fail(err, "cubature: %d rows and %d candidates (need at least 1 of each)", p->rows, p->candidates);
    if (!p->column || !p->b) return rk_fail(err, "cubature: no column callback or no target");
    if (p->max_points < 1) return rk_fail(err, "cubature: max_points is %d (need at least 1)", p->max_points);
    if (p->sample < 0) return rk_fail(err, "cubature: sample is %d (0 means all candidates)", p->sample);
    if (!(p->tolerance >= 0)) return rk_fail(err, "cubature: tolerance %g is not a non-negative number", p->tolerance);
    for (int i = 0; i < p->rows; i++)
        if (!isfinite(p->b[i])) return rk_fail(err, "cubature: target entry %d is not finite", i);
    if (cblas_dnrm2(p->rows, p->b, 1) == 0)
        return rk_fail(err, "cubature: the target is zero, so the relative error is undefined");
    return 0;
}

static void greedy_free(greedy *g)
{
    free(g->cols); free(g->idx); free(g->w); free(g->w_trial); free(g->gram); free(g->gram_packed);
    free(g->atb); free(g->r); free(g->r_trial); free(g->col); free(g->best_col);
    free(g->pool); free(g->pos); free(g->draw);
}

/* Replaces *p (old_n elements) by a zeroed array of new_n elements holding the old ones. */
static int grow(void *p, size_t old_n, size_t new_n, size_t size, rk_error *err)
{
    void **slot = p;
    void *fresh = rk_calloc(new_n, size, err);
    if (!fresh) return -1;
    if (*slot) memcpy(fresh, *slot, old_n * size);
    free(*slot);
    *slot = fresh;
    return 0;
}

/* Room for `need` selected columns: capacity doubles (up to max_points), so a run that keeps
 * few points never allocates rows x max_points. */
static int reserve(greedy *g, int need, rk_error *err)
{
    if (need <= g->cap) return 0;
    int cap = g->cap ? 2 * g->cap : 16;
    if (cap < need) cap = need;
    if (cap > g->max_points) cap = g->max_points;
    size_t oc = (size_t)g->cap, nc = (size_t)cap, rows = (size_t)g->rows;
    double *gram = rk_calloc(nc * nc, sizeof(double), err);
    if (!gram) return -1;
    for (size_t j = 0; j < oc; j++) memcpy(gram + j * nc, g->gram + j * oc, oc * sizeof(double));
    free(g->gram);
    g->gram = gram;
    if (grow(&g->cols, rows * oc, rows * nc, sizeof(double), err) ||
        grow(&g->idx, oc, nc, sizeof(int), err) || grow(&g->w, oc, nc, sizeof(double), err) ||
        grow(&g->w_trial, oc, nc, sizeof(double), err) || grow(&g->atb, oc, nc, sizeof(double), err) ||
        grow(&g->gram_packed, 0, nc * nc, sizeof(double), err))
        return -1;
    g->cap = cap;
    return 0;
}

static int greedy_init(greedy *g, const rk_cubature_problem *p, rk_error *err)
{
    memset(g, 0, sizeof *g);
    g->p = p;
    g->rows = p->rows;
    g->max_points = p->max_points < p->candidates ? p->max_points : p->candidates;
    g->rng = p->seed;
    size_t rows = (size_t)p->rows, n = (size_t)p->candidates;
    g->r = rk_calloc(rows, sizeof(double), err);
    g->r_trial = rk_calloc(rows, sizeof(double), err);
    g->col = rk_calloc(rows, sizeof(double), err);
    g->best_col = rk_calloc(rows, sizeof(double), err);
    g->pool = rk_calloc(n, sizeof(int), err);
    g->pos = rk_calloc(n, sizeof(int), err);
    g->draw = rk_calloc(n, sizeof(int), err);
    if (!g->r || !g->r_trial || !g->col || !g->best_col || !g->pool || !g->pos || !g->draw) return -1;
    for (int c = 0; c < p->candidates; c++) g->pool[c] = g->pos[c] = c;
    g->npool = p->candidates;
    memcpy(g->r, p->b, rows * sizeof(double));
    g->bnorm = cblas_dnrm2(p->rows, p->b, 1);
    return reserve(g, 1, err);
}

static void pool_swap(greedy *g, int i, int j)
{
    int a = g->pool[i], b = g->pool[j];
    g->pool[i] = b; g->pos[b] = i;
    g->pool[j] = a; g->pos[a] = j;
}

static void pool_remove(greedy *g, int c)
{
    pool_swap(g, g->pos[c], g->npool - 1);
    g->npool--;
    g->pos[c] = -1;
}

static void pool_add(greedy *g, int c)
{
    g->pool[g->npool] = c;
    g->pos[c] = g->npool++;
}

/* This iteration's subset: a partial Fisher-Yates shuffle of the pool, or all of it. */
static int draw_subset(greedy *g)
{
    int s = g->p->sample;
    if (s <= 0 || s >= g->npool) s = g->npool;
    else
        for (int i = 0; i < s; i++)
            pool_swap(g, i, i + (int)(rk_splitmix64(&g->rng) % (uint64_t)(g->npool - i)));
    memcpy(g->draw, g->pool, sizeof(int) * s);
    return s;
}

static int fetch_column(greedy *g, int c, double *col, rk_error *err)
{
    if (g->p->column(g->p->ctx, c, col, err)) return rk_error_prefix(err, "cubature candidate %d", c);
    for (int i = 0; i < g->rows; i++)
        if (!isfinite(col[i])) return rk_fail(err, "cubature candidate %d: column entry %d is not finite", c, i);
    return 0;
}

/* Scores a fresh subset; *best is the candidate with the largest positive score (its column in
 * best_col), or -1 when none has one. Zero columns (RK_GREEDY_NORM_FLOOR) leave the pool for good. */
static int pick(greedy *g, int *best, rk_error *err)
{
    int s = draw_subset(g);
    double rnorm = cblas_dnrm2(g->rows, g->r, 1), best_score = RK_GREEDY_SCORE_FLOOR * rnorm;
    *best = -1;
    if (g->p->cost_begin) g->p->cost_begin(g->p->ctx, g->idx, g->count);
    for (int i = 0; i < s; i++) {
        int c = g->draw[i];
        if (fetch_column(g, c, g->col, err)) return -1;
        double norm = cblas_dnrm2(g->rows, g->col, 1);
        if (!(norm > RK_GREEDY_NORM_FLOOR * g->bnorm)) { pool_remove(g, c); continue; }
        double score = cblas_ddot(g->rows, g->col, 1, g->r, 1) / norm;
        if (g->p->cost_begin) score /= g->p->cost(g->p->ctx, c);
        if (score > best_score) {
            best_score = score;
            *best = c;
            memcpy(g->best_col, g->col, sizeof(double) * g->rows);
        }
    }
    return 0;
}

/* Puts best_col in the trial slot (count) with its Gram row and column and A^T b entry. */
static void append_trial(greedy *g, int c)
{
    int n = g->count, rows = g->rows;
    size_t cap = (size_t)g->cap;
    double *a = g->cols + (size_t)n * rows, *gcol = g->gram + (size_t)n * cap;
    memcpy(a, g->best_col, sizeof(double) * rows);
    g->idx[n] = c;
    if (n > 0) cblas_dgemv(CblasColMajor, CblasTrans, rows, n, 1.0, g->cols, rows, a, 1, 0.0, gcol, 1);
    for (int i = 0; i < n; i++) g->gram[(size_t)i * cap + n] = gcol[i];
    gcol[n] = cblas_ddot(rows, a, 1, a, 1);
    g->atb[n] = cblas_ddot(rows, a, 1, g->p->b, 1);
}

/* NNLS over the count + 1 trial columns, warm-started from the current weights; the trial
 * residual and its relative norm from the columns. */
static int refit_trial(greedy *g, double *rel, rk_error *err)
{
    int n = g->count + 1;
    for (int j = 0; j < n; j++)
        memcpy(g->gram_packed + (size_t)j * n, g->gram + (size_t)j * g->cap, sizeof(double) * n);
    memcpy(g->w_trial, g->w, sizeof(double) * g->count);
    g->w_trial[g->count] = 0;
    if (rk_nnls_normal(n, g->gram_packed, g->atb, g->w_trial, 0, err)) return -1;
    memcpy(g->r_trial, g->p->b, sizeof(double) * g->rows);
    cblas_dgemv(CblasColMajor, CblasNoTrans, g->rows, n, -1.0, g->cols, g->rows, g->w_trial, 1, 1.0, g->r_trial, 1);
    *rel = cblas_dnrm2(g->rows, g->r_trial, 1) / g->bnorm;
    return 0;
}

/* Moves selected slot `from` to slot `to` (< from): column, index, weights, Gram row/column.
 * Slots are compacted in increasing order, so every source is read before it is overwritten. */
static void move_slot(greedy *g, int from, int to, const int *keep, int kept)
{
    size_t cap = (size_t)g->cap, rows = (size_t)g->rows;
    memcpy(g->cols + (size_t)to * rows, g->cols + (size_t)from * rows, sizeof(double) * rows);
    g->idx[to] = g->idx[from];
    g->w[to] = g->w[from];
    g->atb[to] = g->atb[from];
    for (int a = 0; a < kept; a++) g->gram[(size_t)to * cap + a] = g->gram[(size_t)from * cap + keep[a]];
    for (int a = 0; a < kept; a++) g->gram[(size_t)a * cap + to] = g->gram[(size_t)keep[a] * cap + from];
}

/* Of the n slots, those whose weight is 0 leave the set and return to the pool; the others are
 * compacted to the front in order. keep: scratch for n indices. */
static void drop_zero_weights(greedy *g, int n, int *keep)
{
    int kept = 0;
    for (int j = 0; j < n; j++) {
        if (g->w[j] > 0) keep[kept++] = j;
        else pool_add(g, g->idx[j]);
    }
    for (int a = 0; a < kept; a++)
        if (keep[a] != a) move_slot(g, keep[a], a, keep, a + 1);
    g->count = kept;
}

/* Accepts the trial: the picked candidate joins, the weights and residual become the trial
 * ones, and points whose weight is now 0 leave the set and return to the pool. */
static void commit_trial(greedy *g, int c)
{
    pool_remove(g, c);
    int n = ++g->count;
    memcpy(g->w, g->w_trial, sizeof(double) * n);
    double *t = g->r; g->r = g->r_trial; g->r_trial = t;
    /* keep[] reuses draw[]'s storage: the subset is not needed until the next pick. */
    drop_zero_weights(g, n, g->draw);
}

typedef struct { int index; double weight; } point;

static int by_index(const void *a, const void *b)
{
    int x = ((const point *)a)->index, y = ((const point *)b)->index;
    return (x > y) - (x < y);
}

static int write_set(const greedy *g, double rel, double tolerance, rk_cubature_set *out, rk_error *err)
{
    point *pts = rk_calloc((size_t)g->count, sizeof(point), err);
    out->index = rk_calloc((size_t)g->count, sizeof(int), err);
    out->weight = rk_calloc((size_t)g->count, sizeof(double), err);
    if (!pts || !out->index || !out->weight) { free(pts); rk_cubature_set_free(out); return -1; }
    for (int j = 0; j < g->count; j++) pts[j] = (point){g->idx[j], g->w[j]};
    qsort(pts, (size_t)g->count, sizeof(point), by_index);
    for (int j = 0; j < g->count; j++) { out->index[j] = pts[j].index; out->weight[j] = pts[j].weight; }
    free(pts);
    out->count = g->count;
    out->relative_error = rel;
    out->reached = rel <= tolerance;
    return 0;
}

/* Pruning: the greedy pick adds the point that best reduces the residual now, and some of the
 * early ones end up nearly redundant. Tries dropping each point, smallest weighted contribution
 * w_j |a_j| first, re-fits the others by NNLS, and keeps the drop when the error stays within
 * the tolerance; repeats until a whole pass drops nothing. The set only shrinks and the
 * error never exceeds the tolerance. */
static int prune(greedy *g, double *rel, double tolerance, rk_error *err)
{
    int n0 = g->count, dropped = 1, rc = 0;
    double *score = rk_calloc((size_t)n0 + 1, sizeof(double), err), *atb = rk_calloc((size_t)n0 + 1, sizeof(double), err);
    double *w = rk_calloc((size_t)n0 + 1, sizeof(double), err);
    int *order = rk_calloc((size_t)n0 + 1, sizeof(int), err);
    if (!score || !atb || !w || !order) rc = -1;
    while (rc == 0 && dropped && g->count > 1) {
        int n = g->count, m = n - 1;
        dropped = 0;
        for (int j = 0; j < n; j++) {
            order[j] = j;
            score[j] = g->w[j] * cblas_dnrm2(g->rows, g->cols + (size_t)j * g->rows, 1);
        }
        for (int a = 1; a < n; a++) /* insertion sort by score, ties by slot: deterministic */
            for (int b = a; b > 0 && score[order[b]] < score[order[b - 1]]; b--) {
                int t = order[b];
                order[b] = order[b - 1];
                order[b - 1] = t;
            }
        for (int k = 0; k < n && !dropped && rc == 0; k++) {
            int skip = order[k], a = 0;
            double *G = g->gram_packed;
            for (int u = 0; u < n; u++) {
                if (u == skip) continue;
                for (int v = 0, b = 0; v < n; v++)
                    if (v != skip) G[(size_t)a * m + b++] = g->gram[(size_t)u * g->cap + v];
                atb[a] = g->atb[u];
                w[a++] = g->w[u];
            }
            if ((rc = rk_nnls_normal(m, G, atb, w, 0, err)) != 0) break;
            /* the residual from the columns, as the greedy loop computes it */
            memcpy(g->col, g->p->b, sizeof(double) * g->rows);
            a = 0;
            for (int u = 0; u < n; u++)
                if (u != skip) cblas_daxpy(g->rows, -w[a++], g->cols + (size_t)u * g->rows, 1, g->col, 1);
            double trial = cblas_dnrm2(g->rows, g->col, 1) / g->bnorm;
            if (!(trial <= tolerance)) continue;
            /* kept: the re-fit's weights (slot skip's 0); zero-weight points leave the set too */
            a = 0;
            for (int u = 0; u < n; u++) g->w[u] = u == skip ? 0 : w[a++];
            drop_zero_weights(g, n, order);
            *rel = trial;
            dropped = 1;
        }
    }
    free(score);
    free(atb);
    free(w);
    free(order);
    return rc;
}

int rk_cubature_greedy(const rk_cubature_problem *p, rk_cubature_set *out, rk_error *err)
{
    memset(out, 0, sizeof *out);
    if (check_problem(p, err)) return -1;
    greedy g;
    int rc = greedy_init(&g, p, err), iterations = 0;
    double rel = 1.0;
    while (rc == 0 && rel > p->tolerance && g.count < g.max_points) {
        int c;
        double trial;
        if ((rc = pick(&g, &c, err)) != 0 || c < 0) break;
        iterations++;
        if ((rc = reserve(&g, g.count + 1, err)) != 0) break;
        append_trial(&g, c);
        if ((rc = refit_trial(&g, &trial, err)) != 0) break;
        if (!(trial < rel * (1 - RK_GREEDY_MIN_GAIN))) break;
        commit_trial(&g, c);
        rel = trial;
        rk_progress("cubature points chosen", g.count, 0);
    }
    rk_progress_done("cubature points chosen");
    int greedy_count = g.count;
    if (rc == 0 && p->prune && rel <= p->tolerance) rc = prune(&g, &rel, p->tolerance, err);
    if (rc == 0) rc = write_set(&g, rel, p->tolerance, out, err);
    out->iterations = iterations;
    out->greedy_count = greedy_count;
    greedy_free(&g);
    return rc;
}

void rk_cubature_set_free(rk_cubature_set *s)
{
    if (!s) return;
    free(s->index);
    free(s->weight);
    s->index = NULL;
    s->weight = NULL;
    s->count = 0;
}
