/* Adam and the phased learning rate (neural.h). */
#include "neural/neural.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int rk_adam_init(rk_adam *a, long n, rk_error *err)
{
    memset(a, 0, sizeof *a);
    if (n < 1) return rk_fail(err, "adam: %ld parameters; need at least 1", n);
    a->m = rk_calloc((size_t)n, sizeof(double), err);
    a->v = rk_calloc((size_t)n, sizeof(double), err);
    if (!a->m || !a->v) {
        rk_adam_free(a);
        return -1;
    }
    a->n = n;
    a->beta1 = 0.9;
    a->beta2 = 0.999;
    a->eps = 1e-8;
    return 0;
}

void rk_adam_free(rk_adam *a)
{
    free(a->m);
    free(a->v);
    memset(a, 0, sizeof *a);
}

int rk_adam_step(rk_adam *a, double *params, const double *grad, double lr, rk_error *err)
{
    if (!(lr > 0) || !isfinite(lr)) return rk_fail(err, "adam: learning rate %g; must be finite and above 0", lr);
    /* checked before anything moves, so a failed step leaves params and moments as they were */
    for (long i = 0; i < a->n; i++)
        if (!isfinite(grad[i])) return rk_fail(err, "adam: gradient %ld is %g", i, grad[i]);
    a->step++;
    double c1 = 1.0 - pow(a->beta1, (double)a->step), c2 = 1.0 - pow(a->beta2, (double)a->step);
    for (long i = 0; i < a->n; i++) {
        double g = grad[i];
        a->m[i] = a->beta1 * a->m[i] + (1.0 - a->beta1) * g;
        a->v[i] = a->beta2 * a->v[i] + (1.0 - a->beta2) * g * g;
        params[i] -= lr * (a->m[i] / c1) / (sqrt(a->v[i] / c2) + a->eps);
    }
    return 0;
}

double rk_lr_phased(double base, int epoch, int epochs_total)
{
    static const double factor[4] = {5.0, 2.0, 1.0, 0.5};
    if (epochs_total < 1) return base * factor[3];
    long phase = 4L * epoch / epochs_total;
    if (phase < 0) phase = 0;
    if (phase > 3) phase = 3;
    return base * factor[phase];
}
