/* Reading the model's chunks (loader_impl.h): sizes and types against the header, finiteness, index
 * ranges, and arrays converted into the arena when their precision differs from the runtime's. */
#include <math.h>
#include <string.h>

#include "runtime/loader_impl.h"


/* Value i of a real chunk, whatever the file's real type. */
double rt_real_at(const rt_loader *L, const rombin_chunk *c, uint64_t i)
{
    if (L->file.real_type == ROMBIN_REAL_F32) {
        float x;
        memcpy(&x, c->data + 4 * i, 4);
        return x;
    } else {
        double x;
        memcpy(&x, c->data + 8 * i, 8);
        return x;
    }
}

/* The chunk `id` of `count` elements of `type` (count 0: any whole number of them; *found says
 * whether it is there; required chunks fail when absent). */
romrt_status rt_chunk(rt_loader *L, const char *id, int type, uint64_t count, int required, rombin_chunk *c,
                          int *found)
{
    uint64_t size = type == ROMBIN_TYPE_U32 ? 4 : type == ROMBIN_TYPE_BYTES ? 1 : L->file.real_type == ROMBIN_REAL_F32 ? 4 : 8;
    *found = rombin_find(&L->file, id, c);
    if (!*found) return required ? rt_fail(L->err, ROMRT_E_MODEL, id, "missing (the model needs it)") : ROMRT_OK;
    if (c->compression != ROMBIN_COMP_NONE)
        return rt_fail(L->err, ROMRT_E_UNSUPPORTED, id,
                       "deflate-compressed; the runtime opens stored chunks (bake without compression)");
    if (c->type != type) return rt_fail_n(L->err, ROMRT_E_MODEL, id, "element type ", (uint64_t)c->type, " is wrong");
    if (count && c->raw != count * size)
        return rt_fail_nn(L->err, ROMRT_E_MODEL, id, "holds ", c->raw / size, " values, the header implies ", count, "");
    return ROMRT_OK;
}

/* A real array of `count` values, finite, in place or converted into the arena. */
romrt_status rt_reals(rt_loader *L, const char *id, uint64_t count, int required, const romrt_real **out)
{
    rombin_chunk c;
    int found;
    uint64_t i;
    romrt_status st = rt_chunk(L, id, ROMBIN_TYPE_REAL, count, required, &c, &found);
    *out = 0;
    if (st || !found) return st;
    for (i = 0; i < count && !L->scanned; i++) {
        double x = rt_real_at(L, &c, i);
        if (!isfinite(x)) return rt_fail_n(L->err, ROMRT_E_MODEL, id, "value ", i, " is not finite");
#ifndef ROMRT_DOUBLE
        if (fabs(x) > 3.0e38) return rt_fail_n(L->err, ROMRT_E_MODEL, id, "value ", i, " overflows float");
#endif
    }
    if (L->file.real_type == ROMRT_REAL_TYPE) {
        *out = (const romrt_real *)(const void *)c.data;
        return ROMRT_OK;
    }
    if (L->arena) {
        romrt_real *dst = (romrt_real *)(void *)(L->arena + L->used);
        for (i = 0; i < count; i++) dst[i] = (romrt_real)rt_real_at(L, &c, i);
        *out = dst;
    }
    L->used += rt_align16((size_t)count * sizeof(romrt_real));
    return ROMRT_OK;
}

void rt_scratch(rt_loader *L, size_t count, romrt_real **out)
{
    *out = 0;
    if (L->arena) {
        *out = (romrt_real *)(void *)(L->arena + L->used);
        memset(*out, 0, count * sizeof(romrt_real));
    }
    L->used += rt_align16(count * sizeof(romrt_real));
}

void rt_scratch_u32(rt_loader *L, size_t count, uint32_t **out)
{
    *out = 0;
    if (L->arena) {
        *out = (uint32_t *)(void *)(L->arena + L->used);
        memset(*out, 0, count * sizeof(uint32_t));
    }
    L->used += rt_align16(count * sizeof(uint32_t));
}

void rt_scratch_wide(rt_loader *L, size_t count, double **out)
{
    *out = 0;
    if (L->arena) {
        *out = (double *)(void *)(L->arena + L->used);
        memset(*out, 0, count * sizeof(double));
    }
    L->used += rt_align16(count * sizeof(double));
}

romrt_status rt_u32s(rt_loader *L, const char *id, uint64_t count, int required, const uint32_t **out)
{
    rombin_chunk c;
    int found;
    romrt_status st = rt_chunk(L, id, ROMBIN_TYPE_U32, count, required, &c, &found);
    *out = found && !st ? (const uint32_t *)(const void *)c.data : 0;
    return st;
}

romrt_status rt_indices_below(rt_loader *L, const char *id, const uint32_t *a, uint64_t n, uint64_t stride,
                                  uint64_t lo, uint64_t hi, uint32_t limit)
{
    uint64_t i, k;
    for (i = 0; i < n; i++)
        for (k = lo; k < hi; k++)
            if (a[i * stride + k] >= limit)
                return rt_fail_nn(L->err, ROMRT_E_MODEL, id, "entry ", i, " names index ", a[i * stride + k],
                                  ", beyond its table");
    return ROMRT_OK;
}

romrt_status rt_load_groups_and_surface(rt_loader *L, romrt_model *m)
{
    romrt_status st;
    if ((st = rt_u32s(L, ROMBIN_GRPS, 2 * (uint64_t)m->ngroups, m->ngroups > 0, &m->groups))) return st;
    if (m->ngroups) {
        rombin_chunk c;
        int found;
        if ((st = rt_chunk(L, ROMBIN_GVTX, ROMBIN_TYPE_U32, 0, 1, &c, &found))) return st;
        m->gverts = (const uint32_t *)(const void *)c.data;
        if ((st = rt_chunk(L, ROMBIN_GNAM, ROMBIN_TYPE_BYTES, (uint64_t)m->ngroups * ROMBIN_GROUP_NAME_BYTES, 1, &c, &found)))
            return st;
        m->names = (const char *)c.data;
    }
    {
        rombin_chunk c;
        int found;
        if ((st = rt_chunk(L, ROMBIN_SURF, ROMBIN_TYPE_U32, 0, 0, &c, &found))) return st;
        if (found) {
            if (c.raw % 12 != 0 || c.raw / 12 > ROMRT_MAX_TRIANGLES)
                return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_SURF, "size is not a whole number of triangles");
            m->tris = (const uint32_t *)(const void *)c.data;
            m->ntris = (int)(c.raw / 12);
        }
    }
    return ROMRT_OK;
}

romrt_status rt_check_groups_and_surface(rt_loader *L, const romrt_model *m)
{
    romrt_status st;
    int g;
    rombin_chunk c;
    if ((st = rt_indices_below(L, ROMBIN_SURF, m->tris, (uint64_t)m->ntris, 3, 0, 3, (uint32_t)m->shown))) return st;
    if (m->ngroups) {
        rombin_find(&L->file, ROMBIN_GVTX, &c);
        if ((st = rt_indices_below(L, ROMBIN_GVTX, m->gverts, c.raw / 4, 1, 0, 1, (uint32_t)m->nv))) return st;
        for (g = 0; g < m->ngroups; g++) {
            uint64_t first = m->groups[2 * g], count = m->groups[2 * g + 1];
            if (count == 0 || first > c.raw / 4 || count > c.raw / 4 - first)
                return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_GRPS, "group ", (uint64_t)g, " is empty or runs past GVTX");
            if (memchr(m->names + ROMBIN_GROUP_NAME_BYTES * g, 0, ROMBIN_GROUP_NAME_BYTES) == 0)
                return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_GNAM, "name ", (uint64_t)g, " is not NUL-terminated");
        }
    }
    return ROMRT_OK;
}

romrt_status rt_head(rt_loader *L, const char *id, uint64_t count, int first_reserved, int r_at, int vertices_at,
                     int shown_at, const uint32_t **out)
{
    const uint32_t *head;
    romrt_status st = rt_u32s(L, id, count, 1, &head);
    uint64_t k;
    if (st) return st;
    for (k = (uint64_t)first_reserved; k < count; k++)
        if (head[k]) return rt_fail_n(L->err, ROMRT_E_MODEL, id, "reserved field ", k, " is not 0");
    if (head[r_at] == 0) return rt_fail(L->err, ROMRT_E_MODEL, id, "r is 0");
    if (head[r_at] > ROMRT_MAX_R)
        return rt_fail_nn(L->err, ROMRT_E_LIMIT, id, "r = ", head[r_at], " exceeds this build's ROMRT_MAX_R = ",
                          ROMRT_MAX_R, " (rebuild with a larger one)");
    if (head[vertices_at] == 0 || head[vertices_at] > ROMRT_MAX_VERTICES || head[shown_at] > head[vertices_at])
        return rt_fail_nn(L->err, ROMRT_E_LIMIT, id, "vertex counts out of range (stored ", head[vertices_at],
                          ", shown ", head[shown_at], ")");
    *out = head;
    return ROMRT_OK;
}

romrt_status rt_check_motion(rt_loader *L, const char *id, const char *what, uint64_t i, const romrt_real *p)
{
    if (!(p[0] == 0 || p[0] == 1 || p[0] == 2) || p[ROMBIN_PIN_PARAMS - 1] != 0)
        return rt_fail_n(L->err, ROMRT_E_MODEL, id, what, i, " has an unknown motion kind");
    if (p[0] == 1 && !(p[1] * p[1] + p[2] * p[2] + p[3] * p[3] > 0))
        return rt_fail_n(L->err, ROMRT_E_MODEL, id, what, i, " twists about a zero axis");
    return ROMRT_OK;
}
