/* romrt_arena_size and romrt_open: the container check (formats/rombin_read.c), then every model
 * chunk's size, type, counts, indices and values, once, so that stepping needs no checks. */
#include <math.h>
#include <string.h>

#include "runtime/romrt_impl.h"

static const char *const known_chunks[] = {ROMBIN_HEAD, ROMBIN_PARM, ROMBIN_VERT, ROMBIN_ROWS, ROMBIN_MASS,
                                           ROMBIN_DAMP, ROMBIN_LOAD, ROMBIN_PENA, ROMBIN_PINS, ROMBIN_ELEM,
                                           ROMBIN_ELMR, ROMBIN_PLAN, ROMBIN_CONT, ROMBIN_CMAS, ROMBIN_GRPS,
                                           ROMBIN_GVTX, ROMBIN_GNAM, ROMBIN_SURF, ROMBIN_VMAP, ROMBIN_INFO, 0};

/* Where the model and its converted arrays go: with arena NULL, only counts the bytes. */
typedef struct {
    rombin_file file;
    unsigned char *arena;
    size_t used, cap;
    int scanned;              /* every real already checked finite (by the sizing pass) */
    romrt_error *err;
} loader;

static size_t align16(size_t n) { return (n + 15) / 16 * 16; }

/* Value i of a real chunk, whatever the file's real type. */
static double real_at(const loader *L, const rombin_chunk *c, uint64_t i)
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
static romrt_status chunk(loader *L, const char *id, int type, uint64_t count, int required, rombin_chunk *c,
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
static romrt_status reals(loader *L, const char *id, uint64_t count, int required, const romrt_real **out)
{
    rombin_chunk c;
    int found;
    uint64_t i;
    romrt_status st = chunk(L, id, ROMBIN_TYPE_REAL, count, required, &c, &found);
    *out = 0;
    if (st || !found) return st;
    for (i = 0; i < count && !L->scanned; i++) {
        double x = real_at(L, &c, i);
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
        for (i = 0; i < count; i++) dst[i] = (romrt_real)real_at(L, &c, i);
        *out = dst;
    }
    L->used += align16((size_t)count * sizeof(romrt_real));
    return ROMRT_OK;
}

static romrt_status u32s(loader *L, const char *id, uint64_t count, int required, const uint32_t **out)
{
    rombin_chunk c;
    int found;
    romrt_status st = chunk(L, id, ROMBIN_TYPE_U32, count, required, &c, &found);
    *out = found && !st ? (const uint32_t *)(const void *)c.data : 0;
    return st;
}

static romrt_status indices_below(loader *L, const char *id, const uint32_t *a, uint64_t n, uint64_t stride,
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

static romrt_status sizes(loader *L, romrt_model *m)
{
    const uint32_t *head;
    romrt_status st = u32s(L, ROMBIN_HEAD, ROMBIN_HEAD_COUNT, 1, &head);
    int k;
    if (st) return st;
    for (k = ROMBIN_HEAD_SOURCE_TETS + 1; k < ROMBIN_HEAD_COUNT; k++)
        if (head[k]) return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_HEAD, "reserved field ", (uint64_t)k, " is not 0");
    if (head[ROMBIN_HEAD_R] == 0) return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_HEAD, "r is 0");
    if (head[ROMBIN_HEAD_R] > ROMRT_MAX_R)
        return rt_fail_nn(L->err, ROMRT_E_LIMIT, ROMBIN_HEAD, "r = ", head[ROMBIN_HEAD_R],
                          " exceeds this build's ROMRT_MAX_R = ", ROMRT_MAX_R, " (rebuild with a larger one)");
    if (head[ROMBIN_HEAD_VERTICES] == 0 || head[ROMBIN_HEAD_VERTICES] > ROMRT_MAX_VERTICES ||
        head[ROMBIN_HEAD_SHOWN] > head[ROMBIN_HEAD_VERTICES])
        return rt_fail_nn(L->err, ROMRT_E_LIMIT, ROMBIN_HEAD, "vertex counts out of range (stored ",
                          head[ROMBIN_HEAD_VERTICES], ", shown ", head[ROMBIN_HEAD_SHOWN], ")");
    if (head[ROMBIN_HEAD_ELEMENTS] == 0 || head[ROMBIN_HEAD_ELEMENTS] > ROMRT_MAX_ELEMENTS)
        return rt_fail_n(L->err, ROMRT_E_LIMIT, ROMBIN_HEAD, "element count ", head[ROMBIN_HEAD_ELEMENTS], " out of range");
    if (head[ROMBIN_HEAD_PINS] > ROMRT_MAX_PINS || head[ROMBIN_HEAD_PLANES] > ROMRT_MAX_PLANES ||
        head[ROMBIN_HEAD_GROUPS] > ROMRT_MAX_GROUPS)
        return rt_fail(L->err, ROMRT_E_LIMIT, ROMBIN_HEAD, "pin, plane or group count above the runtime's limits");
    if ((uint64_t)head[ROMBIN_HEAD_CONTACTS] > (uint64_t)head[ROMBIN_HEAD_VERTICES] * head[ROMBIN_HEAD_PLANES])
        return rt_fail_n(L->err, ROMRT_E_LIMIT, ROMBIN_HEAD, "contact count ", head[ROMBIN_HEAD_CONTACTS],
                         " exceeds vertices x planes");
    if (head[ROMBIN_HEAD_INTEGRATOR] > 1)
        return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_HEAD, "unknown integrator ", head[ROMBIN_HEAD_INTEGRATOR], "");
    if (head[ROMBIN_HEAD_NEWTON_MAX_ITER] == 0 || head[ROMBIN_HEAD_NEWTON_MAX_ITER] > ROMRT_MAX_NEWTON)
        return rt_fail_n(L->err, ROMRT_E_LIMIT, ROMBIN_HEAD, "Newton iteration limit ", head[ROMBIN_HEAD_NEWTON_MAX_ITER],
                         " is not in 1..1000");
    m->r = (int)head[ROMBIN_HEAD_R];
    m->nv = (int)head[ROMBIN_HEAD_VERTICES];
    m->shown = (int)head[ROMBIN_HEAD_SHOWN];
    m->ne = (int)head[ROMBIN_HEAD_ELEMENTS];
    m->npins = (int)head[ROMBIN_HEAD_PINS];
    m->nplanes = (int)head[ROMBIN_HEAD_PLANES];
    m->ncontacts = (int)head[ROMBIN_HEAD_CONTACTS];
    m->ngroups = (int)head[ROMBIN_HEAD_GROUPS];
    m->integrator = (int)head[ROMBIN_HEAD_INTEGRATOR];
    m->max_iter = (int)head[ROMBIN_HEAD_NEWTON_MAX_ITER];
    {
        rombin_chunk c;
        int found;
        double p[ROMBIN_PARM_COUNT];
        if ((st = chunk(L, ROMBIN_PARM, ROMBIN_TYPE_REAL, ROMBIN_PARM_COUNT, 1, &c, &found))) return st;
        for (k = 0; k < ROMBIN_PARM_COUNT; k++) {
            p[k] = real_at(L, &c, (uint64_t)k);
            if (!isfinite(p[k])) return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_PARM, "value ", (uint64_t)k, " is not finite");
            if (k > ROMBIN_PARM_KAPPA && p[k] != 0)
                return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_PARM, "reserved value ", (uint64_t)k, " is not 0");
        }
        if (!(p[ROMBIN_PARM_H] > 0) || !(p[ROMBIN_PARM_NEWTON_TOL] > 0) || !(p[ROMBIN_PARM_MASS] > 0) ||
            p[ROMBIN_PARM_KAPPA] < 0 || (m->nplanes && !(p[ROMBIN_PARM_DHAT] > 0)))
            return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_PARM,
                           "time step, tolerance and mass must be positive, kappa non-negative, dhat positive with planes");
        m->h = (romrt_real)p[ROMBIN_PARM_H];
        m->tol = (romrt_real)p[ROMBIN_PARM_NEWTON_TOL];
        m->mass = (romrt_real)p[ROMBIN_PARM_MASS];
        m->dhat = (romrt_real)p[ROMBIN_PARM_DHAT];
        m->kappa = (romrt_real)p[ROMBIN_PARM_KAPPA];
    }
    return ROMRT_OK;
}

static romrt_status arrays(loader *L, romrt_model *m)
{
    uint64_t r = (uint64_t)m->r, nv = (uint64_t)m->nv, rr = r * r;
    romrt_status st;
    if ((st = reals(L, ROMBIN_VERT, 3 * nv, 1, &m->X)) || (st = reals(L, ROMBIN_ROWS, 3 * nv * r, 1, &m->rows)) ||
        (st = reals(L, ROMBIN_MASS, rr, 1, &m->M)) || (st = reals(L, ROMBIN_DAMP, rr, 0, &m->C)) ||
        (st = reals(L, ROMBIN_LOAD, r, 1, &m->f)) || (st = reals(L, ROMBIN_PENA, rr, m->npins > 0, &m->A)) ||
        (st = reals(L, ROMBIN_PINS, (uint64_t)m->npins * (ROMBIN_PIN_PARAMS + 12 * r), m->npins > 0, &m->pins)) ||
        (st = u32s(L, ROMBIN_ELEM, 5 * (uint64_t)m->ne, 1, &m->elem)) ||
        (st = reals(L, ROMBIN_ELMR, 12 * (uint64_t)m->ne, 1, &m->elem_real)) ||
        (st = reals(L, ROMBIN_PLAN, 6 * (uint64_t)m->nplanes, m->nplanes > 0, &m->planes)) ||
        (st = u32s(L, ROMBIN_CONT, 2 * (uint64_t)m->ncontacts, m->ncontacts > 0, &m->contacts)) ||
        (st = reals(L, ROMBIN_CMAS, (uint64_t)m->ncontacts, m->ncontacts > 0, &m->cmass)) ||
        (st = u32s(L, ROMBIN_GRPS, 2 * (uint64_t)m->ngroups, m->ngroups > 0, &m->groups)))
        return st;
    if (m->ngroups) {
        rombin_chunk c;
        int found;
        if ((st = chunk(L, ROMBIN_GVTX, ROMBIN_TYPE_U32, 0, 1, &c, &found))) return st;
        m->gverts = (const uint32_t *)(const void *)c.data;
        if ((st = chunk(L, ROMBIN_GNAM, ROMBIN_TYPE_BYTES, (uint64_t)m->ngroups * ROMBIN_GROUP_NAME_BYTES, 1, &c, &found)))
            return st;
        m->names = (const char *)c.data;
    }
    {
        rombin_chunk c;
        int found;
        if ((st = chunk(L, ROMBIN_SURF, ROMBIN_TYPE_U32, 0, 0, &c, &found))) return st;
        if (found) {
            if (c.raw % 12 != 0 || c.raw / 12 > ROMRT_MAX_TRIANGLES)
                return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_SURF, "size is not a whole number of triangles");
            m->tris = (const uint32_t *)(const void *)c.data;
            m->ntris = (int)(c.raw / 12);
        }
    }
    return ROMRT_OK;
}

/* Indices and values the step relies on. */
static romrt_status contents(loader *L, romrt_model *m)
{
    romrt_status st;
    int e, g, k;
    rombin_chunk c;
    if ((st = indices_below(L, ROMBIN_ELEM, m->elem, (uint64_t)m->ne, 5, 0, 4, (uint32_t)m->nv)) ||
        (st = indices_below(L, ROMBIN_ELEM, m->elem, (uint64_t)m->ne, 5, 4, 5, RK_MAT_NEOHOOKEAN + 1)) ||
        (st = indices_below(L, ROMBIN_CONT, m->contacts, (uint64_t)m->ncontacts, 2, 0, 1, (uint32_t)m->nv)) ||
        (st = indices_below(L, ROMBIN_CONT, m->contacts, (uint64_t)m->ncontacts, 2, 1, 2, (uint32_t)m->nplanes)) ||
        (st = indices_below(L, ROMBIN_SURF, m->tris, (uint64_t)m->ntris, 3, 0, 3, (uint32_t)m->shown)))
        return st;
    if (m->ngroups) {
        rombin_find(&L->file, ROMBIN_GVTX, &c);
        if ((st = indices_below(L, ROMBIN_GVTX, m->gverts, c.raw / 4, 1, 0, 1, (uint32_t)m->nv))) return st;
        for (g = 0; g < m->ngroups; g++) {
            uint64_t first = m->groups[2 * g], count = m->groups[2 * g + 1];
            if (count == 0 || first > c.raw / 4 || count > c.raw / 4 - first)
                return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_GRPS, "group ", (uint64_t)g, " is empty or runs past GVTX");
            if (memchr(m->names + ROMBIN_GROUP_NAME_BYTES * g, 0, ROMBIN_GROUP_NAME_BYTES) == 0)
                return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_GNAM, "name ", (uint64_t)g, " is not NUL-terminated");
        }
    }
    if (!L->arena) return ROMRT_OK; /* the values below live in the arena when converted */
    for (e = 0; e < m->ne; e++) {
        const romrt_real *er = m->elem_real + 12 * (size_t)e;
        if (!(er[9] >= 0) || !(er[10] > 0) || !(er[11] > -er[10]))
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_ELMR, "element ", (uint64_t)e,
                             " has a negative weight or impossible Lame parameters");
    }
    for (g = 0; g < m->npins; g++) {
        const romrt_real *p = m->pins + (ROMBIN_PIN_PARAMS + 12 * (size_t)m->r) * (size_t)g;
        if (!(p[0] == 0 || p[0] == 1 || p[0] == 2) || p[ROMBIN_PIN_PARAMS - 1] != 0)
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_PINS, "pin ", (uint64_t)g, " has an unknown motion kind");
        if (p[0] == 1 && !(p[1] * p[1] + p[2] * p[2] + p[3] * p[3] > 0))
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_PINS, "pin ", (uint64_t)g, " twists about a zero axis");
    }
    for (k = 0; k < m->nplanes; k++) {
        const romrt_real *n = m->planes + 6 * (size_t)k + 3;
        romrt_real len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        if (!(len2 > RT_K(0.99) && len2 < RT_K(1.01)))
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_PLAN, "plane ", (uint64_t)k, " has no unit normal");
    }
    for (k = 0; k < m->ncontacts; k++)
        if (!(m->cmass[k] >= 0)) return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_CMAS, "contact ", (uint64_t)k, " has a negative mass");
    /* M_r must be positive definite: it measures every Newton step. */
    memcpy(m->H, m->M, sizeof(romrt_real) * (size_t)m->r * (size_t)m->r);
    if ((k = rt_cholesky(m->r, m->H)) != 0)
        return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_MASS, "is not positive definite (pivot ", (uint64_t)k, ")");
    for (k = 0; k < m->ncontacts; k++)
        if (!(rt_contact_distance(m, k, m->q) > 0))
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_CONT, "contact ", (uint64_t)k, " starts on or behind its plane");
    return ROMRT_OK;
}

static romrt_status load(const void *asset, size_t asset_bytes, void *arena, size_t arena_bytes, size_t *needed,
                         romrt_model **out, romrt_error *err)
{
    loader L;
    romrt_model scratch, *m;
    romrt_status st;
    int rb;
    if (err) {
        err->status = ROMRT_OK;
        err->chunk[0] = 0;
        err->message[0] = 0;
    }
    if (!asset) return rt_fail(err, ROMRT_E_ARGUMENT, 0, "no asset (NULL)");
    if ((uintptr_t)asset % 8 != 0) return rt_fail(err, ROMRT_E_ARENA, 0, "the asset's address is not 8-byte aligned");
    if (arena && (uintptr_t)arena % 8 != 0) return rt_fail(err, ROMRT_E_ARENA, 0, "the arena's address is not 8-byte aligned");
    memset(&L, 0, sizeof L);
    L.err = err;
    {
        rombin_error e;
        rb = rombin_open(&L.file, asset, asset_bytes, known_chunks, &e);
        if (rb) {
            romrt_status s = rb == ROMBIN_E_VERSION ? ROMRT_E_VERSION : rb == ROMBIN_E_PLATFORM ? ROMRT_E_PLATFORM
                           : rb == ROMBIN_E_UNSUPPORTED ? ROMRT_E_UNSUPPORTED : rb == ROMBIN_E_ARGUMENT ? ROMRT_E_ARGUMENT
                           : ROMRT_E_DAMAGED;
            return rt_error_from(err, s, &e);
        }
    }
    if (arena) {
        if (arena_bytes < sizeof(romrt_model))
            return rt_fail_nn(err, ROMRT_E_ARENA, 0, "the arena has ", (uint64_t)arena_bytes, " bytes, the model needs ",
                              (uint64_t)sizeof(romrt_model), " at least");
        m = (romrt_model *)arena;
        L.arena = (unsigned char *)arena;
        L.cap = arena_bytes;
    } else {
        m = &scratch;
    }
    memset(m, 0, sizeof *m);
    L.used = align16(sizeof(romrt_model));
    if ((st = sizes(&L, m))) return st;
    {
        /* Converted arrays must fit before they are written: count first with a dry run. */
        loader dry = L;
        romrt_model probe = *m;
        dry.arena = 0;
        if ((st = arrays(&dry, &probe))) return st;
        if (needed) *needed = dry.used;
        if (arena && dry.used > arena_bytes)
            return rt_fail_nn(err, ROMRT_E_ARENA, 0, "the arena has ", (uint64_t)arena_bytes, " bytes, the model needs ",
                              (uint64_t)dry.used, "");
        if (!arena) return contents(&dry, &probe);
    }
    L.scanned = 1; /* the sizing pass checked every real; now place them */
    if ((st = arrays(&L, m)) || (st = contents(&L, m))) return st;
    *out = m;
    return ROMRT_OK;
}

romrt_status romrt_arena_size(const void *asset, size_t asset_bytes, size_t *arena_bytes, romrt_error *err)
{
    if (!arena_bytes) return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_arena_size: arena_bytes is NULL");
    *arena_bytes = 0;
    return load(asset, asset_bytes, 0, 0, arena_bytes, 0, err);
}

romrt_status romrt_open(const void *asset, size_t asset_bytes, void *arena, size_t arena_bytes, romrt_model **model,
                        romrt_error *err)
{
    if (!arena || !model) return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_open: arena or model is NULL");
    *model = 0;
    return load(asset, asset_bytes, arena, arena_bytes, 0, model, err);
}
