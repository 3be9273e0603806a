/* The basis keys of a scene's `rom` section. */
#include "basis/scene_basis.h"

#include <math.h>
#include <stdio.h>

#include "scene/json_get.h"

int rk_basis_options_parse(const cJSON *rom, int index, const char *file, rk_basis_options *o,
                           rk_error *err)
{
    rk_json_ctx c = {file, err};
    char path[64];
    const cJSON *e = rom;
    if (!rom) return rk_fail(err, "%s: the scene has no \"rom\" section (it says which basis to build)", file);
    if (cJSON_IsArray(rom)) {
        snprintf(path, sizeof path, "rom[%d]", index);
        e = cJSON_GetArrayItem(rom, index);
        if (!e) return rk_json_fail(&c, "rom", "has no entry %d", index);
    } else {
        snprintf(path, sizeof path, "rom");
    }
    if (!cJSON_IsObject(e)) return rk_json_fail(&c, path, "must be an object");
    static const char *const keys[] = {"basis", "size", "tolerance", "modes", "kernels",
                                       "integration_points", "cubature", "koopman", "name", "reference", "asset", NULL};
    if (rk_json_check_keys(&c, e, path, keys)) return -1;
    const char *name;
    if (rk_json_string(&c, e, path, "basis", 1, &name)) return -1;
    if (rk_basis_type_parse(name, &o->type))
        return rk_json_fail(&c, path, "basis must be modes, modal_derivatives, skinning, rkpm_skinning "
                            "or pod, got \"%s\"", name);
    double tol = 0;
    o->size = 0;
    o->modes = 0;
    o->kernels = 1000;
    o->integration_points = 40000;
    if (rk_json_whole(&c, e, path, "size", 0, 4096, &o->size) || rk_json_number(&c, e, path, "tolerance", 0, &tol) ||
        rk_json_whole(&c, e, path, "modes", 0, 60, &o->modes) ||
        rk_json_whole(&c, e, path, "kernels", 4, 100000, &o->kernels) ||
        rk_json_whole(&c, e, path, "integration_points", 100, 1e7, &o->integration_points))
        return -1;
    if (!(tol >= 0 && tol < 1)) return rk_json_fail(&c, path, "tolerance must be in (0, 1), got %g", tol);
    if (o->size == 0 && tol == 0)
        return rk_json_fail(&c, path, "needs size (how many columns or weights) or tolerance (the "
                            "largest relative error of the scene's full-order frames)");
    o->tolerance = tol;
    return 0;
}
