/* An adaptive subspace entry on the built scene (method_adaptive_subspace.h, rk_scene_adaptive_init): its candidate
 * basis, how the oracle groups its columns, and the simulator under the scene's own options. */
#include "pipeline/method_adaptive_subspace.h"
#include "pipeline/method_fixed.h"

#include <string.h>

int rk_scene_adaptive_init(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *e,
                           const double *frames, int T, rk_adaptive *ad, double *seconds_basis, rk_error *err)
{
    if (sim->cloud_points) return rk_fail(err, "%s: method adaptive_subspace needs tetrahedral meshes, not point clouds", e->path);
    double t0 = rk_now();
    rk_basis basis;
    rk_scene_basis_info info;
    memset(&info, 0, sizeof info);
    if (rk_scene_basis(scene, sim, &e->basis, frames, T, &basis, &info, err)) {
        rk_scene_basis_info_free(&info);
        return rk_error_prefix(err, "%s: the candidate basis", e->path);
    }
    rk_scene_basis_info_free(&info);
    if (seconds_basis) *seconds_basis = rk_now() - t0;
    const rk_adaptive_subspace_entry *own = rk_adaptive_subspace_of(e);
    if (!own) return rk_fail(err, "%s is not method adaptive_subspace", e->path);
    rk_adaptive_options o = own->opt;
    int skinning = basis.W != NULL;
    o.block = skinning ? 12 : 1; /* a skinning weight's 12 affine columns are one candidate (Sec. 3.5) */
    int initial = own->initial_size;
    if (!initial) initial = skinning ? 12 : basis.nzero > 0 ? basis.nzero : 1;
    int rc = 0;
    if (initial % o.block || initial > basis.r)
        rc = rk_fail(err, "%s: initial_size must be a multiple of %d up to the %d candidate columns, got %d", e->path,
                     o.block, basis.r, initial);
    o.initial_blocks = initial / o.block;
    if (!rc && rk_adaptive_init(ad, &sim->fem, &sim->options, basis.U, basis.r, &o, err))
        rc = rk_error_prefix(err, "%s", e->path);
    rk_basis_free(&basis);
    return rc;
}
