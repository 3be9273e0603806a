/* K and M over the free degrees of freedom. */
#include "basis/free_system_impl.h"

#include <stdlib.h>
#include <string.h>

#include "basis/basis.h"

int rk_free_system_init(rk_free_system *s, const rk_fem *f, const unsigned char *constrained,
                        int lumped, rk_error *err)
{
    memset(s, 0, sizeof *s);
    s->ndof = 3 * f->nv;
    s->keep = rk_calloc((size_t)s->ndof, sizeof(int), err);
    rk_sparse K = {0};
    if (!s->keep) return -1;
    for (int v = 0; v < f->nv; v++)
        for (int a = 0; a < 3; a++)
            s->keep[3 * v + a] = constrained && constrained[v] ? -1 : s->nfree++;
    if (s->nfree == 0) {
        rk_free_system_free(s);
        return rk_fail(err, "every vertex is constrained: no free degrees of freedom");
    }
    if (rk_sparse_alloc_pattern(f, &K, err) || rk_sparse_alloc_pattern(f, &s->Mfull, err)) goto fail;
    rk_fem_add_rest_stiffness(f, 1.0, &K);
    rk_fem_add_mass(f, lumped, 1.0, &s->Mfull);
    if (rk_sparse_restrict(&K, s->keep, s->nfree, &s->K, err) ||
        rk_sparse_restrict(&s->Mfull, s->keep, s->nfree, &s->M, err))
        goto fail;
    rk_sparse_free(&K);
    return 0;
fail:
    rk_sparse_free(&K);
    rk_free_system_free(s);
    return -1;
}

void rk_free_system_expand(const rk_free_system *s, const double *xfree, double *xfull)
{
    for (int i = 0; i < s->ndof; i++) xfull[i] = s->keep[i] >= 0 ? xfree[s->keep[i]] : 0.0;
}

void rk_free_system_gather(const rk_free_system *s, const double *xfull, double *xfree)
{
    for (int i = 0; i < s->ndof; i++)
        if (s->keep[i] >= 0) xfree[s->keep[i]] = xfull[i];
}

void rk_free_system_free(rk_free_system *s)
{
    free(s->keep);
    rk_sparse_free(&s->K);
    rk_sparse_free(&s->M);
    rk_sparse_free(&s->Mfull);
    memset(s, 0, sizeof *s);
}
