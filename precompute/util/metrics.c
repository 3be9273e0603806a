/* The error metrics of metrics.h, each defined once. */
#include "util/util.h"

#include <math.h>

void rk_run_error_init(rk_run_error *e, const double *X, int n)
{
    *e = (rk_run_error){.n = n, .X = X, .L = rk_points_diagonal(X, n)};
}

void rk_run_error_add(rk_run_error *e, const double *x, const double *ref)
{
    double frame_sq = 0, frame_ref_sq = 0;
    for (int v = 0; v < e->n; v++) {
        double d2 = 0, u2 = 0;
        for (int i = 0; i < 3; i++) {
            double d = x[3 * v + i] - ref[3 * v + i], u = ref[3 * v + i] - e->X[3 * v + i];
            d2 += d * d;
            u2 += u * u;
        }
        frame_sq += d2;
        frame_ref_sq += u2;
        e->max_dist = fmax(e->max_dist, sqrt(d2));
    }
    e->sum_sq += frame_sq;
    e->sum_ref_sq += frame_ref_sq;
    e->online_num += sqrt(frame_sq);
    e->online_den += sqrt(frame_ref_sq);
    e->frames++;
}

double rk_frame_error(const double *a, const double *b, int n)
{
    double sq = 0;
    for (int v = 0; v < n; v++) {
        double d2 = 0;
        for (int i = 0; i < 3; i++) {
            double d = a[3 * v + i] - (b ? b[3 * v + i] : 0);
            d2 += d * d;
        }
        sq += d2;
    }
    return sqrt(sq);
}

double rk_normalized_mse(const rk_run_error *e)
{
    return e->frames && e->n && e->L > 0 ? e->sum_sq / ((double)e->frames * e->n) / (e->L * e->L) : NAN;
}

double rk_normalized_max_error(const rk_run_error *e)
{
    return e->frames && e->L > 0 ? e->max_dist / e->L : NAN;
}

double rk_relative_error(const rk_run_error *e)
{
    return e->sum_ref_sq > 0 ? sqrt(e->sum_sq / e->sum_ref_sq) : NAN;
}

double rk_relative_online_error(const rk_run_error *e)
{
    return e->online_den > 0 ? e->online_num / e->online_den : NAN;
}

double rk_points_diagonal(const double *X, int n)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int v = 0; v < n; v++)
        for (int i = 0; i < 3; i++) {
            lo[i] = fmin(lo[i], X[3 * v + i]);
            hi[i] = fmax(hi[i], X[3 * v + i]);
        }
    return n ? sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                    (hi[2] - lo[2]) * (hi[2] - lo[2]))
             : 0;
}

double rk_max_abs_eigenvalue(const double *re, const double *im, int n)
{
    double top = 0;
    for (int i = 0; i < n; i++) top = fmax(top, hypot(re[i], im[i]));
    return top;
}
