/* precompute/fom, pressure.c against theory: a thick-walled hollow sphere under internal pressure
 * (static, neo-Hookean at P / E = 1e-3) against Lame's solution, converging with the mesh. */
#include "fom/fom.h"
#include "mesh/mesh.h"
#include "testlib.h"
#include "fem_body.h"
#include "chamber_box.h"

/* Lame: a hollow sphere, radii a < b, internal pressure P, linear elasticity (E, nu):
 * u(r) = P a^3 / (E (b^3 - a^3)) ((1 - 2 nu) r + (1 + nu) b^3 / (2 r^2)). The mesh: a box of n^3
 * cells with the middle (n/2)^3 carved out, each vertex moved along its direction from the centre
 * so that the cube shells |p|_inf = const become spheres from a to b (cells about as long as wide).
 * rel: the mean radial displacement's relative error on the inner and outer spheres. */
static int lame_sphere(int n, double rel[2], rk_error *err)
{
    carved cv;
    const double s = n, lo = n / 4, hi = 3 * n / 4, a = 1.0, b = 2.0, E = 1e6, nu = 0, P = 1000;
    if (carve_box(&cv, n, s, lo, hi, err)) return -1;
    for (int v = 0; v < cv.m.nv; v++) {
        double *p = &cv.m.X[3 * v], q[3], inf = 0, len = 0;
        for (int i = 0; i < 3; i++) q[i] = p[i] - s / 2, inf = fmax(inf, fabs(q[i])), len += q[i] * q[i];
        len = sqrt(len);
        double r = a + (inf - (hi - lo) / 2) / (s / 2 - (hi - lo) / 2) * (b - a);
        for (int i = 0; i < 3; i++) p[i] = q[i] / len * r;
    }
    fem_body body = {.m = cv.m};
    cv.c.pressure = P;
    rk_fom fom;
    int rc = fem_body_init(&body, (rk_material){RK_MAT_NEOHOOKEAN, E, nu, 1000.0}, err) ||
             solve_static(&body, &cv.c, 1e-8, &fom, err);
    if (rc == 0) {
        double sum[2] = {0, 0};
        int cnt[2] = {0, 0};
        for (int v = 0; v < cv.m.nv; v++) {
            const double *X = &cv.m.X[3 * v], *x = &fom.x[3 * v];
            double R = sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]), ur = 0;
            for (int i = 0; i < 3; i++) ur += (x[i] - X[i]) * X[i] / R;
            int side = fabs(R - a) < 1e-9 ? 0 : fabs(R - b) < 1e-9 ? 1 : -1;
            if (side >= 0) sum[side] += ur, cnt[side]++;
        }
        double k = P * a * a * a / (E * (b * b * b - a * a * a));
        double lame[2] = {k * ((1 - 2 * nu) * a + (1 + nu) * b * b * b / (2 * a * a)),
                          k * ((1 - 2 * nu) * b + (1 + nu) * b * b * b / (2 * b * b))};
        for (int side = 0; side < 2; side++) {
            rel[side] = fabs(sum[side] / cnt[side] / lame[side] - 1);
            printf("# Lame, %d^3 cells, %s sphere: mean u_r %.6g m, exact %.6g m (%.2f%% off, %d vertices)\n", n,
                   side ? "outer" : "inner", sum[side] / cnt[side], lame[side], 100 * rel[side], cnt[side]);
        }
        rk_fom_free(&fom);
    }
    rk_fem_free(&body.f);
    free(cv.c.tris);
    rk_mesh_free(&body.m);
    return rc;
}

/* Within 6% at 16^3 cells (21.5k tets), and converging: linear tets are stiff, the error shrinks
 * with the cells (measured at nu = 0, inner / outer sphere: 8^3 15.7 / 11.2%, 12^3 8.0 / 5.4%,
 * 16^3 4.8 / 3.1%; at nu = 0.3, 8^3 22.6 / 18.4%, 12^3 12.2 / 9.5%, 16^3 7.5 / 5.6%). */
TEST(hollow_sphere_under_internal_pressure_follows_lame)
{
    rk_error err;
    double coarse[2], fine[2];
    CHECK_OK(lame_sphere(8, coarse, &err));
    CHECK_OK(lame_sphere(16, fine, &err));
    for (int side = 0; side < 2; side++) {
        CHECK(fine[side] < 0.06, "%s sphere: mean u_r off by %.3g%% at 16^3 cells", side ? "outer" : "inner",
              100 * fine[side]);
        CHECK(fine[side] < coarse[side] / 2.5, "%s sphere: %.3g%% at 8^3 cells, %.3g%% at 16^3: not converging",
              side ? "outer" : "inner", 100 * coarse[side], 100 * fine[side]);
    }
}

int main(void)
{
    RUN(hollow_sphere_under_internal_pressure_follows_lame);
    return test_finish();
}
