/* A cubature for a basis that moves (cubature.h, rk_cubature_train_moving; issue 33). An et al.
 * 2008 fit the reduced forces U^T f_e(u) of one fixed basis U over many poses u (training.c). The
 * adaptive linear ROM integrates every step in the basis that step forms, so here each training
 * pose t brings its own: column e of the training matrix is (U_t^T f_e(u_t))_t, each pose's block
 * divided by the norm of its exact total sum_e U_t^T f_e(u_t) so that every pose counts the same
 * (An et al. Eq. 5), and the same greedy NNLS (greedy.c) picks the elements. A quarter of the
 * poses are held out of the fit and the weights' error is measured on them. Every column is kept
 * (r poses x elements doubles): one pose's bases and stresses are formed once, pose by pose.
 *
 * What a step costs is mostly per vertex, not per element: the runtime forms the moving basis'
 * rows at every vertex of the cubature's elements (runtime/alrom_basis.c, about 850 multiply-adds
 * a row, 3 rows a vertex), and an element's own force and Hessian cost about what 1.3 such rows
 * do. So the greedy's score (the cosine with the residual) is divided by 1 + vertex_cost x the
 * fraction of the candidate's 4 vertices no selected element has yet: it prefers elements beside
 * those it holds. On the armadillo's bench scenes (tolerance 0.01): vertex_cost 0 picks 273
 * elements on 597 vertices, 2: 276 on 433, 8: 300 on 370, 32: 315 on 356, with the same free-run
 * errors (within 6%); 8 is the default. */
#include "cubature/cubature.h"

#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Pose t is held out when t % RK_MOVING_HOLDOUT == RK_MOVING_HOLDOUT - 1. */
#define RK_MOVING_HOLDOUT 4

typedef struct {
    const double *A; /* rows x candidates */
    int rows;
    const rk_fem *f;
    unsigned char *used; /* nv: the vertices of the selected elements */
    double vertex_cost;
} moving_columns;

static void cost_begin(void *ctx, const int *selected, int count)
{
    moving_columns *m = ctx;
    memset(m->used, 0, (size_t)m->f->nv);
    for (int k = 0; k < count; k++)
        for (int a = 0; a < 4; a++) m->used[m->f->tets[4 * selected[k] + a]] = 1;
}

static double cost(void *ctx, int c)
{
    const moving_columns *m = ctx;
    int fresh = 0;
    for (int a = 0; a < 4; a++) fresh += !m->used[m->f->tets[4 * c + a]];
    return 1 + m->vertex_cost * fresh / 4.0;
}

static int column(void *ctx, int c, double *col, rk_error *err)
{
    const moving_columns *m = ctx;
    (void)err;
    memcpy(col, m->A + (size_t)m->rows * c, sizeof(double) * (size_t)m->rows);
    return 0;
}

/* Pose t's block of every column (rows r, at row0 of A with `rows` rows) and its normalised
 * total into b; 0 when the total vanishes (the rest pose: no information), 1 when kept. */
static int pose_block(const rk_fem *f, int r, const rk_moving_poses *P, int t, double *u, double *U, double *A,
                      int rows, int row0, double *b, rk_error *err)
{
    rk_quadrature Q = {0}, Qu = {0};
    int nt = f->nt, kept = -1;
    if (P->pose(P->ctx, t, u, U, err)) return rk_error_prefix(err, "cubature training pose %d", t);
    /* G_e of the pose's basis, and of its displacement as one column: F_e = I + G_e^u 1 */
    if (rk_quadrature_elements(f, U, r, nt, NULL, NULL, &Q, err) || rk_quadrature_elements(f, u, 1, nt, NULL, NULL, &Qu, err))
        goto out;
    const double one = 1;
    memset(b, 0, sizeof(double) * (size_t)r);
    for (int e = 0; e < nt; e++) {
        double F[9], *col = A + (size_t)rows * e + row0;
        rk_quadrature_point_F(&Qu, e, &one, F);
        rk_quadrature_point_force(&Q, e, F, col);
        for (int k = 0; k < r; k++) {
            if (!isfinite(col[k])) {
                rk_fail(err, "cubature training pose %d: element %d's force is not finite", t, e);
                goto out;
            }
            b[k] += col[k];
        }
    }
    double norm = cblas_dnrm2(r, b, 1);
    kept = norm > 0;
    for (int e = 0; e < nt && kept; e++) cblas_dscal(r, 1 / norm, A + (size_t)rows * e + row0, 1);
    if (kept) cblas_dscal(r, 1 / norm, b, 1);
out:
    rk_quadrature_free(&Q);
    rk_quadrature_free(&Qu);
    return kept;
}

int rk_cubature_train_moving(const rk_fem *f, int r, const rk_moving_poses *P, const rk_cubature_options *o,
                             rk_cubature_set *out, rk_moving_fit *fit, rk_error *err)
{
    memset(out, 0, sizeof *out);
    memset(fit, 0, sizeof *fit);
    int n = 3 * f->nv, nt = f->nt, T = P->poses;
    if (r < 1 || T < 1 || !P->pose)
        return rk_fail(err, "cubature for a moving basis: r %d, %d poses (need at least 1 of each and a pose callback)", r, T);
    if (!(o->tolerance > 0 && o->tolerance < 1))
        return rk_fail(err, "cubature: tolerance %g must be in (0, 1)", o->tolerance);
    int nhold = T / RK_MOVING_HOLDOUT, ntrain = T - nhold, rows = r * ntrain, hrows = r * (nhold ? nhold : 1);
    double *u = rk_calloc((size_t)n, sizeof(double), err), *U = rk_calloc((size_t)n * r, sizeof(double), err);
    double *A = rk_calloc((size_t)rows * nt, sizeof(double), err), *b = rk_calloc((size_t)rows, sizeof(double), err);
    double *H = rk_calloc((size_t)hrows * nt, sizeof(double), err), *bh = rk_calloc((size_t)hrows, sizeof(double), err);
    int rc = -1, kept = 0, hkept = 0;
    if (!u || !U || !A || !b || !H || !bh) goto out;
    for (int t = 0; t < T; t++) {
        int hold = t % RK_MOVING_HOLDOUT == RK_MOVING_HOLDOUT - 1;
        int k = hold ? pose_block(f, r, P, t, u, U, H, hrows, r * hkept, bh + (size_t)r * hkept, err)
                     : pose_block(f, r, P, t, u, U, A, rows, r * kept, b + (size_t)r * kept, err);
        if (k < 0) goto out;
        *(hold ? &hkept : &kept) += k;
        rk_progress("cubature training (moving basis)", t + 1, T);
    }
    rk_progress_done("cubature training (moving basis)");
    if (!kept) {
        rk_fail(err, "cubature for a moving basis: every training pose has zero force");
        goto out;
    }
    /* the kept poses' rows: the columns' leading dimension stays `rows` */
    moving_columns C = {A, rows, f, NULL, o->vertex_cost};
    rk_cubature_problem Pr = {0};
    Pr.rows = r * kept;
    if (Pr.rows < rows) { /* compact the columns to the kept poses' rows */
        for (int e = 0; e < nt; e++) memmove(A + (size_t)Pr.rows * e, A + (size_t)rows * e, sizeof(double) * (size_t)Pr.rows);
        C.rows = Pr.rows;
    }
    Pr.candidates = nt;
    Pr.column = column;
    Pr.ctx = &C;
    Pr.b = b;
    Pr.tolerance = o->tolerance;
    Pr.max_points = o->max_points > 0 ? o->max_points : nt;
    Pr.sample = o->sample;
    Pr.seed = o->seed;
    Pr.prune = o->prune;
    if (C.vertex_cost > 0) {
        if (!(C.used = rk_calloc((size_t)f->nv, 1, err))) goto out;
        Pr.cost_begin = cost_begin;
        Pr.cost = cost;
    }
    int bad = rk_cubature_greedy(&Pr, out, err);
    free(C.used);
    if (bad) goto out;
    fit->poses = kept;
    fit->heldout_poses = hkept;
    fit->train_error = out->relative_error;
    fit->heldout_error = NAN;
    if (hkept) { /* |b_h - A_h w| / |b_h| over the held-out poses, with the fitted weights */
        int hr = r * hkept;
        double num = 0, den = 0;
        for (int i = 0; i < hr; i++) {
            double s = bh[i];
            for (int k = 0; k < out->count; k++) s -= H[(size_t)hrows * out->index[k] + i] * out->weight[k];
            num += s * s;
            den += bh[i] * bh[i];
        }
        fit->heldout_error = sqrt(num / den);
    }
    rc = 0;
out:
    free(u);
    free(U);
    free(A);
    free(b);
    free(H);
    free(bh);
    if (rc) rk_cubature_set_free(out);
    return rc;
}
