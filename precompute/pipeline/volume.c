/* rom.volume "projected": the reduced model's pressure space (cubature.h, "the projected volume")
 * at its quadrature's points, from rom.pressure:
 *   constant        {1}: one mean volume change per quadrature (B-bar's constant pressure);
 *   weights         {W_j}: the skinning eigen-weights of the object without its clamp, one
 *                   pressure per handle (a partition of unity, so it holds the constant);
 *   weights_affine  {W_j (1, x, y, z)}: each handle's pressure also varying linearly, as the
 *                   handles' affine maps vary the strain (x centred and scaled by the quadrature's
 *                   extent, which keeps the Gram matrix conditioned).
 * A richer space holds more of theta's pointwise values (the limit, one function per point, is the
 * pointwise energy that locks); a poorer one constrains less and can leave a volume change with no
 * energy. The sag test (tests/unit/test_pipeline_volume_beam.c) measures the three.
 *
 * Why the weights without the clamp. A basis clamped to the scene's fixed region (rom.clamp
 * "dirichlet", issue 37) has weights that vanish there and rise beside it, where a clamped bend's
 * pressure is largest; the pressure takes no boundary condition, so its space is the same problem's
 * eigen-weights with no clamp (as many, computed again without the fixed region). On the FreeForm
 * beam at nu = 0.45 (static; the converged solid, P2: 0.1220 m) the clamped weights as pressures
 * sagged 109 / 109 / 107% of the solid at m = 16 / 20 / 32 (too few patterns held near the clamp;
 * adding the constant changed nothing), the unclamped ones 98.2 / 99.5 / 100.9%. */
#include "pipeline/method_fixed.h"
#include "pipeline/pipeline.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The pressure weights (H) and position at quadrature point k: a mesh-free point's, or the mean of
 * a tet's vertices'. At (n x H, column-major) holds them at the mesh-free points (R->points' order),
 * else at the mesh's vertices. */
static void point_weights(const rk_scene_sim *sim, const rk_scene_rom *R, const double *at, int H, int k, double *W,
                          double X[3])
{
    const rk_quadrature *Q = &R->model.quad;
    int i = Q->source[k];
    if (R->points.n) {
        for (int j = 0; j < H; j++) W[j] = at[(size_t)i + (size_t)R->points.n * j];
        memcpy(X, R->points.X + 3 * (size_t)i, sizeof(double) * 3);
        return;
    }
    const int *v = &sim->fem.tets[4 * (size_t)i];
    int n = sim->mesh.nv;
    memset(X, 0, sizeof(double) * 3);
    for (int j = 0; j < H; j++) W[j] = 0;
    for (int c = 0; c < 4; c++) {
        for (int j = 0; j < H; j++) W[j] += 0.25 * at[(size_t)v[c] + (size_t)n * j];
        for (int a = 0; a < 3; a++) X[a] += 0.25 * sim->mesh.X[3 * (size_t)v[c] + a];
    }
}

/* The weights the pressure space takes (the file's comment says why): the basis's own, or for a
 * clamped skinning basis of one object (no constant weight, nzero 0) the same basis built without
 * the clamp, into *free_basis and *free_points (freed by the caller). *at: n x H at the mesh-free
 * points, or nv x H at the vertices. */
static int pressure_weights(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *o, const rk_scene_rom *R,
                            rk_basis *free_basis, rk_skin_points *free_points, const double **at, rk_error *err)
{
    *at = R->points.n ? R->points.W : R->basis.W;
    if (R->basis.lift_handle)
        return rk_fail(err, "volume \"projected\" with clamp \"lifted\": not yet (the pressure space would take "
                       "the lifting field as a weight); use volume \"pointwise\" or clamp \"dirichlet\"");
    if (R->basis.nzero != 0 || R->basis.nparts > 0 || !R->basis.W) return 0;
    rk_basis_options unclamped = o->basis;
    unclamped.clamp_penalty = 1;
    rk_scene_basis_info info;
    memset(&info, 0, sizeof info);
    int rc = rk_scene_basis(scene, sim, &unclamped, NULL, 0, free_basis, &info, err);
    rk_scene_basis_info_free(&info);
    if (rc) return rk_error_prefix(err, "the unclamped weights of the pressure space");
    /* a basis chosen by rom.tolerance kept a prefix of its weights (basis.c, meet_tolerance); the
     * rebuild, without the frames, does not: keep as many of its lowest eigen-weights */
    if (o->basis.tolerance > 0 && free_basis->m > R->basis.m) rk_basis_truncate(free_basis, 12 * R->basis.m);
    if (free_basis->m != R->basis.m)
        return rk_fail(err, "the unclamped weights of the pressure space: %d weights, the basis %d", free_basis->m,
                       R->basis.m);
    if (!R->points.n) {
        *at = free_basis->W;
        return 0;
    }
    if (rk_scene_object_weights(free_basis, 0, R->points.X, R->points.n, free_points, err))
        return rk_error_prefix(err, "the unclamped weights of the pressure space");
    *at = free_points->W;
    return 0;
}

/* The pointwise volume on a skinning basis locks as nu nears 1/2 (issue 37): the FreeForm beam at
 * nu = 0.45 sags 45-93% of the converged solid from m = 6 to 32 (projected: 96-101% from m = 9,
 * docs/results/volume_sag.md), and tests/data/demo_small.json's m = 4 model is 0.0115 from a P2
 * run where the projected one is 0.0012 (nMSE). The projected volume is the skinning bases'
 * default (parse_rom.c parse_volume); a model that still uses the pointwise one on them (asked
 * for, or clamp "lifted") says so where it can be this stiff: nu >= 0.4 at any point. */
static void volume_warning(const rk_rom_entry *o, rk_scene_rom *R)
{
    const rk_quadrature *Q = &R->model.quad;
    double nu = 0;
    R->volume_warning[0] = 0;
    if (o->volume == RK_VOLUME_PROJECTED || !(R->points.n || R->basis.W)) return;
    for (int i = 0; i < Q->count; i++) /* nu = lambda / (2 (lambda + mu)) */
        if (Q->lambda[i] + Q->mu[i] > 0) nu = fmax(nu, Q->lambda[i] / (2 * (Q->lambda[i] + Q->mu[i])));
    if (nu >= 0.4)
        snprintf(R->volume_warning, sizeof R->volume_warning, "Poisson's ratio %.3g with the pointwise volume: a "
                 "skinning subspace locks (the FreeForm beam at 0.45 sags 7-55%% short); \"volume\": \"projected\", "
                 "the skinning bases' default, does not (docs/scene.md)", nu);
}

int rk_scene_rom_volume(const rk_scene *scene, const rk_scene_sim *sim, const rk_rom_entry *o, rk_scene_rom *R,
                        rk_error *err)
{
    rk_quadrature *Q = &R->model.quad;
    int n = Q->count;
    volume_warning(o, R);
    if (o->volume != RK_VOLUME_PROJECTED || n == 0) return 0;
    int H = R->points.n ? R->points.H : R->basis.m, affine = o->pressure == RK_PRESSURE_WEIGHTS_AFFINE;
    if (o->pressure != RK_PRESSURE_CONSTANT && !(H > 0 && (R->points.n || R->basis.W)))
        return rk_fail(err, "%s: rom.pressure %s needs skinning weights (basis rkpm_skinning or skinning), not basis %s",
                       o->name, affine ? "weights_affine" : "weights", rk_basis_type_name(o->basis.type));
    int k = o->pressure == RK_PRESSURE_CONSTANT ? 1 : (affine ? 4 : 1) * H;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, X[3];
    rk_basis free_basis;
    rk_skin_points free_points;
    memset(&free_basis, 0, sizeof free_basis);
    memset(&free_points, 0, sizeof free_points);
    const double *at = NULL;
    double *psi = rk_calloc((size_t)n * k, sizeof(double), err), *W = rk_calloc(H > 0 ? H : 1, sizeof(double), err);
    int rc = -1;
    if (!psi || !W) goto out;
    if (o->pressure != RK_PRESSURE_CONSTANT && pressure_weights(scene, sim, o, R, &free_basis, &free_points, &at, err))
        goto out;
    for (int i = 0; i < n && o->pressure != RK_PRESSURE_CONSTANT; i++) {
        point_weights(sim, R, at, H, i, W, X);
        for (int a = 0; a < 3; a++) lo[a] = fmin(lo[a], X[a]), hi[a] = fmax(hi[a], X[a]);
    }
    double size = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
    for (int i = 0; i < n; i++) {
        double *row = psi + (size_t)i * k;
        if (o->pressure == RK_PRESSURE_CONSTANT) {
            row[0] = 1;
            continue;
        }
        point_weights(sim, R, at, H, i, W, X);
        for (int j = 0; j < H; j++) {
            if (!affine) {
                row[j] = W[j];
                continue;
            }
            row[4 * j] = W[j];
            for (int a = 0; a < 3; a++) row[4 * j + 1 + a] = W[j] * (X[a] - 0.5 * (lo[a] + hi[a])) / (size > 0 ? size : 1);
        }
    }
    rc = rk_quadrature_volume(Q, k, psi, err);
out:
    free(psi);
    free(W);
    rk_basis_free(&free_basis);
    rk_skin_points_free(&free_points);
    return rc ? rk_error_prefix(err, "%s: pressure space", o->name) : 0;
}
