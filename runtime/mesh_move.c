/* An app mesh's moves within a step (mesh_collider.c has the rule): the step's start kept and put
 * back, the way to the target pose for CCD, the fraction of it made. */
#include <string.h>

#include "runtime/romrt_impl.h"

/* x = R X + p over the mesh (pose: position 3, rotation 9 row-major). */
void rt_mesh_world(const rt_mesh *M, const romrt_real *pose, romrt_real *x)
{
    const romrt_real *p = pose, *R = pose + 3;
    uint32_t v;
    int i;
    for (v = 0; v < M->nv; v++) {
        const romrt_real *X = M->X + 3 * (size_t)v;
        for (i = 0; i < 3; i++) x[3 * (size_t)v + i] = R[3 * i] * X[0] + R[3 * i + 1] * X[1] + R[3 * i + 2] * X[2] + p[i];
    }
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

void rt_meshes_way(romrt_model *m)
{
    rt_mesh *M;
    uint32_t i;
    int k;
    EACH_MESH(m, k, M) {
        if (!mesh_pending(&m->colliders[k])) continue;
        rt_mesh_world(M, m->colliders[k].target, M->dx);
        for (i = 0; i < 3 * M->nv; i++) M->dx[i] -= M->x[i];
        M->moving = 1;
        rt_mesh_refit(M, 1);
    }
}

void rt_meshes_move(romrt_model *m, romrt_real fraction)
{
    rt_mesh *M;
    uint32_t i;
    int k;
    EACH_MESH(m, k, M) {
        rt_collider *c = &m->colliders[k];
        if (!M->moving) continue;
        if (fraction >= 1) { /* at the pose, exactly */
            rt_mesh_world(M, c->target, M->x);
            memcpy(c->now, c->target, sizeof c->now);
            M->part = 0;
        } else if (fraction > 0) {
            for (i = 0; i < 3 * M->nv; i++) M->x[i] += fraction * M->dx[i];
            M->part = 1;
        }
        memset(M->dx, 0, sizeof(romrt_real) * 3 * (size_t)M->nv);
        M->moving = 0;
        rt_mesh_refit(M, 0);
    }
}
