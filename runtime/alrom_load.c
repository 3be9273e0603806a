/* The adaptive linear ROM's chunks (loader_impl.h, formats/ROMBIN.md "Adaptive linear ROM
 * chunks"): their sizes and values, checked once in romrt_open, and its arena buffers. */
#include <math.h>
#include <string.h>

#include "runtime/alrom_impl.h"
#include "runtime/loader_impl.h"

#define MAX_HISTORY 1000u

/* ---- the loader ---- */

/* A CROM's chunks: CRMS's sizes (the encoder 3 nv -> .. -> r, the decoder r + 3 -> .. -> 3, 1 to
 * 64 layers of 1 to 4096 units), CRMX, CRMW (both networks' parameters and the scale), and the
 * buffers of the widest layer. */
static romrt_status crom_arrays(rt_loader *L, romrt_model *m)
{
    rt_alrom *al = &m->al;
    rombin_chunk c;
    int found, k;
    const uint32_t *sz;
    uint64_t count = 0, e_count = 0, d_count = 0;
    romrt_status st = rt_chunk(L, ROMBIN_CRMS, ROMBIN_TYPE_U32, 0, 1, &c, &found);
    const romrt_real *w;
    if (st) return st;
    sz = (const uint32_t *)(const void *)c.data;
    if (c.raw < 8 || sz[0] < 1 || sz[0] > 64 || sz[1] < 1 || sz[1] > 64 || c.raw != 4 * (4 + (uint64_t)sz[0] + sz[1]))
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_CRMS, "layer counts out of 1..64 or sizes missing");
    al->enc_layers = (int)sz[0];
    al->dec_layers = (int)sz[1];
    al->enc_sizes = sz + 2;
    al->dec_sizes = sz + 3 + al->enc_layers;
    if (al->enc_sizes[0] != 3 * (uint32_t)m->nv || al->enc_sizes[al->enc_layers] != (uint32_t)m->r ||
        al->dec_sizes[0] != (uint32_t)m->r + 3 || al->dec_sizes[al->dec_layers] != 3)
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_CRMS,
                       "the encoder must map every stored coordinate to r, the decoder r + 3 to 3");
    al->widest = 3 * m->nv;
    for (k = 0; k <= al->enc_layers + al->dec_layers + 1; k++) {
        uint32_t units = k <= al->enc_layers ? al->enc_sizes[k] : al->dec_sizes[k - al->enc_layers - 1];
        if (units < 1 || (units > 4096 && !(k == 0)))
            return rt_fail_n(L->err, ROMRT_E_LIMIT, ROMBIN_CRMS, "a layer of ", units, " units (1..4096)");
        if ((int)units > al->widest) al->widest = (int)units;
    }
    for (k = 0; k < al->enc_layers; k++) e_count += (uint64_t)al->enc_sizes[k + 1] * (al->enc_sizes[k] + 1);
    for (k = 0; k < al->dec_layers; k++) d_count += (uint64_t)al->dec_sizes[k + 1] * (al->dec_sizes[k] + 1);
    count = e_count + d_count + 1;
    if ((st = rt_reals(L, ROMBIN_CRMX, 3 * (uint64_t)m->nv, 1, &al->crom_x)) ||
        (st = rt_reals(L, ROMBIN_CRMW, count, 1, &w)))
        return st;
    al->enc_w = w;
    al->dec_w = w ? w + e_count : 0;
    al->u_scale = w ? (double)w[count - 1] : 1;
    rt_scratch_wide(L, (uint64_t)al->widest, &al->act[0]);
    rt_scratch_wide(L, (uint64_t)al->widest, &al->act[1]);
    rt_scratch_wide(L, (uint64_t)al->widest * (uint64_t)m->r, &al->tan[0]);
    rt_scratch_wide(L, (uint64_t)al->widest * (uint64_t)m->r, &al->tan[1]);
    return ROMRT_OK;
}

romrt_status rt_alrom_arrays(rt_loader *L, romrt_model *m)
{
    const uint32_t *head;
    const romrt_real *parm;
    rt_alrom *al = &m->al;
    uint64_t nv = (uint64_t)m->nv, r = (uint64_t)m->r, n = 3 * nv;
    romrt_status st;
    int k;
    if ((st = rt_u32s(L, ROMBIN_ALRH, ROMBIN_ALRH_COUNT, 0, &head))) return st;
    if (!head) { /* the rest without their header: a damaged asset, not a fixed-basis model */
        static const char *const rest[] = {ROMBIN_ALRP, ROMBIN_QDRV, ROMBIN_VMSS, ROMBIN_VLOD, ROMBIN_AMOV, ROMBIN_AMOT,
                                           ROMBIN_CRMS, ROMBIN_CRMX, ROMBIN_CRMW};
        rombin_chunk c;
        for (k = 0; k < (int)(sizeof rest / sizeof *rest); k++)
            if (rombin_find(&L->file, rest[k], &c))
                return rt_fail(L->err, ROMRT_E_MODEL, rest[k], "an adaptive linear ROM's chunk without its header ALRH");
        return ROMRT_OK;
    }
    for (k = ROMBIN_ALRH_ENCODER + 1; k < ROMBIN_ALRH_COUNT; k++)
        if (head[k]) return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_ALRH, "reserved field ", (uint64_t)k, " is not 0");
    if (head[ROMBIN_ALRH_DECODER] > 1)
        return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_ALRH, "unknown decoder ", head[ROMBIN_ALRH_DECODER], "");
    if (head[ROMBIN_ALRH_HISTORY] < 1 || head[ROMBIN_ALRH_HISTORY] > MAX_HISTORY)
        return rt_fail_n(L->err, ROMRT_E_LIMIT, ROMBIN_ALRH, "history of ", head[ROMBIN_ALRH_HISTORY], " steps is not in 1..1000");
    if (head[ROMBIN_ALRH_CADENCE] > MAX_HISTORY)
        return rt_fail_n(L->err, ROMRT_E_LIMIT, ROMBIN_ALRH, "basis cadence of ", head[ROMBIN_ALRH_CADENCE], " steps is not in 0..1000");
    if (head[ROMBIN_ALRH_ENCODER] > RT_ALROM_ENCODE_ITERATIONS)
        return rt_fail_n(L->err, ROMRT_E_LIMIT, ROMBIN_ALRH, "encoder iterations ", head[ROMBIN_ALRH_ENCODER], " is not in 0..20");
    if ((uint64_t)head[ROMBIN_ALRH_PAIRS] != r * (r + 1) / 2)
        return rt_fail_nn(L->err, ROMRT_E_MODEL, ROMBIN_ALRH, "names ", head[ROMBIN_ALRH_PAIRS],
                          " modal-derivative pairs; r gives ", r * (r + 1) / 2, "");
    if (head[ROMBIN_ALRH_MOTIONS] > ROMBIN_MAX_MOTIONS)
        return rt_fail_n(L->err, ROMRT_E_LIMIT, ROMBIN_ALRH, "prescribed motion count ", head[ROMBIN_ALRH_MOTIONS],
                         " is above 64");
    m->alrom = 1;
    al->decoder = (int)head[ROMBIN_ALRH_DECODER];
    al->m = (int)head[ROMBIN_ALRH_HISTORY];
    al->pairs = (int)head[ROMBIN_ALRH_PAIRS];
    al->nmotions = (int)head[ROMBIN_ALRH_MOTIONS];
    al->cadence = head[ROMBIN_ALRH_CADENCE] ? (int)head[ROMBIN_ALRH_CADENCE] : 1; /* (assets before it: 0) */
    al->encoder_iterations = head[ROMBIN_ALRH_ENCODER] ? (int)head[ROMBIN_ALRH_ENCODER] : (int)RT_ALROM_ENCODE_ITERATIONS;
    al->since = -1;
    if ((st = rt_reals(L, ROMBIN_ALRP, ROMBIN_ALRP_COUNT, 1, &parm)) ||
        (!al->decoder && (st = rt_reals(L, ROMBIN_QDRV, n * (uint64_t)al->pairs, 1, &al->psi))) ||
        (al->decoder && (st = crom_arrays(L, m))) ||
        (st = rt_reals(L, ROMBIN_VMSS, nv, 1, &al->mass)) || (st = rt_reals(L, ROMBIN_VLOD, n, 1, &al->load)) ||
        (st = rt_u32s(L, ROMBIN_AMOV, nv, 1, &al->motion_of)) ||
        (st = rt_reals(L, ROMBIN_AMOT, (uint64_t)al->nmotions * ROMBIN_PIN_PARAMS, al->nmotions > 0, &al->motions)))
        return st;
    if (parm) {
        al->lambda = parm[ROMBIN_ALRP_LAMBDA];
        al->reg = parm[ROMBIN_ALRP_REG];
        al->damping = parm[ROMBIN_ALRP_DAMPING];
        al->ridge = parm[ROMBIN_ALRP_RIDGE];
        al->budget = parm[ROMBIN_ALRP_BUDGET];
        for (k = ROMBIN_ALRP_BUDGET + 1; k < ROMBIN_ALRP_COUNT; k++)
            if (parm[k] != 0) return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_ALRP, "reserved value ", (uint64_t)k, " is not 0");
    }
    al->X0 = m->X;
    al->phi = m->rows;
    rt_scratch_wide(L, n, &al->u_t);
    rt_scratch_wide(L, n, &al->v);
    rt_scratch_wide(L, n, &al->u_prev);
    rt_scratch_wide(L, n, &al->v_prev);
    rt_scratch_wide(L, n, &al->u_ref);
    rt_scratch(L, n, &al->f_app);
    /* the ring: n-vectors for a CROM, K-space coordinates for the quadratic decoder (alrom.c) */
    rt_scratch_wide(L, (al->decoder ? n : r + (uint64_t)al->pairs) * (uint64_t)(al->m + 1), &al->D);
    rt_scratch_wide(L, r * (uint64_t)(al->m + 1), &al->P);
    rt_scratch_wide(L, r * (uint64_t)(al->m + 1) + r * r, &al->coef); /* and E_u^T below them (form_used) */
    rt_scratch(L, (r + 1) * (uint64_t)(al->m + 1 + r), &al->zr); /* and a row's z (form_used) */
    rt_scratch(L, n, &al->x_ref);
    rt_scratch(L, n * r, &al->rows);
    rt_scratch(L, r * r, &al->M);
    rt_scratch(L, r * r, &al->C);
    rt_scratch(L, r * r, &al->m_fac);
    rt_scratch(L, r, &al->f);
    rt_scratch(L, 9 * (uint64_t)m->ne, &al->Hd0);
    if (al->decoder) rt_scratch_wide(L, n * r, &al->U); /* the quadratic's rows are formed where used */
    rt_scratch_wide(L, (uint64_t)(al->m + 1) * (uint64_t)(al->m + 1), &al->dd);
    rt_scratch_wide(L, r * (uint64_t)(al->m + 1), &al->du);
    rt_scratch_wide(L, 15 * r * r, &al->small);
    rt_scratch_wide(L, n, &al->u);
    rt_scratch_wide(L, n, &al->res);
    if (!al->decoder) {
        uint64_t R = r + (uint64_t)al->pairs;
        rt_scratch_wide(L, R * R, &al->gram);
        rt_scratch_wide(L, R * R, &al->gram_free);
        rt_scratch_wide(L, R * (uint64_t)(al->m + 1), &al->db);
        rt_scratch_wide(L, R * r, &al->gram_c);
        rt_scratch_wide(L, 4 * R + (uint64_t)(al->m + 1) + r, &al->ext); /* or a used row's z (form_used) */
        rt_scratch_wide(L, R, &al->c);
        rt_scratch_wide(L, R, &al->w);
        rt_scratch_wide(L, R, &al->c_prev);
        rt_scratch_wide(L, R, &al->w_prev);
        rt_scratch_wide(L, R * R, &al->gram_wfree);
        rt_scratch_wide(L, R, &al->load_c);
        rt_scratch_wide(L, R * (uint64_t)(al->m + 1), &al->wdb);
        rt_scratch_wide(L, R * r, &al->cs);
        rt_scratch_wide(L, R * r, &al->wcs);
        rt_scratch_wide(L, R * r, &al->wcs_keep);
        rt_scratch_wide(L, 4 * r * r, &al->keep_work);
        rt_scratch(L, r * r, &al->m_keep);
        rt_scratch_u32(L, 2 * nv, &al->sv);
        rt_scratch_wide(L, n * (uint64_t)(al->m + 1), &al->ds); /* 3 ns <= n per slot */
    }
    rt_scratch_wide(L, 4 * r * r, &al->work);
    rt_scratch_u32(L, nv, &al->pv);
    rt_scratch_wide(L, n, &al->u_new);
    rt_scratch_wide(L, n, &al->v_new);
    return ROMRT_OK;
}

romrt_status rt_alrom_contents(rt_loader *L, romrt_model *m)
{
    const rt_alrom *al = &m->al;
    double total = 0;
    int v, g;
    if (!m->alrom) return ROMRT_OK;
    if (m->skin || m->np || m->npins || m->ne < 1)
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_ALRH,
                       "an adaptive linear ROM needs cubature elements and dense rows, and holds its prescribed "
                       "vertices itself (no SKIN, IPNT or PINS)");
    for (v = 0; v < m->nv; v++)
        if (al->motion_of[v] != ROMBIN_NO_MOTION && al->motion_of[v] >= (uint32_t)al->nmotions)
            return rt_fail_nn(L->err, ROMRT_E_MODEL, ROMBIN_AMOV, "stored vertex ", (uint64_t)v, " names motion ",
                              al->motion_of[v], ", beyond AMOT");
    if (!L->arena) return ROMRT_OK; /* the values below live in the arena when converted */
    for (v = 0, m->al.npv = 0; v < m->nv; v++) /* the prescribed vertices, for the passes a step makes over them */
        if (al->motion_of[v] != ROMBIN_NO_MOTION) m->al.pv[m->al.npv++] = (uint32_t)v;
    if (al->decoder && !(al->u_scale > 0))
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_CRMW, "the displacement scale must be positive");
    if (!al->decoder) {
        rt_alrom_gram(m);
        rt_alrom_used(m);
    }
    if (!(al->lambda >= 0 && al->lambda <= 1) || !(al->reg >= 0) || !(al->damping >= 0) || !(al->ridge >= 0) ||
        !(al->budget >= 0))
        return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_ALRP,
                       "lambda must be in [0, 1], the regularisation, damping, ridge and budget >= 0");
    for (v = 0; v < m->nv; v++) {
        if (!(al->mass[v] >= 0)) return rt_fail_n(L->err, ROMRT_E_MODEL, ROMBIN_VMSS, "stored vertex ", (uint64_t)v, " has a negative mass");
        total += al->mass[v];
    }
    if (!(total > 0)) return rt_fail(L->err, ROMRT_E_MODEL, ROMBIN_VMSS, "the stored vertices carry no mass");
    for (g = 0; g < al->nmotions; g++) {
        romrt_status st = rt_check_motion(L, ROMBIN_AMOT, "motion ", (uint64_t)g, al->motions + ROMBIN_PIN_PARAMS * (size_t)g);
        if (st) return st;
    }
    return ROMRT_OK;
}

