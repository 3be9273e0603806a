/* Several objects' chunks (ROMBIN.md "Object chunks", 1.5): COBJ, the object of each collision
 * vertex, and CRAD, each object's proxy radius; the broad phase's scratch in the arena (objects.c
 * steps them). */
#include <math.h>

#include "runtime/loader_impl.h"

romrt_status rt_objects_arrays(rt_loader *L, romrt_model *m)
{
    rombin_chunk c;
    int found;
    uint64_t size = L->file.real_type == ROMBIN_REAL_F32 ? 4 : 8, n;
    romrt_status st = rt_chunk(L, ROMBIN_CRAD, ROMBIN_TYPE_REAL, 0, 0, &c, &found);
    uint32_t *cell;
    m->nobjects = 0;
    if (st) return st;
    if (!found) {
        if (rombin_find(&L->file, ROMBIN_COBJ, &c))
            return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_COBJ, "objects of the collision vertices without their radii (CRAD)");
        return ROMRT_OK;
    }
    n = c.raw / size;
    if (m->ncv == 0) return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_CRAD, "object radii without collision vertices (CVTX)");
    if (n < 2 || n > (uint64_t)m->ncv)
        return rt_fail_nn(L->err, ROMRT_E_MODEL, ROMBIN_CRAD, "holds ", n, " objects, not 2 to the ", (uint64_t)m->ncv,
                          " collision vertices");
    if (!(m->dhat > 0) || !(m->kappa > 0))
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_PARM, "dhat and kappa must be positive with several objects");
    m->nobjects = (int)n;
    if ((st = rt_reals(L, ROMBIN_CRAD, n, 1, &m->obj_rho)) || (st = rt_u32s(L, ROMBIN_COBJ, (uint64_t)m->ncv, 1, &m->cv_obj)))
        return st;
    m->grid_size = 1;
    while (m->grid_size < 2 * (uint32_t)m->ncv) m->grid_size *= 2;
    rt_scratch(L, 3 * (size_t)m->ncv, &m->cv_x);
    rt_scratch(L, 3 * (size_t)m->ncv, &m->cv_dx);
    rt_scratch(L, (size_t)m->r, &m->pair_a);
    rt_scratch_u32(L, 3 * (size_t)m->ncv, &cell);
    m->grid_cell = (int32_t *)(void *)cell;
    rt_scratch_u32(L, m->grid_size, &m->grid_head);
    rt_scratch_u32(L, (size_t)m->ncv, &m->grid_next);
    return ROMRT_OK;
}

romrt_status rt_objects_contents(rt_loader *L, romrt_model *m)
{
    int k;
    romrt_real d;
    romrt_status st;
    if (!m->nobjects) return ROMRT_OK;
    if ((st = rt_indices_below(L, ROMBIN_COBJ, m->cv_obj, (uint64_t)m->ncv, 1, 0, 1, (uint32_t)m->nobjects))) return st;
    if (!L->arena) return ROMRT_OK; /* converted radii live in the arena */
    m->rho_max = 0;
    for (k = 0; k < m->nobjects; k++) {
        if (!(m->obj_rho[k] > 0))
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_CRAD, "object ", (uint64_t)k,
                             "'s proxy radius is not positive (spheres of radius 0 leave the surface between vertices open)");
        if (m->obj_rho[k] > m->rho_max) m->rho_max = m->obj_rho[k];
    }
    d = rt_objects_min_distance(m, m->q);
    if (!(d > 0))
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_COBJ,
                       "two objects start within each other's proxies (collision vertices closer than their radii)");
    return ROMRT_OK;
}
