/* The adaptive linear ROM in the runtime (the adaptive-linear-rom-grassmann paper, Algorithms 1-4),
 * over the asset's stored vertices only and in fixed arena buffers. Before each step:
 *
 *   p = e(u)                          the quadratic decoder's encoder: Gauss-Newton on |g(p) - u|_M
 *   U = dg/dp (p)                     its Jacobian, Phi_k + sum_j Psi_kj p_j (Eq. 8)
 *   Phi_h = D P^T (P P^T + reg I)^-1  the last m steps' displacements D and codes P (Eq. 13)
 *   U_interp = Grassmann(Phi_h, U, lambda)   (Algorithm 4: thin QRs, the SVD of Q_Phi^T Q_U)
 *
 * then the reduced model's own Newton (step.c) in the incremental form x = x_ref + U_interp q
 * (Eq. 5-6), with M_r = U^T M U over the stored vertices' masses (the mesh's lumped mass gathered
 * onto them), C_r = a M_r, f_r = U^T f and the cubature elements' F = F(x_ref) + G_e q. The
 * prescribed vertices move to their targets in x_ref and their rows are zero, as in the
 * precompute's simulator (precompute/grassmann/alrom.c), which this reproduces when every vertex
 * is stored and the mass is lumped. Inner products are Euclidean over the stored rows. With a
 * CROM decoder (ALRH's decoder 1) the code is the encoder network's output and U the decoder
 * network's Jacobian at each stored vertex (forward mode), every vertex stored for the encoder.
 * With the quadratic decoder (issue 33) the state is in K-space: every basis is B C (B = [ROWS |
 * QDRV], R = r + pairs columns), the free part of u is B c and of v B w, the ring holds c_e, M_r,
 * the loads and U^T M (x~ - x_ref) come from Grams of B formed at open, and U's rows are formed
 * only at the vertices a step reads (al->sv); u_t is kept there and on the prescribed vertices,
 * the other shown vertices formed from c when read (rt_alrom_position).
 * With a basis cadence K (ALRH; issue 33) the first four lines run every K steps only, the basis
 * held between (a linear ROM's step, PCA's cost; bench/results/alrom_cadence.csv: cheaper, and
 * on the armadillo's bend less accurate).
 * This file: a step's reference, inertia and forces around the basis (alrom_basis.c, from the
 * decoders of alrom_decoder.c), the state moved on, reset, pushes, and saving the state; the
 * chunks are read in alrom_load.c. */
#include <math.h>
#include <string.h>

#include "runtime/alrom_impl.h"

/* ---- a step ---- */

static void reference_positions(romrt_model *m);

/* x_ref: where the step starts, the prescribed vertices moved to their targets at time t. */
static void place_prescribed(romrt_model *m, double t)
{
    rt_alrom *al = &m->al;
    int k, a, g;
    romrt_real R[ROMBIN_MAX_MOTIONS][9], shift[ROMBIN_MAX_MOTIONS][3];
    for (g = 0; g < al->nmotions; g++) {
        const romrt_real *p = al->motions + ROMBIN_PIN_PARAMS * (size_t)g;
        RT_PHYS(motion)((rk_motion_kind)(int)p[0], p + 1, p + 4, p[7], p + 8, t, R[g], shift[g]);
    }
    for (k = 0; k < al->npv; k++) {
        int v = (int)al->pv[k];
        uint32_t g2 = al->motion_of[v];
        const romrt_real *X = al->X0 + 3 * (size_t)v;
        for (a = 0; a < 3; a++)
            al->u_ref[3 * v + a] = (double)R[g2][3 * a] * X[0] + (double)R[g2][3 * a + 1] * X[1] +
                                   (double)R[g2][3 * a + 2] * X[2] + shift[g2][a] - X[a];
    }
}

/* Each cubature element's F - I at x_ref, from its vertices' displacements. */
static void element_offsets(romrt_model *m)
{
    rt_alrom *al = &m->al;
    int e, k, a, b, c;
    for (e = 0; e < m->ne; e++) {
        const uint32_t *ev = m->elem + 5 * (size_t)e;
        const romrt_real *Dm = m->elem_real + 12 * (size_t)e;
        double u[12];
        for (k = 0; k < 4; k++)
            for (a = 0; a < 3; a++) u[3 * k + a] = al->u_ref[3 * ev[k] + a];
        for (a = 0; a < 3; a++)
            for (b = 0; b < 3; b++) {
                double s = 0;
                for (c = 0; c < 3; c++) s += (u[3 * (c + 1) + a] - u[a]) * Dm[3 * c + b];
                al->Hd0[9 * (size_t)e + 3 * a + b] = (romrt_real)s;
            }
    }
}

/* M_r = U^T diag(mass) U (full), f_r = U^T (f + f_app), C_r = a M_r; qtilde = M_r^-1 U^T M (x~ - x_ref). */
static romrt_status reduced_terms(romrt_model *m, const double *xtilde, romrt_error *err)
{
    rt_alrom *al = &m->al;
    int r = m->r, n = 3 * m->nv, i, j, k;
    romrt_real *b = m->qtilde;
    for (k = 0; k < r * r; k++) al->M[k] = 0;
    for (k = 0; k < r; k++) al->f[k] = b[k] = 0;
    for (i = 0; i < n; i++) {
        const romrt_real *Ui = al->rows + (size_t)i * (size_t)r;
        romrt_real w = al->mass[i / 3], fi = al->load[i] + al->f_app[i], wd = w * (romrt_real)(xtilde[i] - al->u_ref[i]);
        for (k = 0; k < r; k++) {
            romrt_real wk = w * Ui[k];
            al->f[k] += fi * Ui[k];
            b[k] += wd * Ui[k];
            for (j = k; j < r; j++) al->M[k + (size_t)r * j] += wk * Ui[j];
        }
    }
    for (j = 0; j < r; j++)
        for (k = 0; k < j; k++) al->M[j + (size_t)r * k] = al->M[k + (size_t)r * j];
    for (k = 0; k < r * r; k++) al->C[k] = al->damping * al->M[k];
    memcpy(al->m_fac, al->M, sizeof(romrt_real) * (size_t)r * (size_t)r); /* (m->H: a kept Newton matrix) */
    if (rt_cholesky(r, al->m_fac))
        return rt_fail(err, ROMRT_E_DIVERGED, ROMBIN_VMSS, "the step basis has no mass on some direction (U^T M U is singular)");
    rt_cholesky_solve(r, al->m_fac, b);
    return ROMRT_OK;
}

/* The quadratic decoder's reduced terms in K-space (issue 33): with U = B C_s (al->cs, W_F C_s in
 * al->wcs, alrom_basis.c) and the free parts of u and x~ B c and B c~, M_r = C_s^T W_F C_s,
 * U^T M (x~ - x_ref) = (W_F C_s)^T (c~ - c) and f_r = C_s^T B^T (f + f_app) over the free rows
 * (B^T f baked at open, the app's forces gathered where they are nonzero): the same sums as
 * reduced_terms without a pass of n r^2 over the rows. */
static romrt_status reduced_terms_k(romrt_model *m, int bdf2, int held, romrt_error *err)
{
    rt_alrom *al = &m->al;
    int r = m->r, R = r + al->pairs, n = 3 * m->nv, i, j, k;
    double *dc = al->ext, *fc = al->ext + R, h = m->h;
    romrt_real *b = m->qtilde;
    for (k = 0; k < R; k++) {
        double ct = bdf2 ? (4 * al->c[k] - al->c_prev[k]) / 3 + 2 * h / 9 * (4 * al->w[k] - al->w_prev[k])
                         : al->c[k] + h * al->w[k];
        dc[k] = ct - al->c[k];
        fc[k] = al->load_c[k];
    }
    for (i = 0; i < n; i++) {
        double fa = al->f_app[i];
        if (fa == 0 || rt_alrom_prescribed(al, i)) continue;
        for (k = 0; k < r; k++) fc[k] += fa * (double)al->phi[(size_t)i * (size_t)r + (size_t)k];
        for (k = 0; k < al->pairs; k++) fc[r + k] += fa * (double)al->psi[(size_t)i * (size_t)al->pairs + (size_t)k];
    }
    for (j = 0; j < r; j++) {
        const double *cj = al->cs + (size_t)R * (size_t)j, *wj = al->wcs + (size_t)R * (size_t)j;
        double sb = 0, sf = 0;
        for (i = 0; i < R; i++) {
            sb += wj[i] * dc[i];
            sf += cj[i] * fc[i];
        }
        b[j] = (romrt_real)sb;
        al->f[j] = (romrt_real)sf;
        for (k = 0; k <= j && !held; k++) { /* (a held basis' M_r, C_r and factor are kept) */
            const double *ck = al->cs + (size_t)R * (size_t)k;
            double s = 0;
            for (i = 0; i < R; i++) s += ck[i] * wj[i];
            al->M[k + (size_t)r * j] = al->M[j + (size_t)r * k] = (romrt_real)s;
        }
    }
    if (!held) {
        for (k = 0; k < r * r; k++) al->C[k] = al->damping * al->M[k];
        memcpy(al->m_fac, al->M, sizeof(romrt_real) * (size_t)r * (size_t)r); /* (m->H: a kept Newton matrix) */
        if (rt_cholesky(r, al->m_fac))
            return rt_fail(err, ROMRT_E_DIVERGED, ROMBIN_VMSS, "the step basis has no mass on some direction (U^T M U is singular)");
    }
    rt_cholesky_solve(r, al->m_fac, b);
    return ROMRT_OK;
}

/* u_new's row i: u_ref + U_i q (U's row there, formed on the used vertices and zero on the
 * prescribed, as the step read it). */
static void u_step(romrt_model *m, int i)
{
    rt_alrom *al = &m->al;
    const romrt_real *row = al->rows + (size_t)i * (size_t)m->r;
    double du = 0;
    int j;
    for (j = 0; j < m->r && !rt_alrom_prescribed(al, i); j++) du += (double)row[j] * m->q[j];
    al->u_new[i] = al->u_ref[i] + du;
}

/* The collision vertices used from this step on (a collider set, or the asset's collision
 * surface), or no longer: their displacements and the ring's entries there formed from the
 * K-space state once, when they are taken up. */
void rt_alrom_take_collision_vertices(romrt_model *m)
{
    rt_alrom *al = &m->al;
    int k, a, e, slots = al->m + 1;
    if (al->decoder || al->ns_on == al->ns) return;
    for (k = al->ns_base; k < al->ns; k++)
        for (a = 0; a < 3; a++) {
            int i = 3 * (int)al->sv[k] + a;
            if (rt_alrom_prescribed(al, i)) continue; /* held already */
            al->u_t[i] = al->u_ref[i] = rt_alrom_b_dot(m, i, al->c); /* between steps: u_ref = u_t */
            for (e = 1; e <= al->count; e++) { /* the held entries, newest first */
                size_t slot = (size_t)((al->head - e + slots) % slots);
                *rt_alrom_ds(al, (int)slot, 3 * k + a) = rt_alrom_b_dot(m, i, al->D + slot * (size_t)(m->r + al->pairs));
            }
        }
    al->ns_on = al->ns;
    reference_positions(m);
}

void rt_alrom_position(const romrt_model *m, uint32_t v, romrt_real x[3])
{
    const rt_alrom *al = &m->al;
    int a;
    for (a = 0; a < 3; a++) {
        int i = 3 * (int)v + a;
        x[a] = rt_alrom_held(al, (int)v) ? al->x_ref[i] : (romrt_real)(al->X0[i] + rt_alrom_b_dot(m, i, al->c));
    }
}

void rt_alrom_row(const romrt_model *m, uint32_t v, int a, romrt_real *out)
{
    const rt_alrom *al = &m->al;
    int i = 3 * (int)v + a, r = m->r, R = r + al->pairs, j;
    if (al->decoder || rt_alrom_prescribed(al, i)) { /* CROM forms every row; prescribed rows are zero */
        rt_row(m, v, a, out);
        return;
    }
    for (j = 0; j < r; j++) out[j] = (romrt_real)rt_alrom_b_dot(m, i, al->cs + (size_t)R * (size_t)j);
}

/* x_ref = X0 + u_ref (the model's X, for positions and contacts), and the shown positions' bound
 * rt_showable checks (q is 0 between steps, and the rows orthonormal within one). */
static void reference_positions(romrt_model *m)
{
    rt_alrom *al = &m->al;
    size_t n = 3 * (size_t)m->nv, k;
    m->x_bound = 0;
    if (al->decoder) {
        for (k = 0; k < n; k++) al->x_ref[k] = (romrt_real)(al->X0[k] + al->u_ref[k]);
        for (k = 0; k < 3 * (size_t)m->shown; k++)
            if (fabs((double)al->x_ref[k]) > m->x_bound) m->x_bound = fabs((double)al->x_ref[k]);
    }
    for (k = 0; !al->decoder && k < (size_t)(al->ns_on + al->npv); k++) { /* the held vertices' */
        size_t v = (size_t)rt_alrom_held_vertex(al, (int)k), i;
        for (i = 3 * v; i < 3 * v + 3; i++) {
            al->x_ref[i] = (romrt_real)(al->X0[i] + al->u_ref[i]);
            if (v < (size_t)m->shown && fabs((double)al->x_ref[i]) > m->x_bound) m->x_bound = fabs((double)al->x_ref[i]);
        }
    }
    if (!al->decoder) { /* the others', X0 + B c: |B_i c| <= sum |B_i| max |c| */
        int R = m->r + al->pairs, a;
        double top = 0;
        for (a = 0; a < R; a++) top = fabs(al->c[a]) > top ? fabs(al->c[a]) : top;
        if (al->x0_max + al->b_sum * top > m->x_bound) m->x_bound = al->x0_max + al->b_sum * top;
    }
}

romrt_status rt_alrom_begin(romrt_model *m, romrt_real *w_inertia, romrt_error *err)
{
    rt_alrom *al = &m->al;
    int n = 3 * m->nv, r = m->r, i, bdf2 = m->integrator == 1 && m->have_prev;
    romrt_real h = m->h;
    double *xtilde = al->res;
    romrt_status st;
    if (!al->decoder && !rt_surface_on(m) && !m->ncolliders) al->ns_on = al->ns_base;
    else rt_alrom_take_collision_vertices(m);
    /* the basis refreshed every K steps (ALRH's cadence), and whenever the used rows changed or a
     * step failed or the state was set: between refreshes the step is a fixed-basis linear ROM's,
     * PCA's step in the held basis (its rows, G_e and M_r kept; issue 33: the encoder, history,
     * Grassmann point and rows were four fifths of the step) */
    al->refreshed = al->since < 0 || al->since >= al->cadence || al->ns_on != al->held_ns;
    if (al->refreshed) {
        RT_PROF_BEGIN(RT_PROF_ALROM_BASIS);
        st = rt_alrom_step_basis(m, err);
        RT_PROF_END(RT_PROF_ALROM_BASIS);
        if (st) return st;
        al->held_ns = al->ns_on;
    }
    /* the step's reference: the start with the prescribed vertices at their targets */
    rt_alrom_copy_held(m, al->u_ref, al->u_t);
    place_prescribed(m, rt_clock(m, 1));
    reference_positions(m);
    element_offsets(m);
    *w_inertia = bdf2 ? RT_K(9.0) / (RT_K(4.0) * h * h) : 1 / (h * h);
    if (!al->decoder) {
        if ((st = reduced_terms_k(m, bdf2, !al->refreshed, err))) return st;
        /* a Newton matrix kept from an earlier step, into this step's basis (alrom_keep.c; in a
         * held basis it is in this step's coordinates already) */
        if (al->refreshed && m->hessian_age >= 0 && rt_alrom_keep_carry(m, *w_inertia)) m->hessian_age = -1;
    } else {
        for (i = 0; i < n; i++)
            xtilde[i] = bdf2 ? (4 * al->u_t[i] - al->u_prev[i]) / 3 + 2 * (double)h / 9 * (4 * al->v[i] - al->v_prev[i])
                             : al->u_t[i] + (double)h * al->v[i];
        if ((st = reduced_terms(m, xtilde, err))) return st;
    }
    m->C = al->damping > 0 ? al->C : 0;
    for (i = 0; i < r; i++) m->q[i] = m->v[i] = m->f_app[i] = 0;
    return ROMRT_OK;
}

/* A step kept: the ring takes the entry its refresh wrote (a refresh's state and code: with a
 * cadence K the history's m entries are K steps apart), and the held basis' age. */
static void advance(rt_alrom *al)
{
    if (al->refreshed) {
        al->head = (al->head + 1) % (al->m + 1);
        if (al->count < al->m) al->count++;
        al->since = 0;
    }
    al->since++;
}

/* The quadratic decoder's step kept: c += C_s q, w as v is (the free parts of u and v in K-space),
 * and u over the stored rows u_ref + B (C_s q) (zero on the prescribed, which rt_alrom_begin
 * placed). */
static romrt_status commit_k(romrt_model *m, int bdf2, romrt_error *err)
{
    rt_alrom *al = &m->al;
    int r = m->r, R = r + al->pairs, i, j, k;
    double h = m->h, *dq = al->ext, *c_new = al->ext + R, *w_new = al->ext + 2 * R;
    for (i = 0; i < R; i++) {
        double s = 0;
        for (j = 0; j < r; j++) s += al->cs[(size_t)R * (size_t)j + (size_t)i] * (double)m->q[j];
        dq[i] = s;
        c_new[i] = al->c[i] + s;
        w_new[i] = bdf2 ? (3 * c_new[i] - 4 * al->c[i] + al->c_prev[i]) / (2 * h) : s / h;
        if (!isfinite(c_new[i]) || !isfinite(w_new[i]))
            return rt_fail_n(err, ROMRT_E_DIVERGED, 0, "K-space coordinate ", (uint64_t)i, " is not finite after the step");
    }
    for (k = 0; k < al->ns_on + al->npv; k++) { /* the held rows; the others are B c (rt_alrom_position) */
        int i0 = 3 * rt_alrom_held_vertex(al, k);
        for (i = i0; i < i0 + 3; i++) {
            u_step(m, i);
            if (!isfinite(al->u_new[i]) || !isfinite(al->u_new[i] + al->X0[i]))
                return rt_fail_n(err, ROMRT_E_DIVERGED, 0, "stored coordinate ", (uint64_t)i, " is not finite after the step");
        }
    }
    for (i = 0; i < 2 * R; i++) { /* as the state's pairs hold them, so that a saved state's u and v,
                                   * formed from c and w, come back the same (rt_alrom_get_state) */
        romrt_real pair[2];
        rt_split(c_new[i], pair);
        c_new[i] = (double)pair[0] + (double)pair[1];
    }
    memcpy(al->c_prev, al->c, sizeof(double) * (size_t)R);
    memcpy(al->w_prev, al->w, sizeof(double) * (size_t)R);
    memcpy(al->c, c_new, sizeof(double) * (size_t)R);
    memcpy(al->w, w_new, sizeof(double) * (size_t)R);
    rt_alrom_copy_held(m, al->u_t, al->u_new);
    rt_alrom_copy_held(m, al->u_ref, al->u_new);
    reference_positions(m);
    rt_alrom_keep_note(m); /* the coordinates a kept Newton matrix is in */
    advance(al);
    for (i = 0; i < r; i++) m->q[i] = 0;
    return ROMRT_OK;
}

romrt_status rt_alrom_commit(romrt_model *m, romrt_error *err)
{
    rt_alrom *al = &m->al;
    int n = 3 * m->nv, r = m->r, i, bdf2 = m->integrator == 1 && m->have_prev;
    double h = m->h, *u_new = al->u_new, *v_new = al->v_new;
    if (!al->decoder) return commit_k(m, bdf2, err);
    for (i = 0; i < n; i++) {
        const romrt_real *row = al->rows + (size_t)i * (size_t)r;
        double du = 0;
        int j;
        for (j = 0; j < r; j++) du += (double)row[j] * m->q[j];
        u_new[i] = al->u_ref[i] + du;
        v_new[i] = bdf2 ? (3 * u_new[i] - 4 * al->u_t[i] + al->u_prev[i]) / (2 * h) : (u_new[i] - al->u_t[i]) / h;
        if (!isfinite(u_new[i]) || !isfinite(v_new[i]) || !isfinite(u_new[i] + al->X0[i]))
            return rt_fail_n(err, ROMRT_E_DIVERGED, 0, "stored coordinate ", (uint64_t)i, " is not finite after the step");
    }
    memcpy(al->u_prev, al->u_t, sizeof(double) * (size_t)n);
    memcpy(al->v_prev, al->v, sizeof(double) * (size_t)n);
    memcpy(al->u_t, u_new, sizeof(double) * (size_t)n);
    memcpy(al->v, v_new, sizeof(double) * (size_t)n);
    memcpy(al->u_ref, u_new, sizeof(double) * (size_t)n);
    reference_positions(m);
    advance(al);
    for (i = 0; i < r; i++) m->q[i] = 0;
    return ROMRT_OK;
}

void rt_alrom_abort(romrt_model *m)
{
    rt_alrom *al = &m->al;
    int n = 3 * m->nv, k;
    memcpy(al->u_ref, al->u_t, sizeof(double) * (size_t)n);
    reference_positions(m);
    for (k = 0; k < m->r; k++) m->q[k] = 0;
    m->hessian_age = -1; /* a kept Newton matrix may be in the failed step's basis */
    al->since = -1;      /* and the next step's basis formed afresh */
}

void rt_alrom_reset(romrt_model *m)
{
    rt_alrom *al = &m->al;
    size_t n = 3 * (size_t)m->nv;
    memset(al->u_t, 0, sizeof(double) * n);
    memset(al->u_ref, 0, sizeof(double) * n);
    memset(al->v, 0, sizeof(double) * n);
    memset(al->u_prev, 0, sizeof(double) * n);
    memset(al->v_prev, 0, sizeof(double) * n);
    memset(al->f_app, 0, sizeof(romrt_real) * n);
    memset(al->Hd0, 0, sizeof(romrt_real) * 9 * (size_t)m->ne);
    al->count = al->head = al->dd_valid = 0;
    al->since = -1;
    if (!al->decoder) {
        al->ns_on = al->ns_base;
        size_t R = (size_t)(m->r + al->pairs);
        memset(al->c, 0, sizeof(double) * R);
        memset(al->w, 0, sizeof(double) * R);
        memset(al->c_prev, 0, sizeof(double) * R);
        memset(al->w_prev, 0, sizeof(double) * R);
    }
    reference_positions(m); /* the rest */
    /* until the first step, the decoder's linear part (orthonormalised by that step) */
    memcpy(al->rows, al->phi, sizeof(romrt_real) * n * (size_t)m->r);
    {
        size_t i;
        for (i = 0; i < n; i++)
            if (rt_alrom_prescribed(al, (int)i)) memset(al->rows + i * (size_t)m->r, 0, sizeof(romrt_real) * (size_t)m->r);
    }
    m->X = al->x_ref;
    m->rows = al->rows;
    m->force_rows = al->rows;
    m->M = al->M;
    m->f = al->f;
    m->C = 0;
    /* positions are x_ref + rows q with q = 0 between steps and orthonormal rows within one */
    m->row_bound = m->r;
    rt_form_element_G(m); /* G_e follows the rows (potential.c) */
}

int rt_alrom_push(romrt_model *m, uint32_t v, const romrt_real f[3], int apply)
{
    romrt_real *fa = m->al.f_app + 3 * (size_t)v;
    int a;
    for (a = 0; a < 3; a++)
        if (!isfinite(fa[a] + f[a])) return -1;
    for (a = 0; a < 3 && apply; a++) fa[a] += f[a];
    return 0;
}
/* The state after the clock and have_prev (access.c): the ring's count and head, then as pairs
 * (rt_split: the state is double in either build) u_t, then with the quadratic decoder its K-space
 * c, w, c_prev, w_prev, the ring's coordinates and their used rows, with a CROM v, u_prev, v_prev
 * and the ring's D, then P,
 * then the applied forces (romrt_real, as the app gave them). */
int rt_alrom_state_size(const romrt_model *m)
{
    const rt_alrom *al = &m->al;
    int n = 3 * m->nv, slots = al->m + 1, R = m->r + al->pairs;
    if (!al->decoder) /* u_t, v (formed), c, w, c_prev, w_prev, the ring's c_e and P */
        return 2 + 2 * (2 * n + 4 * R + slots * (R + m->r)) + n;
    return 2 + 2 * (4 * n + slots * (n + m->r)) + n;
}

static romrt_real *put(romrt_real *s, const double *x, size_t count)
{
    size_t i;
    for (i = 0; i < count; i++, s += 2) rt_split(x[i], s);
    return s;
}

static const romrt_real *take(const romrt_real *s, double *x, size_t count)
{
    size_t i;
    for (i = 0; i < count; i++, s += 2) x[i] = (double)s[0] + (double)s[1];
    return s;
}

void rt_alrom_get_state(const romrt_model *m, romrt_real *s)
{
    const rt_alrom *al = &m->al;
    size_t n = 3 * (size_t)m->nv, slots = (size_t)al->m + 1, k;
    *s++ = (romrt_real)al->count;
    *s++ = (romrt_real)al->head;
    if (!al->decoder) { /* u and v formed from c and w on the free rows (what a restore reads) */
        size_t R = (size_t)(m->r + al->pairs);
        for (k = 0; k < n; k++, s += 2)
            rt_split(rt_alrom_prescribed(al, (int)k) ? al->u_t[k] : rt_alrom_b_dot(m, (int)k, al->c), s);
        for (k = 0; k < n; k++, s += 2) rt_split(rt_alrom_prescribed(al, (int)k) ? 0 : rt_alrom_b_dot(m, (int)k, al->w), s);
        s = put(s, al->c, R);
        s = put(s, al->w, R);
        s = put(s, al->c_prev, R);
        s = put(s, al->w_prev, R);
        s = put(s, al->D, slots * R);
    } else {
        s = put(s, al->u_t, n);
        s = put(s, al->v, n);
        s = put(s, al->u_prev, n);
        s = put(s, al->v_prev, n);
        s = put(s, al->D, slots * n);
    }
    s = put(s, al->P, slots * (size_t)m->r);
    memcpy(s, al->f_app, sizeof(romrt_real) * n);
}

int rt_alrom_set_state(romrt_model *m, const romrt_real *s)
{
    rt_alrom *al = &m->al;
    size_t n = 3 * (size_t)m->nv, slots = (size_t)al->m + 1, k;
    romrt_real count = s[0], head = s[1];
    if (!(count >= 0 && count <= al->m && count == (romrt_real)(int)count) ||
        !(head >= 0 && head <= al->m && head == (romrt_real)(int)head))
        return -1;
    for (k = 0; k < n; k++) /* positions that would not be representable */
        if (!((double)s[2 + 2 * k] + al->X0[k] < 1e30 && (double)s[2 + 2 * k] + al->X0[k] > -1e30)) return -1;
    al->count = (int)count;
    al->head = (int)head;
    s += 2;
    s = take(s, al->u_t, n);
    if (!al->decoder) { /* c is the state; u's free rows and v are B c and B w (get_state) */
        size_t R = (size_t)(m->r + al->pairs);
        s = take(s, al->res, n);
        s = take(s, al->c, R);
        s = take(s, al->w, R);
        s = take(s, al->c_prev, R);
        s = take(s, al->w_prev, R);
        s = take(s, al->D, slots * R);
    } else {
        s = take(s, al->v, n);
        s = take(s, al->u_prev, n);
        s = take(s, al->v_prev, n);
        s = take(s, al->D, slots * n);
    }
    s = take(s, al->P, slots * (size_t)m->r);
    memcpy(al->f_app, s, sizeof(romrt_real) * n);
    al->dd_valid = 0; /* the ring's inner products, from the restored entries */
    if (!al->decoder) { /* the used rows of u and of the ring's entries formed from K-space */
        int e, j2;
        al->ns_on = al->ns_base;
        for (k = 0; k < (size_t)al->ns_base; k++)
            for (j2 = 0; j2 < 3; j2++) {
                int i = 3 * (int)al->sv[k] + j2;
                if (rt_alrom_prescribed(al, i)) continue;
                al->u_t[i] = rt_alrom_b_dot(m, i, al->c);
                for (e = 1; e <= al->count; e++) {
                    size_t slot = (size_t)((al->head - e + (int)slots) % (int)slots);
                    *rt_alrom_ds(al, (int)slot, 3 * (int)k + j2) = rt_alrom_b_dot(m, i, al->D + slot * (size_t)(m->r + al->pairs));
                }
            }
    }
    rt_alrom_abort(m); /* x_ref, its bound and q from u_t */
    return 0;
}
