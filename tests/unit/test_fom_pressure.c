/* precompute/fom, pressure.c: a chamber's follower pressure force. Its derivative against finite
 * differences, the force as P times the gradient of the void's volume (the conservative load the
 * potential takes), zero total force on a closed chamber, refusals by name, and the patch test
 * (uniform compression under outer pressure). Lame's hollow sphere: test_fom_lame.c. */
#include "fom/fom.h"
#include "mesh/mesh.h"
#include "testlib.h"
#include "fem_body.h"
#include "chamber_box.h"

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

/* The load stiffness the Newton matrix takes: the Hessian of -P V, the negative derivative of the
 * summed force, symmetric over the closed chamber (its upper triangle against finite differences). */
TEST(chamber_stiffness_is_the_force_derivative)
{
    rk_error err;
    carved cv;
    CHECK_OK(carve_box(&cv, 4, 1.0, 0.25, 0.75, &err));
    cv.c.pressure = 1e3;
    fem_body body = {.m = cv.m};
    CHECK_OK(fem_body_init(&body, (rk_material){RK_MAT_NEOHOOKEAN, 1e6, 0.3, 1000.0}, &err));
    rk_sparse H;
    memset(&H, 0, sizeof H);
    CHECK_OK(rk_sparse_alloc_pattern(&body.f, &H, &err));
    int n = 3 * cv.m.nv;
    double *x = calloc((size_t)n, sizeof(double)), *fp = calloc((size_t)n, sizeof(double)),
           *fm = calloc((size_t)n, sizeof(double));
    unsigned seed = 5;
    for (int i = 0; i < n; i++) x[i] = cv.m.X[i] + 0.02 * (urand(&seed) - 0.5);
    rk_chamber_add_stiffness(&cv.c, x, 1.0, &H);
    double worst = 0, big = 0;
    for (int col = 0; col < n; col++) {
        double h = 1e-6, keep = x[col];
        memset(fp, 0, sizeof(double) * n), memset(fm, 0, sizeof(double) * n);
        x[col] = keep + h;
        rk_chamber_force(&cv.c, x, 1.0, fp);
        x[col] = keep - h;
        rk_chamber_force(&cv.c, x, 1.0, fm);
        x[col] = keep;
        for (int k = H.colptr[col]; k < H.colptr[col + 1]; k++) {
            double fd = -(fp[H.rowind[k]] - fm[H.rowind[k]]) / (2 * h);
            worst = fmax(worst, fabs(H.val[k] - fd));
            big = fmax(big, fabs(fd));
        }
    }
    CHECK(big > 0 && worst <= 1e-6 * big, "stiffness off the force's derivative by %g (largest %g)", worst, big);
    free(x), free(fp), free(fm);
    rk_sparse_free(&H);
    rk_fem_free(&body.f);
    free(cv.c.tris);
    rk_mesh_free(&body.m);
}

TEST(keyed_pressure_is_linear_between_keys_and_held_outside)
{
    double keys[6] = {0.1, 0, 0.3, 100, 0.4, 50};
    rk_chamber c = {.pressure = 7, .nkeys = 3, .keys = keys};
    double t[6] = {0, 0.1, 0.2, 0.3, 0.35, 1}, want[6] = {0, 0, 50, 100, 75, 50};
    for (int i = 0; i < 6; i++)
        CHECK(fabs(rk_chamber_pressure_at(&c, t[i]) - want[i]) < 1e-12, "at %g s: %g Pa, expected %g", t[i],
              rk_chamber_pressure_at(&c, t[i]), want[i]);
    c.nkeys = 0;
    CHECK(rk_chamber_pressure_at(&c, 0.2) == 7, "an unkeyed chamber's pressure is its own");
    rk_error err;
    carved cv;
    CHECK_OK(carve_box(&cv, 4, 1.0, 0.25, 0.75, &err));
    cv.c.nkeys = 3;
    cv.c.keys = keys;
    keys[2] = 0.1; /* a key at the same time as the one before */
    CHECK(rk_chamber_check(&cv.c, cv.m.nv, &err) != 0 && strstr(err.msg, "does not come after"), "keys: '%s'",
          err.msg);
    carved_free(&cv);
}

int main(void)
{
    RUN(face_force_derivative_matches_finite_differences);
    RUN(closed_chamber_force_is_the_volume_gradient_and_sums_to_zero);
    RUN(open_empty_and_nan_chambers_are_refused);
    RUN(outer_pressure_compresses_a_box_uniformly);
    RUN(chamber_stiffness_is_the_force_derivative);
    RUN(keyed_pressure_is_linear_between_keys_and_held_outside);
    return test_finish();
}
