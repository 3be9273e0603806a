/* precompute/basis rk_rkpm_sample_mesh_random (the freeform paper's "random" integration points,
 * Table 4): every point in its recorded tet, weights summing to the mesh volume, the same points
 * for one seed and others for another, uniform density (the fraction of points in part of a box
 * against its volume fraction, and the barycentric coordinates inside one tet against the moments
 * of the uniform (Dirichlet(1,1,1,1)) distribution, each within 4 binomial/sampling standard
 * deviations), and the errors. */
#include "basis/basis.h"
#include "testlib.h"

/* Barycentric coordinate f of x in tet t of m: x replaces vertex f. */
static double barycentric(const rk_mesh *m, int t, const double *x, int f)
{
    const int *T = &m->tets[4 * t];
    const double *v[4];
    for (int c = 0; c < 4; c++) v[c] = c == f ? x : &m->X[3 * T[c]];
    double vol = rk_tet_signed_volume(&m->X[3 * T[0]], &m->X[3 * T[1]], &m->X[3 * T[2]], &m->X[3 * T[3]]);
    return rk_tet_signed_volume(v[0], v[1], v[2], v[3]) / vol;
}

TEST(points_lie_in_their_tets_and_weigh_the_volume)
{
    rk_error err;
    rk_mesh m;
    rk_rkpm_points p;
    double size[3] = {2, 0.5, 0.75};
    int cells[3] = {5, 3, 2};
    CHECK_OK(rk_mesh_box(size, cells, &m, &err));
    int count = 5000;
    CHECK_OK(rk_rkpm_sample_mesh_random(&m, count, 7, &p, &err));
    CHECK(p.n == count && p.tet != NULL && p.source == NULL, "n %d", p.n);
    double sum = 0, worst = 1;
    for (int i = 0; i < p.n; i++) {
        int t = p.tet[i];
        CHECK(t >= 0 && t < m.nt, "point %d: tet %d", i, t);
        sum += p.weight[i];
        double bsum = 0;
        for (int f = 0; f < 4; f++) {
            double b = barycentric(&m, t, &p.X[3 * i], f);
            bsum += b;
            worst = fmin(worst, b);
            CHECK(b >= -1e-12, "point %d (%g, %g, %g) outside its tet %d: barycentric %d = %g", i, p.X[3 * i],
                  p.X[3 * i + 1], p.X[3 * i + 2], t, f, b);
        }
        CHECK(fabs(bsum - 1) < 1e-12, "point %d: barycentric coordinates sum to %.17g", i, bsum);
    }
    printf("# %d points: smallest barycentric coordinate %.3g, weights sum %.17g (volume 0.75)\n", count, worst, sum);
    CHECK_CLOSE(p.volume, 2 * 0.5 * 0.75, 1e-12);
    CHECK_CLOSE(sum, 0.75, 1e-12);
    CHECK_CLOSE(p.spacing, cbrt(0.75 / count), 1e-12);
    rk_rkpm_points_free(&p);
    rk_mesh_free(&m);
}

TEST(a_seed_fixes_the_points)
{
    rk_error err;
    rk_mesh m;
    rk_rkpm_points a, b, c;
    double size[3] = {1, 1, 1};
    int cells[3] = {2, 2, 2};
    CHECK_OK(rk_mesh_box(size, cells, &m, &err));
    CHECK_OK(rk_rkpm_sample_mesh_random(&m, 300, 42, &a, &err));
    CHECK_OK(rk_rkpm_sample_mesh_random(&m, 300, 42, &b, &err));
    CHECK_OK(rk_rkpm_sample_mesh_random(&m, 300, 43, &c, &err));
    CHECK(memcmp(a.X, b.X, sizeof(double) * 900) == 0 && memcmp(a.tet, b.tet, sizeof(int) * 300) == 0 &&
              memcmp(a.weight, b.weight, sizeof(double) * 300) == 0,
          "the same seed gave different points");
    int same = 0;
    for (int i = 0; i < 300; i++) same += memcmp(&a.X[3 * i], &c.X[3 * i], 3 * sizeof(double)) == 0;
    CHECK(same == 0, "seeds 42 and 43 share %d of 300 points", same);
    rk_rkpm_points_free(&a);
    rk_rkpm_points_free(&b);
    rk_rkpm_points_free(&c);
    rk_mesh_free(&m);
}

/* A box [0, 4] x [0, 1] x [0, 1] (its tets are not all the same shape, and the part x < 1 holds
 * a quarter of them): the fraction of points with x < 1 against 1/4. Several seeds. */
TEST(density_is_uniform_over_a_box)
{
    rk_error err;
    rk_mesh m;
    rk_rkpm_points p;
    double size[3] = {4, 1, 1};
    int cells[3] = {8, 3, 2}; /* x < 1 is exactly 2 of the 8 cell columns */
    CHECK_OK(rk_mesh_box(size, cells, &m, &err));
    int count = 20000;
    double pr = 0.25, sd = sqrt(pr * (1 - pr) / count), worst = 0;
    for (unsigned long long seed = 1; seed <= 5; seed++) {
        CHECK_OK(rk_rkpm_sample_mesh_random(&m, count, seed, &p, &err));
        int in = 0, in_y = 0;
        for (int i = 0; i < count; i++) in += p.X[3 * i] < 1, in_y += p.X[3 * i + 1] < 1.0 / 3; /* one row of cells */
        double f = (double)in / count, fy = (double)in_y / count;
        double z = fabs(f - pr) / sd, zy = fabs(fy - 1.0 / 3) / sqrt((1.0 / 3) * (2.0 / 3) / count);
        worst = fmax(worst, fmax(z, zy));
        CHECK(z < 4, "seed %llu: %.4f of the points have x < 1, volume fraction 0.25 (%.1f sd)", seed, f, z);
        CHECK(zy < 4, "seed %llu: %.4f of the points have y < 1/3, volume fraction 1/3 (%.1f sd)", seed, fy, zy);
        rk_rkpm_points_free(&p);
    }
    printf("# fraction of points in a quarter (and a third) of the box: at most %.2f sd from the volume fraction\n", worst);
    rk_mesh_free(&m);
}

/* One irregular tet: its barycentric coordinates must be Dirichlet(1,1,1,1): each has mean 1/4,
 * E[b^2] = 1/10, P(b < 1/2) = 1 - 1/8, and b0 + b1 ~ Beta(2,2) has P(b0 + b1 < 1/2) = 1/2. A
 * wrong fold of the cube (Rocchini & Cignoni) would bunch points toward a vertex or a face. */
TEST(density_is_uniform_inside_a_tet)
{
    rk_error err;
    rk_mesh m = {0};
    double X[12] = {0.1, -0.2, 0.3, 2.0, 0.1, -0.4, 0.4, 1.5, 0.2, 0.3, 0.5, 1.7};
    int tets[4] = {0, 1, 2, 3};
    m.nv = 4, m.nt = 1, m.X = X, m.tets = tets;
    double vol = rk_tet_signed_volume(&X[0], &X[3], &X[6], &X[9]);
    if (vol < 0) tets[2] = 3, tets[3] = 2, vol = -vol;
    rk_rkpm_points p;
    int n = 40000;
    CHECK_OK(rk_rkpm_sample_mesh_random(&m, n, 99, &p, &err));
    CHECK_CLOSE(p.volume, vol, 1e-12);
    double mean[4] = {0}, sq[4] = {0}, below[4] = {0}, pair = 0;
    for (int i = 0; i < n; i++) {
        double b[4];
        for (int f = 0; f < 4; f++) {
            b[f] = barycentric(&m, 0, &p.X[3 * i], f);
            mean[f] += b[f] / n;
            sq[f] += b[f] * b[f] / n;
            below[f] += (b[f] < 0.5) / (double)n;
        }
        pair += (b[0] + b[1] < 0.5) / (double)n;
    }
    /* Beta(1,3): variance 3/80; b^2 has variance E[b^4] - E[b^2]^2 = 1/35 - 1/100 */
    double sd_mean = sqrt(3.0 / 80 / n), sd_sq = sqrt((1.0 / 35 - 0.01) / n), sd_below = sqrt(0.875 * 0.125 / n),
           sd_pair = sqrt(0.25 / n), worst = 0;
    for (int f = 0; f < 4; f++) {
        worst = fmax(worst, fmax(fabs(mean[f] - 0.25) / sd_mean, fmax(fabs(sq[f] - 0.1) / sd_sq, fabs(below[f] - 0.875) / sd_below)));
        CHECK(fabs(mean[f] - 0.25) < 4 * sd_mean, "mean barycentric %d = %.5f, uniform 0.25", f, mean[f]);
        CHECK(fabs(sq[f] - 0.1) < 4 * sd_sq, "E[b%d^2] = %.5f, uniform 0.1", f, sq[f]);
        CHECK(fabs(below[f] - 0.875) < 4 * sd_below, "P(b%d < 1/2) = %.5f, uniform 0.875", f, below[f]);
    }
    CHECK(fabs(pair - 0.5) < 4 * sd_pair, "P(b0 + b1 < 1/2) = %.5f, uniform 0.5", pair);
    worst = fmax(worst, fabs(pair - 0.5) / sd_pair);
    printf("# barycentric moments in one tet: at most %.2f sd from the uniform distribution's\n", worst);
    rk_rkpm_points_free(&p);
}

TEST(bad_requests_fail)
{
    rk_error err;
    rk_mesh m;
    rk_rkpm_points p;
    double size[3] = {1, 1, 1};
    int cells[3] = {1, 1, 1};
    CHECK_OK(rk_mesh_box(size, cells, &m, &err));
    CHECK(rk_rkpm_sample_mesh_random(&m, 0, 1, &p, &err) != 0 && strstr(err.msg, "0"), "count 0: %s", err.msg);
    CHECK(p.X == NULL && p.n == 0, "a failed call left points behind");
    CHECK(rk_rkpm_sample_mesh_random(&m, -5, 1, &p, &err) != 0 && strstr(err.msg, "-5"), "count -5: %s", err.msg);
    rk_mesh empty = m;
    empty.nt = 0;
    CHECK(rk_rkpm_sample_mesh_random(&empty, 10, 1, &p, &err) != 0 && strstr(err.msg, "tetrahedra"), "no tets: %s", err.msg);
    /* a mesh whose tets are all flat has no volume to sample */
    rk_mesh flat = m;
    double *X = malloc(sizeof(double) * 3 * m.nv);
    memcpy(X, m.X, sizeof(double) * 3 * m.nv);
    for (int v = 0; v < m.nv; v++) X[3 * v + 2] = 0;
    flat.X = X;
    CHECK(rk_rkpm_sample_mesh_random(&flat, 10, 1, &p, &err) != 0 && strstr(err.msg, "volume"), "flat mesh: %s", err.msg);
    CHECK(p.X == NULL && p.n == 0, "a failed call left points behind");
    free(X);
    rk_mesh_free(&m);
}

int main(void)
{
    RUN(points_lie_in_their_tets_and_weigh_the_volume);
    RUN(a_seed_fixes_the_points);
    RUN(density_is_uniform_over_a_box);
    RUN(density_is_uniform_inside_a_tet);
    RUN(bad_requests_fail);
    return test_finish();
}
