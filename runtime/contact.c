/* Contact with the scene's obstacles other than planes, as the reduced simulator has it
 * (precompute/rom/contact.c over precompute/contact): the IPC barrier (Li et al. 2020, Eq. 6-8)
 * kappa sum_k m_k b(d_k^2 - xi^2, dhat^2 + 2 xi dhat) over the point-triangle and edge-edge pairs
 * within dhat (per stencil: physics/contact_impl.h, the precompute's own code in this precision),
 * each pair's Hessian projected to PSD on its collision vertices and pulled into the r x r system
 * through their basis rows, H += J^T B J; the step filter by additive CCD of every stencil the
 * swept boxes give (Li et al. 2021); the obstacles' scripted motion (OBMO), and the joint CCD of
 * the body and the obstacles moving with it (contact_progress.c). */
#include <math.h>
#include <string.h>

#include "runtime/romrt_impl.h"

int rt_surface_on(const romrt_model *m)
{
    return m->surface && (m->nobs || m->self_contact || m->nobjects > 1 || m->nmeshes);
}

romrt_real *rt_obstacle_point(const romrt_model *m, uint32_t o, int which)
{
    const rt_mesh *M;
    if (o < (uint32_t)m->onv) {
        romrt_real *a = which == RT_AT_NOW ? m->ox : which == RT_AT_MOVE ? m->odx : which == RT_AT_START ? m->fox0 : m->cache_ox;
        return a + 3 * (size_t)o;
    }
    o -= (uint32_t)m->onv;
    M = m->colliders[o >> RT_MESH_SHIFT].mesh;
    o &= (1u << RT_MESH_SHIFT) - 1;
    return (which == RT_AT_NOW ? M->x : which == RT_AT_MOVE ? M->dx : which == RT_AT_START ? M->x0 : M->cache) + 3 * (size_t)o;
}

const romrt_real *rt_obstacle_rest(const romrt_model *m, uint32_t o)
{
    if (o < (uint32_t)m->onv) return m->oX + 3 * (size_t)o;
    o -= (uint32_t)m->onv;
    return m->colliders[o >> RT_MESH_SHIFT].mesh->X + 3 * (size_t)(o & ((1u << RT_MESH_SHIFT) - 1));
}

void rt_obstacles_stencil(const romrt_model *m, const int32_t id[4], const romrt_real *pts[4])
{
    int k;
    for (k = 0; k < 4; k++)
        pts[k] = id[k] >= 0 ? m->ocx + 3 * (size_t)id[k] : rt_obstacle_point(m, (uint32_t)(-1 - id[k]), RT_AT_NOW);
}

/* A baked obstacle's thickness (OBJS), or a collider's (0 for an app mesh, a sphere's or
 * capsule's radius: shape_collider.c). */
romrt_real rt_obstacles_xi(const romrt_model *m, const int32_t id[4])
{
    int k;
    for (k = 0; k < 4; k++)
        if (id[k] < 0) {
            uint32_t o = (uint32_t)(-1 - id[k]);
            return o < (uint32_t)m->onv ? m->obs_xi[4 * (size_t)m->overt_obs[o]]
                                        : m->colliders[(o - (uint32_t)m->onv) >> RT_MESH_SHIFT].mesh->xi;
        }
    return 0;
}

/* |e|^2 of an edge at rest: a collision edge's over VERT, an obstacle edge's over OBVX (an app
 * mesh's in its own frame: the same length). */
static romrt_real rest2(const romrt_model *m, int32_t a, int32_t b)
{
    const romrt_real *p = a >= 0 ? m->X + 3 * (size_t)m->cv[a] : rt_obstacle_rest(m, (uint32_t)(-1 - a));
    const romrt_real *q = b >= 0 ? m->X + 3 * (size_t)m->cv[b] : rt_obstacle_rest(m, (uint32_t)(-1 - b));
    return (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
}

romrt_real rt_obstacles_eps(const romrt_model *m, int edge_edge, const int32_t id[4])
{
    return edge_edge ? RT_K(1e-3) * rest2(m, id[0], id[1]) * rest2(m, id[2], id[3]) : 0;
}

static romrt_real pairs_energy(romrt_model *m, const romrt_real *q, int friction, romrt_real *g, romrt_real *H, int ld)
{
    romrt_real E = 0, gl[12], Hl[144];
    int i, k;
    rt_obstacles_positions(m, q, 0);
    if (rt_obstacles_gather(m)) return (romrt_real)INFINITY;
    for (i = 0; i < m->ncand; i++) {
        const int32_t *c = m->cand + 5 * (size_t)i, *id = c + 1;
        const romrt_real *pts[4];
        romrt_real e;
        int dof[4];
        romrt_real xi = rt_obstacles_xi(m, id), reach = m->dhat + xi, d2;
        rt_obstacles_stencil(m, id, pts);
        /* the candidates out of reach first, by the distance's value alone (the precompute's gather
         * keeps only those within reach, by the same test): the derivatives cost 50 times more */
        d2 = RT_PHYS(contact_distance2)(c[0] ? RT_PHYS(edge_edge_case)(pts) : RT_PHYS(point_triangle_case)(pts), pts, 0, 0);
        if (!(d2 < reach * reach)) continue;
        e = RT_PHYS(pair_barrier)(c[0], pts, xi, m->dhat, rt_obstacles_eps(m, c[0], id), g || H ? gl : 0, H ? Hl : 0, 0);
        if (!isfinite(e)) return (romrt_real)INFINITY;
        if (e == 0) continue;
        m->contact_terms++;
        E += m->kappa * e;
        if (!g && !H) continue;
        for (k = 0; k < 12; k++) gl[k] *= m->kappa;
        if (H) {
            for (k = 0; k < 4; k++) dof[k] = id[k] >= 0 || m->obs_joint; /* the obstacles' too when they move with s */
            RT_PHYS(pair_project)(dof, Hl);
            for (k = 0; k < 144; k++) Hl[k] *= m->kappa;
        }
        rt_obstacles_pull(m, id, gl, H ? Hl : 0, g, H, ld);
        if (m->obs_joint) rt_obstacles_pull_progress(m, id, gl, H ? Hl : 0, g, H, ld);
    }
    if (friction) {
        E += rt_obstacles_friction(m, g, H, ld);
        m->contact_terms += m->nfric;
    }
    return E;
}

romrt_real rt_obstacles_energy(romrt_model *m, const romrt_real *q, int friction, romrt_real *g, romrt_real *H, int ld)
{
    romrt_real E;
    RT_PROF_BEGIN(RT_PROF_NARROW);
    E = pairs_energy(m, q, friction, g, H, ld);
    RT_PROF_END(RT_PROF_NARROW);
    return E;
}

typedef struct {
    romrt_real alpha;
    int body_moves;       /* the body goes by ocdx */
    int obstacles_move;   /* the obstacles go by odx */
} ccd_ctx;

/* In float the filter also keeps CONTACT_FLOOR dhat of every stencil's gap, as the plane filter
 * does (potential.c): positions carry rounding of about 1e-7 of their size, and steps that each
 * keep 10% of a gap shrink it geometrically into that noise, where the distance (and CCD with it)
 * loses every digit and a surface can slip through (moving spikes pushing a slab did, in 12
 * places, within one step). The floor holds for every stencil outside it, whatever its distance
 * does at the step's start: a first-order rate misjudges two edges whose distance first grows and
 * then falls along a straight step (the folded bar of test_runtime_object_contact: 3.6e-6 m, rate
 * >= 0, down to 3.7e-7 m within the step). A stencil already inside the floor (by the rounding
 * of the last steps that each kept 10% over it) may not approach to first order, nor lose more
 * than a tenth of its gap along the step: with CCD's own 10% kept there, that left the fold's last
 * converging step at 1.3e-6 m, now at 1.8e-6 m. The floor holds only for the stencils CCD is
 * handed, so the swept boxes are grown by it (FLOOR_GROW): with boxes that merely touch, a vertex
 * stepping onto a floor without reaching it was never handed, and two fixed Newton steps of the
 * pour (bench/pour.sh, no line search to stop them) left one 8.75e-8 m over the container, below
 * its coordinates' rounding (tests/integration/runtime_pour.sh). The double runtime, like the
 * reduced simulator, goes as close as the barrier lets it. */
#ifdef ROMRT_DOUBLE
#define CONTACT_FLOOR 0
#else
#define CONTACT_FLOOR 1e-3f
#endif
#define FLOOR_GROW(m) (RT_K(CONTACT_FLOOR) * (m)->dhat)

static void ccd_stencil(romrt_model *m, int edge_edge, const int32_t id[4], void *ctx)
{
    static const romrt_real still[3] = {0, 0, 0};
    ccd_ctx *c = (ccd_ctx *)ctx;
    const romrt_real *pts[4], *d[4];
    romrt_real toi, xi = rt_obstacles_xi(m, id);
    int k, a;
    rt_obstacles_stencil(m, id, pts);
    for (k = 0; k < 4; k++)
        d[k] = id[k] >= 0 ? (c->body_moves ? m->ocdx + 3 * (size_t)id[k] : still)
                          : (c->obstacles_move ? rt_obstacle_point(m, (uint32_t)(-1 - id[k]), RT_AT_MOVE) : still);
    if (CONTACT_FLOOR > 0) {
        /* d(d^2)/dt = 2 n . sum_i w_i dx_i, n = sum_i w_i x_i (the closest points held: their
         * own motion along the features does not change the distance to first order) */
        rk_distance_case dc = edge_edge ? RT_PHYS(edge_edge_case)(pts) : RT_PHYS(point_triangle_case)(pts);
        romrt_real w[4], n[3] = {0, 0, 0}, v[3] = {0, 0, 0}, rate;
        romrt_real dist = RT_SQRT(RT_PHYS(contact_distance2)(dc, pts, 0, 0)) - xi, floor = RT_K(CONTACT_FLOOR) * m->dhat;
        RT_PHYS(contact_closest_weights)(dc, pts, w);
        for (k = 0; k < 4; k++)
            for (a = 0; a < 3; a++) n[a] += w[k] * pts[k][a], v[a] += w[k] * d[k][a];
        rate = n[0] * v[0] + n[1] * v[1] + n[2] * v[2];
        if (dist > floor) { /* kept a floor apart */
            xi += floor;
        } else if (rate < 0) { /* inside it already and approaching: no step */
            c->alpha = 0;
            return;
        } else if (dist > 0) { /* inside it, moving apart to first order: at most 10% closer */
            xi += RT_K(0.9) * dist;
        }
    }
    if (RT_PHYS(ccd_stencil)(edge_edge, pts, d, xi, c->alpha, &toi) && toi < c->alpha) c->alpha = toi;
}

static void ccd_visit(romrt_model *m, int edge_edge, const int32_t id[4], void *ctx)
{
    RT_PROF_BEGIN(RT_PROF_NARROW);
    ccd_stencil(m, edge_edge, id, ctx);
    RT_PROF_END(RT_PROF_NARROW);
}

/* In a joint solve (contact_progress.c) the obstacles go by ds D_o along with the body. */
romrt_real rt_obstacles_max_step(romrt_model *m, const romrt_real *y, const romrt_real *d)
{
    ccd_ctx c;
    int p = m->r + m->nmoving;
    c.alpha = 1, c.body_moves = 1, c.obstacles_move = m->obs_joint;
    RT_PROF_BEGIN(RT_PROF_NARROW);
    rt_obstacles_positions(m, y, d);
    if (m->obs_joint) rt_obstacles_place(m, y + p, d + p);
    RT_PROF_END(RT_PROF_NARROW);
    rt_obstacles_swept(m, 1, FLOOR_GROW(m), ccd_visit, &c);
    if (m->obs_joint) rt_obstacles_place(m, y + p, 0);
    return c.alpha;
}

/* Where the obstacles' motions put their vertices at time t, into out (3 onv). */
static void positions_at(const romrt_model *m, double t, romrt_real *out)
{
    int k, v, i;
    for (k = 0; k < m->nobs; k++) {
        const uint32_t *o = m->obs + ROMBIN_OBST_COUNT * (size_t)k;
        const romrt_real *p = m->obs_motion + ROMBIN_PIN_PARAMS * (size_t)k;
        romrt_real R[9], s[3];
        RT_PHYS(motion)((rk_motion_kind)(int)p[0], p + 1, p + 4, p[7], p + 8, t, R, s);
        for (v = (int)o[ROMBIN_OBST_FIRST_VERTEX]; v < (int)(o[ROMBIN_OBST_FIRST_VERTEX] + o[ROMBIN_OBST_VERTICES]); v++) {
            const romrt_real *X = m->oX + 3 * (size_t)v;
            for (i = 0; i < 3; i++)
                out[3 * (size_t)v + i] = R[3 * i] * X[0] + R[3 * i + 1] * X[1] + R[3 * i + 2] * X[2] + s[i];
        }
    }
}

void rt_obstacles_target(romrt_model *m, double t)
{
    positions_at(m, t, m->ox_to);
}

void rt_obstacles_at(romrt_model *m, double t)
{
    int i;
    positions_at(m, t, m->ox);
    for (i = 0; i < 3 * m->onv; i++) m->odx[i] = 0;
    rt_obstacles_refit(m, 0);
    m->obs_time = t;
}

romrt_real rt_obstacles_fraction(romrt_model *m, const romrt_real *q, const int *near)
{
    ccd_ctx c;
    int i, u;
    for (i = 0; i < 3 * m->onv && m->obs_moving; i++) {
        u = near ? rt_obstacle_unit(m, (uint32_t)(i / 3)) : 0;
        m->odx[i] = u >= 0 && (!near || near[u]) ? m->ox_to[i] - m->ox[i] : 0;
    }
    if (m->nmeshes) rt_meshes_way(m, near); /* the app meshes' way to their poses, in their dx */
    rt_obstacles_positions(m, q, 0);
    for (i = 0; i < 3 * m->ncv; i++) m->ocdx[i] = 0;
    if (m->obs_moving) rt_obstacles_refit(m, 1); /* (static ones' boxes are where they are) */
    c.alpha = 1, c.body_moves = 0, c.obstacles_move = 1; /* the surface's own stencils hold still: none of them */
    rt_obstacles_swept(m, 0, FLOOR_GROW(m), ccd_visit, &c);
    for (i = 0; i < 3 * m->onv && m->obs_moving; i++) m->odx[i] = 0;
    if (m->obs_moving) rt_obstacles_refit(m, 0);
    return c.alpha;
}

void rt_obstacles_arrive(romrt_model *m, double t)
{
    if (m->nmeshes) rt_meshes_end(m, 1, 0);
    if (m->obs_moving) rt_obstacles_at(m, t);
}
