/* Friction against the obstacles, lagged as the reduced simulator does (precompute/contact/
 * friction.c; IPC, Li et al. 2020, Sec. 5, Eq. 9-15): at the step's start the collision vertices
 * and obstacle vertices are recorded (x^t); each lag keeps every pair within dhat with its normal
 * force lambda, closest-point weights w and tangent basis T (pair_friction_lag); the potential
 * is then mu sum_k lambda_k f0(|T_k sum_i w_ki (x_i - x_i^t)|) (friction_slip), its gradient
 * and PSD Hessian pulled through the 3 rows sum_i w_ki B_i (contact_pull.c). An app mesh's step
 * start is its index's x0 (rt_meshes_begin). */
#include <string.h>

#include "runtime/romrt_impl.h"

static void lag(romrt_model *m, const romrt_real *q, int start)
{
    int i;
    rt_obstacles_positions(m, q, 0);
    if (start) {
        memcpy(m->fx0, m->ocx, sizeof(romrt_real) * 3 * (size_t)m->ncv);
        memcpy(m->fox0, m->ox, sizeof(romrt_real) * 3 * (size_t)m->onv);
    }
    m->nfric = 0;
    if (!(m->mu > 0) || rt_obstacles_gather(m)) return; /* an overflow: the energy reports it */
    for (i = 0; i < m->ncand; i++) {
        const int32_t *c = m->cand + 5 * (size_t)i, *id = c + 1;
        const romrt_real *pts[4];
        romrt_real *f = m->fric + 11 * (size_t)m->nfric, lambda;
        rt_obstacles_stencil(m, id, pts);
        if (!(RT_PHYS(contact_distance2)(c[0] ? RT_PHYS(edge_edge_case)(pts) : RT_PHYS(point_triangle_case)(pts), pts, 0, 0) <
              (m->dhat + rt_obstacles_xi(m, id)) * (m->dhat + rt_obstacles_xi(m, id))))
            continue; /* out of reach (pair_friction_lag would say 0) */
        lambda = RT_PHYS(pair_friction_lag)(c[0], pts, rt_obstacles_xi(m, id), m->dhat, rt_obstacles_eps(m, c[0], id),
                                            m->kappa, f, f + 4);
        if (!(lambda > 0)) continue;
        f[10] = lambda;
        memcpy(m->fric_id + 4 * (size_t)m->nfric, id, 4 * sizeof(int32_t));
        m->nfric++;
    }
}

void rt_obstacles_lag(romrt_model *m, const romrt_real *q, int start)
{
    RT_PROF_BEGIN(RT_PROF_NARROW);
    lag(m, q, start);
    RT_PROF_END(RT_PROF_NARROW);
}

romrt_real rt_obstacles_friction(romrt_model *m, romrt_real *g, romrt_real *H, int ld)
{
    romrt_real E = 0, eps = m->eps_v * m->h;
    int k, i, a;
    for (k = 0; k < m->nfric; k++) {
        const int32_t *id = m->fric_id + 4 * (size_t)k;
        const romrt_real *f = m->fric + 11 * (size_t)k, *w = f, *T = f + 4;
        romrt_real rel[3] = {0, 0, 0}, gt[3], B[9];
        for (i = 0; i < 4; i++) {
            const romrt_real *now = id[i] >= 0 ? m->ocx + 3 * (size_t)id[i] : rt_obstacle_point(m, (uint32_t)(-1 - id[i]), RT_AT_NOW);
            const romrt_real *then =
                id[i] >= 0 ? m->fx0 + 3 * (size_t)id[i] : rt_obstacle_point(m, (uint32_t)(-1 - id[i]), RT_AT_START);
            for (a = 0; a < 3; a++) rel[a] += w[i] * (now[a] - then[a]);
        }
        E += RT_PHYS(friction_slip)(T, rel, eps, m->mu * f[10], gt, H ? B : 0);
        if (g || H) rt_obstacles_pull_slip(m, id, w, gt, H ? B : 0, g, H, ld);
        if ((g || H) && m->obs_joint) rt_obstacles_slip_progress(m, id, w, gt, H ? B : 0, g, H, ld);
    }
    return E;
}
