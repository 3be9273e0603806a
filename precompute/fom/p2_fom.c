/* Full order on quadratic (P2, 10-node) tets: a dynamic reference converged where P1 is not (issue
 * 37: at nu = 0.45 P1 tets lock in bending, and the freeform beam's 122,880-tet P1 run is 5% short
 * of the converged sag; P2 on 15,360 tets is within 0.5%, docs/results/p2_beam.md).
 *
 * The same incremental potential as the P1 simulator (fom.h), minimised by the same Newton
 * (solver.h) with the same integrator (rk_stepper) and tolerance:
 *   E(x) = w_inertia/2 |x - x~|_M^2 + Psi(x) + w_damping/2 |x - x_t|_C^2 - f.x,   C = a M + b K0,
 * with P2's consistent mass M, its rest stiffness K0 and gravity's consistent load f_a = int rho g N_a
 * (the vertex nodes' loads are negative, the edge nodes' positive: int N_a = -V/20 and V/5).
 * Prescribed groups move every node they hold: a vertex in the group, and an edge node whose two
 * vertices are both in the same group (the group's faces stay its faces). What the reference does
 * not model is refused by name: contact, obstacles, several objects, a lumped mass, a static solve.
 * Extra forces (N per mesh vertex) act on the vertex nodes, as point loads. The mesh's vertices are the first nodes, so its frames are read off directly. */
#include "fom/fom.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/util.h"

typedef struct {
    const rk_fem *fem;
    rk_p2_mesh p2;
    int n;                 /* 3 nn */
    int nfree;
    int *free_of;          /* n: the dof's index among the free ones, -1 prescribed */
    char *prescribed;      /* n flags, for the Newton */
    double (*dL)[12];      /* nt barycentric gradients */
    rk_sparse M, K0;       /* every dof (3 nn), upper-stored; K0.val NULL without stiffness damping */
    rk_sparse A;           /* the Newton matrix over the free dofs */
    rk_chol chol;
    double *f;             /* n: gravity's consistent load */
    double *scratch;       /* n */
    double Mref[100];      /* the unit tet's mass (volume 1, density 1): an element's is rho V times it */
    double w_inertia, w_damping, a, b;
    const double *xtilde, *xt;
    int factored;          /* the last Newton matrix factored (even projected); else solve fails */
    rk_error factor_err;
    rk_fom_stats *stats;
} p2_sim;

/* y += S x for an upper-stored symmetric S over every dof. */
static void sym_apply(const rk_sparse *S, const double *x, double *y)
{
    for (int j = 0; j < S->n; j++)
        for (int k = S->colptr[j]; k < S->colptr[j + 1]; k++) {
            int i = S->rowind[k];
            y[i] += S->val[k] * x[j];
            if (i != j) y[j] += S->val[k] * x[i];
        }
}

/* 1/2 d^T S d with its gradient S d added into g (scaled by w); d = x - ref. */
static double quadratic(const p2_sim *s, const rk_sparse *S, double w, const double *x, const double *ref, double *g)
{
    double *d = s->scratch, *Sd = s->scratch + s->n, e = 0;
    for (int i = 0; i < s->n; i++) {
        d[i] = x[i] - ref[i];
        Sd[i] = 0;
    }
    sym_apply(S, d, Sd);
    for (int i = 0; i < s->n; i++) {
        e += 0.5 * w * d[i] * Sd[i];
        if (g) g[i] += w * Sd[i];
    }
    return e;
}

static void element_u(const p2_sim *s, int t, const double *x, double u[30])
{
    const int *nd = &s->p2.elem[10 * t];
    for (int a = 0; a < 10; a++)
        for (int c = 0; c < 3; c++) u[3 * a + c] = x[3 * nd[a] + c] - s->p2.X[3 * nd[a] + c];
}

/* scale S (every dof, the rest stiffness assembled once) added into the Newton matrix at the free
 * dofs: free dofs are numbered in the dofs' order, so an upper entry stays upper. */
static void add_free(p2_sim *s, const rk_sparse *S, double scale)
{
    for (int j = 0; j < S->n; j++) {
        int col = s->free_of[j];
        if (col < 0) continue;
        for (int k = S->colptr[j]; k < S->colptr[j + 1]; k++) {
            int row = s->free_of[S->rowind[k]];
            if (row >= 0) s->A.val[rk_p2_slot(&s->A, row, col)] += scale * S->val[k];
        }
    }
}

/* The Newton matrix at x over the free dofs (elements projected when project), factored; returns
 * RK_CHOL_NOT_POSDEF when it is not positive definite, -1 on another failure. */
static int newton_matrix(p2_sim *s, const double *x, int project, rk_error *err)
{
    const rk_fem *fem = s->fem;
    memset(s->A.val, 0, (size_t)s->A.nnz * sizeof(double));
    double t0 = rk_now();
    for (int t = 0; t < fem->nt; t++) {
        double u[30], H[900];
        element_u(s, t, x, u);
        rk_p2_element_elastic(fem->model[t], fem->mu[t], fem->lambda[t], s->dL[t], fem->vol[t], u, NULL, H, project);
        double wm = (s->w_inertia + s->w_damping * s->a) * fem->density[t] * fem->vol[t];
        for (int a = 0; a < 10; a++)
            for (int b = 0; b < 10; b++)
                for (int c = 0; c < 3; c++) H[30 * (3 * a + c) + 3 * b + c] += wm * s->Mref[10 * a + b];
        rk_p2_scatter(&s->A, s->free_of, &s->p2.elem[10 * t], H, 1.0);
    }
    if (s->w_damping * s->b != 0) add_free(s, &s->K0, s->w_damping * s->b);
    s->stats->seconds_assemble += rk_now() - t0;
    t0 = rk_now();
    int st = rk_chol_factor(&s->chol, err);
    s->stats->seconds_factor += rk_now() - t0;
    return st;
}

static double energy(void *ctx, const double *x, double *g, int hessian, double *magnitude)
{
    p2_sim *s = ctx;
    const rk_fem *fem = s->fem;
    if (g) memset(g, 0, (size_t)s->n * sizeof(double));
    double e_el = 0, mag = 0;
    for (int t = 0; t < fem->nt; t++) {
        double u[30], ge[30];
        element_u(s, t, x, u);
        double e = rk_p2_element_elastic(fem->model[t], fem->mu[t], fem->lambda[t], s->dL[t], fem->vol[t], u,
                                         g ? ge : NULL, NULL, 0);
        if (!isfinite(e)) return INFINITY; /* an element inverted past what its model defines */
        e_el += e;
        mag += fabs(e);
        if (g) {
            const int *nd = &s->p2.elem[10 * t];
            for (int a = 0; a < 30; a++) g[3 * nd[a / 3] + a % 3] += ge[a];
        }
    }
    double e_in = quadratic(s, &s->M, s->w_inertia, x, s->xtilde, g);
    double e_damp = 0;
    if (s->w_damping * s->a != 0) e_damp += quadratic(s, &s->M, s->w_damping * s->a, x, s->xt, g);
    if (s->w_damping * s->b != 0) e_damp += quadratic(s, &s->K0, s->w_damping * s->b, x, s->xt, g);
    double e_load = 0;
    for (int i = 0; i < s->n; i++) {
        e_load -= s->f[i] * x[i];
        if (g) g[i] -= s->f[i];
    }
    if (g)
        for (int i = 0; i < s->n; i++)
            if (s->prescribed[i]) g[i] = 0;
    if (magnitude) *magnitude = mag + fabs(e_in) + fabs(e_damp) + fabs(e_load);
    if (hessian) {
        /* the exact Newton matrix first; its elements projected to PSD only where it is not positive
         * definite (as the P1 Newton does). A failure is the solve's to report. */
        int st = newton_matrix(s, x, 0, &s->factor_err);
        if (st == RK_CHOL_NOT_POSDEF) {
            s->stats->projected_hessians++;
            st = newton_matrix(s, x, 1, &s->factor_err);
        }
        s->factored = st == 0;
    }
    return e_el + e_in + e_damp + e_load;
}

static int solve(void *ctx, const double *g, double *d, rk_error *err)
{
    p2_sim *s = ctx;
    if (!s->factored) {
        *err = s->factor_err;
        return rk_error_prefix(err, "P2 reference: the Newton matrix, its elements projected to PSD");
    }
    double *rhs = s->scratch;
    for (int i = 0; i < s->n; i++)
        if (s->free_of[i] >= 0) rhs[s->free_of[i]] = -g[i];
    double t0 = rk_now();
    int rc = rk_chol_solve(&s->chol, rhs, rhs, err);
    s->stats->seconds_solve += rk_now() - t0;
    if (rc) return -1;
    for (int i = 0; i < s->n; i++) d[i] = s->free_of[i] >= 0 ? rhs[s->free_of[i]] : 0;
    return 0;
}

static int refuse(const rk_fom_options *o, rk_error *err)
{
    if (o->is_static) return rk_fail(err, "P2 reference: a static solve is not supported (rk_p2_static_linear is)");
    if (o->nobstacles > 0) return rk_fail(err, "P2 reference: obstacles are not supported (%d given)", o->nobstacles);
    if (o->nobjects > 1) return rk_fail(err, "P2 reference: %d objects (contact between them) are not supported", o->nobjects);
    if (o->contact.self) return rk_fail(err, "P2 reference: self-contact is not supported");
    if (o->lumped_mass) return rk_fail(err, "P2 reference: a lumped mass is not supported (P2's has negative vertex rows)");
    if (o->nchambers > 0) return rk_fail(err, "P2 reference: pressure chambers are not supported (%d given)", o->nchambers);
    return 0;
}

/* Each node's prescribed group (-1: free): vertices as the groups list them, edge nodes where both
 * ends are in the same group; ends: the two vertices of each edge node. */
static void node_groups(const p2_sim *s, const rk_fom_options *o, int *group, int *ends)
{
    const rk_p2_mesh *p = &s->p2;
    for (int i = 0; i < p->nn; i++) group[i] = -1;
    for (int g = 0; g < o->nprescribed; g++)
        for (int k = 0; k < o->prescribed[g].count; k++) group[o->prescribed[g].verts[k]] = g;
    for (int t = 0; t < p->nt; t++)
        for (int k = 0; k < 6; k++) {
            int node = p->elem[10 * t + 4 + k], a = p->elem[10 * t + RK_P2_EDGE[k][0]],
                b = p->elem[10 * t + RK_P2_EDGE[k][1]];
            ends[2 * (node - p->nv)] = a;
            ends[2 * (node - p->nv) + 1] = b;
            if (group[a] >= 0 && group[a] == group[b]) group[node] = group[a];
        }
}

static void p2_sim_free(p2_sim *s)
{
    rk_chol_free(&s->chol);
    rk_sparse_free(&s->A);
    rk_sparse_free(&s->M);
    rk_sparse_free(&s->K0);
    rk_p2_mesh_free(&s->p2);
    free(s->free_of);
    free(s->prescribed);
    free(s->dL);
    free(s->f);
    free(s->scratch);
}

int rk_p2_fom_run(const rk_fem *fem, const rk_fom_options *opt, rk_p2_frame_fn frame, void *ctx, rk_fom_stats *stats,
                  rk_error *err)
{
    if (refuse(opt, err) || rk_fom_check_options(opt, fem->nv, err)) return -1;
    rk_fom_stats local;
    memset(&local, 0, sizeof local);
    p2_sim s;
    memset(&s, 0, sizeof s);
    s.fem = fem;
    s.stats = &local;
    rk_stepper st;
    memset(&st, 0, sizeof st);
    int *group = NULL, *ends = NULL, *all = NULL, rc = -1;
    double *x = NULL, *v = NULL, *work = NULL;
    double start = rk_now();
    rk_mesh view;
    memset(&view, 0, sizeof view);
    view.nv = fem->nv;
    view.nt = fem->nt;
    view.X = (double *)fem->X;
    view.tets = (int *)fem->tets;
    if (rk_p2_mesh_init(&s.p2, &view, err)) return -1;
    int nn = s.p2.nn, nv = fem->nv;
    s.n = 3 * nn;
    s.free_of = rk_calloc((size_t)s.n, sizeof(int), err);
    s.prescribed = rk_calloc((size_t)s.n, 1, err);
    s.dL = rk_calloc((size_t)fem->nt, sizeof *s.dL, err);
    s.f = rk_calloc((size_t)s.n, sizeof(double), err);
    s.scratch = rk_calloc((size_t)2 * s.n, sizeof(double), err);
    group = rk_calloc((size_t)nn, sizeof(int), err);
    ends = rk_calloc((size_t)2 * (nn - nv) + 1, sizeof(int), err);
    all = rk_calloc((size_t)s.n, sizeof(int), err);
    x = rk_calloc((size_t)s.n, sizeof(double), err);
    v = rk_calloc((size_t)s.n, sizeof(double), err);
    work = rk_calloc(RK_NEWTON_WORK(s.n), sizeof(double), err);
    if (!s.free_of || !s.prescribed || !s.dL || !s.f || !s.scratch || !group || !ends || !all || !x || !v || !work)
        goto out;
    node_groups(&s, opt, group, ends);
    for (int i = 0; i < nn; i++)
        for (int c = 0; c < 3; c++) {
            s.prescribed[3 * i + c] = group[i] >= 0;
            s.free_of[3 * i + c] = group[i] >= 0 ? -1 : s.nfree++;
        }
    if (s.nfree == 0) {
        rk_fail(err, "P2 reference: every node is prescribed");
        goto out;
    }
    s.a = opt->rayleigh_mass;
    s.b = opt->rayleigh_stiffness;
    /* M and K0 over every dof, free or not (all: the identity numbering), the Newton matrix over the free */
    for (int i = 0; i < s.n; i++) all[i] = i;
    if (rk_p2_pattern(&s.p2, all, s.n, &s.M, err) || (s.b != 0 && rk_p2_pattern(&s.p2, all, s.n, &s.K0, err)) ||
        rk_p2_pattern(&s.p2, s.free_of, s.nfree, &s.A, err))
        goto out;
    rk_p2_mass_element(1.0, 1.0, s.Mref);
    for (int t = 0; t < fem->nt; t++) {
        double Me[100], Mx[900] = {0};
        rk_p2_barycentric_gradients(&fem->Dm_inv[9 * t], s.dL[t]);
        for (int k = 0; k < 100; k++) Me[k] = fem->density[t] * fem->vol[t] * s.Mref[k];
        const int *nd = &s.p2.elem[10 * t];
        for (int a = 0; a < 10; a++)
            for (int b = 0; b < 10; b++)
                for (int c = 0; c < 3; c++) {
                    Mx[30 * (3 * a + c) + 3 * b + c] = Me[10 * a + b];
                    s.f[3 * nd[a] + c] += Me[10 * a + b] * opt->gravity[c];
                }
        rk_p2_scatter(&s.M, all, nd, Mx, 1.0);
        if (s.b != 0) {
            double zero[30] = {0}, K0[900];
            rk_p2_element_elastic(fem->model[t], fem->mu[t], fem->lambda[t], s.dL[t], fem->vol[t], zero, NULL, K0, 0);
            rk_p2_scatter(&s.K0, all, nd, K0, 1.0);
        }
    }
    if (opt->force)
        for (int k = 0; k < 3 * nv; k++) s.f[k] += opt->force[k];
    double t0 = rk_now();
    if (rk_chol_analyze(&s.chol, &s.A, err)) goto out;
    local.seconds_analyze_init = rk_now() - t0;
    local.analyses = 1;
    /* the start: the P1 state interpolated (an edge node midway between its ends) */
    for (int i = 0; i < nn; i++)
        for (int c = 0; c < 3; c++) {
            int k = 3 * i + c;
            if (i < nv) {
                x[k] = opt->position0 ? opt->position0[k] : fem->X[k];
                v[k] = opt->velocity0 ? opt->velocity0[k] : 0;
            } else {
                int a = ends[2 * (i - nv)], b = ends[2 * (i - nv) + 1];
                x[k] = opt->position0 ? 0.5 * (opt->position0[3 * a + c] + opt->position0[3 * b + c]) : s.p2.X[k];
                v[k] = opt->velocity0 ? 0.5 * (opt->velocity0[3 * a + c] + opt->velocity0[3 * b + c]) : 0;
            }
        }
    double tol = opt->newton_tol;
    if (tol <= 0) tol = RK_FOM_DEFAULT_TOL * rk_points_diagonal(fem->X, nv);
    int max_iter = rk_fom_max_iter(opt, 0);
    if (rk_stepper_init(&st, s.n, opt->integrator, opt->h, err)) goto out;
    rk_newton_problem prob = {.n = s.n, .ctx = &s, .what = "P2 incremental potential", .energy = energy,
                              .solve = solve, .prescribed = s.prescribed};
    if (frame && frame(ctx, 0, x, v, 0, err)) goto out;
    for (int step = 1; step <= opt->steps; step++) {
        double ts = rk_now(), time = step * opt->h;
        rk_stepper_predict(&st, x, v);
        s.w_inertia = st.w_inertia;
        s.w_damping = 1.0 / opt->h;
        s.xtilde = st.xtilde;
        s.xt = st.xt;
        memcpy(x, st.xtilde, (size_t)s.n * sizeof(double));
        for (int i = 0; i < nn; i++) {
            if (group[i] < 0) continue;
            double R[9], shift[3];
            rk_prescribed_transform(&opt->prescribed[group[i]], time, R, shift);
            const double *X = &s.p2.X[3 * i];
            for (int c = 0; c < 3; c++) x[3 * i + c] = R[3 * c] * X[0] + R[3 * c + 1] * X[1] + R[3 * c + 2] * X[2] + shift[c];
        }
        int converged;
        rk_newton_stats ns = {0, 0};
        if (rk_newton_solve(&prob, x, tol * opt->h, max_iter, work, &converged, &ns, err)) {
            rk_error_prefix(err, "P2 reference, step %d (t = %g s)", step, time);
            goto out;
        }
        rk_stepper_finish(&st, x, v);
        local.steps++;
        local.newton_iterations += ns.iterations;
        local.line_search_halvings += ns.halvings;
        local.unconverged_steps += !converged;
        if (frame && frame(ctx, step, x, v, rk_now() - ts, err)) goto out;
    }
    rc = 0;
out:
    local.seconds_total = rk_now() - start;
    if (stats) *stats = local;
    rk_stepper_free(&st);
    p2_sim_free(&s);
    free(group);
    free(ends);
    free(all);
    free(x);
    free(v);
    free(work);
    return rc;
}
