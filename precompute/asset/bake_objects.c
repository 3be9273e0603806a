/* Several objects in one asset (ROMBIN.md "Object chunks"): COBJ, the object of each collision
 * vertex. The objects touch through their collision surfaces as the reduced simulator's do (the
 * surface and the pair capacity: bake_obstacles.c; the runtime: runtime/contact_surface.c), and
 * COBJ tells which stencils join two objects (those within one need contact.self). */
#include "asset/bake_impl.h"

#include <stdlib.h>

int rk_bake_objects(const rk_rom_model *m, int ncv, rombin_writer *w, rk_error *err)
{
    if (!m->has_contact || ncv == 0) return 0;
    const rk_contact *c = &m->contact;
    int K = 0;
    for (int i = 0; i < c->nv; i++) K = c->object[c->vertex[i]] + 1 > K ? c->object[c->vertex[i]] + 1 : K;
    if (K < 2) return 0; /* one object: its surface touches nothing of another */
    if (ncv != c->nv || ncv != m->ncv) return rk_fail(err, "COBJ: %d collision vertices, the contact stage has %d", ncv, c->nv);
    int *obj = rk_calloc((size_t)ncv, sizeof(int), err);
    if (!obj) return -1;
    for (int i = 0; i < ncv; i++) obj[i] = c->object[m->cv[i]];
    int rc = rk_bake_add_u32s(w, ROMBIN_COBJ, 1, obj, (size_t)ncv, err) ? -1 : 0;
    free(obj);
    return rc;
}
