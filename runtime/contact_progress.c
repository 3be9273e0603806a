/* The scene's moving obstacles solved for with the body (precompute/rom/obstacle_solve.c has the
 * model): over a step the baked obstacle vertices go on straight lines from where they are (ox_from)
 * to where their scripted motions put them at the step's end (ox_to), and the app's moved meshes'
 * vertices from where they were (x0) to where their poses put them, each mover (a baked obstacle
 * with a motion, an app mesh) at its own progress s_u in [0, 1], one more unknown beside q, pulled
 * to 1 by w_u/2 (1 - s_u)^2: one pinned against the body stops short alone, the others arrive.
 * The barrier pushes the body ahead of them within one Newton solve, and CCD filters the joint
 * motion, as for the app's moved colliders (colliders.c; IPC's moving obstacles, Li et al. 2020, Sec. 4.6). Safe moves (CCD's
 * fraction with the body still, then a solve) took one move per closing of the body's barrier gap:
 * ~700 moves a step in double for a box thrown into a terrain rising at 1 m/s, past 1000 in float.
 *
 * A stencil's terms depend on s_u through its points of mover u alone, x_o(s_u) = ox_from + s_u D_o
 * with D_o = ox_to - ox_from: dE/ds_u = sum_{o of u} g_o . D_o, d2E/ds_u ds_v = D_u^T B D_v and
 * d2E/dq ds_u = sum_{v body} J_v^T (B D_u)_v (D_u: the way at u's points, 0 elsewhere), each over
 * the pair's PSD-projected block with the obstacle points as degrees of freedom.
 * w_u = RK_COLLIDER_PULL m L_u^2 / h^2 with L_u mover u's longest D_o. */
#include <math.h>
#include <string.h>

#include "runtime/romrt_impl.h"

/* The mover index of baked obstacle k (a bisection of the ascending movers), -1 when it stays. */
static int mover_of(const romrt_model *m, int k)
{
    int lo = 0, hi = m->nmovers;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (m->movers[mid] < k) lo = mid + 1;
        else hi = mid;
    }
    return lo < m->nmovers && m->movers[lo] == k ? lo : -1;
}

int rt_obstacle_unit(const romrt_model *m, uint32_t o)
{
    int j = mover_of(m, (int)m->overt_obs[o]);
    return j < 0 ? -1 : m->obs_unit[j];
}

/* D_o of obstacle point id (< 0) into D and its unknown u, or -1 when it does not move with any. */
static int way(const romrt_model *m, int32_t id, romrt_real D[3])
{
    uint32_t o = (uint32_t)(-1 - id);
    int a, u;
    if (id >= 0 || !m->obs_joint) return -1;
    if (o >= (uint32_t)m->onv) {
        o -= (uint32_t)m->onv;
        u = m->obs_unit[ROMRT_MAX_MOVING_OBSTACLES + (o >> RT_MESH_SHIFT)];
        return m->nmeshes && u >= 0 && rt_mesh_way(m, o, D) ? u : -1;
    }
    if (!m->obs_moving || (u = rt_obstacle_unit(m, o)) < 0) return -1;
    for (a = 0; a < 3; a++) D[a] = m->ox_to[3 * (size_t)o + a] - m->ox_from[3 * (size_t)o + a];
    return u;
}

/* A new unknown for mover j whose longest way is sqrt(L2) (none when it does not move). */
static void add_unit(romrt_model *m, int j, romrt_real L2)
{
    int u;
    m->obs_unit[j] = -1;
    if (!(L2 > 0)) return;
    u = m->obs_unit[j] = m->obs_joint++;
    m->obs_L[u] = RT_SQRT(L2);
    m->obs_w[u] = RT_K(RK_COLLIDER_PULL) * m->mass * L2 / (m->h * m->h);
    m->obs_s[u] = 0, m->obs_lambda[u] = 0, m->obs_short[u] = (romrt_real)INFINITY;
}

int rt_obstacles_begin_joint(romrt_model *m, double t)
{
    int j, k, v;
    m->obs_joint = 0;
    if (m->obs_moving) {
        rt_obstacles_target(m, t);
        memcpy(m->ox_from, m->ox, sizeof(romrt_real) * 3 * (size_t)m->onv);
    }
    for (j = 0; j < m->nmovers && m->obs_moving; j++) { /* the baked movers first, in their order */
        const uint32_t *o = m->obs + ROMBIN_OBST_COUNT * (size_t)m->movers[j];
        romrt_real L2 = 0, d2, D[3];
        for (v = (int)o[ROMBIN_OBST_FIRST_VERTEX]; v < (int)(o[ROMBIN_OBST_FIRST_VERTEX] + o[ROMBIN_OBST_VERTICES]); v++) {
            int a;
            for (a = 0; a < 3; a++) D[a] = m->ox_to[3 * (size_t)v + a] - m->ox_from[3 * (size_t)v + a];
            d2 = D[0] * D[0] + D[1] * D[1] + D[2] * D[2];
            if (d2 > L2) L2 = d2;
        }
        add_unit(m, j, L2);
    }
    for (; j < ROMRT_MAX_MOVING_OBSTACLES; j++) m->obs_unit[j] = -1;
    for (k = 0; k < ROMRT_MAX_COLLIDERS; k++) /* then the app meshes, by slot */
        add_unit(m, ROMRT_MAX_MOVING_OBSTACLES + k, m->nmeshes ? rt_mesh_longest_way2(m, k) : 0);
    return m->obs_joint;
}

void rt_obstacles_place(romrt_model *m, const romrt_real *s, const romrt_real *ds)
{
    int i, a, u;
    if (m->obs_moving) {
        for (i = 0; i < m->onv; i++) {
            u = rt_obstacle_unit(m, (uint32_t)i);
            for (a = 0; a < 3; a++) {
                size_t x = 3 * (size_t)i + a;
                m->ox[x] = u >= 0 ? m->ox_from[x] + s[u] * (m->ox_to[x] - m->ox_from[x]) : m->ox_from[x];
                m->odx[x] = u >= 0 && ds ? ds[u] * (m->ox_to[x] - m->ox_from[x]) : 0;
            }
        }
        rt_obstacles_refit(m, ds != 0);
        m->obs_time = (double)NAN; /* part way */
    }
    if (m->nmeshes) rt_meshes_at(m, s, ds);
}

/* The baked movers' vertices of the unknowns marked in near where the clock puts them (ox_to). */
static void arrive_some(romrt_model *m, const int *near)
{
    int i, u;
    for (i = 0; i < m->onv && m->obs_moving; i++)
        if ((u = rt_obstacle_unit(m, (uint32_t)i)) >= 0 && near[u])
            memcpy(m->ox + 3 * (size_t)i, m->ox_to + 3 * (size_t)i, sizeof(romrt_real) * 3);
    if (m->obs_moving) rt_obstacles_refit(m, 0);
}

int rt_obstacles_end_joint(romrt_model *m, const romrt_real *s, double t, romrt_real tol)
{
    int n = m->obs_joint, u, v, nnear = 0, ndone = 0;
    rt_obstacles_place(m, s, 0);
    m->obs_joint = 0; /* (rt_obstacles_place above used the units) */
    /* all within the solve's tolerance of their ends: there, when CCD lets their last bits go */
    for (u = 0; u < n; u++) nnear += (1 - s[u]) * m->obs_L[u] <= tol;
    if (nnear == n && rt_obstacles_fraction(m, m->q, 0) >= 1) {
        rt_obstacles_arrive(m, t);
        return 0;
    }
    /* else each whose rest of the way CCD lets go on its own, the others where they are (those
     * gone before it at the end): near the end, or short only because the solve stopped at its
     * floor first (in float a free obstacle's s creeps by the pinned one's CCD fractions); a
     * pinned one's rest runs into the body (precompute/contact/progress.c's rule) */
    for (u = 0; u < n; u++) {
        for (v = 0; v < n; v++) m->obs_near[v] = v == u;
        if (rt_obstacles_fraction(m, m->q, m->obs_near) < 1) continue;
        ndone++;
        arrive_some(m, m->obs_near);
        if (m->nmeshes) rt_meshes_end(m, 1, m->obs_near);
    }
    if (ndone == n) { /* all there after all */
        rt_obstacles_arrive(m, t);
        return 0;
    }
    if (m->nmeshes) rt_meshes_end(m, 0, 0);
    return 1;
}

void rt_obstacles_pull_progress(romrt_model *m, const int32_t id[4], const romrt_real *gx, const romrt_real *B,
                                romrt_real *g, romrt_real *H, int ld)
{
    int p = m->r + m->nmoving, k, l, a, i, j, nu = 0, unit[4], u;
    romrt_real D[4][12], BD[4][12], Dk[3];
    for (k = 0; k < 4; k++) {
        if ((u = way(m, id[k], Dk)) < 0) continue;
        for (j = 0; j < nu && unit[j] != u; j++) continue;
        if (j == nu) { /* a mover new to this stencil: its way, 0 at every other point */
            unit[nu++] = u;
            for (l = 0; l < 12; l++) D[j][l] = 0;
        }
        for (a = 0; a < 3; a++) D[j][3 * k + a] = Dk[a];
    }
    for (j = 0; j < nu; j++) {
        if (g)
            for (k = 0; k < 12; k++) g[p + unit[j]] += gx[k] * D[j][k];
        if (!H || !B) continue;
        for (k = 0; k < 12; k++) { /* BD = B D */
            BD[j][k] = 0;
            for (l = 0; l < 12; l++) BD[j][k] += B[12 * k + l] * D[j][l];
        }
        for (k = 0; k < 4; k++)
            for (a = 0; a < 3 && id[k] >= 0; a++)
                if (BD[j][3 * k + a] != 0) rt_row_axpy(m, m->cv[id[k]], a, BD[j][3 * k + a], H + (size_t)ld * (p + unit[j]));
    }
    if (!H || !B) return;
    for (i = 0; i < nu; i++) /* the upper triangle: D_i.B D_j at row min, column max */
        for (j = 0; j < nu; j++) {
            int r0 = p + unit[i], c0 = p + unit[j];
            if (r0 > c0 || (r0 == c0 && i != j)) continue;
            for (k = 0; k < 12; k++) H[r0 + (size_t)ld * c0] += D[i][k] * BD[j][k];
        }
}

void rt_obstacles_slip_progress(romrt_model *m, const int32_t id[4], const romrt_real w[4], const romrt_real gt[3],
                                const romrt_real *B3, romrt_real *g, romrt_real *H, int ld)
{
    int p = m->r + m->nmoving, k, a, i, j, nu = 0, unit[4], u;
    romrt_real c[4][3], Bc[4][3], D[3];
    for (k = 0; k < 4; k++) {
        if ((u = way(m, id[k], D)) < 0) continue;
        for (j = 0; j < nu && unit[j] != u; j++) continue;
        if (j == nu) {
            unit[nu++] = u;
            c[j][0] = c[j][1] = c[j][2] = 0;
        }
        for (a = 0; a < 3; a++) c[j][a] += w[k] * D[a];
    }
    for (j = 0; j < nu; j++) {
        if (g) g[p + unit[j]] += gt[0] * c[j][0] + gt[1] * c[j][1] + gt[2] * c[j][2];
        if (!H || !B3) continue;
        for (a = 0; a < 3; a++) Bc[j][a] = B3[3 * a] * c[j][0] + B3[3 * a + 1] * c[j][1] + B3[3 * a + 2] * c[j][2];
        for (k = 0; k < 4; k++)
            for (a = 0; a < 3 && id[k] >= 0 && w[k] != 0; a++)
                if (Bc[j][a] != 0) rt_row_axpy(m, m->cv[id[k]], a, w[k] * Bc[j][a], H + (size_t)ld * (p + unit[j]));
    }
    if (!H || !B3) return;
    for (i = 0; i < nu; i++)
        for (j = 0; j < nu; j++) {
            int r0 = p + unit[i], c0 = p + unit[j];
            if (r0 > c0 || (r0 == c0 && i != j)) continue;
            H[r0 + (size_t)ld * c0] += c[i][0] * Bc[j][0] + c[i][1] * Bc[j][1] + c[i][2] * Bc[j][2];
        }
}
