/* The adaptive subspace simulator (adaptive.h): set-up, and each time step's minimisation as the
 * solver's projected Newton (solver.h) whose direction comes from the running reduced model
 * (Algorithm 1): at each iteration the potential and gradient in full space, the subspace
 * Hessian, the oracle's updates, the Schur-complement solve; then the shared line search (CCD
 * filtered) and termination on |d|_inf / h. Downdating follows the step. */
#include "adaptive/adaptive_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void rk_adaptive_default_options(rk_adaptive_options *o)
{
    *o = (rk_adaptive_options){.block = 12, .initial_blocks = 1, .eps_g_modal = 1, .eps_g_nodal = 1,
                               .eps_e = 1, .eps_d = 0.1, .subdomains = 0, .downdate = 1, .modal = 1,
                               .nodal = 1, .exact_hessian = 0, .pcg_tol = 1e-5, .pcg_max_iter = 10000,
                               .residual = 1, .residual_rounds = 8, .accuracy = 1e-3,
                               .full_fraction = 0.25};
}

static int check_options(const rk_adaptive_options *o, const rk_fem *f, int r, rk_error *err)
{
    if (!(o->eps_g_modal > 0) || !isfinite(o->eps_g_modal))
        return rk_fail(err, "eps_g_modal (the modal error threshold) must be positive, got %g", o->eps_g_modal);
    if (!(o->eps_g_nodal > 0) || !isfinite(o->eps_g_nodal))
        return rk_fail(err, "eps_g_nodal (the nodal error threshold) must be positive, got %g", o->eps_g_nodal);
    if (!isfinite(o->eps_e)) return rk_fail(err, "eps_e (the progress threshold) must be finite, got %g", o->eps_e);
    if (!(o->eps_d > 0) || !isfinite(o->eps_d))
        return rk_fail(err, "eps_d (the downdating threshold) must be positive, got %g", o->eps_d);
    if (!(o->pcg_tol > 0 && o->pcg_tol < 1)) return rk_fail(err, "pcg_tol must be in (0, 1), got %g", o->pcg_tol);
    if (o->pcg_max_iter < 1) return rk_fail(err, "pcg_max_iter must be at least 1, got %d", o->pcg_max_iter);
    if (o->block < 1) return rk_fail(err, "block (columns per candidate) must be at least 1, got %d", o->block);
    if (r < o->block || r % o->block)
        return rk_fail(err, "the candidate basis has %d columns, not a whole number of blocks of %d", r, o->block);
    if (o->initial_blocks < 1 || o->initial_blocks * o->block > r)
        return rk_fail(err, "initial_blocks must be from 1 to %d (the candidate blocks), got %d", r / o->block,
                       o->initial_blocks);
    if (f->nt == 0) return rk_fail(err, "needs a tetrahedral mesh (a point cloud has no elements to enrich)");
    if (!(o->accuracy >= 0) || !isfinite(o->accuracy))
        return rk_fail(err, "accuracy (the target error over the bounding-box diagonal) must be 0 or positive, got %g",
                       o->accuracy);
    if (!(o->full_fraction > 0 && o->full_fraction <= 1))
        return rk_fail(err, "full_fraction (the enriched share at which full order finishes a step) must be in (0, 1], "
                       "got %g", o->full_fraction);
    if (o->residual_rounds < 0) return rk_fail(err, "residual_rounds must be at least 0, got %d", o->residual_rounds);
    if (o->subdomains < 0 || o->subdomains > f->nv)
        return rk_fail(err, "subdomains must be from 1 to the %d vertices, got %d", f->nv, o->subdomains);
    return 0;
}

#define ALLOC(p, count) (((p) = rk_calloc((size_t)(count) + 1, sizeof *(p), err)) == NULL)

static int alloc_impl(rk_adaptive_impl *im, int nt, rk_error *err)
{
    size_t n = (size_t)im->n, nv = (size_t)im->nv, r = (size_t)im->r;
    size_t work = n > 12 * r ? n : 12 * r;
    if (ALLOC(im->psi_bar, nv) || ALLOC(im->area, nv) || ALLOC(im->volume, nv) || ALLOC(im->G, nv) || ALLOC(im->gscale, nv) || ALLOC(im->prog, nv) || ALLOC(im->solved_enriched, nv) || ALLOC(im->pscale, nv) || ALLOC(im->gpsi, nv) ||
        ALLOC(im->dE, nv) || ALLOC(im->e0, nv) || ALLOC(im->e1, nv) || ALLOC(im->block_on, im->nblocks) ||
        ALLOC(im->cols, r) || ALLOC(im->enriched, nv) || ALLOC(im->xdof, n) || ALLOC(im->xindex, n) ||
        ALLOC(im->q_total, r) || ALLOC(im->elem_exact, nt) || ALLOC(im->He, (size_t)nt * RK_TET_SLOTS) ||
        ALLOC(im->coup_pos, n) || ALLOC(im->block_size, n) || ALLOC(im->part_mark_dofs, n) ||
        ALLOC(im->Dinv, 9 * n) || ALLOC(im->dx, n) || ALLOC(im->rhs, n) || ALLOC(im->work, work) ||
        ALLOC(im->pcg_work, 4 * n) || ALLOC(im->xtry, n) || ALLOC(im->sc_a, r) || ALLOC(im->sc1, n) ||
        ALLOC(im->sc2, n) || ALLOC(im->sc3, n) || ALLOC(im->sc4, n) || ALLOC(im->elem_e, nt) ||
        ALLOC(im->fixed_vertex, nv) || ALLOC(im->elem_psi, nt) || ALLOC(im->elem_g, 12 * (size_t)nt) || ALLOC(im->g, n) || ALLOC(im->x_prev, n) || ALLOC(im->d_last, n) ||
        ALLOC(im->newton_work, RK_NEWTON_WORK(n + 1)) || ALLOC(im->x_moved, n) || ALLOC(im->y, n + 1) ||
        ALLOC(im->prescribed_y, n + 1) || ALLOC(im->hxs, n) || ALLOC(im->sx, n) || ALLOC(im->dq_b, r) || ALLOC(im->x_start, n) ||
        ALLOC(im->hss, 1))
        return -1;
    im->kcap = 1;
    return 0;
}

/* M and C (upper-stored on the fem pattern) on the full pattern. */
static int full_values(rk_adaptive_impl *im, const rk_sparse *S, double **out, rk_error *err)
{
    if (!S->val) {
        *out = NULL;
        return 0;
    }
    if (S->nnz != im->f->pattern.nnz) return rk_fail(err, "the mass matrix is not on the mesh's pattern");
    if (ALLOC(*out, im->P.nnz)) return -1;
    for (int k = 0; k < S->nnz; k++) {
        (*out)[im->P.up[k]] = S->val[k];
        (*out)[im->P.lo[k]] = S->val[k];
    }
    return 0;
}

int rk_adaptive_init(rk_adaptive *ad, const rk_fem *fem, const rk_fom_options *fo, const double *U, int r,
                     const rk_adaptive_options *o, rk_error *err)
{
    memset(ad, 0, sizeof *ad);
    if (check_options(o, fem, r, err)) return -1;
    if (fo->is_static) return rk_fail(err, "simulates dynamics only (the scene asks for a static solve)");
    if (fo->contact_surface) /* its contact reads fom's contact model at x (energy.c, system.c, obstacles.c) */
        return rk_fail(err, "a contact surface embedded in the elements (a point cloud's at full order) is not "
                            "supported: give the objects as tet meshes");
    ad->opt = *o;
    /* moving obstacles go by their progress s, an unknown of this solver (obstacles.c) */
    rk_fom_options fom_opt = *fo;
    fom_opt.obstacle_progress = 1;
    for (int k = 0; k < fo->nobstacles; k++)
        if (fo->obstacles[k].kind == RK_OBSTACLE_PLANE && fo->obstacles[k].motion != RK_MOTION_FIXED)
            return rk_fail(err, "obstacle %d: a moving plane is not supported (a plane has no vertices to move "
                                "by their progress; make it a box)", k);
    if (rk_fom_init(&ad->fom, fem, &fom_opt, err)) return -1;
    rk_adaptive_impl *im = rk_calloc(1, sizeof *im, err);
    if (!im) goto fail;
    ad->impl = im;
    im->f = fem;
    im->nv = fem->nv;
    im->n = 3 * fem->nv;
    im->r = r;
    im->nblocks = r / o->block;
    rk_fom_view_get(&ad->fom, &im->view);
    if (alloc_impl(im, fem->nt, err) || ALLOC(im->U, (size_t)im->n * r)) goto fail;
    for (size_t k = 0; k < (size_t)im->n * r; k++) {
        if (!isfinite(U[k])) {
            rk_fail(err, "the candidate basis has a non-finite entry (row %zu, column %zu)", k % im->n, k / im->n);
            goto fail;
        }
        im->U[k] = im->view.prescribed[k % im->n] ? 0 : U[k];
    }
    memcpy(im->prescribed_y, im->view.prescribed, (size_t)im->n);
    for (int v = 0; v < im->nv; v++) im->mass += fem->vertex_mass[v];
    for (int v = 0; v < im->nv; v++) {
        im->fixed_vertex[v] =
            (char)(im->view.prescribed[3 * v] && im->view.prescribed[3 * v + 1] && im->view.prescribed[3 * v + 2]);
        im->free_vertices += !im->fixed_vertex[v];
    }
    rk_adaptive_vertex_scales(fem, im->psi_bar, im->area, im->volume);
    im->length = rk_points_diagonal(fem->X, im->nv);
    ad->tolerance = rk_adaptive_own_tolerance(o->accuracy, im->length, ad->fom.opt.h, fo->steps, ad->fom.opt.newton_tol);
    if (o->paper_units) {
        memcpy(im->gscale, im->area, sizeof(double) * (size_t)im->nv);
        memcpy(im->gpsi, im->psi_bar, sizeof(double) * (size_t)im->nv);
        memcpy(im->pscale, im->volume, sizeof(double) * (size_t)im->nv);
    } else {
        rk_adaptive_tolerance_scale(fem, ad->fom.opt.h, ad->tolerance, im->gscale, im->pscale);
        for (int v = 0; v < im->nv; v++) im->gpsi[v] = 1;
    }
    int parts = o->subdomains ? o->subdomains : fem->nt / 250;
    if (parts < 2) parts = 2;
    if (parts > im->nv) parts = im->nv;
    ad->opt.subdomains = parts;
    if (ALLOC(im->part_mark, parts) || rk_adaptive_partition(im, parts, err) ||
        rk_full_pattern_init(&im->P, &fem->pattern, err) || full_values(im, im->view.M, &im->Mf, err) ||
        full_values(im, im->view.C, &im->Cf, err) || ALLOC(im->Hf, im->P.nnz))
        goto fail;
    for (int b = 0; b < o->initial_blocks; b++) im->block_on[b] = 1;
    ad->enriched = im->enriched;
    if (rk_adaptive_set_columns(ad, err)) goto fail;
    return 0;
fail:
    rk_adaptive_free(ad);
    return -1;
}

void rk_adaptive_free(rk_adaptive *ad)
{
    rk_adaptive_impl *im = ad->impl;
    if (im) {
        rk_adaptive_partition_free(im);
        rk_full_pattern_free(&im->P);
        rk_contact_set_free(&im->pairs);
        void *arrays[] = {im->U, im->prog, im->solved_enriched, im->gscale, im->pscale, im->gpsi, im->psi_bar, im->area, im->volume, im->G, im->dE, im->e0, im->e1, im->block_on,
                          im->cols, im->Ua, im->Ba, im->enriched, im->xdof, im->xindex, im->q_total, im->Mf,
                          im->Cf, im->Hf, im->UMU, im->UCU, im->BMB, im->BCB, im->Ha, im->Hq, im->Lq,
                          im->elem_exact, im->He, im->hx_rowptr, im->hx_col, im->hx_val, im->coup_dof, im->Cq, im->c_part,
                          im->Dinv, im->coup_pos, im->block_size, im->part_mark_dofs, im->gq, im->dq, im->dx,
                          im->rhs, im->work, im->pcg_work, im->xtry, im->sc_a, im->sc1, im->sc2, im->sc3,
                          im->sc4, im->elem_e, im->part_mark, im->fixed_vertex, im->g, im->x_prev, im->d_last,
                          im->dq_last, im->newton_work, im->x_moved, im->elem_psi, im->elem_g, im->MU, im->CU, im->ctri_r, im->ctri_v,
                          im->y, im->prescribed_y, im->hxs, im->sx, im->dq_b, im->hss, im->x_start};
        for (size_t k = 0; k < sizeof arrays / sizeof *arrays; k++) free(arrays[k]);
        free(im);
    }
    rk_fom_free(&ad->fom);
    memset(ad, 0, sizeof *ad);
}

/* ---- the Newton iterations of a step ---- */

typedef struct {
    rk_adaptive *ad;
    const rk_fom_terms *T;
    rk_error failure;
} newton_ctx;

/* What the last line search did: x moved by alpha d_last; alpha d_q is the secant's s (Eq. 20) and
 * adds to the step's modal coordinates (downdating). */
static void account_step(rk_adaptive_impl *im, const double *x)
{
    if (!im->have_prev) return;
    double dd = 0, xd = 0;
    for (int i = 0; i < im->n; i++) {
        dd += im->d_last[i] * im->d_last[i];
        xd += (x[i] - im->x_prev[i]) * im->d_last[i];
    }
    double alpha = dd > 0 ? xd / dd : 0;
    for (int j = 0; j < im->a; j++) {
        im->dq_last[j] *= alpha;
        im->q_total[im->cols[j]] += im->dq_last[j];
    }
    for (int i = 0; i < im->n; i++) im->x_moved[i] += alpha * im->d_last[i];
    im->have_step = alpha > 0;
    im->have_prev = 0;
}

/* The enrichment has passed opt.full_fraction of the free vertices (moving obstacles aside: full order
 * moves them its own way, not by their progress). */
static int over_full(const rk_adaptive *ad)
{
    const rk_adaptive_impl *im = ad->impl;
    return ad->opt.full_fraction < 1 && !im->view.og && ad->nodes > ad->opt.full_fraction * im->free_vertices;
}

static double energy_x(void *ctx, const double *x, double *g, int hessian, double *magnitude)
{
    newton_ctx *c = ctx;
    rk_adaptive *ad = c->ad;
    rk_adaptive_impl *im = ad->impl;
    double t0 = rk_now();
    if (!hessian) {
        double E = rk_fom_potential(&ad->fom, c->T, x, g, RK_FOM_NO_HESSIAN, magnitude, &c->failure);
        ad->stats.seconds_line_search += rk_now() - t0;
        return E;
    }
    /* the elastic terms element by element (kept for BFGS's secants and the oracle), the rest by
     * the full-order potential */
    rk_fom_terms rest = *c->T;
    rest.no_elastic = 1;
    double E = rk_fom_potential(&ad->fom, &rest, x, g, RK_FOM_CONTACT_BLOCKS, magnitude, &c->failure);
    double psi = isfinite(E) ? rk_adaptive_elastic(ad, x, g) : INFINITY;
    E += psi;
    if (magnitude) *magnitude += fabs(psi);
    ad->stats.seconds_potential += rk_now() - t0;
    if (!isfinite(E)) return INFINITY;
    for (int i = 0; i < im->n; i++)
        if (im->view.prescribed[i]) g[i] = 0;
    rk_fom_view_get(&ad->fom, &im->view);
    account_step(im, x);
    if (over_full(ad)) { /* enriched past full_fraction already (a residual round, the last step's) */
        im->go_full = 1;
        return NAN;
    }
    double t1 = rk_now();
    int changed_modes = 0, changed_nodes = 0;
    if (im->first_iteration) { /* BFGS starts each solve at the exact subspace Hessians */
        if (rk_adaptive_bfgs_restart(ad, x, &c->failure)) return NAN;
        im->first_iteration = 0;
    }
    if (!ad->opt.exact_hessian) rk_adaptive_bfgs_update(ad, x);
    if (rk_adaptive_subspace_hessian(ad, c->T, x, &c->failure)) return NAN;
    double t2 = rk_now();
    ad->stats.seconds_hessian += t2 - t1;
    if (rk_adaptive_oracle(ad, c->T, x, E, g, &changed_modes, &changed_nodes, &c->failure)) return NAN;
    double t3 = rk_now();
    ad->stats.seconds_oracle += t3 - t2;
    /* Full order finishes the step (adaptive_newton) past full_fraction, and, on a step that tries the
     * subspace again after full-order steps, as soon as the oracle wants more than the model it
     * restarted with: such a try asks whether the body moves as the initial blocks hold it (free flight
     * again), and growing the model to find out cost several full-order steps a try (docs/methods.md) */
    if ((changed_nodes && over_full(ad)) || (im->full_backoff > 0 && (changed_nodes || changed_modes))) {
        im->go_full = 1;
        return NAN;
    }
    if (changed_modes) { /* new columns: the subspace Hessians from scratch (Sec. 3.10) */
        if (rk_adaptive_set_columns(ad, &c->failure) || rk_adaptive_bfgs_restart(ad, x, &c->failure)) return NAN;
        if (!ad->opt.exact_hessian) rk_adaptive_bfgs_update(ad, x);
    } else if (changed_nodes) {
        rk_adaptive_update_mask(ad);
    }
    if ((changed_modes || changed_nodes) && rk_adaptive_subspace_hessian(ad, c->T, x, &c->failure)) return NAN;
    ad->stats.seconds_hessian += rk_now() - t3;
    memcpy(im->x_prev, x, sizeof(double) * (size_t)im->n);
    return E;
}

/* With moving obstacles the unknowns are x and their progress s (obstacles.c): the obstacles
 * placed at s, their points degrees of freedom of the contact blocks, and the pull added. */
static double energy(void *ctx, const double *y, double *g, int hessian, double *magnitude)
{
    newton_ctx *c = ctx;
    rk_adaptive_impl *im = c->ad->impl;
    if (!im->way) return energy_x(ctx, y, g, hessian, magnitude);
    rk_contact *oc = im->view.contact;
    rk_obstacle_way_place(im->way, oc, y + im->n);
    oc->obstacle_dofs = 1;
    double E = energy_x(ctx, y, g, hessian, magnitude);
    oc->obstacle_dofs = 0;
    if (!isfinite(E)) return E;
    return E + rk_adaptive_obstacle_terms(c->ad, y, g, hessian, magnitude);
}

/* The same iterate's full-space Newton system, by CHOLMOD and by block-Jacobi CG (opt.probe). */
static int probe(rk_adaptive *ad, const rk_fom_terms *T, const double *d_ours, double seconds_ours, long pcg_before,
                 rk_error *err)
{
    rk_adaptive_impl *im = ad->impl;
    rk_adaptive_probe *p = &ad->stats.probe;
    int n = im->n;
    double *g = im->sc3, *d = im->sc4;
    p->modes = im->a;
    p->enriched_dofs = im->nx;
    p->coupled_dofs = im->nx ? im->ncoup : 0;
    p->schur_seconds = seconds_ours;
    p->schur_iterations = (int)(ad->stats.pcg_iterations - pcg_before);
    p->schur_nnz = (long)im->a * im->a + (long)im->a * p->coupled_dofs + (im->nx ? im->hx_rowptr[im->nx] : 0);
    if (!isfinite(rk_fom_potential(&ad->fom, T, im->x_prev, g, RK_FOM_NEWTON_MATRIX, NULL, err))) return -1;
    for (int i = 0; i < n; i++)
        if (im->view.prescribed[i]) g[i] = 0;
    double t0 = rk_now();
    if (rk_fom_newton_direction(&ad->fom, g, d, err)) return -1;
    p->cholmod_seconds = rk_now() - t0;
    const rk_sparse *A = rk_fom_newton_matrix(&ad->fom);
    p->full_nnz = 2L * A->nnz - A->n;
    double *dcg = malloc(sizeof(double) * (size_t)A->n);
    if (!dcg) return rk_fail(err, "out of memory for the probe");
    t0 = rk_now();
    p->bjcg_iterations = rk_block_jacobi_cg(A, g, dcg, ad->opt.pcg_tol, ad->opt.pcg_max_iter, err);
    p->bjcg_seconds = rk_now() - t0;
    free(dcg);
    double diff = 0, size = 0;
    for (int i = 0; i < n; i++) {
        diff = fmax(diff, fabs(d_ours[i] - d[i]));
        size = fmax(size, fabs(d[i]));
    }
    p->direction_difference = size > 0 ? diff / size : 0;
    p->done = 1;
    rk_fom_view_get(&ad->fom, &im->view); /* the contact blocks are the same pairs, at the same iterate */
    return 0;
}

static int solve(void *ctx, const double *g, double *d, rk_error *err)
{
    newton_ctx *c = ctx;
    rk_adaptive_impl *im = c->ad->impl;
    double t0 = rk_now();
    long pcg_before = c->ad->stats.pcg_iterations;
    if (im->way ? rk_adaptive_solve_bordered(c->ad, c->T, g, d, err) : rk_adaptive_solve(c->ad, c->T, g, d, err))
        return -1;
    if (c->ad->opt.probe && !c->ad->stats.probe.done &&
        probe(c->ad, c->T, d, rk_now() - t0, pcg_before, err))
        return -1;
    memcpy(im->d_last, d, sizeof(double) * (size_t)im->n);
    memcpy(im->dq_last, im->dq, sizeof(double) * (size_t)im->a);
    im->have_prev = 1;
    return 0;
}

static double max_step(void *ctx, const double *x, const double *d)
{
    newton_ctx *c = ctx;
    rk_adaptive_impl *im = c->ad->impl;
    if (im->way) /* the body and the obstacles together, s within [0, 1] */
        return rk_obstacle_way_max_step(im->way, im->view.contact, x, d, x + im->n, d + im->n, &c->failure);
    double alpha = rk_fom_max_step(&c->ad->fom, x, d, &c->failure);
    return alpha >= 0 ? alpha : 0;
}

/* The full-space Newton step at s->x into d (n): |d|_inf / h, m/s; -1 on failure. */
static double full_residual(rk_adaptive *ad, rk_fom *s, const rk_fom_terms *T, double *d, rk_error *err)
{
    rk_adaptive_impl *im = ad->impl;
    double *g = im->sc3, r = 0, t0 = rk_now();
    /* full order's assembly and factorization as full order runs them: OpenBLAS on every thread
     * (CHOLMOD's supernodes; bit-identical across thread counts, as full order is: cli_fom.sh) */
    int blas = rk_threads_blas(rk_threads());
    int rc = !isfinite(rk_fom_potential(s, T, s->x, g, RK_FOM_NEWTON_MATRIX, NULL, err));
    for (int i = 0; i < im->n && !rc; i++)
        if (im->view.prescribed[i]) g[i] = 0;
    if (!rc) rc = rk_fom_newton_direction(s, g, d, err);
    rk_threads_blas(blas);
    if (rc) return -1;
    rk_fom_view_get(&ad->fom, &im->view);
    for (int i = 0; i < im->n; i++) r = fmax(r, fabs(d[i]));
    ad->stats.seconds_residual += rk_now() - t0;
    return r / s->opt.h;
}

/* The parts of the free vertices whose full-space step |d_i| / h exceeds tol (m/s), enriched;
 * returns the vertices added. (The largest of the residual, not all of it above the Newton
 * tolerance: the step is spread over the body around what the subspace missed, Fig. 8 of the
 * paper, and enriching all of it would enrich everything.) */
static int enrich_residual(rk_adaptive *ad, const double *d, double h, double tol)
{
    rk_adaptive_impl *im = ad->impl;
    char *grow = im->part_mark;
    memset(grow, 0, (size_t)im->L);
    for (int v = 0; v < im->nv; v++) {
        if (im->enriched[v] || im->fixed_vertex[v]) continue;
        const double *dv = &d[3 * v];
        if (sqrt(dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2]) / h > tol) grow[im->part[v]] = 1;
    }
    int added = 0;
    for (int l = 0; l < im->L; l++)
        if (grow[l]) added += rk_adaptive_enrich_part(ad, l);
    if (added) rk_adaptive_update_mask(ad);
    return added;
}

/* Each enrichment round for the residual enriches the parts of the vertices whose |d_i| / h is
 * within this share of the largest (or above the tolerance, whichever is higher). */
#define RK_ADAPTIVE_RESIDUAL_SHARE 0.5

/* The body's |d|_inf and, with moving obstacles, their step along the way (m). */
static double step_norm(void *ctx, const double *d)
{
    rk_adaptive_impl *im = ((newton_ctx *)ctx)->ad->impl;
    double size = 0;
    for (int i = 0; i < im->n; i++) size = fmax(size, fabs(d[i]));
    return im->way ? fmax(size, rk_obstacle_way_step_norm(im->way, d + im->n)) : size;
}

/* Newton from im->y; with moving obstacles, rounds of the method of multipliers on their pull
 * until they arrive within tol_d or a round does not halve the shortfall (obstacle_solve.c's). */
static int solve_rounds(rk_adaptive *ad, const newton_ctx *c, const rk_newton_problem *p, const rk_fom *s,
                        double tol_d, int *converged, rk_newton_stats *stats, rk_error *err)
{
    rk_adaptive_impl *im = ad->impl;
    for (int round = 0;; round++) {
        im->first_iteration = 1;
        im->have_prev = 0;
        im->have_step = 0;
        int rc = rk_newton_solve(p, im->y, tol_d, rk_fom_max_iter(&s->opt, 1), im->newton_work, converged, stats, err);
        account_step(im, im->y);
        if (rc || c->failure.msg[0] || !im->way || round + 1 >= RK_OBSTACLE_ROUNDS ||
            !rk_obstacle_way_round(im->way, im->y + im->n, tol_d))
            return rc;
        ad->stats.obstacle_rounds++;
    }
}

/* The obstacles' way over the step (their progress an unknown: obstacles.c) unless nothing moves
 * or the whole way is clear of the body as it is (then they are there at once, the body after):
 * the number of progress unknowns with *way set, 0, -1 on failure. */
static int obstacle_way(rk_adaptive *ad, rk_fom *s, rk_obstacle_way *way, rk_error *err)
{
    rk_adaptive_impl *im = ad->impl;
    if (!im->view.contact || !im->view.og) return 0;
    double t = s->t + s->opt.h;
    int moving = rk_obstacle_way_init(way, im->view.contact, t, im->mass, s->opt.h, err);
    if (moving <= 0) return moving;
    if (rk_adaptive_progress_room(im, moving, err)) {
        rk_obstacle_way_free(way);
        return -1;
    }
    memset(im->sx, 0, sizeof(double) * (size_t)im->n);
    double clear = rk_contact_max_step(im->view.contact, s->x, im->sx, way->way, err);
    if (clear >= 1) rk_contact_set_time(im->view.contact, t);
    if (clear < 0 || clear >= 1) rk_obstacle_way_free(way);
    return clear < 0 ? -1 : clear < 1 ? moving : 0;
}

/* Steps handed to full order at once, at most, after a run of steps that went past full_fraction. */
#define RK_ADAPTIVE_FULL_WAIT 8

/* Full order's own Newton (CHOLMOD on its Newton matrix, as full order runs it: OpenBLAS on every
 * thread, bit-identical across thread counts) from s->x to the method's tolerance tol_d. */
static int full_order(rk_adaptive *ad, rk_fom *s, const rk_fom_terms *T, double tol_d, int *converged, rk_error *err)
{
    rk_adaptive_impl *im = ad->impl;
    long before = s->stats.newton_iterations;
    int blas = rk_threads_blas(rk_threads());
    int rc = rk_fom_newton(s, T, tol_d, converged, err);
    rk_threads_blas(blas);
    rk_fom_view_get(&ad->fom, &im->view);
    ad->stats.newton_iterations += s->stats.newton_iterations - before;
    im->full_this_step = 1;
    return rc;
}

/* A step handed to full order: the next 1, 2, 4, then up to RK_ADAPTIVE_FULL_WAIT steps go there at
 * once (the subspace tried again after each run of them). */
static void hand_to_full(rk_adaptive_impl *im)
{
    im->full_backoff = im->full_backoff ? 2 * im->full_backoff : 1;
    if (im->full_backoff > RK_ADAPTIVE_FULL_WAIT) im->full_backoff = RK_ADAPTIVE_FULL_WAIT;
    im->full_wait = im->full_backoff;
}

static int adaptive_newton(void *ctx, rk_fom *s, const rk_fom_terms *T, double tol_d, int *converged, rk_error *err)
{
    rk_adaptive *ad = ctx;
    rk_adaptive_impl *im = ad->impl;
    newton_ctx c = {.ad = ad, .T = T};
    rk_obstacle_way way;
    int moving = obstacle_way(ad, s, &way, err);
    if (moving < 0) return -1;
    im->way = moving ? &way : NULL;
    memcpy(im->y, s->x, sizeof(double) * (size_t)im->n);
    memcpy(im->x_start, s->x, sizeof(double) * (size_t)im->n);
    rk_contact *c0 = im->view.contact;
    double kappa0 = c0 ? c0->kappa : 0, closest0 = c0 ? c0->min_distance_last : 0;
    int kappa_set0 = c0 ? c0->kappa_set : 0;
    memset(im->y + im->n, 0, sizeof(double) * (size_t)moving); /* s = 0: the obstacles where they are */
    rk_newton_problem p = {.n = im->n + moving, .ctx = &c, .what = "incremental potential (adaptive subspace)",
                           .energy = energy, .solve = solve,
                           .max_step = im->view.has_contact ? max_step : NULL,
                           .step_norm = step_norm, .prescribed = im->prescribed_y};
    rk_newton_stats stats = {0};
    double tol_v = ad->tolerance; /* its own tolerance, m/s (rk_adaptive_own_tolerance), for its Newton
                                   * iterations and the residual check; full order keeps its own */
    tol_d = tol_v * s->opt.h;
    int rc = 0;
    im->go_full = 0;
    if (im->full_wait > 0 && !moving) { /* the last steps went past full_fraction: this one at once */
        im->full_wait--;
        im->go_full = 1;
    }
    for (int round = 0; !im->go_full; round++) {
        rc = solve_rounds(ad, &c, &p, s, tol_d, converged, &stats, err);
        memcpy(s->x, im->y, sizeof(double) * (size_t)im->n);
        if (im->go_full) { /* the oracle passed full_fraction: not a failure, the iterate stands */
            rc = 0;
            err->msg[0] = 0;
            hand_to_full(im);
            break;
        }
        if (moving) rk_obstacle_way_place(&way, im->view.contact, im->y + im->n); /* not a line search's trial */
        if (rc || c.failure.msg[0] || !ad->opt.residual) break;
        /* the full-order Newton step that would remain from here: the paper's accuracy measure
         * (Fig. 12), which its oracle's thresholds do not bound; where it exceeds the tolerance the
         * subspace and the enrichment missed motion there: enrich those parts and solve again */
        double r = full_residual(ad, s, T, im->sc4, err);
        if (r < 0) {
            rc = -1;
            break;
        }
        int added = 0;
        if (r > tol_v && round < ad->opt.residual_rounds && ad->opt.nodal)
            added = enrich_residual(ad, im->sc4, s->opt.h, fmax(tol_v, RK_ADAPTIVE_RESIDUAL_SHARE * r));
        if (added && (over_full(ad) || im->full_backoff > 0)) {
            im->go_full = 1;
            hand_to_full(im);
            break;
        }
        if (!added) {
            im->full_backoff = 0; /* the subspace held this step */
            ad->stats.residual_last = r;
            ad->stats.residual_max = fmax(ad->stats.residual_max, r);
            ad->stats.residual_sum += r;
            if (r > tol_v) ad->stats.residual_over++;
            break;
        }
        ad->stats.residual_rounds++;
        ad->stats.residual_nodes_added += added;
    }
    im->stepped_full = im->go_full;
    /* full order from where its own step starts, not from the subspace's iterate: that one may have
     * crept up to an obstacle (the bunny drop of docs/methods.md ended 5e-11 m from it so, against
     * full order's 8e-7; from the step's start, 1e-6); and with the barrier stiffness it had there:
     * IPC's adaptive kappa is set at the first Hessian with a pair and doubled at later ones, so the
     * subspace's iterates would set it differently from full order's (a stiff octopus landing on a
     * soft slab bounced 0.1 m apart so, docs/methods.md) */
    if (im->go_full) {
        memcpy(s->x, im->x_start, sizeof(double) * (size_t)im->n);
        if (c0) {
            c0->kappa = kappa0;
            c0->kappa_set = kappa_set0;
            c0->min_distance_last = closest0;
        }
    }
    if (im->go_full && (rc = full_order(ad, s, T, tol_d, converged, err)) == 0) {
        double r = ad->opt.residual ? full_residual(ad, s, T, im->sc4, err) : 0;
        if (r < 0) {
            rc = -1;
        } else if (ad->opt.residual) {
            ad->stats.residual_last = r;
            ad->stats.residual_max = fmax(ad->stats.residual_max, r);
            ad->stats.residual_sum += r;
            if (r > tol_v) ad->stats.residual_over++;
        }
    }
    im->way = NULL;
    if (moving) { /* at t + h when within the tolerance of it and CCD lets the last bit go */
        int behind = 0;
        memset(im->sx, 0, sizeof(double) * (size_t)im->n);
        if (!rc && !c.failure.msg[0] &&
            rk_obstacle_way_arrive(&way, im->view.contact, s->x, im->sx, im->y + im->n, s->t + s->opt.h, tol_d,
                                   &behind, err))
            rc = -1;
        ad->stats.obstacles_behind += behind;
        rk_obstacle_way_free(&way);
    }
    ad->stats.newton_iterations += stats.iterations;
    s->stats.newton_iterations += stats.iterations;
    s->stats.line_search_halvings += stats.halvings;
    if (c.failure.msg[0]) {
        *err = c.failure;
        return -1;
    }
    return rc;
}

int rk_adaptive_step(rk_adaptive *ad, rk_error *err)
{
    rk_adaptive_impl *im = ad->impl;
    double t0 = rk_now();
    if (im->model_dirty) {
        if (rk_adaptive_set_columns(ad, err)) return -1;
        im->model_dirty = 0;
    }
    memset(im->q_total, 0, sizeof(double) * (size_t)im->r);
    memset(im->x_moved, 0, sizeof(double) * (size_t)im->n);
    im->full_this_step = 0;
    im->oracle_this_step = 0;
    /* The dense products are small (a columns): OpenBLAS on one thread, so that the results do not
     * depend on the thread count (a threaded product splits its sums differently). */
    int blas = rk_threads_blas(1);
    int rc = rk_fom_step_with(&ad->fom, adaptive_newton, ad, err);
    rk_threads_blas(blas);
    if (rc) return -1;
    ad->stats.steps++;
    ad->stats.steps_full += im->full_this_step;
    if (im->stepped_full) { /* every free vertex solved at full order; the model starts again from its
                             * initial blocks (what it had does not describe a full-order step) */
        for (int v = 0; v < im->nv; v++) im->enriched[v] = (char)!im->fixed_vertex[v];
        ad->nodes = im->free_vertices;
    }
    ad->stats.sum_modes += ad->modes;
    ad->stats.sum_nodes += ad->nodes;
    if (ad->modes > ad->stats.max_modes) ad->stats.max_modes = ad->modes;
    if (ad->nodes > ad->stats.max_nodes) ad->stats.max_nodes = ad->nodes;
    memcpy(im->solved_enriched, im->enriched, (size_t)im->nv);
    if (im->stepped_full) {
        memset(im->enriched, 0, (size_t)im->nv);
        for (int b = 0; b < im->nblocks; b++) im->block_on[b] = (char)(b < ad->opt.initial_blocks);
        im->model_dirty = 1;
    } else if (ad->opt.downdate) {
        rk_adaptive_downdate(ad);
    }
    ad->stats.seconds_total += rk_now() - t0;
    return 0;
}
