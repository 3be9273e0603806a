/* Skinning eigenmodes on meshes: M-orthonormal weights, the constant mode, the weight-space
 * eigenvalues of a bar against the 1D analytic problem (homogeneous and two-material, which is
 * Proposition 1's (lambda + 4 mu) weighting), LBS columns, disconnected objects (refused as one, taken as several), and the clamp
 * (issue 37): weights that vanish at fixed vertices, the 1D problem with a Dirichlet end. */
#include "basis/basis.h"
#include "bar_1d.h"
#include "fem_body.h"
#include "testlib.h"

static const rk_material soft = {RK_MAT_NEOHOOKEAN, 1e5, 0.3, 1000};

TEST(weights_are_mass_orthonormal_and_start_constant)
{
    rk_error err;
    fem_body b;
    CHECK_OK(fem_body_box(&b, 2.0, 0.5, 0.5, 12, 3, 3, soft, &err));
    rk_basis s;
    CHECK_OK(rk_basis_skinning(&b.f, NULL, 0, 6, &s, &err));
    CHECK(s.m == 7 && s.r == 84 && s.nzero == 1, "m %d r %d zero %d", s.m, s.r, s.nzero);
    /* Volume mass, written out here: V/20 (1 + delta_ab) per tet vertex pair. */
    double worst = 0, cmin = INFINITY, cmax = -INFINITY;
    for (int i = 0; i < s.m; i++)
        for (int j = 0; j < s.m; j++) {
            const double *wi = s.W + (size_t)i * s.n, *wj = s.W + (size_t)j * s.n;
            double g = 0;
            for (int t = 0; t < b.f.nt; t++)
                for (int p = 0; p < 4; p++)
                    for (int q = 0; q < 4; q++)
                        g += b.f.vol[t] / 20.0 * (1 + (p == q)) * wi[b.f.tets[4 * t + p]] * wj[b.f.tets[4 * t + q]];
            worst = fmax(worst, fabs(g - (i == j)));
        }
    for (int v = 0; v < s.n; v++) { cmin = fmin(cmin, s.W[v]); cmax = fmax(cmax, s.W[v]); }
    double vol = 2.0 * 0.5 * 0.5;
    rk_basis_free(&s);
    fem_body_free(&b);
    CHECK(worst < 1e-10, "W^T M W differs from I by %.3g", worst);
    CHECK(fabs(cmin - cmax) < 1e-9 * fabs(cmax) && fabs(cmax - 1 / sqrt(vol)) < 1e-9,
          "first weight not the constant 1/sqrt(V): %.12g..%.12g", cmin, cmax);
}

TEST(bar_eigenvalues_match_the_1d_problem)
{
    rk_error err;
    const double L = 4.0;
    fem_body b;
    CHECK_OK(fem_body_box(&b, L, 0.25, 0.25, 64, 2, 2, soft, &err));
    rk_basis s;
    CHECK_OK(rk_basis_skinning(&b.f, NULL, 0, 2, &s, &err));
    double c = lame_sum(soft), l1 = c * pow(M_PI / L, 2), l2 = c * pow(2 * M_PI / L, 2);
    printf("# mesh skinning, homogeneous bar: lambda_1 %.6g vs (lambda + 4 mu)(pi/L)^2 = %.6g, lambda_2 %.6g vs %.6g\n",
           s.values[1], l1, s.values[2], l2);
    double e1 = fabs(s.values[1] - l1) / l1, e2 = fabs(s.values[2] - l2) / l2;
    rk_basis_free(&s);
    fem_body_free(&b);
    CHECK(e1 < 2e-3 && e2 < 5e-3, "relative errors %.3g, %.3g", e1, e2);
}

TEST(heterogeneous_material_shifts_modes_as_proposition_1_says)
{
    rk_error err;
    const double L = 4.0, a = 1.5;
    fem_body b;
    CHECK_OK(rk_mesh_box((double[3]){L, 0.25, 0.25}, (int[3]){64, 2, 2}, &b.m, &err));
    rk_material stiff = {RK_MAT_NEOHOOKEAN, 1e6, 0.45, 3000};
    rk_material *mats = malloc(sizeof *mats * b.m.nt);
    for (int t = 0; t < b.m.nt; t++) {
        double cx = 0;
        for (int k = 0; k < 4; k++) cx += 0.25 * b.m.X[3 * b.m.tets[4 * t + k]];
        mats[t] = cx < a ? stiff : soft;
    }
    CHECK_OK(rk_fem_init(&b.f, &b.m, mats, &err));
    free(mats);
    rk_basis s;
    CHECK_OK(rk_basis_skinning(&b.f, NULL, 0, 1, &s, &err));
    double c1 = lame_sum(stiff), c2 = lame_sum(soft);
    double exact = two_material_eigenvalue(c1, c2, a, L);
    /* Density plays no part (volume mass), so only lambda + 4 mu shifts the mode. */
    printf("# mesh skinning, two-material bar (lambda+4mu %.3g | %.3g): lambda_1 %.6g, 1D analytic %.6g\n",
           c1, c2, s.values[1], exact);
    double e = fabs(s.values[1] - exact) / exact;
    rk_basis_free(&s);
    fem_body_free(&b);
    CHECK(e < 5e-3, "relative error %.3g", e);
}

TEST(lbs_columns_move_vertices_by_weight_times_affine_map)
{
    double X[6] = {1, 2, 3, -1, 0.5, 2};
    double W[4] = {0.5, 2.0, 1.0, -1.0}; /* n = 2, m = 2 */
    double U[6 * 24];
    rk_skinning_to_U(W, 2, 2, X, U);
    /* Handle j = 1, entry (a = 2, b = 0): vertex i's z moves by W[i, 1] * x_i. */
    const double *col = U + 6 * (12 * 1 + 4 * 2 + 0);
    CHECK(col[2] == 1.0 * 1 && col[5] == -1.0 * -1 && col[0] == 0 && col[4] == 0, "column wrong");
    /* Handle 0, translation (b = 3) in y: W[i, 0]. */
    col = U + 6 * (4 * 1 + 3);
    CHECK(col[1] == 0.5 && col[4] == 2.0, "translation column wrong");
}

/* One mesh of two pieces is refused as one object (two zero eigenvalues) and taken as two
 * objects (rk_basis_skinning_objects): each its own m + 1 weights, the first constant on it,
 * every weight 0 on the other piece, the second piece's eigenvalues those of the piece alone, and
 * the second one fixed at one end clamped on its own (no constant weight there). */
TEST(disconnected_pieces_are_refused_as_one_object_taken_as_two)
{
    rk_error err;
    fem_body b;
    rk_mesh one;
    CHECK_OK(rk_mesh_box((double[3]){1, 1, 1}, (int[3]){2, 2, 2}, &one, &err));
    /* Two copies, the second moved 3 m away: one mesh, two pieces. */
    b.m = one;
    b.m.nv = 2 * one.nv;
    b.m.nt = 2 * one.nt;
    b.m.X = malloc(sizeof(double) * 3 * b.m.nv);
    b.m.tets = malloc(sizeof(int) * 4 * b.m.nt);
    b.m.tet_tag = calloc(b.m.nt, sizeof(int));
    for (int i = 0; i < 3 * one.nv; i++) {
        b.m.X[i] = one.X[i];
        b.m.X[3 * one.nv + i] = one.X[i] + (i % 3 == 0 ? 3.0 : 0.0);
    }
    for (int i = 0; i < 4 * one.nt; i++) {
        b.m.tets[i] = one.tets[i];
        b.m.tets[4 * one.nt + i] = one.tets[i] + one.nv;
    }
    rk_mesh_free(&one);
    CHECK_OK(fem_body_init(&b, soft, &err));
    rk_basis s;
    int rc = rk_basis_skinning(&b.f, NULL, 0, 3, &s, &err);
    CHECK(rc != 0, "two pieces accepted");
    CHECK(strstr(err.msg, "disconnected pieces"), "message: %s", err.msg);
    int n1 = b.f.nv / 2, first[3] = {0, n1, 2 * n1};
    fem_body alone;
    CHECK_OK(fem_body_box(&alone, 1, 1, 1, 2, 2, 2, soft, &err));
    rk_basis a, two;
    CHECK_OK(rk_basis_skinning(&alone.f, NULL, 0, 3, &a, &err));
    CHECK_OK(rk_basis_skinning_objects(&b.f, NULL, 0, 3, first, 2, &two, &err));
    CHECK(two.nparts == 2 && two.m == 8 && two.r == 96 && two.nzero == 2, "parts %d m %d r %d zero %d", two.nparts,
          two.m, two.r, two.nzero);
    double spread = 0, leak = 0, value = 0;
    for (int k = 0; k < 2; k++)
        for (int v = 0; v < b.f.nv; v++) {
            int mine = (v >= first[k] && v < first[k + 1]);
            double c = two.W[(size_t)b.f.nv * two.part_handle[k] + v], c0 = two.W[(size_t)b.f.nv * two.part_handle[k] + first[k]];
            if (mine) spread = fmax(spread, fabs(c - c0));
            for (int j = 0; !mine && j < 4; j++) leak = fmax(leak, fabs(two.W[(size_t)b.f.nv * (two.part_handle[k] + j) + v]));
        }
    for (int j = 0; j < 4; j++) /* (the cube's eigenvalues repeat: its weights are not unique, its values are) */
        value = fmax(value, fabs(two.values[4 + j] - a.values[j]) / a.values[3]);
    CHECK(spread < 1e-9 && leak == 0, "first weight varies by %g on its piece, a weight is %g on the other", spread, leak);
    CHECK(value < 1e-8, "second piece's eigenvalues off by %g (relative)", value);
    rk_basis_free(&two);
    unsigned char *fixed = calloc((size_t)b.f.nv, 1);
    for (int v = n1; v < 2 * n1; v++) fixed[v] = b.f.X[3 * v] < 3 + 1e-9;
    CHECK_OK(rk_basis_skinning_objects(&b.f, fixed, 0, 3, first, 2, &two, &err));
    CHECK(two.part[0].nzero == 1 && two.part[1].nzero == 0 && two.part[1].values[0] > 0, "zero eigenvalues %d, %d",
          two.part[0].nzero, two.part[1].nzero);
    rk_basis_free(&two);
    rk_basis_free(&a);
    free(fixed);
    fem_body_free(&alone);
    fem_body_free(&b);
}

/* The Dirichlet clamp: a bar fixed at x = 0 and free at x = L has the weight-space eigenvalues
 * (lambda + 4 mu)((k + 1/2) pi / L)^2 (quarter waves sin((k + 1/2) pi x / L)), no constant
 * weight, and every weight exactly 0 at the fixed vertices; m + 1 weights still make
 * r = 12 (m + 1). */
TEST(a_clamped_bar_has_quarter_wave_weights_that_vanish_at_the_clamp)
{
    rk_error err;
    const double L = 4.0;
    fem_body b;
    CHECK_OK(fem_body_box(&b, L, 0.25, 0.25, 64, 2, 2, soft, &err));
    unsigned char *fixed = calloc((size_t)b.f.nv, 1);
    for (int v = 0; v < b.f.nv; v++) fixed[v] = b.f.X[3 * v] < 1e-9;
    rk_basis s;
    CHECK_OK(rk_basis_skinning(&b.f, fixed, 0, 2, &s, &err));
    double c = lame_sum(soft), l0 = c * pow(M_PI / (2 * L), 2), l1 = c * pow(3 * M_PI / (2 * L), 2), held = 0;
    printf("# clamped bar: lambda_0 %.6g vs (lambda + 4 mu)(pi/2L)^2 = %.6g, lambda_1 %.6g vs %.6g\n", s.values[0], l0,
           s.values[1], l1);
    CHECK(s.m == 3 && s.r == 36 && s.nzero == 0, "m %d r %d zero %d", s.m, s.r, s.nzero);
    CHECK(fabs(s.values[0] / l0 - 1) < 0.01 && fabs(s.values[1] / l1 - 1) < 0.02, "eigenvalues %g %g, 1D %g %g",
          s.values[0], s.values[1], l0, l1);
    for (int j = 0; j < s.m; j++)
        for (int v = 0; v < s.n; v++)
            if (fixed[v]) held = fmax(held, fabs(s.W[(size_t)j * s.n + v]));
    for (size_t k = 0; k < (size_t)3 * s.n * s.r; k++)
        if (fixed[(k % (3 * (size_t)s.n)) / 3]) held = fmax(held, fabs(s.U[k]));
    CHECK(held == 0, "a weight or LBS row is %g at a fixed vertex", held);
    rk_basis_free(&s);
    memset(fixed, 1, (size_t)b.f.nv);
    CHECK(rk_basis_skinning(&b.f, fixed, 0, 2, &s, &err) != 0 && strstr(err.msg, "every vertex is fixed"),
          "an all-fixed object was accepted: %s", err.msg);
    free(fixed);
    fem_body_free(&b);
}

int main(void)
{
    RUN(weights_are_mass_orthonormal_and_start_constant);
    RUN(bar_eigenvalues_match_the_1d_problem);
    RUN(heterogeneous_material_shifts_modes_as_proposition_1_says);
    RUN(lbs_columns_move_vertices_by_weight_times_affine_map);
    RUN(disconnected_pieces_are_refused_as_one_object_taken_as_two);
    RUN(a_clamped_bar_has_quarter_wave_weights_that_vanish_at_the_clamp);
    return test_finish();
}
