/* The basis types by name, and freeing a basis. */
#include "basis/basis.h"

#include <stdlib.h>
#include <string.h>

static const char *const names[] = {"modes", "modal_derivatives", "skinning", "rkpm_skinning", "pod"};

const char *rk_basis_type_name(rk_basis_type t)
{
    return (unsigned)t < sizeof names / sizeof *names ? names[t] : "unknown";
}

int rk_basis_type_parse(const char *name, rk_basis_type *t)
{
    for (unsigned i = 0; i < sizeof names / sizeof *names; i++)
        if (!strcmp(name, names[i])) { *t = (rk_basis_type)i; return 0; }
    return -1;
}

void rk_basis_free(rk_basis *b)
{
    free(b->U);
    free(b->values);
    free(b->W);
    free(b->C);
    if (b->rkpm) rk_rkpm_free(b->rkpm);
    free(b->rkpm);
    for (int k = 0; b->part && k < b->nparts; k++) rk_basis_free(&b->part[k]);
    free(b->part);
    free(b->part_vertex);
    free(b->part_handle);
    memset(b, 0, sizeof *b);
}

void rk_basis_default_options(rk_basis_options *o)
{
    memset(o, 0, sizeof *o);
    o->kernels = 1000;
    o->integration_points = 40000;
}

int rk_basis_needs_frames(const rk_basis_options *o)
{
    return o->type == RK_BASIS_POD || o->tolerance > 0;
}
