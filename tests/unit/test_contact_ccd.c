/* Continuous collision detection, the broad phase and the exact predicates (precompute/contact):
 * the adversarial cases (a thin plate crossed in one step, a near miss at 1e-8, nearly parallel
 * edges, a point that starts on the triangle), random motions against dense sampling, the spatial
 * hash against brute force, and orient3d where floating point alone gets the sign wrong. */
#include "contact/contact.h"
#include "testlib.h"
#include "util/util.h"

static uint64_t seed = 7;
static double rnd(void) { return 2 * rk_uniform(&seed) - 1; }

/* The stencil's squared distance at time t of linear motion x + t dx. */
static double distance_at(int ee, double X[4][3], double D[4][3], double t)
{
    double y[4][3];
    for (int k = 0; k < 4; k++)
        for (int a = 0; a < 3; a++) y[k][a] = X[k][a] + t * D[k][a];
    const double *p[4] = {y[0], y[1], y[2], y[3]};
    rk_distance_case c = ee ? rk_edge_edge_case(p) : rk_point_triangle_case(p);
    return rk_contact_distance2(c, p, NULL, NULL);
}

static int ccd(int ee, double X[4][3], double D[4][3], double *toi)
{
    const double *x[4] = {X[0], X[1], X[2], X[3]}, *dx[4] = {D[0], D[1], D[2], D[3]};
    return rk_ccd_stencil(ee, x, dx, 0, 1, toi);
}

TEST(a_thin_plate_crossed_in_one_step_is_caught)
{
    /* the point goes from 1 m above the triangle to 1 m below in one step: at t = 1 it is far
     * from the plate, so a check of the end state alone sees nothing */
    double X[4][3] = {{0.3, 0.3, 1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, D[4][3] = {{0, 0, -2}};
    double toi;
    CHECK(distance_at(0, X, D, 1) > 0.9, "the end state is not far");
    CHECK(ccd(0, X, D, &toi) && toi > 0 && toi < 0.5, "impact %g (true 0.5)", toi);
    double z = 1 - 2 * toi;
    CHECK(z >= 0.1 - 1e-12, "at the reported time the point is at z = %g, under 10%% of its start", z);
    /* the triangle moving up through a resting point: the same, relative */
    double Y[4][3] = {{0.3, 0.3, 0}, {0, 0, -1}, {1, 0, -1}, {0, 1, -1}}, E[4][3] = {{0}, {0, 0, 2}, {0, 0, 2}, {0, 0, 2}};
    CHECK(ccd(0, Y, E, &toi) && toi < 0.5, "moving triangle: impact %g", toi);
}

TEST(a_near_miss_at_1e_8_is_never_a_crossing)
{
    /* the point passes 1e-8 outside the edge x = 0 */
    double X[4][3] = {{-1e-8, 0.5, 1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, D[4][3] = {{0, 0, -2}};
    double toi;
    int hit = ccd(0, X, D, &toi);
    double closest = sqrt(distance_at(0, X, D, 0.5));
    printf("# near miss: closest approach %.3g m at t = 0.5; additive CCD %s (t = %.6f)\n", closest,
           hit ? "stops the step" : "lets it pass", hit ? toi : 1.0);
    /* conservative either way: if it stops the step, it stops it before the closest approach */
    CHECK(!hit || (toi <= 0.5 && distance_at(0, X, D, toi) > 0), "toi %g", toi);
    /* edges passing 1e-8 apart */
    double A[4][3] = {{0, 0, 0}, {1, 0, 0}, {0.5, -1, 1e-8}, {0.5, 1, 1e-8}}, B[4][3] = {{0}, {0}, {0, 0, 0}, {0, 0, 0}};
    A[2][2] = A[3][2] = 1; /* start 1 m above, come down to 1e-8 above at t = 1 */
    B[2][2] = B[3][2] = -(1 - 1e-8);
    hit = ccd(1, A, B, &toi);
    CHECK(!hit || distance_at(1, A, B, toi) > 0, "edges: toi %g", toi);
}

TEST(nearly_parallel_edges_that_cross_are_caught)
{
    /* edge b lies 1e-6 rad off parallel to edge a and sweeps through it */
    double X[4][3] = {{0, 0, 0}, {1, 0, 0}, {0.1, 1, 1e-7}, {0.9, 1, -1e-7}}, D[4][3] = {{0}, {0}, {0, -2, 0}, {0, -2, 0}};
    double toi;
    CHECK(ccd(1, X, D, &toi) && toi <= 0.5, "impact %g (true 0.5)", toi);
    CHECK(distance_at(1, X, D, toi) > 0, "touching at the reported time");
    /* exactly parallel, sliding along each other 0.01 apart: no impact */
    double Y[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 0.01, 0}, {1, 0.01, 0}}, E[4][3] = {{0}, {0}, {0.5, 0, 0}, {0.5, 0, 0}};
    CHECK(!ccd(1, Y, E, &toi), "parallel sliding edges reported an impact at %g", toi);
}

TEST(a_point_that_starts_on_the_triangle_has_impact_time_zero)
{
    double X[4][3] = {{0.25, 0.25, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, D[4][3] = {{0, 0, 1}};
    double toi = 1;
    CHECK(ccd(0, X, D, &toi) && toi == 0, "toi %g", toi);
}

TEST(random_motions_never_pass_through)
{
    int impacts = 0, checked = 0;
    for (int k = 0; k < 600; k++) {
        int ee = k % 2;
        double X[4][3], D[4][3];
        for (int j = 0; j < 4; j++)
            for (int a = 0; a < 3; a++) X[j][a] = rnd(), D[j][a] = 2 * rnd();
        if (distance_at(ee, X, D, 0) < 1e-4) continue;
        double toi;
        int hit = ccd(ee, X, D, &toi);
        double t_end = hit ? toi : 1, d0 = sqrt(distance_at(ee, X, D, 0)), closest = INFINITY;
        for (int s = 0; s <= 20000; s++) closest = fmin(closest, sqrt(distance_at(ee, X, D, t_end * s / 20000)));
        CHECK(closest > 0, "case %d: the motion up to t = %g touches (closest %g)", k, t_end, closest);
        if (hit) CHECK(sqrt(distance_at(ee, X, D, toi)) >= 0.1 * d0 - 1e-12, "case %d: under 10%% of the gap at toi", k);
        impacts += hit;
        checked++;
    }
    printf("# random motions: %d checked, %d stopped by CCD, none passes through\n", checked, impacts);
    CHECK(impacts > 50 && impacts < checked, "impacts %d of %d", impacts, checked);
}

/* n random boxes in [-2, 2]^3 of sizes in [lo, hi] (lo 0: some are points). */
static void random_boxes(double *boxes, int n, double lo, double hi)
{
    for (int i = 0; i < n; i++) {
        double *b = boxes + 6 * i, size = lo + (hi - lo) * fabs(rnd());
        for (int a = 0; a < 3; a++) {
            b[a] = 2 * rnd();
            b[3 + a] = b[a] + size * (i % 7 == 0 && lo == 0 ? 0 : 0.5 + fabs(rnd()));
        }
    }
}

/* The broad phase against every pair tested: the same pairs, each once. */
static int broad_phase_matches_brute_force(const double *A, int na, const double *B, int nb, int *brute_out)
{
    int *pairs, np;
    rk_error err;
    if (rk_broad_phase(A, na, B, nb, &pairs, &np, &err)) return 0;
    int brute = 0, found = 0;
    for (int a = 0; a < na; a++)
        for (int b = 0; b < nb; b++) {
            const double *x = A + 6 * a, *y = B + 6 * b;
            int overlap = !(x[0] > y[3] || x[3] < y[0] || x[1] > y[4] || x[4] < y[1] || x[2] > y[5] || x[5] < y[2]);
            brute += overlap;
            for (int p = 0; p < np && overlap; p++)
                if (pairs[2 * p] == a && pairs[2 * p + 1] == b) {
                    found++;
                    break;
                }
        }
    free(pairs);
    *brute_out = brute;
    return found == brute && np == brute;
}

TEST(broad_phase_finds_exactly_the_overlapping_boxes)
{
    enum { NA = 300, NB = 400 };
    static double A[6 * NA], B[6 * NB];
    /* similar sizes and one huge box; many points against a few big boxes (an obstacle's
     * triangles against a mesh's vertices), both ways round; big boxes against big boxes */
    const double sizes[5][4] = {{0.02, 0.22, 0.02, 0.22}, {0, 1e-3, 0.5, 1.5}, {0.5, 1.5, 0, 1e-3},
                                {0.1, 0.4, 0, 0.05}, {1, 3, 1, 3}};
    const int counts[5][2] = {{NA, NB}, {NA, 12}, {12, NB}, {NA, NB}, {40, 40}};
    for (int c = 0; c < 5; c++) {
        random_boxes(A, counts[c][0], sizes[c][0], sizes[c][1]);
        random_boxes(B, counts[c][1], sizes[c][2], sizes[c][3]);
        if (c == 0) B[0] = -50, B[3] = 50; /* one huge box */
        int brute = -1;
        int same = broad_phase_matches_brute_force(A, counts[c][0], B, counts[c][1], &brute);
        printf("# broad phase, %d x %d boxes of %g-%g m and %g-%g m: %d overlapping pairs%s\n", counts[c][0],
               counts[c][1], sizes[c][0], sizes[c][1], sizes[c][2], sizes[c][3], brute, same ? ", each reported once" : "");
        CHECK(same, "case %d: the broad phase's pairs differ from the %d overlapping ones", c, brute);
    }
}

TEST(orient3d_is_exact_where_floating_point_is_not)
{
    /* four points on the plane z = x + y, exactly, where the plain double determinant rounds to
     * 2^31 instead of 0 */
    double a[3] = {8561.875, -11134.75, -2572.875}, b[3] = {-77475.625, 999999999884965.875, 999999999807490.25},
           c[3] = {-126246.0, 68788.75, -57457.25}, d[3] = {90238.625, -14841.75, 75396.875};
    CHECK(rk_orient3d_sign(a, b, c, d) == 0, "coplanar points: sign %d", rk_orient3d_sign(a, b, c, d));
    double up[3] = {90238.625, -14841.75, 75396.875 + 1.0 / 64}, down[3] = {90238.625, -14841.75, 75396.875 - 1.0 / 64};
    int su = rk_orient3d_sign(a, b, c, up), sd = rk_orient3d_sign(a, b, c, down);
    CHECK(su == -sd && su != 0, "1/64 above %d, below %d", su, sd);
    double adx = a[0] - d[0], ady = a[1] - d[1], adz = a[2] - d[2], bdx = b[0] - d[0], bdy = b[1] - d[1],
           bdz = b[2] - d[2], cdx = c[0] - d[0], cdy = c[1] - d[1], cdz = c[2] - d[2];
    double det = adx * (bdy * cdz - bdz * cdy) + bdx * (cdy * adz - cdz * ady) + cdx * (ady * bdz - adz * bdy);
    CHECK(det != 0, "the plain determinant is exact here: the case tests nothing");
    printf("# coplanar points: double determinant %.3g, exact 0\n", det);
}

TEST(segment_triangle_test_is_exact)
{
    double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0};
    double p[3] = {0.2, 0.2, 1}, q[3] = {0.2, 0.2, -1};
    CHECK(rk_segment_triangle_intersect(p, q, a, b, c), "crossing missed");
    double r[3] = {0.2, 0.2, 0}; /* ends on the triangle: touching counts */
    CHECK(rk_segment_triangle_intersect(p, r, a, b, c), "touching missed");
    double s[3] = {0.2, 0.2, 1e-300};
    CHECK(!rk_segment_triangle_intersect(p, s, a, b, c), "a segment ending 1e-300 above crosses");
    double e0[3] = {-1, 0.5, 0}, e1[3] = {0.2, 0.5, 0}; /* coplanar, entering the triangle */
    CHECK(rk_segment_triangle_intersect(e0, e1, a, b, c), "coplanar crossing missed");
    double f0[3] = {-1, 0.5, 0}, f1[3] = {-0.1, 0.5, 0};
    CHECK(!rk_segment_triangle_intersect(f0, f1, a, b, c), "coplanar miss reported");
    double g0[3] = {0.5, 0.5 + 1e-16, 1}, g1[3] = {0.5, 0.5 + 1e-16, -1}; /* just outside the hypotenuse */
    CHECK(!rk_segment_triangle_intersect(g0, g1, a, b, c), "outside the hypotenuse by 1e-16 reported");
}

int main(void)
{
    RUN(a_thin_plate_crossed_in_one_step_is_caught);
    RUN(a_near_miss_at_1e_8_is_never_a_crossing);
    RUN(nearly_parallel_edges_that_cross_are_caught);
    RUN(a_point_that_starts_on_the_triangle_has_impact_time_zero);
    RUN(random_motions_never_pass_through);
    RUN(broad_phase_finds_exactly_the_overlapping_boxes);
    RUN(orient3d_is_exact_where_floating_point_is_not);
    RUN(segment_triangle_test_is_exact);
    return test_finish();
}
