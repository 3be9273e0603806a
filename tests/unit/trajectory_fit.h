/* The acceleration of a trajectory sampled every h seconds: 2 c2 of the least-squares fit
 * c0 + c1 t + c2 t^2 to x[k] at t = (k - first) h, k = first .. last (the incline tests: under a
 * constant force backward Euler moves the centre of mass exactly quadratically in time). */
#ifndef RK_TEST_TRAJECTORY_FIT_H
#define RK_TEST_TRAJECTORY_FIT_H

static double fit_acceleration(const double *x, int first, int last, double h)
{
    double A[9] = {0}, b[3] = {0};
    for (int k = first; k <= last; k++) {
        double t = (k - first) * h, p[3] = {1, t, t * t};
        for (int i = 0; i < 3; i++) {
            b[i] += p[i] * x[k];
            for (int j = 0; j < 3; j++) A[3 * i + j] += p[i] * p[j];
        }
    }
    /* Cramer's rule on the 3 x 3 normal equations: c2 */
    double det = A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) + A[2] * (A[3] * A[7] - A[4] * A[6]);
    double det2 = A[0] * (A[4] * b[2] - b[1] * A[7]) - A[1] * (A[3] * b[2] - b[1] * A[6]) + b[0] * (A[3] * A[7] - A[4] * A[6]);
    return 2 * det2 / det;
}

#endif
