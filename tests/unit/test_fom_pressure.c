/* precompute/fom, pressure.c: a chamber's follower pressure force. Its derivative against finite
 * differences, the force as P times the gradient of the void's volume (the conservative load the
 * potential takes), zero total force on a closed chamber, refusals by name, and the thick-walled
 * sphere under internal pressure against Lame's solution. */
#include "fom/fom.h"
#include "mesh/mesh.h"
#include "testlib.h"
#include "fem_body.h"

static double urand(unsigned *s)
{
    *s = *s * 1103515245u + 12345u;
    return (double)((*s >> 8) & 0xffff) / 65536.0;
}

TEST(face_force_derivative_matches_finite_differences)
{
    unsigned seed = 7;
    double x[9], f[3], J[27], fp[3], fm[3];
    for (int i = 0; i < 9; i++) x[i] = urand(&seed) - 0.5;
    double P = 1234.5;
    rk_pressure_face(x, x + 3, x + 6, P, f, J);
    double worst = 0, scale = 0;
    for (int k = 0; k < 27; k++) scale = fmax(scale, fabs(J[k]));
    for (int w = 0; w < 3; w++)
        for (int j = 0; j < 3; j++) {
            double h = 1e-6, xp[9], xm[9];
            memcpy(xp, x, sizeof x);
            memcpy(xm, x, sizeof x);
            xp[3 * w + j] += h;
            xm[3 * w + j] -= h;
            rk_pressure_face(xp, xp + 3, xp + 6, P, fp, NULL);
            rk_pressure_face(xm, xm + 3, xm + 6, P, fm, NULL);
            for (int i = 0; i < 3; i++) worst = fmax(worst, fabs((fp[i] - fm[i]) / (2 * h) - J[9 * w + 3 * i + j]));
        }
    CHECK(worst <= 1e-7 * scale, "largest difference %g of %g", worst, scale);
    /* direction: a face counter-clockwise about +z (pointing into the void above it) pushed down */
    double flat[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    rk_pressure_face(flat, flat + 3, flat + 6, 6.0, f, NULL);
    CHECK(fabs(f[0]) + fabs(f[1]) == 0 && fabs(f[2] + 1.0) < 1e-15, "face force (%g %g %g), expected (0 0 -1)", f[0],
          f[1], f[2]);
}

/* A box of n^3 cells, size s, with the middle cells inside [lo, hi]^3 carved out; the chamber is
 * the boundary faces whose centroid lies inside the box [lo - eps, hi + eps]^3. */
typedef struct {
    rk_mesh m;
    rk_chamber c;
} carved;

static int carve_box(carved *cv, int n, double s, double lo, double hi, rk_error *err)
{
    double size[3] = {s, s, s};
    int cells[3] = {n, n, n};
    memset(cv, 0, sizeof *cv);
    rk_box b = {{lo, lo, lo}, {hi, hi, hi}};
    if (rk_mesh_box(size, cells, &cv->m, err) || rk_mesh_carve(&cv->m, &b, 1, err)) return -1;
    int *tris, nf;
    if (rk_mesh_boundary(&cv->m, &tris, &nf, err)) return -1;
    cv->c.tris = calloc(3 * (size_t)nf, sizeof(int));
    double eps = 1e-9 * s;
    rk_box g = {{lo - eps, lo - eps, lo - eps}, {hi + eps, hi + eps, hi + eps}};
    for (int t = 0; t < nf; t++) {
        double c[3] = {0, 0, 0};
        for (int k = 0; k < 3; k++)
            for (int i = 0; i < 3; i++) c[i] += cv->m.X[3 * tris[3 * t + k] + i] / 3;
        if (rk_box_contains(&g, c, 0)) memcpy(&cv->c.tris[3 * cv->c.nf++], &tris[3 * t], 3 * sizeof(int));
    }
    free(tris);
    return 0;
}

static void carved_free(carved *cv)
{
    free(cv->c.tris);
    rk_mesh_free(&cv->m);
}

TEST(closed_chamber_force_is_the_volume_gradient_and_sums_to_zero)
{
    rk_error err;
    carved cv;
    CHECK_OK(carve_box(&cv, 4, 1.0, 0.25, 0.75, &err));
    cv.c.pressure = 1e3;
    CHECK(cv.c.nf == 6 * 2 * 4, "%d faces in the chamber, expected 48 (a 2x2x2-cell cube's walls)", cv.c.nf);
    CHECK_OK(rk_chamber_check(&cv.c, cv.m.nv, &err));
    int n = 3 * cv.m.nv;
    double *x = calloc((size_t)n, sizeof(double)), *f = calloc((size_t)n, sizeof(double));
    unsigned seed = 3;
    for (int i = 0; i < n; i++) x[i] = cv.m.X[i] + 0.02 * (urand(&seed) - 0.5); /* deformed */
    double V = rk_chamber_volume(&cv.c, cv.m.X);
    CHECK(fabs(V - 0.125) < 1e-12, "rest void volume %g, expected 0.125", V);
    rk_chamber_force(&cv.c, x, 1.0, f);
    double total[3] = {0, 0, 0}, worst = 0, big = 0;
    for (int v = 0; v < cv.m.nv; v++)
        for (int i = 0; i < 3; i++) total[i] += f[3 * v + i], big = fmax(big, fabs(f[3 * v + i]));
    for (int i = 0; i < 3; i++) CHECK(fabs(total[i]) <= 1e-12 * big * cv.m.nv, "total force %g along %d", total[i], i);
    for (int i = 0; i < n; i++) {
        if (f[i] == 0) continue;
        double h = 1e-6, keep = x[i];
        x[i] = keep + h;
        double Vp = rk_chamber_volume(&cv.c, x);
        x[i] = keep - h;
        double Vm = rk_chamber_volume(&cv.c, x);
        x[i] = keep;
        worst = fmax(worst, fabs(cv.c.pressure * (Vp - Vm) / (2 * h) - f[i]));
    }
    CHECK(worst <= 1e-6 * big, "force differs from P dV/dx by %g (largest force %g)", worst, big);
    /* the walls move out of the void: the force on a wall vertex points away from the centre */
    int v = cv.c.tris[0];
    double out = 0;
    for (int i = 0; i < 3; i++) out += f[3 * v + i] * (x[3 * v + i] - 0.5);
    CHECK(out > 0, "the pressure pulls wall vertex %d into the void", v);
    free(x);
    free(f);
    carved_free(&cv);
}

TEST(open_empty_and_nan_chambers_are_refused)
{
    rk_error err;
    carved cv;
    CHECK_OK(carve_box(&cv, 4, 1.0, 0.25, 0.75, &err));
    cv.c.pressure = 1.0;
    cv.c.nf--; /* one wall face missing */
    CHECK(rk_chamber_check(&cv.c, cv.m.nv, &err) != 0 && strstr(err.msg, "not a closed surface"), "open: '%s'",
          err.msg);
    cv.c.nf++;
    cv.c.pressure = NAN;
    CHECK(rk_chamber_check(&cv.c, cv.m.nv, &err) != 0 && strstr(err.msg, "not finite"), "NaN: '%s'", err.msg);
    rk_chamber empty = {0};
    CHECK(rk_chamber_check(&empty, cv.m.nv, &err) != 0 && strstr(err.msg, "no faces"), "empty: '%s'", err.msg);
    carved_free(&cv);
}

/* Static equilibrium of body under its chambers (neo-Hookean, tolerance tol metres): x in fom. */
static int solve_static(fem_body *body, const rk_chamber *c, double tol, rk_fom *fom, rk_error *err)
{
    rk_fom_options opt;
    rk_fom_default_options(&opt);
    opt.is_static = 1;
    opt.nchambers = 1;
    opt.chambers = c;
    opt.newton_tol = tol;
    if (rk_fom_init(fom, &body->f, &opt, err)) return -1;
    if (rk_fom_static(fom, err)) {
        rk_fom_free(fom);
        return -1;
    }
    return 0;
}

/* The patch test: pressure P on the whole outer surface of a box (a chamber whose void is the outside)
 * compresses it uniformly, u = -P (1 - 2 nu) / E (X - centre), a linear field that linear tets hold
 * exactly; the split-equal face loads are the consistent ones for a uniform traction. Neo-Hookean at
 * P / E = 1e-5 is linear to about that. */
TEST(outer_pressure_compresses_a_box_uniformly)
{
    rk_error err;
    fem_body body;
    const double E = 1e6, nu = 0.3, P = 10;
    CHECK_OK(fem_body_box(&body, 1, 0.5, 0.5, 4, 2, 2, (rk_material){RK_MAT_NEOHOOKEAN, E, nu, 1000.0}, &err));
    rk_chamber c = {.pressure = P};
    CHECK_OK(rk_mesh_boundary(&body.m, &c.tris, &c.nf, &err));
    CHECK_OK(rk_chamber_check(&c, body.m.nv, &err));
    CHECK(rk_chamber_volume(&c, body.m.X) < 0, "the outside's volume is %g", rk_chamber_volume(&c, body.m.X));
    rk_fom fom;
    CHECK_OK(solve_static(&body, &c, 1e-12, &fom, &err));
    double eps = -P * (1 - 2 * nu) / E, centre[3] = {0.5, 0.25, 0.25}, worst = 0, big = 0;
    /* up to a rigid motion (the body is free): compare displacement differences to vertex 0's */
    for (int v = 0; v < body.m.nv; v++)
        for (int i = 0; i < 3; i++) {
            double X = body.m.X[3 * v + i], u = fom.x[3 * v + i] - X, u0 = fom.x[i] - body.m.X[i];
            double want = eps * (X - centre[i]) - eps * (body.m.X[i] - centre[i]);
            worst = fmax(worst, fabs((u - u0) - want));
            big = fmax(big, fabs(want));
        }
    CHECK(worst <= 1e-3 * big, "displacement off the uniform compression by %g (largest %g)", worst, big);
    rk_fom_free(&fom);
    free(c.tris);
    fem_body_free(&body);
}

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
    RUN(face_force_derivative_matches_finite_differences);
    RUN(closed_chamber_force_is_the_volume_gradient_and_sums_to_zero);
    RUN(open_empty_and_nan_chambers_are_refused);
    RUN(outer_pressure_compresses_a_box_uniformly);
    RUN(hollow_sphere_under_internal_pressure_follows_lame);
    return test_finish();
}
