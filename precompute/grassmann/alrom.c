/* The adaptive linear ROM simulator (grassmann.h; the paper's Algorithms 1-4): each step's basis
 * from the decoder and the history, then the full-order step (fom.h) minimised over u(t-1) +
 * U_interp q by the solver's Newton with the reduced gradient U^T g and Hessian U^T H U (Eq. 11-12). */
#include "grassmann/grassmann_impl.h"

#include "fem/fem.h"

#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

struct rk_alrom_impl {
    const rk_fem *f;
    const rk_decoder *dec;
    int n, r, m;
    int count, head;        /* history entries held, the next slot */
    double *D, *P;          /* n x m, r x m: displacements and latent codes, a ring */
    double *u, *p, *U, *Phi, *Ui, *HU, *Hq, *L, *gq, *dq; /* n, r, n r, n r, n r, n r, r r, r r, r, r */
    double *Dc, *Pc;        /* the ring in time order (n x count, r x count) */
    double *UMU, *UCU;      /* r x r: the step basis' inertia and damping (cubature) */
    int inertia_valid;
    int first_solve;        /* the step's first Newton solve: it starts from u(t-1) (Algorithm 2) */
    int since;              /* steps taken in the held basis since it was formed; -1: form it next */
    double *newton_work;
    const char *prescribed;
    rk_error failure;
};

void rk_alrom_default_options(rk_alrom_options *o)
{
    /* ridge and budget: issue 33 (history.c, history_ridge); 0 and 0 are the paper's step */
    *o = (rk_alrom_options){.history = 20, .lambda = 0.2, .reg = 1e-8, .ridge = 0.01, .budget = 0.01,
                             .cadence = 1, .encoder_iterations = 20};
}

void rk_alrom_free(rk_alrom *s)
{
    rk_alrom_impl *im = s->impl;
    if (im) {
        void *arrays[] = {im->D, im->P, im->u, im->p, im->U, im->Phi, im->Ui, im->HU, im->Hq, im->L, im->gq, im->dq,
                          im->Dc, im->Pc, im->newton_work, im->UMU, im->UCU};
        for (size_t k = 0; k < sizeof arrays / sizeof *arrays; k++) free(arrays[k]);
        free(im);
    }
    rk_fom_free(&s->fom);
    memset(s, 0, sizeof *s);
}

int rk_alrom_init(rk_alrom *s, const rk_fem *fem, const rk_fom_options *fo, const rk_decoder *dec,
                  const rk_alrom_options *o, rk_error *err)
{
    memset(s, 0, sizeof *s);
    if (o->history < 1) return rk_fail(err, "history (m) must be at least 1, got %d", o->history);
    if (!(o->lambda >= 0 && o->lambda <= 1)) return rk_fail(err, "lambda must be in [0, 1], got %g", o->lambda);
    if (!(o->reg >= 0)) return rk_fail(err, "the history's regularisation must be >= 0, got %g", o->reg);
    if (!(o->ridge >= 0)) return rk_fail(err, "the history's ridge must be >= 0, got %g", o->ridge);
    if (!(o->budget >= 0)) return rk_fail(err, "the history's growth budget must be >= 0, got %g", o->budget);
    if (o->cadence < 1) return rk_fail(err, "the basis cadence (K) must be at least 1 step, got %d", o->cadence);
    if (o->ncub < 0 || (o->ncub > 0 && (!o->cub_element || !o->cub_weight)))
        return rk_fail(err, "a cubature needs its elements and weights (%d given)", o->ncub);
    for (int k = 0; k < o->ncub; k++)
        if (o->cub_element[k] < 0 || o->cub_element[k] >= fem->nt || !(o->cub_weight[k] > 0))
            return rk_fail(err, "cubature point %d: element %d of %d, weight %g", k, o->cub_element[k], fem->nt,
                           o->cub_weight[k]);
    if (o->ncub > 0 && dec->r > 64) return rk_fail(err, "a cubature handles r up to 64, got %d", dec->r);
    if (dec->n != 3 * fem->nv || dec->r < 1)
        return rk_fail(err, "the decoder maps %d latent coordinates to %d dofs; the mesh has %d", dec->r, dec->n,
                       3 * fem->nv);
    if (fo->is_static) return rk_fail(err, "simulates dynamics only (the scene asks for a static solve)");
    if (fo->contact_surface) /* its contact blocks are read at x (rk_fom_contact_sandwich) */
        return rk_fail(err, "a contact surface embedded in the elements (a point cloud's at full order) is not "
                            "supported: give the objects as tet meshes");
    s->opt = *o;
    if (rk_fom_init(&s->fom, fem, fo, err)) return -1;
    rk_alrom_impl *im = rk_calloc(1, sizeof *im, err);
    if (!im) {
        rk_alrom_free(s);
        return -1;
    }
    s->impl = im;
    im->since = -1;
    im->f = fem;
    im->dec = dec;
    im->n = dec->n;
    im->r = dec->r;
    im->m = o->history;
    size_t n = (size_t)im->n, r = (size_t)im->r, m = (size_t)im->m;
    im->D = malloc(sizeof(double) * n * m);
    im->P = malloc(sizeof(double) * r * m);
    im->Dc = malloc(sizeof(double) * n * m);
    im->Pc = malloc(sizeof(double) * r * m);
    im->u = malloc(sizeof(double) * n);
    im->p = malloc(sizeof(double) * r);
    im->U = malloc(sizeof(double) * n * r);
    im->Phi = malloc(sizeof(double) * n * r);
    im->Ui = malloc(sizeof(double) * n * r);
    im->HU = malloc(sizeof(double) * n * r);
    im->Hq = malloc(sizeof(double) * r * r);
    im->L = malloc(sizeof(double) * r * r);
    im->gq = malloc(sizeof(double) * r);
    im->dq = malloc(sizeof(double) * r);
    im->newton_work = malloc(sizeof(double) * RK_NEWTON_WORK(n));
    im->UMU = malloc(sizeof(double) * r * r);
    im->UCU = malloc(sizeof(double) * r * r);
    if (!im->D || !im->P || !im->Dc || !im->Pc || !im->u || !im->p || !im->U || !im->Phi || !im->Ui || !im->HU ||
        !im->Hq || !im->L || !im->gq || !im->dq || !im->newton_work || !im->UMU || !im->UCU) {
        rk_alrom_free(s);
        return rk_fail(err, "out of memory for the adaptive linear ROM (%zu dofs, r %zu, m %zu)", n, r, m);
    }
    rk_fom_view view;
    rk_fom_view_get(&s->fom, &view);
    if (view.nobs) {
        rk_alrom_free(s);
        return rk_fail(err, "moving obstacles are not supported (they are unknowns of the full-order solve)");
    }
    im->prescribed = view.prescribed;
    return 0;
}

/* ---- the step's basis (Algorithm 3, lines 3-6) ---- */

static void zero_prescribed_rows(const rk_alrom_impl *im, double *A)
{
    for (int j = 0; j < im->r; j++)
        for (int i = 0; i < im->n; i++)
            if (im->prescribed[i]) A[(size_t)j * im->n + i] = 0;
}

/* The history's ridge toward the decoder's basis (history.c), in units of tr(P P^T): at least
 * opt.ridge, and at least h |v| |u| / (budget sum_k |u_k|^2) over the free dofs, u the newest of
 * the history's displacements u_k. Why (issue 33): the history basis follows its displacements,
 * so a perturbation e of the newest one that lies outside the basis (one the step itself never
 * damps: it keeps it as it is) turns the basis toward it by about e |u| / sum_k |u_k|^2 (Eq. 13 of
 * a history along one direction), and the step, of about h |v|, carries it on by that times h |v|
 * times the history's share in the basis, at most 1 / (1 + ridge): so the history adds about
 * `budget` to a step's growth factor at most, and is trusted more where the motion is slow against
 * the history's size. At rest, -1: the decoder's basis alone. */
static double history_ridge(const rk_alrom *s, const double *u)
{
    const rk_alrom_impl *im = s->impl;
    double uu = 0, vv = 0, dd = 0;
    for (int i = 0; i < im->n; i++)
        if (!im->prescribed[i]) {
            uu += u[i] * u[i], vv += s->fom.v[i] * s->fom.v[i];
            for (int k = 0; k < im->count; k++) dd += im->Dc[(size_t)k * im->n + i] * im->Dc[(size_t)k * im->n + i];
        }
    if (!(dd > 0)) return -1;
    if (!(s->opt.budget > 0)) return s->opt.ridge;
    return fmax(s->opt.ridge, s->fom.opt.h * sqrt(vv * uu) / (s->opt.budget * dd));
}

static int step_basis(rk_alrom *s, rk_error *err)
{
    rk_alrom_impl *im = s->impl;
    const rk_decoder *dec = im->dec;
    int n = im->n, r = im->r;
    for (int i = 0; i < n; i++) im->u[i] = s->fom.x[i] - im->f->X[i];
    if (dec->encode(dec->ctx, im->u, im->p, err) || dec->jacobian(dec->ctx, im->p, im->U, err))
        return rk_error_prefix(err, "the decoder at step %ld", s->stats.steps + 1);
    zero_prescribed_rows(im, im->U);
    /* the history ring: this step's start and its latent code */
    memcpy(im->D + (size_t)im->head * n, im->u, sizeof(double) * (size_t)n);
    memcpy(im->P + (size_t)im->head * r, im->p, sizeof(double) * (size_t)r);
    im->head = (im->head + 1) % im->m;
    if (im->count < im->m) im->count++;
    for (int k = 0; k < im->count; k++) { /* oldest first */
        int slot = (im->head - im->count + k + im->m) % im->m;
        memcpy(im->Dc + (size_t)k * n, im->D + (size_t)slot * n, sizeof(double) * (size_t)n);
        memcpy(im->Pc + (size_t)k * r, im->P + (size_t)slot * r, sizeof(double) * (size_t)r);
    }
    /* Phi, then the geodesic from span(Phi) to span(U); while the history spans fewer than r
     * directions (at rest it is all zero) the decoder's basis alone */
    rk_error quiet;
    double ridge = history_ridge(s, im->u);
    /* a history of one state is no motion yet (and at rest there is none) */
    int blended = im->count >= 2 && ridge >= 0 && !rk_history_basis(n, r, im->count, im->Dc, im->Pc, im->U, ridge, s->opt.reg, im->Phi, &quiet);
    if (blended) {
        zero_prescribed_rows(im, im->Phi);
        blended = !rk_grassmann_interpolate(n, r, im->Phi, im->U, s->opt.lambda, im->Ui, &quiet);
    }
    if (!blended && rk_thin_q(n, r, im->U, im->Ui, "the decoder's basis", err))
        return rk_error_prefix(err, "step %ld", s->stats.steps + 1);
    s->stats.history_used += blended;
    im->inertia_valid = 0; /* a new basis */
    return 0;
}

/* ---- Newton on q (Algorithm 2) ---- */

typedef struct {
    rk_alrom *s;
    const rk_fom_terms *T;
} newton_ctx;

/* The cubature's elastic energy at x; with g, its gradient added; with H (r x r), its reduced
 * Hessian sum_k w_k U_e^T H_e U_e added. */
static double cubature_terms(rk_alrom *s, const double *x, double *g, double *H)
{
    rk_alrom_impl *im = s->impl;
    const rk_fem *f = im->f;
    const rk_alrom_options *o = &s->opt;
    int n = im->n, r = im->r;
    double E = 0;
    for (int k = 0; k < o->ncub; k++) {
        int t = o->cub_element[k];
        double w = o->cub_weight[k], xe[12];
        const int *v = &f->tets[4 * t];
        rk_fem_gather(f, t, x, xe);
        E += w * rk_tet_energy(f->model[t], f->mu[t], f->lambda[t], xe, &f->Dm_inv[9 * t], f->vol[t]);
        if (g) {
            double ge[12] = {0};
            rk_tet_gradient(f->model[t], f->mu[t], f->lambda[t], xe, &f->Dm_inv[9 * t], f->vol[t], ge);
            rk_fem_scatter_vector(f, t, ge, w, g);
        }
        if (H) {
            double He[144], Ue[12 * 64], HU[12 * 64];
            rk_tet_hessian(f->model[t], f->mu[t], f->lambda[t], xe, &f->Dm_inv[9 * t], f->vol[t], He, 1);
            for (int j = 0; j < r; j++)
                for (int a = 0; a < 4; a++)
                    for (int b = 0; b < 3; b++) Ue[12 * j + 3 * a + b] = im->Ui[(size_t)j * n + 3 * v[a] + b];
            for (int j = 0; j < r; j++)
                for (int p = 0; p < 12; p++) {
                    double acc = 0;
                    for (int q = 0; q < 12; q++) acc += He[12 * p + q] * Ue[12 * j + q];
                    HU[12 * j + p] = acc;
                }
            for (int j = 0; j < r; j++)
                for (int i = 0; i < r; i++) {
                    double acc = 0;
                    for (int p = 0; p < 12; p++) acc += Ue[12 * i + p] * HU[12 * j + p];
                    H[(size_t)j * r + i] += w * acc;
                }
        }
    }
    return isfinite(E) ? E : INFINITY;
}

/* U^T A U for A upper-stored on the fem pattern (the inertia and damping: constant in a step). */
static void sandwich(rk_alrom_impl *im, const rk_sparse *A, double *out)
{
    int n = im->n, r = im->r;
    for (int k = 0; k < r; k++) rk_sparse_mul(A, im->Ui + (size_t)k * n, im->HU + (size_t)k * n);
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, r, r, n, 1.0, im->Ui, n, im->HU, n, 0.0, out, r);
}

static double energy_cubature(newton_ctx *c, const double *x, double *g, int hessian, double *magnitude)
{
    rk_alrom *s = c->s;
    rk_alrom_impl *im = s->impl;
    int r = im->r;
    rk_fom_terms rest = *c->T;
    rest.no_elastic = 1;
    double E = rk_fom_potential(&s->fom, &rest, x, g, hessian ? RK_FOM_CONTACT_BLOCKS : RK_FOM_NO_HESSIAN, magnitude,
                                &im->failure);
    if (!isfinite(E)) return E;
    if (hessian) { /* inertia and damping exactly, in this step's basis */
        rk_fom_view view;
        rk_fom_view_get(&s->fom, &view);
        if (!im->inertia_valid) {
            sandwich(im, view.M, im->UMU);
            if (view.C->val) sandwich(im, view.C, im->UCU);
            else memset(im->UCU, 0, sizeof(double) * (size_t)r * r);
            im->inertia_valid = 1;
        }
        for (int k = 0; k < r * r; k++) im->Hq[k] = c->T->w_inertia * im->UMU[k] + c->T->w_damping * im->UCU[k];
        rk_fom_contact_sandwich(&view, im->n, r, im->Ui, im->HU, im->Hq); /* HU: scratch here */
    }
    double psi = cubature_terms(s, x, g, hessian ? im->Hq : NULL);
    if (magnitude) *magnitude += fabs(psi);
    return E + psi;
}

static double energy(void *ctx, const double *x, double *g, int hessian, double *magnitude)
{
    newton_ctx *c = ctx;
    rk_alrom *s = c->s;
    rk_alrom_impl *im = s->impl;
    if (s->opt.ncub > 0) return energy_cubature(c, x, g, hessian, magnitude);
    double E = rk_fom_potential(&s->fom, c->T, x, g, hessian ? RK_FOM_NEWTON_MATRIX : RK_FOM_NO_HESSIAN, magnitude,
                                &im->failure);
    if (!hessian || !isfinite(E)) return E;
    sandwich(im, rk_fom_newton_matrix(&s->fom), im->Hq); /* Eq. 12, the prescribed dofs eliminated */
    return E;
}

static int solve(void *ctx, const double *g, double *d, rk_error *err)
{
    newton_ctx *c = ctx;
    rk_alrom_impl *im = c->s->impl;
    int n = im->n, r = im->r;
    cblas_dgemv(CblasColMajor, CblasTrans, n, r, -1.0, im->Ui, n, g, 1, 0.0, im->gq, 1); /* Eq. 11 */
    if (rk_spd_solve_shifted(r, im->Hq, im->L, im->gq, im->dq, 6))
        return rk_fail(err, "the reduced Hessian U^T H U (%d x %d) is not positive definite", r, r);
    cblas_dgemv(CblasColMajor, CblasNoTrans, n, r, 1.0, im->Ui, n, im->dq, 1, 0.0, d, 1);
    return 0;
}

static double max_step(void *ctx, const double *x, const double *d)
{
    newton_ctx *c = ctx;
    double a = rk_fom_max_step(&c->s->fom, x, d, &c->s->impl->failure);
    return a >= 0 ? a : 0;
}

static int newton(void *ctx, rk_fom *fom, const rk_fom_terms *T, double tol_d, int *converged, rk_error *err)
{
    rk_alrom *s = ctx;
    rk_alrom_impl *im = s->impl;
    newton_ctx c = {s, T};
    rk_fom_view view;
    rk_fom_view_get(fom, &view);
    rk_newton_problem p = {.n = im->n, .ctx = &c, .what = "incremental potential (adaptive linear ROM)",
                           .energy = energy, .solve = solve, .max_step = view.has_contact ? max_step : NULL,
                           .prescribed = im->prescribed};
    rk_newton_stats stats = {0};
    im->failure.msg[0] = 0;
    /* Algorithm 2: u_k = u(t-1) + U q_k from q_0 = 0, so the free dofs start where the step did (the
     * full-order step starts them at its predictor x_t + h v_t, which lies outside the subspace
     * and would carry into the solution motion the basis cannot express); the prescribed ones are
     * at their targets */
    if (im->first_solve)
        for (int i = 0; i < im->n; i++)
            if (!im->prescribed[i]) fom->x[i] = T->xt[i];
    im->first_solve = 0;
    int rc = rk_newton_solve(&p, fom->x, tol_d, rk_fom_max_iter(&fom->opt, 1), im->newton_work, converged, &stats, err);
    s->stats.newton_iterations += stats.iterations;
    fom->stats.newton_iterations += stats.iterations;
    if (im->failure.msg[0]) {
        *err = im->failure;
        return -1;
    }
    return rc;
}

int rk_alrom_step(rk_alrom *s, rk_error *err)
{
    double t0 = rk_now();
    int blas = rk_threads_blas(1); /* small dense products: the same sums on any thread count */
    /* the basis every K steps, held between (the runtime's cadence, runtime/alrom.c: the history's
     * entries are then K steps apart); a held basis keeps its inertia terms */
    int refresh = s->impl->since < 0 || s->impl->since >= s->opt.cadence, rc = refresh ? step_basis(s, err) : 0;
    if (refresh && !rc) s->impl->since = 0;
    s->stats.seconds_basis += rk_now() - t0;
    s->impl->first_solve = 1;
    if (!rc) rc = rk_fom_step_with(&s->fom, newton, s, err);
    rk_threads_blas(blas);
    if (rc) {
        s->impl->since = -1;
        return -1;
    }
    s->impl->since++;
    s->stats.steps++;
    s->stats.seconds_total += rk_now() - t0;
    return 0;
}

const double *rk_alrom_step_basis(const rk_alrom *s)
{
    return s->impl && s->stats.steps > 0 ? s->impl->Ui : NULL;
}

void rk_alrom_set_state(rk_alrom *s, const double *x, const double *v, const double *x_prev, const double *v_prev,
                        double t)
{
    rk_fom_set_state(&s->fom, x, v, x_prev, v_prev, t);
    s->impl->since = -1; /* a basis for the state set */
}

void rk_alrom_copy_state(rk_alrom *dst, const rk_alrom *src)
{
    rk_alrom_impl *d = dst->impl;
    const rk_alrom_impl *s = src->impl;
    rk_fom_set_state(&dst->fom, src->fom.x, src->fom.v, NULL, NULL, src->fom.t);
    memcpy(d->D, s->D, sizeof(double) * (size_t)s->n * s->m);
    memcpy(d->P, s->P, sizeof(double) * (size_t)s->r * s->m);
    d->count = s->count;
    d->head = s->head;
    d->since = -1; /* (the held basis is not copied: dst forms its own next step) */
    dst->stats.steps = src->stats.steps;
}
