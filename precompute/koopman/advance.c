/* Lifting, reading back, stepping and forcing a fitted Koopman operator, and its real
 * eigen-coordinate form for the asset (koopman.h). */
#include "koopman/koopman.h"

#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* x (d observables) from v (n values): P_in v, or v itself. */
static void observe(const rk_koopman *k, const double *v, double *x)
{
    if (k->P_in)
        cblas_dgemv(CblasColMajor, CblasNoTrans, k->d, k->n, 1.0, k->P_in, k->d, v, 1, 0.0, x, 1);
    else
        memcpy(x, v, sizeof(double) * (size_t)k->d);
}

void rk_koopman_lift(const rk_koopman *k, const double *u, const double *u_prev, double *z)
{
    int d = k->d, n2 = 2 * d;
    double *X = malloc(sizeof(double) * (size_t)(n2 + d));
    if (!X) return;
    observe(k, u, X);
    observe(k, u_prev, X + n2);
    for (int i = 0; i < d; i++) X[d + i] = k->vscale * (X[i] - X[n2 + i]); /* the fit's scaled state */
    cblas_dgemv(CblasColMajor, CblasTrans, n2, k->r, 1.0, k->U, n2, X, 1, 0.0, z, 1);
    free(X);
}

/* n values from one block of U_r z: rows `row0` .. row0 + d - 1 (0: displacements, d: velocities),
 * times `scale`, through P_out when the fit was projected. */
static void read_block(const rk_koopman *k, const double *z, int row0, double scale, double *out)
{
    if (!k->P_out) {
        cblas_dgemv(CblasColMajor, CblasNoTrans, k->d, k->r, scale, k->U + row0, 2 * k->d, z, 1, 0.0, out, 1);
        return;
    }
    double *x = malloc(sizeof(double) * (size_t)k->d);
    if (!x) return;
    cblas_dgemv(CblasColMajor, CblasNoTrans, k->d, k->r, scale, k->U + row0, 2 * k->d, z, 1, 0.0, x, 1);
    cblas_dgemv(CblasColMajor, CblasNoTrans, k->n, k->d, 1.0, k->P_out, k->n, x, 1, 0.0, out, 1);
    free(x);
}

void rk_koopman_positions(const rk_koopman *k, const double *z, double *u) { read_block(k, z, 0, 1.0, u); }

void rk_koopman_velocities(const rk_koopman *k, const double *z, double *v)
{
    read_block(k, z, k->d, 1 / k->vscale, v); /* the fit scaled this block by beta */
}

void rk_koopman_impulse(const rk_koopman *k, const double *a, double *z)
{
    double h2 = k->h * k->h, *x = malloc(sizeof(double) * (size_t)k->d);
    if (!x) return;
    observe(k, a, x);
    /* Eq. 19 on the velocity rows; a displacement-only fit has none and takes it on u (koopman.h) */
    int row0 = k->displacement_only ? 0 : k->d;
    cblas_dgemv(CblasColMajor, CblasTrans, k->d, k->r, k->vscale * h2, k->U + row0, 2 * k->d, x, 1, 1.0, z, 1);
    free(x);
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

int rk_koopman_real_form(const rk_koopman *k, double *out, double *in, const double *u, const double *u_prev,
                         double *y0, rk_error *err)
{
    int d = k->d, n = k->n, r = k->r, n2 = 2 * d;
    double *UW = rk_calloc((size_t)n2 * r, sizeof(double), err); /* U_r W: z = W y, so X = U_r W y */
    double *VWi = rk_calloc((size_t)d * r, sizeof(double), err); /* velocity rows of U_r Winv^T */
    double *z = rk_calloc((size_t)r, sizeof(double), err);
    int rc = -1;
    if (!UW || !VWi || !z) goto done;
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n2, r, r, 1.0, k->U, n2, k->W, r, 0.0, UW, n2);
    if (k->P_out)
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n, r, d, 1.0, k->P_out, n, UW, n2, 0.0, out, n);
    else
        for (int j = 0; j < r; j++) memcpy(out + (size_t)n * j, UW + (size_t)n2 * j, sizeof(double) * d);
    /* in = beta Winv U_v^T P_in: (r x d) (d x n), beta the fit's velocity scale */
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, d, r, r, k->vscale, k->U + (k->displacement_only ? 0 : d), n2,
                k->Winv, r, 0.0, VWi, d);
    if (k->P_in)
        cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, r, n, d, 1.0, VWi, d, k->P_in, d, 0.0, in, r);
    else
        for (int j = 0; j < r; j++)
            for (int i = 0; i < d; i++) in[(size_t)r * i + j] = VWi[(size_t)d * j + i];
    if (u && u_prev && y0) {
        rk_koopman_lift(k, u, u_prev, z);
        cblas_dgemv(CblasColMajor, CblasNoTrans, r, r, 1.0, k->Winv, r, z, 1, 0.0, y0, 1);
    }
    rc = 0;
done:
    free(UW);
    free(VWi);
    free(z);
    return rc;
}

void rk_koopman_real_step(const rk_koopman *k, double *y)
{
    for (int j = 0; j < k->r; j++) {
        double a = k->lambda_re[j], b = k->lambda_im[j];
        if (k->block[j] == 1) {
            y[j] *= a;
        } else if (k->block[j] == 2) { /* the pair's block [[a, b], [-b, a]] (koopman.h) */
            double y0 = y[j], y1 = y[j + 1];
            y[j] = a * y0 + b * y1;
            y[j + 1] = -b * y0 + a * y1;
        }
    }
}

/* The rollout against t (rk_koopman_rollout_error); with X (3 n rest positions, n = k->n / 3)
 * each predicted frame also goes into e as positions beside the reference's. */
static int rollout(const rk_koopman *k, const rk_koopman_trajectory *t, const double *X, rk_run_error *e, double *pct,
                   double *peak, rk_error *err)
{
    int n = k->n, T = t->frames;
    double *z = rk_calloc((size_t)k->r, sizeof(double), err), *u = rk_calloc((size_t)n, sizeof(double), err);
    double *x = X ? rk_calloc((size_t)n, sizeof(double), err) : NULL, *xr = X ? rk_calloc((size_t)n, sizeof(double), err) : NULL;
    double se = 0, sr = 0, worst = 0, scale = 0;
    int rc = -1;
    if (!z || !u || (X && (!x || !xr))) goto done;
    rk_koopman_lift(k, t->u + n, t->u, z);
    for (int s = 2; s < T; s++) {
        if (rk_koopman_forced(k, 1, t->accel, z, err)) goto done;
        rk_koopman_positions(k, z, u);
        const double *ref = t->u + (size_t)n * s;
        double e2 = 0, r = 0;
        for (int i = 0; i < n; i++) e2 += (u[i] - ref[i]) * (u[i] - ref[i]), r += ref[i] * ref[i];
        se += e2, sr += r;
        worst = fmax(worst, sqrt(e2));
        scale = fmax(scale, sqrt(r));
        if (X) {
            for (int i = 0; i < n; i++) x[i] = X[i] + u[i], xr[i] = X[i] + ref[i];
            rk_run_error_add(e, x, xr);
        }
    }
    *pct = 100 * se / sr;
    *peak = worst / scale;
    rc = isfinite(*pct) && isfinite(*peak) ? 0 : rk_fail(err, "the rollout is not finite");
done:
    free(z);
    free(u);
    free(x);
    free(xr);
    return rc;
}

int rk_koopman_rollout_error(const rk_koopman *k, const rk_koopman_trajectory *t, double *pct, double *peak,
                             rk_error *err)
{
    return rollout(k, t, NULL, NULL, pct, peak, err);
}

int rk_koopman_rollout_run_error(const rk_koopman *k, const rk_koopman_trajectory *t, const double *X, rk_run_error *e,
                                 double *pct, double *peak, rk_error *err)
{
    if (k->n % 3) return rk_fail(err, "a rollout's run error needs positions: %d values a frame", k->n);
    rk_run_error_init(e, X, k->n / 3);
    return rollout(k, t, X, e, pct, peak, err);
}
