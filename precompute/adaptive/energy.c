/* The per-vertex potential of the progress measure (adaptive-subspace paper, Eq. 7): each vertex's
 * share of the incremental potential. The paper sums "the stencil-size weighted IP energies in the
 * one-ring"; here each element's elastic energy is split equally among its four vertices (so the
 * shares add up to the potential, as the per-vertex volume V_i of Eq. 8 splits the volume), the
 * inertia and damping quadratic forms by rows (r_i . (M r)_i), the load per vertex, and each
 * contact pair's barrier equally among its mesh points. */
#include "adaptive/adaptive_impl.h"

#include <math.h>
#include <string.h>

typedef struct {
    const rk_fem *f;
    const double *x;
    double *out;
} energy_job;

static void energy_range(void *ctx, long begin, long end)
{
    energy_job *j = ctx;
    const rk_fem *f = j->f;
    for (long t = begin; t < end; t++) {
        double xe[12];
        rk_fem_gather(f, (int)t, j->x, xe);
        j->out[t] = rk_tet_energy(f->model[t], f->mu[t], f->lambda[t], xe, &f->Dm_inv[9 * t], f->vol[t]);
    }
}

/* Adds w/2 r_i . (S r)_i per vertex, r = x - ref. */
static void quadratic_share(const rk_adaptive_impl *im, const double *val, double w, const double *x,
                            const double *ref, double *r, double *Sr, double *e)
{
    for (int i = 0; i < im->n; i++) r[i] = x[i] - ref[i];
    rk_full_mul(&im->P, val, r, Sr);
    for (int i = 0; i < im->n; i++) e[i / 3] += 0.5 * w * r[i] * Sr[i];
}

typedef struct {
    const rk_fem *f;
    const double *x;
    double *psi, *g;
} elastic_job;

static void elastic_range(void *ctx, long begin, long end)
{
    elastic_job *j = ctx;
    const rk_fem *f = j->f;
    for (long t = begin; t < end; t++) {
        double xe[12], *g = j->g + 12 * (size_t)t;
        rk_fem_gather(f, (int)t, j->x, xe);
        j->psi[t] = rk_tet_energy(f->model[t], f->mu[t], f->lambda[t], xe, &f->Dm_inv[9 * t], f->vol[t]);
        memset(g, 0, 12 * sizeof(double));
        rk_tet_gradient(f->model[t], f->mu[t], f->lambda[t], xe, &f->Dm_inv[9 * t], f->vol[t], g);
    }
}

double rk_adaptive_elastic(rk_adaptive *ad, const double *x, double *g)
{
    rk_adaptive_impl *im = ad->impl;
    const rk_fem *f = im->f;
    elastic_job j = {f, x, im->elem_psi, im->elem_g};
    rk_parallel_for(f->nt, 512, elastic_range, &j);
    double E = 0; /* in element order: the same sum on any thread count */
    for (int t = 0; t < f->nt; t++) {
        E += im->elem_psi[t];
        rk_fem_scatter_vector(f, t, &im->elem_g[12 * (size_t)t], 1.0, g);
    }
    return isfinite(E) ? E : INFINITY;
}

double rk_adaptive_elastic_energy(rk_adaptive *ad, const double *x, double *elem)
{
    const rk_fem *f = ad->impl->f;
    energy_job j = {f, x, elem};
    rk_parallel_for(f->nt, 512, energy_range, &j);
    double E = 0;
    for (int t = 0; t < f->nt; t++) E += elem[t];
    return isfinite(E) ? E : INFINITY;
}

int rk_adaptive_vertex_energy(rk_adaptive *ad, const rk_fom_terms *T, const double *x, const double *elem_psi,
                              double *e, rk_error *err)
{
    rk_adaptive_impl *im = ad->impl;
    const rk_fem *f = im->f;
    if (!elem_psi) {
        rk_adaptive_elastic_energy(ad, x, im->elem_e);
        elem_psi = im->elem_e;
    }
    memset(e, 0, sizeof(double) * (size_t)im->nv);
    for (int t = 0; t < f->nt; t++) {
        if (!isfinite(elem_psi[t])) return 1;
        for (int k = 0; k < 4; k++) e[f->tets[4 * t + k]] += 0.25 * elem_psi[t];
    }
    if (T->w_inertia > 0) quadratic_share(im, im->Mf, T->w_inertia, x, T->xtilde, im->sc1, im->sc2, e);
    if (T->w_damping > 0 && im->Cf) quadratic_share(im, im->Cf, T->w_damping, x, T->xt, im->sc1, im->sc2, e);
    for (int i = 0; i < im->n; i++) e[i / 3] -= T->load * im->view.f_ext[i] * x[i];
    if (im->view.contact) {
        if (rk_contact_gather(im->view.contact, x, &im->pairs, err)) return -1;
        rk_contact_point_energy(im->view.contact, &im->pairs, x, e);
    }
    for (int v = 0; v < im->nv; v++)
        if (!isfinite(e[v])) return 1;
    return 0;
}
