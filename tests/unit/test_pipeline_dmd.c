/* romkit dmd's library (dmd.h). rk_koopman_fit_pod on data with a known answer: frames of a damped
 * oscillation (rho = 0.99, 9 degrees a step) in a random 2-plane of R^30; its two POD directions
 * span that plane, so the fit on them finds the oscillation's eigenvalues rho e^{+-i theta}, the
 * same as a fit on the plane's own basis, and asking for more directions than the data has is
 * refused with the numbers. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pipeline/dmd.h"
#include "testlib.h"

enum { NV = 10, N = 3 * NV, T = 60 };

static void plane(double Q[N * 2])
{
    uint64_t seed = 7;
    for (int i = 0; i < 2 * N; i++) Q[i] = (double)(rk_splitmix64(&seed) >> 11) / 9007199254740992.0 - 0.5;
    /* Gram-Schmidt: two orthonormal columns */
    double n0 = 0, d = 0, n1 = 0;
    for (int i = 0; i < N; i++) n0 += Q[i] * Q[i];
    for (int i = 0; i < N; i++) Q[i] /= sqrt(n0);
    for (int i = 0; i < N; i++) d += Q[i] * Q[N + i];
    for (int i = 0; i < N; i++) Q[N + i] -= d * Q[i];
    for (int i = 0; i < N; i++) n1 += Q[N + i] * Q[N + i];
    for (int i = 0; i < N; i++) Q[N + i] /= sqrt(n1);
}

static double max_modulus(const rk_koopman *k)
{
    return rk_max_abs_eigenvalue(k->lambda_re, k->lambda_im, k->r);
}

TEST(pod_fit_finds_the_oscillation_in_its_plane)
{
    rk_error err;
    double Q[N * 2], Qt[2 * N], *u = malloc(sizeof(double) * N * T);
    const double rho = 0.99, theta = 9 * M_PI / 180;
    plane(Q);
    for (int i = 0; i < N; i++) Qt[2 * i] = Q[i], Qt[2 * i + 1] = Q[N + i];
    for (int t = 0; t < T; t++) {
        double a = pow(rho, t) * cos(theta * t), b = pow(rho, t) * sin(theta * t);
        for (int i = 0; i < N; i++) u[(size_t)N * t + i] = 0.01 * (a * Q[i] + b * Q[N + i]);
    }
    rk_koopman_trajectory traj = {u, T, NULL};
    rk_koopman_options o;
    rk_koopman_default_options(&o);
    o.h = 0.01;
    o.stabilize = -1;
    rk_koopman pod, known;
    memset(&pod, 0, sizeof pod);
    memset(&known, 0, sizeof known);
    CHECK_OK(rk_koopman_fit_pod(&traj, 1, N, 2, &o, &pod, &err));
    CHECK_OK(rk_koopman_fit_projected(&traj, 1, N, Qt, Q, 2, &o, &known, &err));
    printf("# POD fit: rank %d, max |lambda| %.12f; on the plane's basis: rank %d, %.12f\n", pod.r, max_modulus(&pod),
           known.r, max_modulus(&known));
    CHECK(pod.r == known.r, "ranks %d and %d", pod.r, known.r);
    CHECK(fabs(max_modulus(&pod) - rho) < 1e-8, "max |lambda| %.12f, the oscillation's %.2f", max_modulus(&pod), rho);
    CHECK(fabs(max_modulus(&pod) - max_modulus(&known)) < 1e-10, "the two fits differ: %.15f %.15f", max_modulus(&pod),
          max_modulus(&known));
    /* the eigenvalue with the largest modulus turns by theta a step */
    int top = 0;
    for (int j = 1; j < pod.r; j++)
        if (hypot(pod.lambda_re[j], pod.lambda_im[j]) > hypot(pod.lambda_re[top], pod.lambda_im[top])) top = j;
    CHECK(fabs(fabs(atan2(pod.lambda_im[top], pod.lambda_re[top])) - theta) < 1e-8, "angle %.12f, expected %.12f",
          fabs(atan2(pod.lambda_im[top], pod.lambda_re[top])), theta);
    rk_koopman_free(&pod);
    rk_koopman_free(&known);
    rk_koopman k;
    memset(&k, 0, sizeof k);
    rk_koopman_trajectory short_traj = {u, 3, NULL};
    CHECK(rk_koopman_fit_pod(&short_traj, 1, N, 5, &o, &k, &err) != 0 && strstr(err.msg, "at most 3 directions from 3 frames"),
          "too many directions: %s", err.msg);
    rk_koopman_free(&k);
    free(u);
}

int main(void)
{
    RUN(pod_fit_finds_the_oscillation_in_its_plane);
    return test_finish();
}
