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
}

/* m->G = G_e (9 x r, row-major). */
static void element_G(romrt_model *m, int e)
{
    const uint32_t *ev = m->elem + 5 * (size_t)e;
    const romrt_real *Dm = m->elem_real + 12 * (size_t)e;
    int r = m->r, a, b, c, j;
    for (a = 0; a < 3; a++) {
        const romrt_real *r0 = row_of(m, ev[0], a);
        for (b = 0; b < 3; b++) {
            romrt_real *Gab = m->G + (size_t)r * (3 * a + b);
            for (j = 0; j < r; j++) Gab[j] = 0;
            for (c = 0; c < 3; c++) {
                const romrt_real *rc = row_of(m, ev[c + 1], a);
                romrt_real w = Dm[3 * c + b];
                for (j = 0; j < r; j++) Gab[j] += w * (rc[j] - r0[j]);
            }
        }
    }
}

static romrt_real elastic(romrt_model *m, const romrt_real *q, romrt_real *g, romrt_real *H, int ld)
{
    int r = m->r, e, i, j, k, l;
    romrt_real E = 0;
    for (e = 0; e < m->ne; e++) {
        const romrt_real *er = m->elem_real + 12 * (size_t)e;
        rk_material_model model = (rk_material_model)m->elem[5 * (size_t)e + 4];
        romrt_real Hd[9], F[9], P[9], A[81], w = er[9], psi;
        element_H(m, e, q, Hd);
        psi = RT_PHYS(psi_h)(model, er[10], er[11], Hd);
        if (!isfinite(psi)) return (romrt_real)INFINITY;
        E += w * psi;
        if (!g && !H) continue;
        element_G(m, e);
        if (g) {
            RT_PHYS(pk1_h)(model, er[10], er[11], Hd, P);
            for (k = 0; k < 9; k++) {
                const romrt_real *Gk = m->G + (size_t)r * k;
                romrt_real wp = w * P[k];
                for (j = 0; j < r; j++) g[j] += wp * Gk[j];
            }
        }
        if (H) {
            for (k = 0; k < 9; k++) F[k] = Hd[k] + (romrt_real)(k % 4 == 0);
            RT_PHYS(dpdf)(model, er[10], er[11], F, A, 1);
            for (k = 0; k < 9; k++) { /* AG = w dP/dF G */
                romrt_real *AGk = m->AG + (size_t)r * k;
                for (j = 0; j < r; j++) AGk[j] = 0;
                for (l = 0; l < 9; l++) {
                    const romrt_real *Gl = m->G + (size_t)r * l;
                    romrt_real a = w * A[9 * k + l];
                    if (a != 0)
                        for (j = 0; j < r; j++) AGk[j] += a * Gl[j];
                }
            }
            /* upper triangle of G^T AG as one rank-9 update: a single pass over H per element (nine
             * rank-1 passes would stream the r x r matrix through the cache nine times) */
            for (j = 0; j < r; j++) {
                const romrt_real *G = m->G;
                romrt_real *Hj = H + (size_t)ld * j, a[9];
                for (k = 0; k < 9; k++) a[k] = m->AG[(size_t)r * k + j];
                for (i = 0; i <= j; i++)
                    Hj[i] += G[i] * a[0] + G[r + i] * a[1] + G[2 * r + i] * a[2] + G[3 * r + i] * a[3] +
                             G[4 * r + i] * a[4] + G[5 * r + i] * a[5] + G[6 * r + i] * a[6] + G[7 * r + i] * a[7] +
                             G[8 * r + i] * a[8];
            }
        }
    }
    return E;
}

/* a = the gradient of contact c's distance (n . B_v), into out (r). */
static void contact_gradient(const romrt_model *m, int c, romrt_real *out)
{
    uint32_t v = m->contacts[2 * (size_t)c];
    const romrt_real *n = m->planes + 6 * (size_t)m->contacts[2 * (size_t)c + 1] + 3;
    int j, a;
    for (j = 0; j < m->r; j++) out[j] = 0;
    for (a = 0; a < 3; a++) {
        const romrt_real *row = row_of(m, v, a);
        for (j = 0; j < m->r; j++) out[j] += n[a] * row[j];
    }
}

romrt_real rt_contact_distance(const romrt_model *m, int c, const romrt_real *q)
{
    uint32_t v = m->contacts[2 * (size_t)c];
    const romrt_real *p = m->planes + 6 * (size_t)m->contacts[2 * (size_t)c + 1], *X = m->X + 3 * (size_t)v;
    romrt_real d = 0;
    int a;
    for (a = 0; a < 3; a++) d += p[3 + a] * (X[a] - p[a] + rt_dot(m->r, row_of(m, v, a), q));
    return d;
}

romrt_real rt_contact_max_step(const romrt_model *m, const romrt_real *q, const romrt_real *dq)
{
    romrt_real alpha = 1;
    int c, a;
    for (c = 0; c < m->ncontacts; c++) {
        uint32_t v = m->contacts[2 * (size_t)c];
        const romrt_real *n = m->planes + 6 * (size_t)m->contacts[2 * (size_t)c + 1] + 3;
        romrt_real dd = 0, d = rt_contact_distance(m, c, q);
        for (a = 0; a < 3; a++) dd += n[a] * rt_dot(m->r, row_of(m, v, a), dq);
        if (dd < 0 && RT_K(0.9) * d / -dd < alpha) alpha = RT_K(0.9) * d / -dd; /* keep 10% of the distance */
    }
    return alpha;
}

void rt_vertex_position(const romrt_model *m, uint32_t v, const romrt_real *q, romrt_real x[3])
{
    int a;
    for (a = 0; a < 3; a++) x[a] = m->X[3 * (size_t)v + (size_t)a] + rt_dot(m->r, row_of(m, v, a), q);
}

void rt_vertex_pull(const romrt_model *m, uint32_t v, const romrt_real gx[3], const romrt_real *B, romrt_real *g,
                    romrt_real *H, int ld)
{
    const romrt_real *row[3];
    int r = m->r, a, b, i, j;
    for (a = 0; a < 3; a++) row[a] = row_of(m, v, a);
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

void rt_pin_target(romrt_model *m, romrt_real t)
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
    if (g)
        for (i = 0; i < r; i++) g[i] = 0;
    if (H)
        for (j = 0; j < r; j++)
            for (i = 0; i < r; i++) H[i + (size_t)ld * j] = 0;
    stored = elastic(m, q, g, H, ld);
    if (m->ncontacts && isfinite(stored)) stored += barrier(m, q, T->friction, g, H, ld);
    if (m->ncolliders && isfinite(stored)) stored += rt_colliders_energy(m, q, T->friction, g, H, ld);
    if (!isfinite(stored)) return (romrt_real)INFINITY;
    /* Loads, applied forces and the pins' linear part: -(f + f_app + b(t)) . q. */
    work = 0;
    for (i = 0; i < r; i++) work += (m->f[i] + m->f_app[i] + m->pin_b[i]) * q[i];
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
    E = stored - work + quad;
    if (magnitude) *magnitude = RT_FABS(stored) + RT_FABS(work) + quad;
    return isfinite(E) ? E : (romrt_real)INFINITY;
}
