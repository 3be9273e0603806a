/* util/metrics on a hand-worked case: two points, two frames, every metric from its definition. */
#include "testlib.h"
#include "util/util.h"

TEST(metrics_match_a_hand_worked_case)
{
    /* rest: the origin and (3, 4, 0): L = 5 */
    const double X[6] = {0, 0, 0, 3, 4, 0};
    const double ref1[6] = {0, 0, 0, 3, 4, 1}, x1[6] = {1, 0, 0, 3, 4, 1}; /* errors 1, 0; |ref - X| 0, 1 */
    const double ref2[6] = {0, 0, 2, 3, 4, 0}, x2[6] = {0, 0, 2, 3, 4, 1}; /* errors 0, 1; |ref - X| 2, 0 */
    rk_run_error e;
    rk_run_error_init(&e, X, 2);
    CHECK(isnan(rk_normalized_mse(&e)) && isnan(rk_relative_error(&e)), "metrics of no frame are not NAN");
    rk_run_error_add(&e, x1, ref1);
    rk_run_error_add(&e, x2, ref2);
    CHECK_CLOSE(e.L, 5.0, 1e-15);
    /* sum |x - ref|^2 = 2 over 2 frames x 2 points, over L^2 = 25 */
    CHECK_CLOSE(rk_normalized_mse(&e), 2.0 / 4 / 25, 1e-15);
    CHECK_CLOSE(rk_normalized_max_error(&e), 1.0 / 5, 1e-15);
    /* sqrt(2 / (0 + 1 + 4 + 0)) */
    CHECK_CLOSE(rk_relative_error(&e), sqrt(2.0 / 5), 1e-15);
    /* frame norms: errors 1, 1; reference displacements 1, 2 */
    CHECK_CLOSE(rk_relative_online_error(&e), 2.0 / 3, 1e-15);
    CHECK_CLOSE(rk_points_diagonal(X, 2), 5.0, 1e-15);
}

TEST(frame_error_is_the_norm_the_online_error_sums)
{
    const double X[6] = {0, 0, 0, 3, 4, 0};
    const double a[6] = {1, 2, 2, 3, 4, 0}, b[6] = {1, 0, 0, 3, 4, 3}; /* differences (0, 2, 2), (0, 0, -3) */
    CHECK_CLOSE(rk_frame_error(a, b, 2), sqrt(17.0), 1e-15);
    CHECK_CLOSE(rk_frame_error(a, NULL, 2), sqrt(9.0 + 25), 1e-15);
    CHECK(rk_frame_error(a, a, 2) == 0, "a frame against itself");
    /* the online error's numerator is the sum of these, bit for bit */
    rk_run_error e;
    rk_run_error_init(&e, X, 2);
    rk_run_error_add(&e, a, b);
    rk_run_error_add(&e, b, a);
    CHECK(e.online_num == rk_frame_error(a, b, 2) + rk_frame_error(b, a, 2), "online %.17g", e.online_num);
}

TEST(max_abs_eigenvalue_takes_the_modulus)
{
    const double re[3] = {0.6, -1.1, 0.2}, im[3] = {0.8, 0, -0.3};
    CHECK_CLOSE(rk_max_abs_eigenvalue(re, im, 3), 1.1, 1e-15);
    CHECK(rk_max_abs_eigenvalue(re, im, 0) == 0, "no eigenvalue");
}

int main(void)
{
    RUN(metrics_match_a_hand_worked_case);
    RUN(frame_error_is_the_norm_the_online_error_sums);
    RUN(max_abs_eigenvalue_takes_the_modulus);
    return test_finish();
}
