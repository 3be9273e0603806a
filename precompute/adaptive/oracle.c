/* The update oracle (adaptive-subspace paper, Sec. 3.7) and downdating (Sec. 3.11). */
#include "adaptive/adaptive_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The integrator's alpha from the potential's inertia weight 1 / (alpha h^2). */
static double integrator_alpha(const rk_adaptive *ad, const rk_fom_terms *T)
{
    double h = ad->fom.opt.h;
    return T->w_inertia > 0 ? 1.0 / (T->w_inertia * h * h) : 1.0;
}

/* The active subspace's Newton direction p = -H_a^-1 U_a^T g, line-searched (Eq. 18): the
 * displacement U_a alpha p into dx. Returns alpha (0: no decrease found). */
static double subspace_direction(rk_adaptive *ad, const rk_fom_terms *T, const double *x, double E,
                                 const double *g, double *dx, rk_error *err)
{
    rk_adaptive_impl *im = ad->impl;
    int a = im->a, n = im->n;
    double *b = im->gq, *p = im->dq;
    rk_dense_atb(n, a, 1, im->Ua, g, b);
    for (int k = 0; k < a; k++) b[k] = -b[k];
    if (rk_spd_solve_shifted(a, im->Ha, im->Lq, b, p, RK_ADAPTIVE_SHIFTS)) return 0;
    rk_adaptive_combine(n, a, im->Ua, p, dx);
    double gd = 0;
    for (int i = 0; i < n; i++) gd += g[i] * dx[i];
    if (!(gd < 0)) return 0;
    double alpha = rk_fom_max_step(&ad->fom, x, dx, err);
    if (alpha < 0) return -1;
    alpha = fmin(1, alpha);
    rk_fom_terms rest = *T; /* the elastic part element by element: the accepted trial's are kept in
                             * im->elem_e for the progress measure's one-ring energies */
    rest.no_elastic = 1;
    for (int k = 0; k <= RK_MAX_HALVINGS; k++, alpha *= 0.5) {
        for (int i = 0; i < n; i++) im->xtry[i] = x[i] + alpha * dx[i];
        double Et = rk_fom_potential(&ad->fom, &rest, im->xtry, NULL, 0, NULL, err);
        if (isfinite(Et)) Et += rk_adaptive_elastic_energy(ad, im->xtry, im->elem_e);
        if (Et <= E + RK_ARMIJO_C * alpha * gd) {
            for (int i = 0; i < n; i++) dx[i] *= alpha;
            return alpha;
        }
    }
    return 0;
}

/* The modal measures (Eq. 14-17) of the inactive candidate blocks [begin, end) into GE (error,
 * progress, computed: 3 per block); a work vector of n per range (a block's projection). */
typedef struct {
    const rk_adaptive_impl *im;
    const double *g;
    double alpha;
    int k;
    double *GE;
} modal_job;

static void modal_blocks(void *ctx, long begin, long end)
{
    modal_job *j = ctx;
    const rk_adaptive_impl *im = j->im;
    int n = im->n, nv = im->nv;
    double *work = malloc(sizeof(double) * (size_t)n);
    for (long b = begin; b < end; b++) {
        j->GE[3 * b] = j->GE[3 * b + 1] = 0;
        j->GE[3 * b + 2] = work != NULL; /* 0: out of memory (the caller fails) */
        if (im->block_on[b] || !work) continue;
        const double *Um = im->U + (size_t)b * j->k * n;
        j->GE[3 * b] = rk_adaptive_modal_error(nv, Um, j->k, j->g, im->gscale, im->gpsi, j->alpha, work);
        j->GE[3 * b + 1] = rk_adaptive_modal_progress(nv, Um, j->k, im->dE, im->pscale, im->gpsi, j->alpha);
    }
    free(work);
}

int rk_adaptive_oracle(rk_adaptive *ad, const rk_fom_terms *T, const double *x, double E, const double *g,
                       int *changed_modes, int *changed_nodes, rk_error *err)
{
    rk_adaptive_impl *im = ad->impl;
    const rk_adaptive_options *o = &ad->opt;
    int nv = im->nv, n = im->n;
    *changed_modes = *changed_nodes = 0;
    im->oracle_this_step = 1;
    if (!o->modal && !o->nodal) return 0;
    double alpha_int = integrator_alpha(ad, T);
    /* progress: the one-ring potentials before and after the subspace's own step */
    double *dx = im->sc3;
    double step = subspace_direction(ad, T, x, E, g, dx, err);
    if (step < 0) return -1;
    int rc = rk_adaptive_vertex_energy(ad, T, x, im->elem_psi, im->e0, err); /* the iterate's, computed already */
    if (rc < 0) return -1;
    if (step > 0) {
        for (int i = 0; i < n; i++) im->xtry[i] = x[i] + dx[i];
        rc = rk_adaptive_vertex_energy(ad, T, im->xtry, im->elem_e, im->e1, err);
        if (rc < 0) return -1;
    }
    for (int v = 0; v < nv; v++) im->dE[v] = step > 0 && rc == 0 ? im->e0[v] - im->e1[v] : 0;
    /* In the tolerance's units the oracle acts once the active subspace's own Newton step is within
     * the tolerance (or finds no decrease): before that G is mostly the step's unfinished motion,
     * which the subspace is still removing (a free fall's first iteration: G 3e3-7e3 at every vertex,
     * none after the rigid columns' step), and the paper's progress measure, which should veto it,
     * is a signed projection that came out negative for every candidate block there, so six blocks
     * were taken in free fall (docs/methods.md, "Why the defaults enriched"). Not in the paper,
     * which acts at every iteration; its units (paper_units) keep that. */
    int converging = 0;
    if (!o->paper_units && step > 0) {
        double size = 0;
        for (int i = 0; i < n; i++) size = fmax(size, fabs(dx[i]));
        converging = size / step / ad->fom.opt.h > ad->tolerance;
    }
    if (o->nodal) {
        rk_adaptive_nodal_error(nv, g, im->gscale, im->gpsi, alpha_int, im->G);
        char *grow = im->part_mark;
        memset(grow, 0, (size_t)im->L);
        for (int v = 0; v < nv; v++) {
            double s = im->pscale[v] * im->gpsi[v];
            double progress = im->prog[v] = s > 0 ? alpha_int * im->dE[v] / s : 0;
            if (im->enriched[v] || im->fixed_vertex[v]) continue;
            if (im->G[v] > o->eps_g_nodal && progress < o->eps_e && !converging) grow[im->part[v]] = 1;
        }
        for (int l = 0; l < im->L; l++)
            if (grow[l]) {
                int added = rk_adaptive_enrich_part(ad, l);
                ad->stats.oracle_nodes_added += added;
                *changed_nodes |= added > 0;
            }
    }
    if (o->modal && !converging) {
        int k = o->block;
        /* each inactive block's measures on the threads (each block its own), then taken in order */
        double *GE = rk_calloc(3 * (size_t)im->nblocks + 1, sizeof(double), err);
        if (!GE) return -1;
        modal_job j = {im, g, alpha_int, k, GE};
        rk_parallel_for(im->nblocks, 1, modal_blocks, &j);
        for (int b = 0; b < im->nblocks; b++)
            if (!GE[3 * b + 2]) {
                free(GE);
                return rk_fail(err, "out of memory for the oracle's modal measures (%d dofs)", n);
            }
        for (int b = 0; b < im->nblocks; b++) {
            if (im->block_on[b]) continue;
            if (GE[3 * b] > o->eps_g_modal && GE[3 * b + 1] < o->eps_e) {
                im->block_on[b] = 1;
                ad->stats.oracle_modes_added += k;
                *changed_modes = 1;
            }
        }
        free(GE);
    }
    return 0;
}

void rk_adaptive_downdate(rk_adaptive *ad)
{
    rk_adaptive_impl *im = ad->impl;
    const rk_adaptive_options *o = &ad->opt;
    int n = im->n, k = o->block;
    double scale = im->length * ad->fom.opt.h, *u = im->sc3;
    /* modes: the displacement each active block made over the step */
    int modes_changed = 0;
    for (int b = o->initial_blocks; b < im->nblocks; b++) {
        if (!im->block_on[b]) continue;
        memset(u, 0, sizeof(double) * (size_t)n);
        for (int j = b * k; j < (b + 1) * k; j++)
            for (int i = 0; i < n; i++) u[i] += im->U[(size_t)j * n + i] * im->q_total[j];
        double m = 0;
        for (int i = 0; i < n; i++) m = fmax(m, fabs(u[i]));
        if (m / scale < o->eps_d) {
            im->block_on[b] = 0;
            ad->stats.modes_downdated += k;
            modes_changed = 1;
        }
    }
    /* vertices: what the enrichment added beyond the subspace's own displacement there: the Newton
     * iterations' displacement (x_{t+1} - x_t in the paper's Algorithm 1, which starts at x_t; here
     * Newton may start at the prediction) against U_a q */
    memset(u, 0, sizeof(double) * (size_t)n);
    for (int j = 0; j < im->r; j++)
        if (im->q_total[j] != 0)
            for (int i = 0; i < n; i++) u[i] += im->U[(size_t)j * n + i] * im->q_total[j];
    for (int v = 0; v < im->nv; v++) {
        if (!im->enriched[v]) continue;
        double e = 0;
        for (int c = 0; c < 3; c++) {
            double r = im->x_moved[3 * v + c] - u[3 * v + c];
            e += r * r;
        }
        if (sqrt(e) / scale < o->eps_d) {
            im->enriched[v] = 0;
            ad->stats.nodes_downdated++;
        }
    }
    im->model_dirty = 1;
    (void)modes_changed;
}

void rk_adaptive_fields(const rk_adaptive *ad, double *out)
{
    const rk_adaptive_impl *im = ad->impl;
    /* a step handed to full order at once (after steps past full_fraction) ran no oracle: its G and
     * E are not this step's, NaN says so rather than repeat an earlier step's */
    int stale = ad->stats.steps > 0 && !im->oracle_this_step;
    for (int v = 0; v < im->nv; v++) {
        out[3 * v] = im->solved_enriched[v];
        out[3 * v + 1] = stale ? NAN : im->G[v];
        out[3 * v + 2] = stale ? NAN : im->prog[v];
    }
}
