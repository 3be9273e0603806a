/* The running reduced model (adaptive-subspace paper, Sec. 3.2, 3.6): the active columns U_a of the
 * candidate basis, the enriched vertices X_a and the mask that keeps the two apart (the modal
 * basis B_a is U_a with the enriched dofs' rows zeroed: a non-overlapping decomposition). */
#include "adaptive/adaptive_impl.h"

#include <stdlib.h>
#include <string.h>

static int grow(double **p, size_t count, rk_error *err)
{
    double *q = realloc(*p, sizeof(double) * (count ? count : 1));
    if (!q) return rk_fail(err, "out of memory for the adaptive model (%zu numbers)", count);
    *p = q;
    return 0;
}

int rk_adaptive_set_columns(rk_adaptive *ad, rk_error *err)
{
    rk_adaptive_impl *im = ad->impl;
    int block = ad->opt.block, a = 0;
    for (int b = 0; b < im->nblocks; b++)
        if (im->block_on[b])
            for (int j = 0; j < block; j++) im->cols[a++] = b * block + j;
    im->a = a;
    size_t na = (size_t)im->n * (size_t)a, aa = (size_t)a * (size_t)a;
    if (grow(&im->Ua, na, err) || grow(&im->Ba, na, err) || grow(&im->MU, na, err) || grow(&im->CU, na, err) || grow(&im->UMU, aa, err) || grow(&im->UCU, aa, err) ||
        grow(&im->BMB, aa, err) || grow(&im->BCB, aa, err) || grow(&im->Ha, aa, err) || grow(&im->Hq, aa, err) ||
        grow(&im->Lq, aa, err) || grow(&im->gq, (size_t)a, err) || grow(&im->dq, (size_t)a, err) ||
        grow(&im->dq_last, (size_t)a, err))
        return -1;
    for (int l = 0; l < im->L; l++) {
        rk_subdomain *s = &im->sub[l];
        if (grow(&s->B, aa, err) || grow(&s->Bu, aa, err) || grow(&s->proj, (size_t)a, err)) return -1;
        s->have_proj = 0;
    }
    for (int j = 0; j < a; j++)
        memcpy(im->Ua + (size_t)j * im->n, im->U + (size_t)im->cols[j] * im->n, sizeof(double) * (size_t)im->n);
    ad->modes = a;
    im->columns_valid = 0;
    im->inertia_valid = 0;
    im->have_step = 0;
    rk_adaptive_update_mask(ad);
    return 0;
}

void rk_adaptive_update_mask(rk_adaptive *ad)
{
    rk_adaptive_impl *im = ad->impl;
    int nx = 0, nodes = 0;
    for (int i = 0; i < im->n; i++) im->xindex[i] = -1;
    for (int v = 0; v < im->nv; v++) {
        if (!im->enriched[v]) continue;
        nodes++;
        for (int k = 0; k < 3; k++) {
            int d = 3 * v + k;
            if (im->view.prescribed[d]) continue;
            im->xindex[d] = nx;
            im->xdof[nx++] = d;
        }
    }
    im->nx = nx;
    ad->nodes = nodes;
    memcpy(im->Ba, im->Ua, sizeof(double) * (size_t)im->n * (size_t)im->a);
    for (int j = 0; j < im->a; j++)
        for (int k = 0; k < nx; k++) im->Ba[(size_t)j * im->n + im->xdof[k]] = 0;
    for (int l = 0; l < im->L; l++) {
        rk_subdomain *s = &im->sub[l];
        int exact = ad->opt.exact_hessian;
        for (int i = 0; i < s->nv && !exact; i++) exact = im->enriched[s->vert[i]];
        s->exact = exact;
        for (int e = 0; e < s->ne; e++) im->elem_exact[s->elem[e]] = (char)exact;
    }
    im->inertia_valid = 0;
}

int rk_adaptive_enrich_part(rk_adaptive *ad, int part)
{
    rk_adaptive_impl *im = ad->impl;
    int added = 0;
    for (int k = im->part_first[part]; k < im->part_first[part + 1]; k++) {
        int v = im->part_vert[k];
        if (!im->enriched[v]) {
            im->enriched[v] = 1;
            added++;
        }
    }
    return added;
}
