/* The reduced incremental potential the runtime minimises each step, term by term as the
 * precompute's reduced simulator (precompute/rom/potential.c), with the elastic energy over the
 * asset's cubature elements computed from their vertices' basis rows:
 *
 *   F_e = I + G_e q,  G_e row (3a + b) = sum_c Dm^-1_cb (B_{v_c+1, a} - B_{v_0, a})   (cubature.h)
 *   E = sum_e w_e Psi(F_e),  g = sum_e w_e G_e^T P_e,  H = sum_e w_e G_e^T dP/dF_e G_e. */
#include <math.h>

#include "runtime/romrt_impl.h"

static const romrt_real *row_of(const romrt_model *m, uint32_t v, int a)
{
    return m->rows + ((size_t)3 * v + (size_t)a) * (size_t)m->r;
}

/* The displacement gradient Hd = F - I of element e at q (kept apart from I: physics_impl.h). */
static void element_H(const romrt_model *m, int e, const romrt_real *q, romrt_real Hd[9])
{
    const uint32_t *ev = m->elem + 5 * (size_t)e;
    const romrt_real *Dm = m->elem_real + 12 * (size_t)e;
    romrt_real u[12];
    int k, a, b, c;
    for (k = 0; k < 4; k++)
        for (a = 0; a < 3; a++) u[3 * k + a] = rt_dot(m->r, row_of(m, ev[k], a), q);
    for (a = 0; a < 3; a++)
        for (b = 0; b < 3; b++) {
            romrt_real s = 0;
            for (c = 0; c < 3; c++) s += (u[3 * (c + 1) + a] - u[a]) * Dm[3 * c + b];
            Hd[3 * a + b] = s;
        }
    if (m->alrom) /* the incremental form: F = F(x_ref) + G_e q */
        for (k = 0; k < 9; k++) Hd[k] += m->al.Hd0[9 * (size_t)e + k];
}

/* The element kernels take their rows as restrict-qualified arguments: that is what lets the
 * compiler vectorize them (through the model's fields it cannot prove the rows apart). */

/* G rows 3a, 3a+1, 3a+2 = Dm^-T (r1 - r0, r2 - r0, r3 - r0) over r columns, zero to rp. */
static void g_rows(int r, int rp, const romrt_real *RT_RESTRICT r0, const romrt_real *RT_RESTRICT r1,
                   const romrt_real *RT_RESTRICT r2, const romrt_real *RT_RESTRICT r3, const romrt_real *RT_RESTRICT Dm,
                   romrt_real *RT_RESTRICT G0, romrt_real *RT_RESTRICT G1, romrt_real *RT_RESTRICT G2)
{
    int j;
    for (j = 0; j < r; j++) {
        romrt_real e1 = r1[j] - r0[j], e2 = r2[j] - r0[j], e3 = r3[j] - r0[j];
        G0[j] = e1 * Dm[0] + e2 * Dm[3] + e3 * Dm[6];
        G1[j] = e1 * Dm[1] + e2 * Dm[4] + e3 * Dm[7];
        G2[j] = e1 * Dm[2] + e2 * Dm[5] + e3 * Dm[8];
    }
    for (; j < rp; j++) G0[j] = G1[j] = G2[j] = 0;
}

/* G = G_e (9 rows of RT_PAD(r), row-major, zero past r), in one pass over the element's four
 * vertex rows: G row 3a + b = sum_c Dm^-1_cb (B_{v_c+1, a} - B_{v_0, a}). */
static void element_G(const romrt_model *m, int e, romrt_real *G)
{
    const uint32_t *ev = m->elem + 5 * (size_t)e;
    int rp = RT_PAD(m->r), a;
    for (a = 0; a < 3; a++) {
        romrt_real *G0 = G + (size_t)rp * (3 * a);
        g_rows(m->r, rp, row_of(m, ev[0], a), row_of(m, ev[1], a), row_of(m, ev[2], a), row_of(m, ev[3], a),
               m->elem_real + 12 * (size_t)e, G0, G0 + rp, G0 + 2 * rp);
    }
}

/* out = sum_l a_l G_l over rp columns. */
static void combine9(int rp, const romrt_real *RT_RESTRICT G, const romrt_real *RT_RESTRICT a, romrt_real *RT_RESTRICT out)
{
    int j;
    for (j = 0; j < rp; j++)
        out[j] = a[0] * G[j] + a[1] * G[rp + j] + a[2] * G[2 * rp + j] + a[3] * G[3 * rp + j] + a[4] * G[4 * rp + j] +
                 a[5] * G[5 * rp + j] + a[6] * G[6 * rp + j] + a[7] * G[7 * rp + j] + a[8] * G[8 * rp + j];
}

/* m->AG = w dP/dF G (9 rows of RT_PAD(r)). */
static void element_AG(romrt_model *m, const romrt_real *G, const romrt_real A[81], romrt_real w)
{
    int rp = RT_PAD(m->r), k, l;
    for (k = 0; k < 9; k++) {
        romrt_real a[9];
        for (l = 0; l < 9; l++) a[l] = w * A[9 * k + l];
        combine9(rp, G, a, m->AG + (size_t)rp * k);
    }
}

/* H0 += G^T a, H1 += G^T b over the first len rows: two columns of a rank-9 update, each load of
 * G serving both. */
static void rank9_pair(int len, int rp, const romrt_real *RT_RESTRICT G, const romrt_real *RT_RESTRICT a,
                       const romrt_real *RT_RESTRICT b, romrt_real *RT_RESTRICT H0, romrt_real *RT_RESTRICT H1)
{
    int i;
    for (i = 0; i < len; i++) {
        romrt_real g0 = G[i], g1 = G[rp + i], g2 = G[2 * rp + i], g3 = G[3 * rp + i], g4 = G[4 * rp + i],
                   g5 = G[5 * rp + i], g6 = G[6 * rp + i], g7 = G[7 * rp + i], g8 = G[8 * rp + i];
        H0[i] += g0 * a[0] + g1 * a[1] + g2 * a[2] + g3 * a[3] + g4 * a[4] + g5 * a[5] + g6 * a[6] + g7 * a[7] + g8 * a[8];
        H1[i] += g0 * b[0] + g1 * b[1] + g2 * b[2] + g3 * b[3] + g4 * b[4] + g5 * b[5] + g6 * b[6] + g7 * b[7] + g8 * b[8];
    }
}

/* m->He (RT_PAD(r) square, column-major) += G^T AG over its upper triangle, rounded up to whole
 * vectors: a single rank-9 pass over the matrix per element (nine rank-1 passes would stream it
 * through the cache nine times). */
static void element_hessian(romrt_model *m, const romrt_real *G)
{
    int rp = RT_PAD(m->r), j, k;
    for (j = 0; j < rp; j += 2) {
        romrt_real a[9], b[9];
        for (k = 0; k < 9; k++) {
            a[k] = m->AG[(size_t)rp * k + j];
            b[k] = m->AG[(size_t)rp * k + j + 1];
        }
        rank9_pair(RT_PAD(j + 2), rp, G, a, b, m->He + (size_t)rp * j, m->He + (size_t)rp * (j + 1));
    }
}

/* The material of element e (ELEM, ELMR), or of integration point e - ne (IPMD, IPNT): its mu and
 * lambda at lame[0..1]. */
rk_material_model rt_material(const romrt_model *m, int e, const romrt_real **lame)
{
    if (e < m->ne) {
        *lame = m->elem_real + 12 * (size_t)e + 10;
        return (rk_material_model)m->elem[5 * (size_t)e + 4];
    }
    *lame = m->pt + (6 + 4 * (size_t)m->skin) * (size_t)(e - m->ne) + 4;
    return (rk_material_model)m->pt_model[e - m->ne];
}

romrt_real rt_point_weight(const romrt_model *m, int e)
{
    return e < m->ne ? m->elem_real[12 * (size_t)e + 9] : m->pt[(6 + 4 * (size_t)m->skin) * (size_t)(e - m->ne) + 3];
}

/* With a projected volume (VPRS) lambda is carried by rt_volume_gather's 1/2 |c|^2, and each
 * element or point adds its pressure p_e's terms: p_e dtheta/dF to P, p_e d2theta/dF2 to A. */
romrt_real rt_element_psi(const romrt_model *m, int e, const romrt_real Hd[9])
{
    const romrt_real *lame;
    rk_material_model model = rt_material(m, e, &lame);
    return RT_PHYS(psi_h)(model, lame[0], m->vk ? 0 : lame[1], Hd);
}

void rt_element_stress(const romrt_model *m, int e, const romrt_real Hd[9], romrt_real *P, romrt_real *A)
{
    const romrt_real *lame;
    rk_material_model model = rt_material(m, e, &lame);
    romrt_real F[9], lambda = m->vk ? 0 : lame[1], p = m->vk ? m->vp[e] : 0;
    int k;
    if (P) RT_PHYS(pk1_h)(model, lame[0], lambda, Hd, P);
    if (P && m->vk) {
        romrt_real dth[9];
        RT_PHYS(volume_h)(model, Hd, dth);
        for (k = 0; k < 9; k++) P[k] += p * dth[k];
    }
    if (!A) return;
    for (k = 0; k < 9; k++) F[k] = Hd[k] + (romrt_real)(k % 4 == 0);
    RT_PHYS(dpdf_p)(model, lame[0], lambda, p, F, A, !m->exact_hessian);
}

void rt_form_element_G(romrt_model *m)
{
    int e;
    for (e = 0; m->G_all && e < m->ne; e++) element_G(m, e, m->G_all + (size_t)9 * RT_PAD(m->r) * (size_t)e);
}

/* Hd = F - I = G q over the formed G's rows (9 dot products); an adaptive basis's incremental form
 * adds F(x_ref) - I (element_H). */
static void element_H_formed(const romrt_model *m, int e, const romrt_real *q, romrt_real Hd[9])
{
    int k, r = m->r;
    const romrt_real *G = m->G_all + (size_t)9 * RT_PAD(r) * (size_t)e;
    for (k = 0; k < 9; k++) Hd[k] = rt_dot(r, G + (size_t)RT_PAD(r) * k, q);
    if (m->alrom)
        for (k = 0; k < 9; k++) Hd[k] += m->al.Hd0[9 * (size_t)e + k];
}

/* Element e's Hd at q, as elastic() forms it (rt_volume_gather's pass). */
static void element_Hd(romrt_model *m, int e, const romrt_real *q, romrt_real Hd[9])
{
    if (m->G_all) element_H_formed(m, e, q, Hd);
    else element_H(m, e, q, Hd);
}

static romrt_real elastic(romrt_model *m, const romrt_real *q, romrt_real *g, romrt_real *H, int ld)
{
    int r = m->r, rp = RT_PAD(r), e, i, j, k;
    romrt_real E = 0;
    if (m->skin) return rt_skin_elastic(m, q, g, H, ld);
    if (m->vk) {
        E = rt_volume_gather(m, q, H != 0, element_Hd);
        if (!isfinite(E)) return (romrt_real)INFINITY;
    }
    if (H)
        for (i = 0; i < rp * rp; i++) m->He[i] = 0;
    for (e = 0; e < m->ne; e++) {
        romrt_real Hd[9], P[9], A[81], w = m->elem_real[12 * (size_t)e + 9], psi;
        const romrt_real *G = m->G_all ? m->G_all + (size_t)9 * rp * (size_t)e : m->G;
        /* F - I by the same arithmetic whether or not the gradient is asked, so the line search
         * compares energies computed alike: G q with G formed at open, else from the vertices'
         * displacements (12 dot products) */
        if (m->vk) /* formed by rt_volume_gather */
            for (k = 0; k < 9; k++) Hd[k] = m->vHd[9 * (size_t)e + k];
        else if (m->G_all) element_H_formed(m, e, q, Hd);
        else element_H(m, e, q, Hd);
        psi = rt_element_psi(m, e, Hd);
        if (!isfinite(psi)) return (romrt_real)INFINITY;
        E += w * psi;
        if (!g && !H) continue;
        if (!m->G_all) element_G(m, e, m->G);
        rt_element_stress(m, e, Hd, g ? P : 0, H ? A : 0);
        if (g) {
            for (k = 0; k < 9; k++) {
                const romrt_real *Gk = G + (size_t)rp * k;
                romrt_real wp = w * P[k];
                for (j = 0; j < r; j++) g[j] += wp * Gk[j];
            }
        }
        if (H) {
            element_AG(m, G, A, w);
            element_hessian(m, G);
        }
        if (H && m->vk) { /* dtheta/dq = G^T dtheta/dF */
            const romrt_real *lame;
            romrt_real dth[9];
            RT_PHYS(volume_h)(rt_material(m, e, &lame), Hd, dth);
            combine9(rp, G, dth, m->vt);
            rt_volume_add(m, e, w, m->vt);
        }
    }
    if (H)
        for (j = 0; j < r; j++)
            for (i = 0; i <= j; i++) H[i + (size_t)ld * j] += m->He[i + (size_t)rp * j];
    if (H && m->vk) rt_volume_hessian(m, H, ld);
    return E;
}

/* a = the gradient of contact c's distance (n . B_v), into out (r). */
static void contact_gradient(const romrt_model *m, int c, romrt_real *out)
{
    uint32_t v = m->contacts[2 * (size_t)c];
    const romrt_real *n = m->planes + 6 * (size_t)m->contacts[2 * (size_t)c + 1] + 3;
    int j, a;
    for (j = 0; j < m->r; j++) out[j] = 0;
    for (a = 0; a < 3; a++) rt_row_axpy(m, v, a, n[a], out);
}

romrt_real rt_contact_distance(const romrt_model *m, int c, const romrt_real *q)
{
    uint32_t v = m->contacts[2 * (size_t)c];
    const romrt_real *p = m->planes + 6 * (size_t)m->contacts[2 * (size_t)c + 1], *X = m->X + 3 * (size_t)v;
    romrt_real d = 0;
    int a;
    for (a = 0; a < 3; a++) d += p[3 + a] * (X[a] - p[a] + rt_row_dot(m, v, a, q));
    return d;
}

/* The step filter keeps 10% of every plane distance, and in float also CONTACT_FLOOR dhat: positions
 * carry rounding of about 1e-7 of their size, so an impact the fixed barrier stiffness cannot stop
 * in time would otherwise drive a distance into that noise (a splat cloud dropped 1 m onto a plane
 * ended a step at 1.2e-7 m, one unit in the last place of y, then at 0). The double runtime, like
 * the reduced simulator, goes as close as the barrier lets it. */
#ifdef ROMRT_DOUBLE
#define CONTACT_FLOOR 0
#else
#define CONTACT_FLOOR 1e-3f
#endif

romrt_real rt_contact_max_step(const romrt_model *m, const romrt_real *q, const romrt_real *dq)
{
    romrt_real alpha = 1, floor = RT_K(CONTACT_FLOOR) * m->dhat;
    int c, a;
    for (c = 0; c < m->ncontacts; c++) {
        uint32_t v = m->contacts[2 * (size_t)c];
        const romrt_real *n = m->planes + 6 * (size_t)m->contacts[2 * (size_t)c + 1] + 3;
        romrt_real dd = 0, d = rt_contact_distance(m, c, q);
        for (a = 0; a < 3; a++) dd += n[a] * rt_row_dot(m, v, a, dq);
        if (dd < 0 && RT_K(0.9) * (d - floor) / -dd < alpha) alpha = RT_K(0.9) * (d - floor) / -dd;
        if (alpha < 0) alpha = 0;
    }
    return alpha;
}

void rt_vertex_pull(const romrt_model *m, uint32_t v, const romrt_real gx[3], const romrt_real *B, romrt_real *g,
                    romrt_real *H, int ld)
{
    const romrt_real *row[3];
    int r = m->r, rp = RT_PAD(r), a, b, i, j;
    for (a = 0; a < 3; a++) { /* stored rows, or formed into m->AG (free here: no element is being summed) */
        if (m->rows) row[a] = row_of(m, v, a);
        else {
            rt_row(m, v, a, m->AG + (size_t)rp * a);
            row[a] = m->AG + (size_t)rp * a;
        }
    }
    if (g)
        for (a = 0; a < 3; a++)
            for (j = 0; j < r; j++) g[j] += gx[a] * row[a][j];
    if (H && B)
        for (j = 0; j < r; j++) {
            romrt_real Bj[3]; /* B J column j */
            for (a = 0; a < 3; a++) Bj[a] = B[3 * a] * row[0][j] + B[3 * a + 1] * row[1][j] + B[3 * a + 2] * row[2][j];
            for (b = 0; b < 3; b++)
                if (Bj[b] != 0)
                    for (i = 0; i <= j; i++) H[i + (size_t)ld * j] += row[b][i] * Bj[b];
        }
}

/* Friction of contact c (a vertex on a plane), lagged at q_lag on its slip since q_t (the
 * precompute's point-plane friction pair, contact/friction.c): energy, g and H. */
static romrt_real plane_friction(romrt_model *m, int c, const romrt_real *q, romrt_real *g, romrt_real *H, int ld)
{
    uint32_t v = m->contacts[2 * (size_t)c];
    const romrt_real *n = m->planes + 6 * (size_t)m->contacts[2 * (size_t)c + 1] + 3;
    romrt_real dl = rt_contact_distance(m, c, m->q_lag), f1, f2, T[6], x[3], xs[3], rel[3], u[2], f1y, M[4];
    romrt_real scale, E, gx[3], B[9];
    int a, b;
    if (!(dl > 0 && dl < m->dhat)) return 0;
    m->contact_terms++;
    RT_PHYS(barrier_distance)(dl, m->dhat, &f1, &f2);
    scale = m->mu * m->kappa * RT_FABS(f1);
    RT_PHYS(tangent_basis)(n, T);
    rt_vertex_position(m, v, q, x);
    rt_vertex_position(m, v, m->qt, xs);
    for (a = 0; a < 3; a++) rel[a] = x[a] - xs[a];
    u[0] = T[0] * rel[0] + T[1] * rel[1] + T[2] * rel[2];
    u[1] = T[3] * rel[0] + T[4] * rel[1] + T[5] * rel[2];
    E = scale * RT_PHYS(friction_smoothed)(u, m->eps_v * m->h, &f1y, M);
    if (!g && !H) return E;
    for (a = 0; a < 3; a++) {
        gx[a] = scale * f1y * (T[a] * u[0] + T[3 + a] * u[1]);
        for (b = 0; b < 3; b++)
            B[3 * a + b] = scale * (T[a] * (M[0] * T[b] + M[1] * T[3 + b]) + T[3 + a] * (M[2] * T[b] + M[3] * T[3 + b]));
    }
    rt_vertex_pull(m, v, gx, B, g, H, ld);
    return E;
}

/* The contacts' barrier (physics.h, barrier_distance: IPC's b(d^2, dhat^2) on each contact
 * vertex's signed distance to its plane), kappa times it; and their friction. */
static romrt_real barrier(romrt_model *m, const romrt_real *q, int friction, romrt_real *g, romrt_real *H, int ld)
{
    romrt_real E = 0, *a = m->AG; /* free between elements and here */
    int c, i, j, r = m->r;
    for (c = 0; c < m->ncontacts; c++) {
        romrt_real d = rt_contact_distance(m, c, q), f1, f2;
        if (!(d > 0)) return (romrt_real)INFINITY;
        if (friction) E += plane_friction(m, c, q, g, H, ld);
        if (d >= m->dhat) continue;
        m->contact_terms++;
        E += m->kappa * RT_PHYS(barrier_distance)(d, m->dhat, &f1, &f2);
        if (!g && !H) continue;
        contact_gradient(m, c, a);
        if (g)
            for (j = 0; j < r; j++) g[j] += m->kappa * f1 * a[j];
        if (H)
            for (j = 0; j < r; j++)
                for (i = 0; i <= j; i++) H[i + (size_t)ld * j] += m->kappa * f2 * a[i] * a[j];
    }
    return E;
}

void rt_lift(const romrt_model *m, double t, romrt_real *q)
{
    const romrt_real *p = m->lift;
    romrt_real R[9], shift[3];
    int a, b;
    if (!p) return;
    RT_PHYS(motion)((rk_motion_kind)(int)p[0], p + 1, p + 4, p[7], p + 8, t, R, shift);
    /* coordinate 4 a + b of a handle moves x_a by w X_b (b < 3) or w (b = 3): rk_skinning_to_U */
    for (a = 0; a < 3; a++) {
        for (b = 0; b < 3; b++) q[m->lift_col + 4 * a + b] = R[3 * a + b] - (romrt_real)(a == b);
        q[m->lift_col + 4 * a + 3] = shift[a];
    }
}

void rt_pin_target(romrt_model *m, double t)
{
    int r = m->r, g, j, k;
    size_t per = ROMBIN_PIN_PARAMS + 12 * (size_t)r;
    for (j = 0; j < r; j++) m->pin_b[j] = 0;
    for (g = 0; g < m->npins; g++) {
        const romrt_real *p = m->pins + per * (size_t)g, *T = p + ROMBIN_PIN_PARAMS;
        romrt_real R[9], shift[3], e[12];
        RT_PHYS(motion)((rk_motion_kind)(int)p[0], p + 1, p + 4, p[7], p + 8, t, R, shift);
        for (k = 0; k < 9; k++) e[k] = R[k] - (romrt_real)(k % 4 == 0);
        for (k = 0; k < 3; k++) e[9 + k] = shift[k];
        for (k = 0; k < 12; k++)
            for (j = 0; j < r; j++) m->pin_b[j] += T[(size_t)r * k + j] * e[k];
    }
}

/* w/2 (q - ref)^T S (q - ref), adding w S (q - ref) into g (ref NULL: 0). Uses m->tmp, m->trial
 * is not touched (it may be q). */
static romrt_real quadratic(romrt_model *m, const romrt_real *S, romrt_real w, const romrt_real *q,
                            const romrt_real *ref, romrt_real *g, romrt_real *Sd)
{
    int r = m->r, i;
    for (i = 0; i < r; i++) m->tmp[i] = q[i] - (ref ? ref[i] : 0);
    rt_symv(r, S, m->tmp, Sd);
    if (g)
        for (i = 0; i < r; i++) g[i] += w * Sd[i];
    return RT_K(0.5) * w * rt_dot(r, m->tmp, Sd);
}

romrt_real rt_potential(romrt_model *m, const rt_terms *T, const romrt_real *q, romrt_real *g, romrt_real *H, int ld,
                        romrt_real *magnitude)
{
    int r = m->r, i, j;
    romrt_real stored, work, quad = 0, E, Sd[ROMRT_MAX_R];
    m->contact_terms = 0;
    if (g)
        for (i = 0; i < r; i++) g[i] = 0;
    if (H)
        for (j = 0; j < r; j++)
            for (i = 0; i < r; i++) H[i + (size_t)ld * j] = 0;
    stored = elastic(m, q, g, H, ld);
    if (m->ncontacts && isfinite(stored)) stored += barrier(m, q, T->friction, g, H, ld);
    if (m->ncolliders && isfinite(stored)) stored += rt_colliders_energy(m, q, T->friction, g, H, ld);
    if (rt_surface_on(m) && isfinite(stored)) stored += rt_obstacles_energy(m, q, T->friction, g, H, ld);
    if (!isfinite(stored)) return (romrt_real)INFINITY;
    /* Loads, applied forces and the pins' linear part: -(f + f_app + b(t)) . (q - q_t), their work
     * since the step began. Against q itself the work is the constant f . q_t (gravity's whole work
     * on the fall so far: 1.38 J on issue 30's pour at rest) plus the step's part, and in float
     * that constant's rounding (1e-7 J) hid the line search's decreases at rest (friction's 1e-6 J
     * an iteration), whose round-off floor (RT_ENERGY_NOISE of the magnitude) it also set: float
     * Newton took 7.5 iterations and 10.7 halvings a step there (docs/runtime.md). A constant moves
     * neither the gradient nor the minimum. */
    work = 0;
    for (i = 0; i < r; i++) work += (m->f[i] + m->f_app[i] + m->pin_b[i]) * (q[i] - m->qt[i]);
    if (m->A) quad += quadratic(m, m->A, 1, q, 0, g, Sd);
    quad += quadratic(m, m->M, T->w_inertia, q, m->qtilde, g, Sd);
    if (m->C) quad += quadratic(m, m->C, T->w_damping, q, m->qt, g, Sd);
    if (g)
        for (i = 0; i < r; i++) g[i] -= m->f[i] + m->f_app[i] + m->pin_b[i];
    if (H)
        for (j = 0; j < r; j++)
            for (i = 0; i <= j; i++) {
                size_t k = i + (size_t)r * j;
                romrt_real a = T->w_inertia * m->M[k];
                if (m->A) a += m->A[k];
                if (m->C) a += T->w_damping * m->C[k];
                H[i + (size_t)ld * j] += a;
            }
    if (m->lift) /* the lifting handle's coordinates are set (rt_lift), not solved for: Newton leaves them */
        for (i = m->lift_col; i < m->lift_col + 12; i++) {
            if (g) g[i] = 0;
            for (j = 0; H && j < r; j++) H[i + (size_t)ld * j] = H[j + (size_t)ld * i] = (romrt_real)(i == j);
        }
    E = stored - work + quad;
    if (magnitude) *magnitude = RT_FABS(stored) + RT_FABS(work) + quad;
    return isfinite(E) ? E : (romrt_real)INFINITY;
}
