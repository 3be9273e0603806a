/* An app mesh's moves within a step (mesh_collider.c has the rule): the step's start kept and put
 * back, the way from there to the target pose that a step's joint solve moves it along
 * (contact_progress.c), its CCD moves, and where the solve leaves it. */
#include <string.h>

#include "runtime/romrt_impl.h"

/* x = R X + p for one point (pose: position 3, rotation 9 row-major). */
static void pose_point(const romrt_real *pose, const romrt_real *X, romrt_real *x)
{
    const romrt_real *p = pose, *R = pose + 3;
    int i;
    for (i = 0; i < 3; i++) x[i] = R[3 * i] * X[0] + R[3 * i + 1] * X[1] + R[3 * i + 2] * X[2] + p[i];
}

/* x = R X + p over the mesh. */
void rt_mesh_world(const rt_mesh *M, const romrt_real *pose, romrt_real *x)
{
    uint32_t v;
    for (v = 0; v < M->nv; v++) pose_point(pose, M->X + 3 * (size_t)v, x + 3 * (size_t)v);
}

#define EACH_MESH(m, k, M)                                                                                             \
    for (k = 0; k < ROMRT_MAX_COLLIDERS; k++)                                                                          \
        if ((M = m->colliders[k].active ? m->colliders[k].mesh : 0) != 0)

void rt_meshes_begin(romrt_model *m)
{
    rt_mesh *M;
    int k;
    EACH_MESH(m, k, M) {
        memcpy(M->x0, M->x, sizeof(romrt_real) * 3 * (size_t)M->nv);
        M->part_start = M->part;
    }
}

void rt_meshes_abort(romrt_model *m)
{
    rt_mesh *M;
    int k;
    EACH_MESH(m, k, M) {
        memcpy(M->x, M->x0, sizeof(romrt_real) * 3 * (size_t)M->nv);
        memset(M->dx, 0, sizeof(romrt_real) * 3 * (size_t)M->nv);
        M->part = M->part_start, M->moving = 0;
        rt_mesh_refit(M, 0);
    }
}

static int mesh_pending(const rt_collider *c)
{
    return c->mesh->part || memcmp(c->now, c->target, sizeof c->now);
}

int rt_meshes_pending(const romrt_model *m)
{
    const rt_mesh *M;
    int k;
    if (!m->nmeshes) return 0;
    EACH_MESH(m, k, M)
        if (mesh_pending(&m->colliders[k])) return 1;
    return 0;
}

/* Where the slot's target pose puts vertex v, less where it was at the step's start. */
static void target_way(const rt_collider *c, uint32_t v, romrt_real D[3])
{
    const romrt_real *x0 = c->mesh->x0 + 3 * (size_t)v;
    int i;
    pose_point(c->target, c->mesh->X + 3 * (size_t)v, D);
    for (i = 0; i < 3; i++) D[i] -= x0[i];
}

int rt_mesh_way(const romrt_model *m, uint32_t o, romrt_real D[3])
{
    const rt_collider *c = &m->colliders[o >> RT_MESH_SHIFT];
    if (!c->active || !c->mesh || !mesh_pending(c)) return 0;
    target_way(c, o & ((1u << RT_MESH_SHIFT) - 1), D);
    return 1;
}

romrt_real rt_mesh_longest_way2(const romrt_model *m, int k)
{
    const rt_collider *c = &m->colliders[k];
    romrt_real L2 = 0, D[3], d2;
    uint32_t v;
    if (!c->active || !c->mesh || !mesh_pending(c)) return 0;
    for (v = 0; v < c->mesh->nv; v++) {
        target_way(c, v, D);
        d2 = D[0] * D[0] + D[1] * D[1] + D[2] * D[2];
        if (d2 > L2) L2 = d2;
    }
    return L2;
}

/* Slot k's unknown in the joint solve (-1: none). */
static int unit_of(const romrt_model *m, int k)
{
    return m->obs_unit[ROMRT_MAX_MOVING_OBSTACLES + k];
}

/* The moving meshes each at its progress s[u] of its way (ds NULL), or still there with its CCD
 * move ds[u] of it in dx (boxes swept). */
void rt_meshes_at(romrt_model *m, const romrt_real *s, const romrt_real *ds)
{
    rt_mesh *M;
    romrt_real D[3], sk, dsk;
    uint32_t v;
    int k, a, u;
    EACH_MESH(m, k, M) {
        if (!mesh_pending(&m->colliders[k])) continue;
        u = unit_of(m, k);
        sk = u >= 0 ? s[u] : 0, dsk = u >= 0 && ds ? ds[u] : 0;
        for (v = 0; v < M->nv; v++) {
            target_way(&m->colliders[k], v, D);
            for (a = 0; a < 3; a++) {
                M->x[3 * (size_t)v + a] = M->x0[3 * (size_t)v + a] + sk * D[a];
                M->dx[3 * (size_t)v + a] = dsk * D[a];
            }
        }
        M->moving = ds != 0;
        rt_mesh_refit(M, M->moving);
    }
}

/* The rest of the way to the target poses in dx (CCD with the body still), of the meshes whose
 * unknown is near (all with near NULL); the others' dx zero. */
void rt_meshes_way(romrt_model *m, const int *near)
{
    rt_mesh *M;
    uint32_t i;
    int k, u;
    EACH_MESH(m, k, M) {
        if (!mesh_pending(&m->colliders[k])) continue;
        u = unit_of(m, k);
        if (near && (u < 0 || !near[u])) {
            memset(M->dx, 0, sizeof(romrt_real) * 3 * (size_t)M->nv);
            M->moving = 0;
            rt_mesh_refit(M, 0);
            continue;
        }
        rt_mesh_world(M, m->colliders[k].target, M->dx);
        for (i = 0; i < 3 * M->nv; i++) M->dx[i] -= M->x[i];
        M->moving = 1;
        rt_mesh_refit(M, 1);
    }
}

/* The end of a step's solve: the moving meshes at their poses exactly (arrive, theirs near or near
 * NULL), or where the solve left them, short of their poses (part), their dx cleared. */
void rt_meshes_end(romrt_model *m, int arrive, const int *near)
{
    rt_mesh *M;
    int k, u;
    EACH_MESH(m, k, M) {
        rt_collider *c = &m->colliders[k];
        if (!mesh_pending(c)) continue;
        u = unit_of(m, k);
        if (arrive && (!near || (u >= 0 && near[u]))) {
            rt_mesh_world(M, c->target, M->x);
            memcpy(c->now, c->target, sizeof c->now);
            M->part = 0;
        } else if (memcmp(M->x, M->x0, sizeof(romrt_real) * 3 * (size_t)M->nv)) {
            M->part = 1;
        }
        memset(M->dx, 0, sizeof(romrt_real) * 3 * (size_t)M->nv);
        M->moving = 0;
        rt_mesh_refit(M, 0);
    }
}
