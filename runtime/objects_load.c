/* Several objects' chunk (ROMBIN.md "Object chunks"): COBJ, the object of each collision vertex.
 * Since 1.7 the objects touch through their collision surfaces, as the reduced simulator's do
 * (OBHD, CEDG, CTRI; contact_surface.c), and COBJ says which stencils join two objects. 1.5's
 * CRAD (a sphere proxy of radius rho at every collision vertex) is refused by name: its spheres
 * kept objects 2 rho apart, and the same asset run another way would not be what was baked. */
#include "runtime/loader_impl.h"

romrt_status rt_objects_arrays(rt_loader *L, romrt_model *m)
{
    rombin_chunk c;
    romrt_status st;
    uint64_t n;
    uint32_t k;
    m->nobjects = 0, m->cv_obj = 0;
    if (rombin_find(&L->file, ROMBIN_CRAD, &c))
        return rt_fail(L->err, ROMRT_E_UNSUPPORTED, ROMBIN_CRAD,
                       "sphere-proxy objects (ROMBIN 1.5) are no longer run: rebake the asset with romkit build "
                       "(1.7 gives the objects exact contact through their surfaces)");
    if (!rombin_find(&L->file, ROMBIN_COBJ, &c)) return ROMRT_OK;
    if (m->ncv == 0) return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_COBJ, "objects without collision vertices (CVTX)");
    if ((st = rt_u32s(L, ROMBIN_COBJ, (uint64_t)m->ncv, 1, &m->cv_obj))) return st;
    /* the object count: one more than the largest index, at most the collision vertices (the
     * counting is read in place, so both passes see it) */
    for (n = 0, k = 0; k < (uint32_t)m->ncv; k++)
        if (m->cv_obj[k] >= n) n = (uint64_t)m->cv_obj[k] + 1;
    if (n < 2 || n > (uint64_t)m->ncv)
        return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_COBJ, "names ", n, " objects, not 2 to CVTX's count");
    m->nobjects = (int)n;
    return ROMRT_OK;
}

romrt_status rt_objects_contents(rt_loader *L, romrt_model *m)
{
    if (m->nobjects && !m->surface)
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_COBJ, "objects without their collision surface (OBHD, CEDG, CTRI)");
    return ROMRT_OK;
}
