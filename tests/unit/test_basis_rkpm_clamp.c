/* The clamp of RKPM skinning weights (issue 37; rkpm_clamp.c): Kantorovich masking d(X) phi_k with
 * d = 0 on the fixed region. On the beam's mesh with its first 0.5 m fixed: every weight is exactly
 * 0 at every fixed vertex and at grid points inside the fixed tets, non-zero beyond the rise; the
 * gradients from rk_rkpm_interpolate match central differences of the weights (the product rule
 * and the mask's own gradient); the same mask without tets (a point cloud) also vanishes at the
 * fixed points; and the build is deterministic. */
#include <math.h>
#include <string.h>

#include "basis/basis.h"
#include "testlib.h"

static const rk_material mat = {RK_MAT_LINEAR, 5e6, 0.0, 1000};

static double lame(void)
{
    double mu, lambda;
    rk_lame(mat.young, mat.poisson, &mu, &lambda);
    return lambda + 4 * mu;
}

/* The 5 x 1 x 1 beam (20 x 4 x 4 cells), its vertices with x <= 0.5 fixed, and its clamped basis
 * (tets: with the mesh's region; else as a cloud). */
static int clamped_beam(int tets, rk_mesh *m, unsigned char **fixed, rk_rkpm_points *pts, rk_basis *b, rk_error *err)
{
    if (rk_mesh_box((double[3]){5, 1, 1}, (int[3]){20, 4, 4}, m, err)) return -1;
    *fixed = calloc((size_t)m->nv, 1);
    for (int v = 0; v < m->nv; v++) (*fixed)[v] = m->X[3 * v] <= 0.5 + 1e-9;
    if (rk_rkpm_sample_mesh(m, 8000, pts, err)) return -1;
    double *coef = malloc(sizeof(double) * pts->n);
    for (int i = 0; i < pts->n; i++) coef[i] = lame();
    int rc = rk_basis_rkpm_skinning(pts, coef, 300, 6, m->X, m->nv, *fixed, tets ? m->tets : NULL, tets ? m->nt : 0, b,
                                    NULL, err);
    free(coef);
    return rc;
}

TEST(weights_vanish_on_the_fixed_region_and_gradients_match_differences)
{
    rk_error err;
    rk_mesh m;
    unsigned char *fixed;
    rk_rkpm_points pts;
    rk_basis b;
    CHECK_OK(clamped_beam(1, &m, &fixed, &pts, &b, &err));
    if (!b.W) return;
    CHECK(b.nzero == 0 && b.values[0] > 0, "a clamped basis has a zero eigenvalue (%g)", b.values[0]);
    double worst_fixed = 0, free_max = 0;
    for (int j = 0; j < b.m; j++)
        for (int v = 0; v < m.nv; v++) {
            double w = fabs(b.W[(size_t)m.nv * j + v]);
            if (fixed[v]) worst_fixed = fmax(worst_fixed, w);
            else free_max = fmax(free_max, w);
        }
    CHECK(worst_fixed == 0, "a weight is %g at a fixed vertex", worst_fixed);
    CHECK(free_max > 0.1, "the weights barely move the free part (%g)", free_max);
    /* Points inside the fixed tets (between the vertices, on the face's plane), on the free side
     * just past the face, and elsewhere: values and analytic gradients. */
    const double P[][3] = {{0.3, 0.4, 0.6}, {0.5, 0.37, 0.62}, {0.45, 0.9, 0.1}, {0.53, 0.37, 0.62},
                           {0.6, 0.2, 0.5}, {0.9, 0.5, 0.5}, {2.7, 0.3, 0.8}, {4.9, 0.95, 0.05}};
    const int np = 8;
    double W[8 * 7], dW[3 * 8 * 7];
    CHECK_OK(rk_rkpm_interpolate(b.rkpm, &P[0][0], np, b.C, b.m, W, dW, NULL, &err));
    for (int j = 0; j < b.m; j++)
        for (int i = 0; i < 3; i++)
            CHECK(W[i + np * j] == 0 && dW[3 * i + 3 * np * j] == 0, "weight %d at fixed-region point %d: %g", j, i,
                  W[i + np * j]);
    CHECK(fabs(W[3 + np]) > 0, "the weight is 0 just past the clamp's face");
    double worst = 0, h = 1e-6;
    for (int i = 3; i < np; i++)
        for (int c = 0; c < 3; c++) {
            double Xp[3], Xm[3], Wp[7], Wm[7];
            memcpy(Xp, P[i], sizeof Xp);
            memcpy(Xm, P[i], sizeof Xm);
            Xp[c] += h;
            Xm[c] -= h;
            CHECK_OK(rk_rkpm_interpolate(b.rkpm, Xp, 1, b.C, b.m, Wp, NULL, NULL, &err));
            CHECK_OK(rk_rkpm_interpolate(b.rkpm, Xm, 1, b.C, b.m, Wm, NULL, NULL, &err));
            for (int j = 0; j < b.m; j++) {
                double fd = (Wp[j] - Wm[j]) / (2 * h), an = dW[3 * i + c + 3 * np * j];
                worst = fmax(worst, fabs(fd - an) / (1 + fabs(an)));
            }
        }
    CHECK(worst < 1e-6, "analytic and finite-difference weight gradients differ by %g", worst);
    /* deterministic: the same build, the same bits */
    rk_mesh m2;
    unsigned char *fixed2;
    rk_rkpm_points pts2;
    rk_basis b2;
    CHECK_OK(clamped_beam(1, &m2, &fixed2, &pts2, &b2, &err));
    CHECK(b2.C && !memcmp(b.C, b2.C, sizeof(double) * b.rkpm->K * b.m), "two builds differ");
    rk_basis_free(&b2);
    rk_rkpm_points_free(&pts2);
    rk_mesh_free(&m2);
    free(fixed2);
    rk_basis_free(&b);
    rk_rkpm_points_free(&pts);
    rk_mesh_free(&m);
    free(fixed);
}

TEST(a_cloud_clamp_vanishes_at_its_fixed_points)
{
    rk_error err;
    rk_mesh m;
    unsigned char *fixed;
    rk_rkpm_points pts;
    rk_basis b;
    CHECK_OK(clamped_beam(0, &m, &fixed, &pts, &b, &err));
    if (!b.W) return;
    double worst_fixed = 0;
    for (int j = 0; j < b.m; j++)
        for (int v = 0; v < m.nv; v++)
            if (fixed[v]) worst_fixed = fmax(worst_fixed, fabs(b.W[(size_t)m.nv * j + v]));
    CHECK(worst_fixed == 0, "a weight is %g at a fixed point", worst_fixed);
    /* every point fixed: refused by name */
    memset(fixed, 1, (size_t)m.nv);
    rk_basis all;
    double *coef = malloc(sizeof(double) * pts.n);
    for (int i = 0; i < pts.n; i++) coef[i] = lame();
    CHECK(rk_basis_rkpm_skinning(&pts, coef, 100, 3, m.X, m.nv, fixed, NULL, 0, &all, NULL, &err) != 0 &&
              strstr(err.msg, "all 525 points are fixed"),
          "an all-fixed clamp was accepted or misnamed: %s", err.msg);
    free(coef);
    rk_basis_free(&b);
    rk_rkpm_points_free(&pts);
    rk_mesh_free(&m);
    free(fixed);
}

int main(void)
{
    RUN(weights_vanish_on_the_fixed_region_and_gradients_match_differences);
    RUN(a_cloud_clamp_vanishes_at_its_fixed_points);
    return test_finish();
}
