/* The incremental potential (fom_impl.h, rk_fom_terms): one evaluation of value, gradient and
 * Hessian shared by time steps and static solves. */
#include "fom/fom_impl.h"

#include "fem/element_impl.h"
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
    rk_fem_add_hessian(f, x, 1.0, 1, H);
    if (s->opt.obstacles.count) rk_barrier_add_hessian(f, &s->opt.obstacles, x, 1.0, H);
}

double rk_fom_potential(rk_fom *s, const rk_fom_terms *T, const double *x, double *g, rk_sparse *H,
                        double *magnitude)
{
    rk_fom_impl *im = s->impl;
    const rk_fem *f = s->fem;
    int n = im->n;
    double t0 = rk_now();
    if (g) memset(g, 0, (size_t)n * sizeof(double));
    double stored = rk_fem_energy(f, x); /* Psi + B */
    if (s->opt.obstacles.count) stored += rk_barrier_energy(f, &s->opt.obstacles, x);
    double work = 0;
    for (int i = 0; i < n; i++) work += im->f_ext[i] * x[i];
    work *= T->load;
    double quad = 0; /* inertia and damping, both >= 0 */
    if (T->w_inertia > 0) quad += quadratic_term(&im->M, T->w_inertia, x, T->xtilde, g, im->work, im->work2, n);
    if (T->w_damping > 0 && im->C.val)
        quad += quadratic_term(&im->C, T->w_damping, x, T->xt, g, im->work, im->work2, n);
    double E = stored - work + quad;
    if (magnitude) *magnitude = fabs(stored) + fabs(work) + quad;
    if (g && isfinite(E)) {
        rk_fem_add_gradient(f, x, 1.0, g);
        if (s->opt.obstacles.count) rk_barrier_add_gradient(f, &s->opt.obstacles, x, 1.0, g);
        for (int i = 0; i < n; i++) g[i] -= T->load * im->f_ext[i];
    }
    if (H && isfinite(E)) assemble_hessian(s, T, x, H);
    rk_fom_eliminate(s, H);
    s->stats.seconds_assemble += rk_now() - t0;
    return isfinite(E) ? E : INFINITY;
}
