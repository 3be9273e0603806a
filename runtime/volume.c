/* The projected volume in the runtime (romrt_impl.h, rt_volume_gather): the lambda part of every
 * element's or integration point's energy on the L2 projection of its volume measure theta onto the
 * asset's pressure space, condensed by the precompute into vk reduced pressure functions Phi per
 * point (VPRS; precompute/cubature/volume.c derives them):
 *   E_vol = 1/2 |c|^2,  c = sum_e w_e theta_e Phi_e,  dE_vol/dq = sum_e w_e p_e dtheta_e/dq,
 *   p_e = Phi_e . c,  d2E_vol/dq2 = C^T C + sum_e w_e p_e d2theta_e/dq2,  C = sum_e w_e Phi_e dtheta_e/dq^T. */
#include "runtime/romrt_impl.h"

romrt_real rt_volume_gather(romrt_model *m, const romrt_real *q, int hessian, rt_point_hd hd)
{
    int n = m->ne + m->np, k = m->vk, e, a;
    romrt_real half = 0;
    for (a = 0; a < k; a++) m->vc[a] = 0;
    if (hessian)
        for (a = 0; a < k * m->r; a++) m->vC[a] = 0;
    for (e = 0; e < n; e++) {
        const romrt_real *lame, *phi = m->vphi + (size_t)k * (size_t)e;
        romrt_real *Hd = m->vHd + 9 * (size_t)e, dth[9], wt;
        hd(m, e, q, Hd);
        wt = rt_point_weight(m, e) * RT_PHYS(volume_h)(rt_material(m, e, &lame), Hd, dth);
        for (a = 0; a < k; a++) m->vc[a] += wt * phi[a];
    }
    for (e = 0; e < n; e++) {
        const romrt_real *phi = m->vphi + (size_t)k * (size_t)e;
        romrt_real p = 0;
        for (a = 0; a < k; a++) p += phi[a] * m->vc[a];
        m->vp[e] = p;
    }
    for (a = 0; a < k; a++) half += m->vc[a] * m->vc[a];
    return RT_K(0.5) * half;
}

void rt_volume_add(romrt_model *m, int e, romrt_real w, const romrt_real *t)
{
    int k = m->vk, r = m->r, a, j;
    const romrt_real *phi = m->vphi + (size_t)k * (size_t)e;
    for (a = 0; a < k; a++) {
        romrt_real s = w * phi[a], *Ca = m->vC + (size_t)r * (size_t)a;
        if (s != 0)
            for (j = 0; j < r; j++) Ca[j] += s * t[j];
    }
}

void rt_volume_hessian(const romrt_model *m, romrt_real *H, int ld)
{
    int k = m->vk, r = m->r, a, i, j;
    for (a = 0; a < k; a++) {
        const romrt_real *Ca = m->vC + (size_t)r * (size_t)a;
        for (j = 0; j < r; j++) {
            romrt_real cj = Ca[j];
            romrt_real *Hj = H + (size_t)ld * (size_t)j;
            if (cj != 0)
                for (i = 0; i <= j; i++) Hj[i] += Ca[i] * cj;
        }
    }
}
