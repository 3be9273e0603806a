/* rom.volume "projected": the reduced model's pressure space (cubature.h, "the projected volume")
 * at its quadrature's points, from rom.pressure:
 *   constant        {1}: one mean volume change per quadrature (B-bar's constant pressure);
 *   weights         {W_j}: the skinning weights, one pressure per handle (a partition of unity,
 *                   so it holds the constant);
 *   weights_affine  {W_j (1, x, y, z)}: each handle's pressure also varying linearly, as the
 *                   handles' affine maps vary the strain (x centred and scaled by the quadrature's
 *                   extent, which keeps the Gram matrix conditioned).
 * A richer space holds more of theta's pointwise values (the limit, one function per point, is the
 * pointwise energy that locks); a poorer one constrains less and can leave a volume change with no
 * energy. The sag test (tests/unit/test_pipeline_meshfree_beam.c) measures the three. */
#include "pipeline/method_fixed.h"
#include "pipeline/pipeline.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The skinning weights (H) and position at quadrature point k: a mesh-free point's own, or the
 * mean of a tet's vertices'. */
static void point_weights(const rk_scene_sim *sim, const rk_scene_rom *R, int k, double *W, double X[3])
{
    const rk_quadrature *Q = &R->model.quad;
    int i = Q->source[k];
    if (R->points.n) {
        for (int j = 0; j < R->points.H; j++) W[j] = R->points.W[(size_t)i + (size_t)R->points.n * j];
        memcpy(X, R->points.X + 3 * (size_t)i, sizeof(double) * 3);
        return;
    }
    const int *v = &sim->fem.tets[4 * (size_t)i];
    int n = R->basis.n, m = R->basis.m;
    memset(X, 0, sizeof(double) * 3);
    for (int j = 0; j < m; j++) W[j] = 0;
    for (int c = 0; c < 4; c++) {
        for (int j = 0; j < m; j++) W[j] += 0.25 * R->basis.W[(size_t)v[c] + (size_t)n * j];
        for (int a = 0; a < 3; a++) X[a] += 0.25 * sim->mesh.X[3 * (size_t)v[c] + a];
    }
}

int rk_scene_rom_volume(const rk_scene_sim *sim, const rk_rom_entry *o, rk_scene_rom *R, rk_error *err)
{
    rk_quadrature *Q = &R->model.quad;
    int n = Q->count;
    if (o->volume != RK_VOLUME_PROJECTED || n == 0) return 0;
    int H = R->points.n ? R->points.H : R->basis.m, affine = o->pressure == RK_PRESSURE_WEIGHTS_AFFINE;
    if (o->pressure != RK_PRESSURE_CONSTANT && !(H > 0 && (R->points.n || R->basis.W)))
        return rk_fail(err, "%s: rom.pressure %s needs skinning weights (basis rkpm_skinning or skinning), not basis %s",
                       o->name, affine ? "weights_affine" : "weights", rk_basis_type_name(o->basis.type));
    int k = o->pressure == RK_PRESSURE_CONSTANT ? 1 : (affine ? 4 : 1) * H;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, X[3];
    double *psi = rk_calloc((size_t)n * k, sizeof(double), err), *W = rk_calloc(H > 0 ? H : 1, sizeof(double), err);
    if (!psi || !W) {
        free(psi);
        free(W);
        return rk_error_prefix(err, "%s: pressure space", o->name);
    }
    for (int i = 0; i < n && o->pressure != RK_PRESSURE_CONSTANT; i++) {
        point_weights(sim, R, i, W, X);
        for (int a = 0; a < 3; a++) lo[a] = fmin(lo[a], X[a]), hi[a] = fmax(hi[a], X[a]);
    }
    double size = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
    for (int i = 0; i < n; i++) {
        double *row = psi + (size_t)i * k;
        if (o->pressure == RK_PRESSURE_CONSTANT) {
            row[0] = 1;
            continue;
        }
        point_weights(sim, R, i, W, X);
        for (int j = 0; j < H; j++) {
            if (!affine) {
                row[j] = W[j];
                continue;
            }
            row[4 * j] = W[j];
            for (int a = 0; a < 3; a++) row[4 * j + 1 + a] = W[j] * (X[a] - 0.5 * (lo[a] + hi[a])) / (size > 0 ? size : 1);
        }
    }
    int rc = rk_quadrature_volume(Q, k, psi, err);
    free(psi);
    free(W);
    return rc ? rk_error_prefix(err, "%s", o->name) : 0;
}
