/* The incremental potential (fom_impl.h, rk_fom_terms): one evaluation of value, gradient and
 * Newton matrix shared by time steps and static solves. */
#include "fom/fom_impl.h"

#include "fem/fem.h"
#include "util/util.h"

#include <math.h>
#include <string.h>

/* Adds w/2 |x - ref|_S^2 to the energy it returns and, with g, w S (x - ref) into g. */
static double quadratic_term(const rk_sparse *S, double w, const double *x, const double *ref, double *g,
                             double *r, double *Sr, int n)
{
    for (int i = 0; i < n; i++) r[i] = x[i] - ref[i];
    if (!g) return 0.5 * w * rk_sparse_dot(S, r, r);
    rk_sparse_mul(S, r, Sr);
    double rSr = 0;
    for (int i = 0; i < n; i++) {
        rSr += r[i] * Sr[i];
        g[i] += w * Sr[i];
    }
    return 0.5 * w * rSr;
}

static void assemble_hessian(rk_fom *s, const rk_fom_terms *T, const double *x, rk_sparse *H)
{
    rk_fom_impl *im = s->impl;
    const rk_fem *f = s->fem;
    for (int k = 0; k < H->nnz; k++) {
        double a = T->w_inertia * im->M.val[k];
        if (T->w_damping > 0 && im->C.val) a += T->w_damping * im->C.val[k];
        H->val[k] = a;
    }
    if (T->reg > 0)
        for (int v = 0; v < f->nv; v++)
            for (int i = 0; i < 3; i++) H->val[rk_fem_diag_slot(H, v, i, i)] += T->reg * f->vertex_mass[v];
    double t0 = rk_now();
    rk_fem_add_hessian(f, x, 1.0, !im->exact_elastic, H);
    for (int k = 0; im->exact_elastic && k < s->opt.nchambers; k++) /* indefinite: with the exact dP/dF only */
        rk_chamber_add_stiffness(&im->chambers[k], x, T->load, H);
    s->stats.seconds_hessian += rk_now() - t0;
}

/* N.A from the elements' Hessian at y, the contact blocks recorded by the potential, the
 * moving obstacles' diagonal, the prescribed dofs eliminated. Its seconds: contact's share in
 * *contact, the symbolic analysis (when contact changed the pattern) in *analysis. */
static int newton_matrix(rk_fom *s, const rk_fom_terms *T, const double *y, double *contact, double *analysis,
                         rk_error *err)
{
    rk_fom_impl *im = s->impl;
    assemble_hessian(s, T, y, &im->H);
    int changed = 0;
    double tc = rk_now();
    int failed = rk_newton_matrix_couple(&im->N, &im->H, &changed, err);
    *contact += rk_now() - tc;
    tc = rk_now();
    if (!failed && changed) failed = rk_fom_chol_reanalyze(im, err);
    *analysis += rk_now() - tc; /* counted in seconds_analyze */
    if (failed) return -1;
    rk_newton_matrix_fill(&im->N, &im->H);
    for (int i = 0; i < 3 * im->nobs; i++) { /* the augmented Lagrangian's diagonal */
        int d = im->n + i;
        im->N.A.val[im->N.A.colptr[d + 1] - 1] += im->al_kappa * im->al_mass;
    }
    rk_fom_eliminate(s, &im->N.A);
    return 0;
}

int rk_fom_newton_matrix_projected(rk_fom *s, const rk_fom_terms *T, const double *y, rk_error *err)
{
    double t0 = rk_now(), contact = 0, analysis = 0;
    s->impl->exact_elastic = 0;
    int rc = newton_matrix(s, T, y, &contact, &analysis, err);
    s->stats.seconds_contact += contact;
    s->stats.seconds_assemble += rk_now() - t0 - contact - analysis;
    return rc;
}

/* The barrier at y: the pairs gathered here, kappa adapted at a Hessian (against ge, the rest of
 * the gradient), the blocks recorded for the Newton matrix through sink. The obstacle vertices are at
 * y[n..] when they are unknowns. cy: the contact positions at y (rk_fom_contact_x), cg: where
 * the contact stage's gradient goes (rk_fom_contact_gradient; the caller pulls it back). */
static double contact_term(rk_fom *s, const double *y, const double *cy, double *g, double *cg, int hessian,
                           rk_hessian_sink sink, void *ctx, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    rk_contact *c = &im->contact;
    if (hessian) /* a caller's evaluation without one (a line search, the adaptive oracle's) keeps the
                  * blocks of the last Hessian: rk_fom_view hands them on */
        im->N.nblocks = 0;
    if (im->nobs) memcpy(c->ox, y + im->n, sizeof(double) * 3 * (size_t)im->nobs);
    if (rk_contact_gather(c, cy, &im->pairs, err)) return NAN;
    double closest;
    double *og = !g ? NULL : im->nobs ? g + im->n : im->og;
    if (og == im->og && og) memset(og, 0, sizeof(double) * 3 * (size_t)c->onv);
    if (g && hessian && !c->kappa_set && im->pairs.n > 0) {
        /* the first contact sets kappa: measure the barrier's push at the current kappa first (in x:
         * pulled back through the embedding), against the rest of the gradient, g so far */
        memset(im->g_barrier, 0, sizeof(double) * (size_t)im->ndof);
        double *gb = im->emb.on ? im->emb.gb : im->g_barrier;
        if (im->emb.on) memset(gb, 0, sizeof(double) * 3 * (size_t)im->emb.nv);
        rk_contact_energy(c, &im->pairs, cy, gb, im->nobs ? im->g_barrier + im->n : NULL, NULL, NULL, &closest);
        rk_fom_contact_pull(im, gb, im->g_barrier);
        for (int i = 0; i < im->ndof; i++)
            if (im->prescribed_dof[i]) im->g_barrier[i] = 0;
        rk_contact_adapt_kappa(c, g, im->g_barrier, im->n, closest);
    }
    double B = rk_contact_energy(c, &im->pairs, cy, cg, og, hessian ? sink : NULL, ctx, &closest);
    if (hessian && c->kappa_set) rk_contact_adapt_kappa(c, NULL, NULL, 0, closest);
    if (im->N.overflow) {
        im->N.overflow = 0;
        rk_fail(err, "out of memory for the contact Hessian blocks");
        return NAN;
    }
    return B;
}

/* The moving obstacles' augmented Lagrangian (IPC, Sec. 4.6): k m/2 |y_o - target|^2 - lambda .
 * (y_o - target) over the vertices of moving obstacles; the Hessian's k m on the diagonal comes
 * after the fill. */
static double obstacle_term(rk_fom *s, const double *y, double *g)
{
    rk_fom_impl *im = s->impl;
    double E = 0, k = im->al_kappa * im->al_mass;
    for (int i = 0; i < 3 * im->nobs; i++) {
        if (im->prescribed_dof[im->n + i]) continue;
        double r = y[im->n + i] - im->obs_target[i];
        E += 0.5 * k * r * r - im->al_lambda[i] * r;
        if (g) g[im->n + i] += k * r - im->al_lambda[i];
    }
    return E;
}

/* The chambers' pressure work load sum_c P_c V_c(y) (pressure.c: -P V is the load's potential), and
 * with g its negative gradient, the follower forces, subtracted from g. Its stiffness joins the
 * Newton matrix with the exact dP/dF only (assemble_hessian; pressure.c says why). */
static double chamber_work(rk_fom *s, double load, const double *y, double *g)
{
    double W = 0;
    for (int k = 0; k < s->opt.nchambers; k++) {
        const rk_chamber *c = &s->impl->chambers[k];
        W += load * c->pressure * rk_chamber_volume(c, y);
        if (g) rk_chamber_force(c, y, -load, g);
    }
    return W;
}

double rk_fom_potential(rk_fom *s, const rk_fom_terms *T, const double *y, double *g, int hessian,
                        double *magnitude, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    const rk_fem *f = s->fem;
    int n = im->n;
    double t0 = rk_now(), tc, contact = 0, analysis = 0; /* contact: seconds in the contact stage's terms */
    if (hessian) rk_fom_iteration_start(im, t0);
    if (g) memset(g, 0, (size_t)im->ndof * sizeof(double));
    double stored = T->no_elastic ? 0 : rk_fem_energy(f, y); /* Psi */
    double work = 0;
    for (int i = 0; i < n; i++) work += im->f_ext[i] * y[i];
    work *= T->load;
    double quad = 0; /* inertia and damping, both >= 0 */
    if (T->w_inertia > 0) quad += quadratic_term(&im->M, T->w_inertia, y, T->xtilde, g, im->work, im->work2, n);
    if (T->w_damping > 0 && im->C.val)
        quad += quadratic_term(&im->C, T->w_damping, y, T->xt, g, im->work, im->work2, n);
    if (g && isfinite(stored)) {
        if (!T->no_elastic) rk_fem_add_gradient(f, y, 1.0, g);
        for (int i = 0; i < n; i++) g[i] -= T->load * im->f_ext[i];
    }
    if (isfinite(stored)) work += chamber_work(s, T->load, y, g);
    if (im->nobs) stored += obstacle_term(s, y, g);
    tc = rk_now();
    if (im->has_contact && isfinite(stored)) { /* on the contact positions (contact_view.c), pulled back */
        const double *cy = rk_fom_contact_x(im, y);
        double *cg = rk_fom_contact_gradient(im, g);
        void *ctx; /* where the barrier's and friction's Hessian blocks go (pulled back when embedded) */
        rk_hessian_sink sink = rk_fom_contact_sink(im, &ctx);
        stored += contact_term(s, y, cy, g, cg, hessian, sink, ctx, err);
        if (T->friction && isfinite(stored))
            stored += rk_contact_friction_energy(&im->contact, cy, s->opt.h, cg, !g ? NULL : im->nobs ? g + n : im->og,
                                                 hessian ? sink : NULL, ctx);
        rk_fom_contact_pull(im, cg, g);
    }
    contact += rk_now() - tc;
    double E = stored - work + quad;
    if (magnitude) *magnitude = fabs(stored) + fabs(work) + quad;
    if (hessian == RK_FOM_NEWTON_MATRIX && isfinite(E) && newton_matrix(s, T, y, &contact, &analysis, err)) E = NAN;
    double dt = rk_now() - t0;
    s->stats.seconds_contact += contact;
    if (g) s->stats.seconds_assemble += dt - contact - analysis;
    else s->stats.seconds_line_search += dt - contact - analysis;
    return isfinite(E) ? E : INFINITY;
}

void rk_fom_obstacle_targets(rk_fom *s, double t)
{
    rk_fom_impl *im = s->impl;
    if (!im->nobs) return;
    rk_contact_obstacles_at(&im->contact, t, im->obs_target);
    memset(im->al_lambda, 0, sizeof(double) * 3 * (size_t)im->nobs);
    im->al_kappa = RK_FOM_AL_KAPPA / (s->opt.h * s->opt.h);
}

void rk_fom_view_get(const rk_fom *s, rk_fom_view *v)
{
    const rk_fom_impl *im = s->impl;
    *v = (rk_fom_view){.n = im->n, .nobs = im->nobs, .M = &im->M, .C = &im->C, .f_ext = im->f_ext,
                       .prescribed = im->prescribed_dof, .has_contact = im->has_contact,
                       .nblocks = im->N.nblocks, .blocks = im->N.blocks,
                       .contact = im->has_contact ? (rk_contact *)&im->contact : NULL, .og = im->og};
}

double rk_fom_max_step(rk_fom *s, const double *x, const double *d, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    if (!im->has_contact) return 1;
    double t0 = rk_now();
    double alpha = rk_fom_contact_ccd(im, x, d, NULL, err);
    s->stats.seconds_contact += rk_now() - t0;
    return alpha;
}

void rk_fom_contact_sandwich(const rk_fom_view *v, int n, int a, const double *A, double *work, double *out)
{
    double *R = work; /* the block's rows of A: 3 np x a */
    for (int b = 0; b < v->nblocks; b++) {
        const rk_contact_block *blk = &v->blocks[b];
        int m = 3 * blk->np;
        for (int j = 0; j < a; j++)
            for (int p = 0; p < blk->np; p++)
                for (int k = 0; k < 3; k++) /* an obstacle's point (id < 0) does not move with the subspace */
                    R[(size_t)j * m + 3 * p + k] = blk->id[p] >= 0 ? A[(size_t)j * n + 3 * blk->id[p] + k] : 0;
        double HR[12];
        for (int j = 0; j < a; j++) {
            for (int r = 0; r < m; r++) {
                double s = 0;
                for (int c = 0; c < m; c++) s += blk->H[r * m + c] * R[(size_t)j * m + c];
                HR[r] = s;
            }
            for (int i = 0; i < a; i++) {
                double s = 0;
                for (int r = 0; r < m; r++) s += R[(size_t)i * m + r] * HR[r];
                out[(size_t)j * a + i] += s;
            }
        }
    }
}
