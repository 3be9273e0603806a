/* Lifting, reading back, stepping and forcing a fitted Koopman operator (koopman.h). */
#include "koopman/koopman.h"

#include <cblas.h>
#include <math.h>
#include <stdlib.h>

void rk_koopman_lift(const rk_koopman *k, const double *u, const double *u_prev, double *z)
{
    int d = k->d, n2 = 2 * d;
    double *X = malloc(sizeof(double) * (size_t)n2);
    if (!X) return;
    for (int i = 0; i < d; i++) {
        X[i] = u[i];
        X[d + i] = u[i] - u_prev[i];
    }
    cblas_dgemv(CblasColMajor, CblasTrans, n2, k->r, 1.0, k->U, n2, X, 1, 0.0, z, 1);
    free(X);
}

void rk_koopman_positions(const rk_koopman *k, const double *z, double *u)
{
    cblas_dgemv(CblasColMajor, CblasNoTrans, k->d, k->r, 1.0, k->U, 2 * k->d, z, 1, 0.0, u, 1);
}

void rk_koopman_impulse(const rk_koopman *k, const double *a, double *z)
{
    double h2 = k->h * k->h;
    cblas_dgemv(CblasColMajor, CblasTrans, k->d, k->r, h2, k->U + k->d, 2 * k->d, a, 1, 1.0, z, 1);
}

/* lambda^p for a real eigenvalue: the principal branch's real part, exp(p log|l|) cos(p arg l),
 * which is (+-1)^p |l|^p for whole p and the Eq. 21 rescaling otherwise. */
static double real_power(double l, double p)
{
    double m = pow(fabs(l), p);
    return l >= 0 ? m : m * cos(M_PI * p);
}

void rk_koopman_advance(const rk_koopman *k, double *z, long long n, double dt_scale, double damping)
{
    int r = k->r;
    double *w = malloc(sizeof(double) * (size_t)r);
    if (!w) return;
    double p = (double)n * dt_scale, keep = 1 - damping;
    cblas_dgemv(CblasColMajor, CblasNoTrans, r, r, 1.0, k->Winv, r, z, 1, 0.0, w, 1);
    for (int j = 0; j < r; j++) {
        if (k->block[j] == 1) {
            w[j] *= real_power(k->lambda_re[j] * keep, p);
        } else if (k->block[j] == 2) {
            /* K' W = W B on the pair's columns (x, y): B = [[a, b], [-b, a]] = rho [[cos t, sin t],
             * [-sin t, cos t]], and B^p turns by p t. */
            double rho = hypot(k->lambda_re[j], k->lambda_im[j]) * keep;
            double t = atan2(k->lambda_im[j], k->lambda_re[j]) * p, m = pow(rho, p);
            double c = m * cos(t), s = m * sin(t), w0 = w[j], w1 = w[j + 1];
            w[j] = c * w0 + s * w1;
            w[j + 1] = -s * w0 + c * w1;
        }
    }
    cblas_dgemv(CblasColMajor, CblasNoTrans, r, r, 1.0, k->W, r, w, 1, 0.0, z, 1);
    free(w);
}
