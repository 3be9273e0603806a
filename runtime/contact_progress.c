/* The scene's moving obstacles solved for with the body (precompute/rom/obstacle_solve.c has the
 * model): over a step the baked obstacle vertices go on straight lines from where they are (ox_from)
 * to where their scripted motions put them at the step's end (ox_to), and the app's moved meshes'
 * vertices from where they were (x0) to where their poses put them, at a progress s in [0, 1]
 * that is one more unknown beside q, pulled to 1 by w/2 (1 - s)^2. The barrier pushes the body
 * ahead of them within one Newton solve, and CCD filters the joint motion, as for the app's moved
 * colliders (colliders.c; IPC's moving obstacles, Li et al. 2020, Sec. 4.6). Safe moves (CCD's
 * fraction with the body still, then a solve) took one move per closing of the body's barrier gap:
 * ~700 moves a step in double for a box thrown into a terrain rising at 1 m/s, past 1000 in float.
 *
 * A stencil's terms depend on s through its obstacle points alone, x_o(s) = ox_from + s D_o with
 * D_o = ox_to - ox_from: dE/ds = sum_o g_o . D_o, d2E/ds2 = sum_{o,p} D_o^T B_op D_p and
 * d2E/dq ds = sum_{v body} J_v^T sum_p B_vp D_p, each over the pair's PSD-projected block with the
 * obstacle points as degrees of freedom. w = RK_COLLIDER_PULL m L^2 / h^2 with L the longest D_o. */
#include <math.h>
#include <string.h>

#include "runtime/romrt_impl.h"

/* D_o of obstacle point id (< 0) into D: 1, or 0 when it does not move with s. */
static int way(const romrt_model *m, int32_t id, romrt_real D[3])
{
    uint32_t o = (uint32_t)(-1 - id);
    int a;
    if (id >= 0) return 0;
    if (o >= (uint32_t)m->onv) return m->nmeshes && rt_mesh_way(m, o - (uint32_t)m->onv, D);
    if (!m->obs_moving) return 0;
    for (a = 0; a < 3; a++) D[a] = m->ox_to[3 * (size_t)o + a] - m->ox_from[3 * (size_t)o + a];
    return 1;
}

int rt_obstacles_begin_joint(romrt_model *m, double t)
{
    romrt_real L2 = m->nmeshes ? rt_meshes_longest_way2(m) : 0;
    int i;
    if (m->obs_moving) {
        rt_obstacles_target(m, t);
        memcpy(m->ox_from, m->ox, sizeof(romrt_real) * 3 * (size_t)m->onv);
        for (i = 0; i < m->onv; i++) {
            romrt_real D[3] = {0, 0, 0}, d2;
            way(m, -1 - i, D);
            d2 = D[0] * D[0] + D[1] * D[1] + D[2] * D[2];
            if (d2 > L2) L2 = d2;
        }
    }
    if (!(L2 > 0)) return 0; /* nothing moves this step */
    m->obs_L = RT_SQRT(L2);
    m->obs_w = RT_K(RK_COLLIDER_PULL) * m->mass * L2 / (m->h * m->h);
    m->obs_joint = 1;
    return 1;
}

void rt_obstacles_place(romrt_model *m, romrt_real s, romrt_real ds)
{
    int i;
    if (m->obs_moving) {
        for (i = 0; i < 3 * m->onv; i++) {
            m->ox[i] = m->ox_from[i] + s * (m->ox_to[i] - m->ox_from[i]);
            m->odx[i] = ds * (m->ox_to[i] - m->ox_from[i]);
        }
        rt_obstacles_refit(m, ds != 0);
        m->obs_time = (double)NAN; /* part way */
    }
    if (m->nmeshes) rt_meshes_at(m, s, ds);
}

int rt_obstacles_end_joint(romrt_model *m, romrt_real s, double t, romrt_real tol)
{
    m->obs_joint = 0;
    rt_obstacles_place(m, s, 0);
    /* within the solve's tolerance of the end: there, when CCD lets the last bit go */
    if ((1 - s) * m->obs_L <= tol && rt_obstacles_fraction(m, m->q) >= 1) {
        rt_obstacles_arrive(m, t);
        return 0;
    }
    if (m->nmeshes) rt_meshes_end(m, 0);
    return 1;
}

void rt_obstacles_pull_progress(romrt_model *m, const int32_t id[4], const romrt_real *gx, const romrt_real *B,
                                romrt_real *g, romrt_real *H, int ld)
{
    int p = m->r + m->nmoving, k, l, a, any = 0;
    romrt_real D[12], BD[12];
    for (k = 0; k < 4; k++) {
        int moves = way(m, id[k], D + 3 * k);
        any |= moves;
        if (!moves) D[3 * k] = D[3 * k + 1] = D[3 * k + 2] = 0;
    }
    if (!any) return;
    if (g)
        for (k = 0; k < 12; k++) g[p] += gx[k] * D[k];
    if (!H || !B) return;
    for (k = 0; k < 12; k++) { /* BD = B D */
        BD[k] = 0;
        for (l = 0; l < 12; l++) BD[k] += B[12 * k + l] * D[l];
    }
    for (k = 0; k < 12; k++) H[p + (size_t)ld * p] += D[k] * BD[k];
    for (k = 0; k < 4; k++)
        for (a = 0; a < 3 && id[k] >= 0; a++)
            if (BD[3 * k + a] != 0) rt_row_axpy(m, m->cv[id[k]], a, BD[3 * k + a], H + (size_t)ld * p);
}

void rt_obstacles_slip_progress(romrt_model *m, const int32_t id[4], const romrt_real w[4], const romrt_real gt[3],
                                const romrt_real *B3, romrt_real *g, romrt_real *H, int ld)
{
    int p = m->r + m->nmoving, k, a, any = 0;
    romrt_real c[3] = {0, 0, 0}, Bc[3], D[3];
    for (k = 0; k < 4; k++)
        if (way(m, id[k], D))
            for (a = 0, any = 1; a < 3; a++) c[a] += w[k] * D[a];
    if (!any) return;
    if (g) g[p] += gt[0] * c[0] + gt[1] * c[1] + gt[2] * c[2];
    if (!H || !B3) return;
    for (a = 0; a < 3; a++) Bc[a] = B3[3 * a] * c[0] + B3[3 * a + 1] * c[1] + B3[3 * a + 2] * c[2];
    H[p + (size_t)ld * p] += c[0] * Bc[0] + c[1] * Bc[1] + c[2] * Bc[2];
    for (k = 0; k < 4; k++)
        for (a = 0; a < 3 && id[k] >= 0 && w[k] != 0; a++)
            if (Bc[a] != 0) rt_row_axpy(m, m->cv[id[k]], a, w[k] * Bc[a], H + (size_t)ld * p);
}
