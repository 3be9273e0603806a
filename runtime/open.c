/* romrt_arena_size and romrt_open: the container check (formats/rombin_read.c), then every model
 * chunk's size, type, counts, indices and values, once, so that stepping needs no checks. */
#include <math.h>
#include <string.h>

#include "runtime/loader_impl.h"

static const char *const known_chunks[] = {ROMBIN_HEAD, ROMBIN_PARM, ROMBIN_VERT, ROMBIN_ROWS, ROMBIN_MASS,
                                           ROMBIN_DAMP, ROMBIN_LOAD, ROMBIN_VEL0, ROMBIN_PENA, ROMBIN_PINS, ROMBIN_LIFT, ROMBIN_ELEM,
                                           ROMBIN_ELMR, ROMBIN_PLAN, ROMBIN_CONT, ROMBIN_CVTX, ROMBIN_FRIC, ROMBIN_SKIN, ROMBIN_WGHT, ROMBIN_IPNT, ROMBIN_IPMD, ROMBIN_VPRS, ROMBIN_GRAD, ROMBIN_SPLY, ROMBIN_GRPS,
                                           ROMBIN_GVTX, ROMBIN_GNAM, ROMBIN_SURF, ROMBIN_VMAP, ROMBIN_INFO,
                                           ROMBIN_KHED, ROMBIN_KPRM, ROMBIN_KEIG, ROMBIN_KOUT, ROMBIN_KIMP, ROMBIN_KACC,
                                           ROMBIN_KINI, ROMBIN_ALRH, ROMBIN_ALRP, ROMBIN_QDRV, ROMBIN_VMSS,
                                           ROMBIN_VLOD, ROMBIN_AMOV, ROMBIN_AMOT, ROMBIN_COBJ, ROMBIN_CRAD, ROMBIN_CRMS, ROMBIN_CRMX, ROMBIN_CRMW,
                                           ROMBIN_OBHD, ROMBIN_OBJS, ROMBIN_OBMO, ROMBIN_OBVX, ROMBIN_OBED, ROMBIN_OBTR,
                                           ROMBIN_OBVN, ROMBIN_OBVB, ROMBIN_OBIT, ROMBIN_CEDG, ROMBIN_CTRI, 0};

/* The three passes over one kind of model's chunks. */
typedef struct {
    romrt_status (*sizes)(rt_loader *L, romrt_model *m);
    romrt_status (*arrays)(rt_loader *L, romrt_model *m);
    romrt_status (*contents)(rt_loader *L, romrt_model *m);
} model_reader;

/* FRIC: mu >= 0, eps_v > 0 and 1..100 lagging iterations when mu > 0, the reserved value 0. */
static romrt_status friction(rt_loader *L, romrt_model *m)
{
    rombin_chunk c;
    int found, k;
    double f[ROMBIN_FRIC_COUNT];
    romrt_status st = rt_chunk(L, ROMBIN_FRIC, ROMBIN_TYPE_REAL, ROMBIN_FRIC_COUNT, 0, &c, &found);
    if (st || !found) return st;
    for (k = 0; k < ROMBIN_FRIC_COUNT; k++) {
        f[k] = rt_real_at(L, &c, (uint64_t)k);
        if (!isfinite(f[k])) return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_FRIC, "value ", (uint64_t)k, " is not finite");
    }
    if (!(f[ROMBIN_FRIC_MU] >= 0) || (f[ROMBIN_FRIC_MU] > 0 && !(f[ROMBIN_FRIC_EPS_V] > 0)) ||
        !(f[ROMBIN_FRIC_ITERATIONS] >= 1 && f[ROMBIN_FRIC_ITERATIONS] <= 100) ||
        f[ROMBIN_FRIC_ITERATIONS] != (double)(int)f[ROMBIN_FRIC_ITERATIONS] || f[ROMBIN_FRIC_COUNT - 1] != 0)
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_FRIC,
                       "mu must not be negative, eps_v positive, the lagging iterations a whole 1..100");
    m->mu = (romrt_real)f[ROMBIN_FRIC_MU];
    m->eps_v = (romrt_real)f[ROMBIN_FRIC_EPS_V];
    m->friction_iterations = (int)f[ROMBIN_FRIC_ITERATIONS];
    return ROMRT_OK;
}

static romrt_status sizes(rt_loader *L, romrt_model *m)
{
    const uint32_t *head;
    romrt_status st = rt_head(L, ROMBIN_HEAD, ROMBIN_HEAD_COUNT, ROMBIN_HEAD_POINTS + 1, ROMBIN_HEAD_R,
                              ROMBIN_HEAD_VERTICES, ROMBIN_HEAD_SHOWN, &head);
    int k;
    if (st) return st;
    if (head[ROMBIN_HEAD_ELEMENTS] > ROMRT_MAX_ELEMENTS || head[ROMBIN_HEAD_POINTS] > ROMRT_MAX_ELEMENTS ||
        (uint64_t)head[ROMBIN_HEAD_ELEMENTS] + head[ROMBIN_HEAD_POINTS] == 0)
        return rt_fail_nn(L->err, ROMRT_E_LIMIT, ROMBIN_HEAD, "element count ", head[ROMBIN_HEAD_ELEMENTS],
                          " and integration point count ", head[ROMBIN_HEAD_POINTS], ": none, or more than the runtime takes");
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
    m->np = (int)head[ROMBIN_HEAD_POINTS];
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
        if ((st = rt_chunk(L, ROMBIN_PARM, ROMBIN_TYPE_REAL, ROMBIN_PARM_COUNT, 1, &c, &found))) return st;
        for (k = 0; k < ROMBIN_PARM_COUNT; k++) {
            p[k] = rt_real_at(L, &c, (uint64_t)k);
            if (!isfinite(p[k])) return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_PARM, "value ", (uint64_t)k, " is not finite");
            if (k > ROMBIN_PARM_KAPPA && p[k] != 0)
                return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_PARM, "reserved value ", (uint64_t)k, " is not 0");
        }
        if (!(p[ROMBIN_PARM_H] > 0) || !(p[ROMBIN_PARM_NEWTON_TOL] > 0) || !(p[ROMBIN_PARM_MASS] > 0) ||
            p[ROMBIN_PARM_KAPPA] < 0 || (m->nplanes && !(p[ROMBIN_PARM_DHAT] > 0)))
            return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_PARM,
                           "time step, tolerance and mass must be positive, kappa non-negative, dhat positive with planes");
        {
            rombin_chunk cv;
            int has_cv;
            if ((st = rt_chunk(L, ROMBIN_CVTX, ROMBIN_TYPE_U32, 0, 0, &cv, &has_cv))) return st;
            if (has_cv && (cv.raw / 4 > head[ROMBIN_HEAD_VERTICES] || cv.raw == 0))
                return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_CVTX, "lists ", cv.raw / 4, " vertices, none or more than stored");
            m->ncv = has_cv ? (int)(cv.raw / 4) : 0;
            if (m->ncv && !(p[ROMBIN_PARM_DHAT] > 0 && p[ROMBIN_PARM_KAPPA] > 0))
                return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_PARM, "dhat and kappa must be positive with collision vertices");
        }
        if ((st = friction(L, m))) return st;
        m->h = (romrt_real)p[ROMBIN_PARM_H];
        m->tol = (romrt_real)p[ROMBIN_PARM_NEWTON_TOL];
        m->mass = (romrt_real)p[ROMBIN_PARM_MASS];
        m->dhat = (romrt_real)p[ROMBIN_PARM_DHAT];
        m->kappa = (romrt_real)p[ROMBIN_PARM_KAPPA];
    }
    return ROMRT_OK;
}

/* IPNT and IPMD: mesh-free integration points need a skinning basis (their F comes from the
 * weights and gradients they carry, runtime/skinning.c). */
static romrt_status integration_points(rt_loader *L, romrt_model *m)
{
    romrt_status st;
    if (m->np == 0) {
        rombin_chunk c;
        int found;
        if ((st = rt_chunk(L, ROMBIN_IPNT, ROMBIN_TYPE_REAL, 0, 0, &c, &found))) return st;
        return found ? rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_IPNT, "integration points, but HEAD counts none") : ROMRT_OK;
    }
    if (m->skin <= 0)
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_IPNT, "mesh-free integration points need a skinning basis (SKIN)");
    if ((st = rt_reals(L, ROMBIN_IPNT, (uint64_t)m->np * (6 + 4 * (uint64_t)m->skin), 1, &m->pt)) ||
        (st = rt_u32s(L, ROMBIN_IPMD, (uint64_t)m->np, 1, &m->pt_model)))
        return st;
    return ROMRT_OK;
}

/* VPRS: the projected volume's reduced pressure functions (precompute/cubature/volume.c), k per
 * element or integration point in their order, 1 <= k <= r; absent: every one's volume is its own. */
static romrt_status volume_pressure(rt_loader *L, romrt_model *m)
{
    rombin_chunk c;
    int found;
    uint64_t n = (uint64_t)m->ne + (uint64_t)m->np, size = L->file.real_type == ROMBIN_REAL_F32 ? 4 : 8, k;
    romrt_status st = rt_chunk(L, ROMBIN_VPRS, ROMBIN_TYPE_REAL, 0, 0, &c, &found);
    m->vk = 0;
    m->vphi = 0;
    if (st || !found) return st;
    k = n ? c.raw / size / n : 0;
    if (n == 0 || c.raw % (size * n) != 0 || k < 1 || k > (uint64_t)m->r)
        return rt_fail_nn(L->err, ROMRT_E_MODEL, ROMBIN_VPRS, "holds ", c.raw / size,
                          " values, not 1 to r per element or integration point (", n, " of them)");
    m->vk = (int)k;
    if ((st = rt_reals(L, ROMBIN_VPRS, n * k, 1, &m->vphi))) return st;
    rt_scratch(L, (size_t)k, &m->vc);
    rt_scratch(L, (size_t)k * (size_t)m->r, &m->vC);
    rt_scratch(L, (size_t)n, &m->vp);
    rt_scratch(L, (size_t)m->r, &m->vt);
    rt_scratch(L, 9 * (size_t)n, &m->vHd);
    return ROMRT_OK;
}

/* GRAD: the weights' gradients at the shown vertices (romrt_deformation_gradients), with SKIN only. */
static romrt_status shown_gradients(rt_loader *L, romrt_model *m)
{
    rombin_chunk c;
    int found;
    romrt_status st = rt_chunk(L, ROMBIN_GRAD, ROMBIN_TYPE_REAL, 0, 0, &c, &found);
    if (st || !found) return st;
    if (m->skin <= 0) return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_GRAD, "weight gradients without a skinning basis (SKIN)");
    return rt_reals(L, ROMBIN_GRAD, (uint64_t)m->shown * 3 * (uint64_t)m->skin, 1, &m->grad);
}

/* The basis rows: ROWS, or for a skinning basis stored as its weights (SKIN and WGHT) the weights,
 * the rows formed from them where needed (rows.c). */
static romrt_status basis_rows(rt_loader *L, romrt_model *m)
{
    const uint32_t *skin;
    const romrt_real *w;
    int r = m->r, v, j, c;
    romrt_status st;
    rombin_chunk chunk;
    int has_weights;
    if ((st = rt_u32s(L, ROMBIN_SKIN, 1, 0, &skin))) return st;
    m->skin = skin && skin[0] <= (uint32_t)ROMRT_MAX_R ? (int)skin[0] : skin ? -1 : 0; /* -1: refused in contents */
    has_weights = rombin_find(&L->file, ROMBIN_WGHT, &chunk);
    if (!has_weights) return rt_reals(L, ROMBIN_ROWS, 3 * (uint64_t)m->nv * (uint64_t)r, 1, &m->rows);
    if (m->skin <= 0 || r != 12 * m->skin)
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_WGHT, "skinning weights without a SKIN chunk whose handles give r");
    if ((st = rt_reals(L, ROMBIN_WGHT, (uint64_t)m->nv * (uint64_t)m->skin, 1, &w))) return st;
    m->w = w;
    m->rows = 0;
    m->rows_from_weights = 1;
    if (!w) return ROMRT_OK; /* the sizing pass */
    for (v = 0; v < m->nv; v++)
        for (j = 0; j < m->skin; j++)
            for (c = 0; c < 4; c++) {
                /* as ROWS's values are checked: finite, and in float below its overflow */
                double x = (double)w[(size_t)v * (size_t)m->skin + (size_t)j] *
                           (c < 3 ? (double)m->X[3 * (size_t)v + (size_t)c] : 1.0);
                if (!isfinite(x) || (sizeof(romrt_real) == 4 && fabs(x) > 3.0e38))
                    return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_WGHT, "stored vertex ", (uint64_t)v,
                                     "'s weight times its rest position overflows");
            }
    return ROMRT_OK;
}

static romrt_status arrays(rt_loader *L, romrt_model *m)
{
    uint64_t r = (uint64_t)m->r, nv = (uint64_t)m->nv, rr = r * r;
    romrt_status st;
    if ((st = rt_reals(L, ROMBIN_VERT, 3 * nv, 1, &m->X)) || (st = basis_rows(L, m)) ||
        (st = rt_reals(L, ROMBIN_MASS, rr, 1, &m->M)) || (st = rt_reals(L, ROMBIN_DAMP, rr, 0, &m->C)) ||
        (st = rt_reals(L, ROMBIN_LOAD, r, 1, &m->f)) || (st = rt_reals(L, ROMBIN_VEL0, r, 0, &m->v0)) ||
        (st = rt_reals(L, ROMBIN_PENA, rr, m->npins > 0, &m->A)) ||
        (st = rt_reals(L, ROMBIN_PINS, (uint64_t)m->npins * (ROMBIN_PIN_PARAMS + 12 * r), m->npins > 0, &m->pins)) ||
        (st = rt_reals(L, ROMBIN_LIFT, ROMBIN_LIFT_COUNT, 0, &m->lift)) ||
        (st = rt_u32s(L, ROMBIN_ELEM, 5 * (uint64_t)m->ne, m->ne > 0, &m->elem)) ||
        (st = rt_reals(L, ROMBIN_ELMR, 12 * (uint64_t)m->ne, m->ne > 0, &m->elem_real)) ||
        (st = integration_points(L, m)) || (st = volume_pressure(L, m)) || (st = shown_gradients(L, m)) ||
        (st = rt_reals(L, ROMBIN_PLAN, 6 * (uint64_t)m->nplanes, m->nplanes > 0, &m->planes)) ||
        (st = rt_u32s(L, ROMBIN_CONT, 2 * (uint64_t)m->ncontacts, m->ncontacts > 0, &m->contacts)) ||
        (st = rt_u32s(L, ROMBIN_CVTX, (uint64_t)m->ncv, m->ncv > 0, &m->cv)))
        return st;
    m->force_rows = m->rows;
    {
        /* The elastic Hessian is kept in whole vectors, in (a, j, c) order for a skinning basis. */
        size_t rp = RT_PAD((size_t)r);
        size_t sp = m->skin > 0 ? 3 * (size_t)RT_PAD(4 * m->skin) : 0, he = sp > rp ? sp : rp;
        rt_scratch(L, he * he, &m->He);
        rt_scratch(L, 9 * rp, &m->G);
        rt_scratch(L, 9 * rp, &m->AG);
        if (sp) {
            rt_scratch(L, sp, &m->skin_N);
            rt_scratch(L, sp, &m->skin_C);
            rt_scratch(L, sp, &m->skin_Q);
            rt_scratch(L, sp, &m->skin_gQ);
        }
    }
    if ((st = rt_alrom_arrays(L, m)) || (st = rt_objects_arrays(L, m)) || (st = rt_obstacles_arrays(L, m))) return st;
    {
        /* The Newton matrix has a row per moved collider only when the asset takes colliders, and
         * in a joint solve one per moving obstacle (contact_progress.c: the app meshes and the
         * scene's obstacles, at most ROMRT_MAX_MOVING_OBSTACLES of these; which of them move is
         * read after the arena is laid out, so any obstacle counts) */
        size_t movers = m->nobs < ROMRT_MAX_MOVING_OBSTACLES ? (size_t)m->nobs : ROMRT_MAX_MOVING_OBSTACLES;
        size_t n = (size_t)r + (m->ncv ? ROMRT_MAX_COLLIDERS + movers : 0);
        rt_scratch(L, n * n, &m->H);
    }
    /* A fixed basis of stored rows maps q to each element's F linearly: that map, G_e, formed once
     * here (rt_form_element_G) saves re-forming it from four vertices' rows at every potential
     * (12 r dot products and 63 r flops an element, the step's largest cost after the Hessian).
     * An adaptive basis is fixed within a step: its G_e formed once a step (alrom.c), not at every
     * potential of the step's Newton iterations and line searches (issue 33). */
    if (!m->skin && !m->rows_from_weights && m->ne > 0)
        rt_scratch(L, (size_t)m->ne * 9 * (size_t)RT_PAD((size_t)r), &m->G_all);
    return rt_load_groups_and_surface(L, m);
}

/* Indices and values the step relies on. */
/* LIFT: a motion as PINS's, and the first of 12 skinning coordinates (a whole handle's, inside r)
 * that nothing but the motion moves: no contact the handle would have to give way to (the reduced
 * simulator refuses it too, precompute/rom/model.c's set_lift), no adaptive basis. */
static romrt_status lifted_group(rt_loader *L, romrt_model *m)
{
    romrt_real c = m->lift[ROMBIN_PIN_PARAMS];
    romrt_status st = rt_check_motion(L, ROMBIN_LIFT, "lifted group ", 0, m->lift);
    if (st) return st;
    if (!(c >= 0 && c + 12 <= (romrt_real)m->r && c == (romrt_real)(int)c && (int)c % 12 == 0 && m->skin > 0))
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_LIFT, "the lifting handle is not a skinning handle's 12 coordinates");
    if (m->ncontacts || m->nobs || m->self_contact || m->nobjects > 1 || m->alrom)
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_LIFT, "a lifted group with contact or an adaptive basis: it "
                       "cannot give way");
    m->lift_col = (int)c;
    return ROMRT_OK;
}

static romrt_status contents(rt_loader *L, romrt_model *m)
{
    romrt_status st;
    int e, g, k;
    if ((st = rt_indices_below(L, ROMBIN_ELEM, m->elem, (uint64_t)m->ne, 5, 0, 4, (uint32_t)m->nv)) ||
        (st = rt_indices_below(L, ROMBIN_ELEM, m->elem, (uint64_t)m->ne, 5, 4, 5, RK_MAT_NEOHOOKEAN + 1)) ||
        (st = rt_indices_below(L, ROMBIN_CONT, m->contacts, (uint64_t)m->ncontacts, 2, 0, 1, (uint32_t)m->nv)) ||
        (st = rt_indices_below(L, ROMBIN_CONT, m->contacts, (uint64_t)m->ncontacts, 2, 1, 2, (uint32_t)m->nplanes)) ||
        (st = rt_indices_below(L, ROMBIN_CVTX, m->cv, (uint64_t)m->ncv, 1, 0, 1, (uint32_t)m->nv)) ||
        (st = rt_indices_below(L, ROMBIN_IPMD, m->pt_model, (uint64_t)m->np, 1, 0, 1, RK_MAT_NEOHOOKEAN + 1)))
        return st;
    if ((st = rt_check_groups_and_surface(L, m)) || (st = rt_alrom_contents(L, m))) return st;
    if (m->skin < 0 || (m->skin > 0 && m->r != 12 * m->skin))
        return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_SKIN, "names a handle count that does not give r = 12 per handle: r = ",
                         (uint64_t)m->r, "");
    if ((st = rt_objects_contents(L, m))) return st; /* COBJ's indices in both passes, the rest in the arena's */
    if (!L->arena) return ROMRT_OK; /* the values below live in the arena when converted */
    if (m->skin && !m->rows_from_weights && (st = rt_skin_check(L, m))) return st;
    for (e = 0; e < m->ne; e++) {
        const romrt_real *er = m->elem_real + 12 * (size_t)e;
        if (!(er[9] >= 0) || !(er[10] > 0) || !(er[11] > -er[10]))
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_ELMR, "element ", (uint64_t)e,
                             " has a negative weight or impossible Lame parameters");
    }
    for (e = 0; m->grad && e < 3 * m->shown * m->skin; e++)
        if (!isfinite(m->grad[e])) return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_GRAD, "value ", (uint64_t)e, " is not finite");
    for (e = 0; e < m->np; e++) {
        const romrt_real *p = m->pt + (6 + 4 * (size_t)m->skin) * (size_t)e;
        size_t k2;
        if (!(p[3] >= 0) || !(p[4] > 0) || !(p[5] > -p[4]))
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_IPNT, "integration point ", (uint64_t)e,
                             " has a negative weight or impossible Lame parameters");
        for (k2 = 0; k2 < 6 + 4 * (size_t)m->skin; k2++)
            if (!isfinite(p[k2]))
                return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_IPNT, "integration point ", (uint64_t)e, " is not finite");
    }
    for (g = 0; g < m->npins; g++)
        if ((st = rt_check_motion(L, ROMBIN_PINS, "pin ", (uint64_t)g,
                                  m->pins + (ROMBIN_PIN_PARAMS + 12 * (size_t)m->r) * (size_t)g)))
            return st;
    if (m->lift && (st = lifted_group(L, m))) return st;
    for (k = 0; k < m->nplanes; k++) {
        const romrt_real *n = m->planes + 6 * (size_t)k + 3;
        romrt_real len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        if (!(len2 > RT_K(0.99) && len2 < RT_K(1.01)))
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_PLAN, "plane ", (uint64_t)k, " has no unit normal");
    }
    /* M_r must be positive definite: it measures every Newton step. */
    memcpy(m->H, m->M, sizeof(romrt_real) * (size_t)m->r * (size_t)m->r);
    if ((k = rt_cholesky(m->r, m->H)) != 0)
        return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_MASS, "is not positive definite (pivot ", (uint64_t)k, ")");
    for (k = 0; k < m->ncontacts; k++)
        if (!(rt_contact_distance(m, k, m->q) > 0))
            return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_CONT, "contact ", (uint64_t)k, " starts on or behind its plane");
    rt_form_element_G(m);
    return rt_obstacles_contents(L, m); /* last: its start check steps the potential's pieces */
}

/* kind: ROMRT_KIND_REDUCED or ROMRT_KIND_KOOPMAN, or -1: the reduced model if there is one. */
static romrt_status load(const void *asset, size_t asset_bytes, int kind, void *arena, size_t arena_bytes,
                         size_t *needed, romrt_model **out, romrt_error *err)
{
    rt_loader L;
    romrt_model scratch, *m;
    romrt_status st;
    const model_reader *reader;
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
    L.used = rt_align16(sizeof(romrt_model));
    {
        rombin_chunk c;
        static const model_reader reduced = {sizes, arrays, contents};
        static const model_reader koopman = {rt_koopman_sizes, rt_koopman_arrays, rt_koopman_contents};
        int has_head = rombin_find(&L.file, ROMBIN_HEAD, &c), has_khed = rombin_find(&L.file, ROMBIN_KHED, &c);
        if (kind == ROMRT_KIND_KOOPMAN && !has_khed)
            return rt_fail(err, ROMRT_E_UNSUPPORTED, ROMBIN_KHED, "the asset has no Koopman operator");
        if (kind == ROMRT_KIND_REDUCED && !has_head)
            return rt_fail(err, ROMRT_E_UNSUPPORTED, ROMBIN_HEAD, "the asset has no reduced model");
        reader = kind == ROMRT_KIND_KOOPMAN || (kind < 0 && !has_head) ? &koopman : &reduced;
    }
    if ((st = reader->sizes(&L, m))) return st;
    {
        /* Converted arrays must fit before they are written: count first with a dry run. */
        rt_loader dry = L;
        romrt_model probe = *m;
        dry.arena = 0;
        if ((st = reader->arrays(&dry, &probe))) return st;
        if (needed) *needed = dry.used;
        if (arena && dry.used > arena_bytes)
            return rt_fail_nn(err, ROMRT_E_ARENA, 0, "the arena has ", (uint64_t)arena_bytes, " bytes, the model needs ",
                              (uint64_t)dry.used, "");
        if (!arena) return reader->contents(&dry, &probe);
    }
    L.scanned = 1; /* the sizing pass checked every real; now place them */
    if ((st = reader->arrays(&L, m)) || (st = reader->contents(&L, m))) return st;
    rt_position_bounds(m);
    if (m->kind != ROMRT_KIND_KOOPMAN) rt_initial_state(m); /* a Koopman model starts at KINI (its contents) */
    if (m->alrom) rt_alrom_reset(m);
    if (!rt_showable(m, m->q)) /* the start: rows and rest positions so large that it draws as Inf */
        return rt_fail(err, ROMRT_E_MODEL, m->kind == ROMRT_KIND_KOOPMAN ? ROMBIN_KINI : ROMBIN_VERT,
                       "the start state's positions are not representable (rows or rest positions too large)");
    *out = m;
    return ROMRT_OK;
}

static romrt_status arena_size(const void *asset, size_t asset_bytes, int kind, size_t *arena_bytes, romrt_error *err)
{
    if (!arena_bytes) return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_arena_size: arena_bytes is NULL");
    *arena_bytes = 0;
    return load(asset, asset_bytes, kind, 0, 0, arena_bytes, 0, err);
}

static romrt_status open_model(const void *asset, size_t asset_bytes, int kind, void *arena, size_t arena_bytes,
                               romrt_model **model, romrt_error *err)
{
    if (!arena || !model) return rt_fail(err, ROMRT_E_ARGUMENT, 0, "romrt_open: arena or model is NULL");
    *model = 0;
    return load(asset, asset_bytes, kind, arena, arena_bytes, 0, model, err);
}

romrt_status romrt_arena_size(const void *asset, size_t asset_bytes, size_t *arena_bytes, romrt_error *err)
{
    return arena_size(asset, asset_bytes, -1, arena_bytes, err);
}

romrt_status romrt_arena_size_kind(const void *asset, size_t asset_bytes, romrt_kind kind, size_t *arena_bytes,
                                   romrt_error *err)
{
    if (kind != ROMRT_KIND_REDUCED && kind != ROMRT_KIND_KOOPMAN) return rt_fail(err, ROMRT_E_ARGUMENT, 0, "unknown kind");
    return arena_size(asset, asset_bytes, (int)kind, arena_bytes, err);
}

romrt_status romrt_open(const void *asset, size_t asset_bytes, void *arena, size_t arena_bytes, romrt_model **model,
                        romrt_error *err)
{
    return open_model(asset, asset_bytes, -1, arena, arena_bytes, model, err);
}

romrt_status romrt_open_kind(const void *asset, size_t asset_bytes, romrt_kind kind, void *arena, size_t arena_bytes,
                             romrt_model **model, romrt_error *err)
{
    if (kind != ROMRT_KIND_REDUCED && kind != ROMRT_KIND_KOOPMAN) return rt_fail(err, ROMRT_E_ARGUMENT, 0, "unknown kind");
    return open_model(asset, asset_bytes, (int)kind, arena, arena_bytes, model, err);
}
