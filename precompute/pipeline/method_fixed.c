/* Method fixed as a module (method.h): a reduced model on a fixed basis. Its keys are the shared
 * basis, cubature and mesh_free keys (rom.c reads them), its run beside full order is
 * rom_compare.c, its bake bake.c's. */
#include "pipeline/method_fixed.h"

#include <stdio.h>

int rk_fixed_compare(rk_compare_ctx *c, const rk_rom_entry *e, rk_compare_method *m, rk_error *err);

void rk_method_basis_name(const rk_rom_entry *o, char *name, size_t size)
{
    const char *type = rk_basis_type_name(o->basis.type), *cub = o->cubature ? "-cubature" : "";
    const char *mf = !o->mesh_free.enabled                         ? ""
                     : o->mesh_free.sampling == RK_SAMPLING_RANDOM ? "-meshfree-random"
                     : o->mesh_free.sampling == RK_SAMPLING_CLOUD  ? "-cloud"
                                                                   : "-meshfree";
    if (o->basis.size) snprintf(name, size, "%s-%d%s%s", type, o->basis.size, mf, cub);
    else snprintf(name, size, "%s-tol%g%s%s", type, o->basis.tolerance, mf, cub);
}

const rk_method rk_method_fixed = {
    .name = "fixed",
    .kind = "reduced",
    .basis_required = 1,
    .training_needs_pod = 1,
    .reduced_model = 1,
    .measures_contact = 1,
    .default_name = rk_method_basis_name,
    .compare = rk_fixed_compare,
    .bake = rk_method_bake_models,
};
