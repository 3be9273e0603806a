/* L-BFGS (Nocedal & Wright, Algorithm 7.4 and 7.5) with a backtracking Armijo line search: the
 * full-batch polish after Adam, where a deterministic loss with an exact gradient lets a
 * quasi-Newton method go far below where Adam's noisy, rate-limited steps stop (neural.h). */
#include "neural/neural.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double dot(long n, const double *a, const double *b)
{
    double s = 0;
    for (long i = 0; i < n; i++) s += a[i] * b[i];
    return s;
}

int rk_lbfgs_minimize(long n, double *x, rk_objective f, void *ctx, const rk_lbfgs_options *o, rk_lbfgs_report *rep,
                      rk_error *err)
{
    rk_lbfgs_options def = {.iterations = 100, .memory = 10, .tolerance = 0};
    if (!o) o = &def;
    if (n < 1 || o->iterations < 0 || o->memory < 1 || !(o->tolerance >= 0))
        return rk_fail(err, "l-bfgs: bad options (%ld unknowns, %d iterations, memory %d, tolerance %g)", n,
                       o->iterations, o->memory, o->tolerance);
    int M = o->memory, rc = -1, stored = 0, head = 0;
    double *g = rk_calloc((size_t)n, sizeof(double), err), *d = rk_calloc((size_t)n, sizeof(double), err);
    double *xn = rk_calloc((size_t)n, sizeof(double), err), *gn = rk_calloc((size_t)n, sizeof(double), err);
    double *S = rk_calloc((size_t)n * M, sizeof(double), err), *Y = rk_calloc((size_t)n * M, sizeof(double), err);
    double *rho = rk_calloc((size_t)M, sizeof(double), err), *alpha = rk_calloc((size_t)M, sizeof(double), err);
    rk_lbfgs_report r = {0};
    double fx;
    if (!g || !d || !xn || !gn || !S || !Y || !rho || !alpha) goto out;
    if (f(ctx, x, &fx, g, err)) goto out;
    if (!isfinite(fx)) {
        rk_fail(err, "l-bfgs: the objective is %g at the start", fx);
        goto out;
    }
    r.initial = fx;
    for (int it = 0; it < o->iterations; it++) {
        double gnorm = sqrt(dot(n, g, g));
        if (gnorm <= o->tolerance) break;
        /* d = -H g by the two-loop recursion over the stored pairs, newest first */
        for (long i = 0; i < n; i++) d[i] = -g[i];
        for (int k = 0; k < stored; k++) {
            int j = (head - 1 - k + M) % M;
            alpha[j] = rho[j] * dot(n, S + (size_t)n * j, d);
            for (long i = 0; i < n; i++) d[i] -= alpha[j] * Y[(size_t)n * j + i];
        }
        if (stored) { /* H0 = (s'y / y'y) I of the newest pair */
            int j = (head - 1 + M) % M;
            double gamma = dot(n, S + (size_t)n * j, Y + (size_t)n * j) / dot(n, Y + (size_t)n * j, Y + (size_t)n * j);
            for (long i = 0; i < n; i++) d[i] *= gamma;
        } else { /* the first step: a gradient step of unit length, which the line search may shorten */
            for (long i = 0; i < n; i++) d[i] /= gnorm;
        }
        for (int k = stored - 1; k >= 0; k--) {
            int j = (head - 1 - k + M) % M;
            double beta = rho[j] * dot(n, Y + (size_t)n * j, d);
            for (long i = 0; i < n; i++) d[i] += (alpha[j] - beta) * S[(size_t)n * j + i];
        }
        double slope = dot(n, g, d);
        if (!(slope < 0)) { /* not a descent direction (round-off in the pairs): start over from the gradient */
            stored = 0;
            for (long i = 0; i < n; i++) d[i] = -g[i] / gnorm;
            slope = -gnorm;
        }
        /* Armijo backtracking from the full step */
        double t = 1, fn = INFINITY;
        int accepted = 0;
        for (int ls = 0; ls < 40; ls++, t *= 0.5) {
            for (long i = 0; i < n; i++) xn[i] = x[i] + t * d[i];
            if (f(ctx, xn, &fn, gn, err)) goto out;
            r.evaluations++;
            if (isfinite(fn) && fn <= fx + 1e-4 * t * slope) {
                accepted = 1;
                break;
            }
        }
        if (!accepted) break; /* no decrease along d: as far as round-off lets it go */
        double *s = S + (size_t)n * head, *y = Y + (size_t)n * head;
        for (long i = 0; i < n; i++) {
            s[i] = xn[i] - x[i];
            y[i] = gn[i] - g[i];
        }
        double sy = dot(n, s, y);
        if (sy > 1e-300) { /* curvature condition: keep the pair only where it holds */
            rho[head] = 1 / sy;
            head = (head + 1) % M;
            if (stored < M) stored++;
        }
        memcpy(x, xn, sizeof(double) * n);
        memcpy(g, gn, sizeof(double) * n);
        fx = fn;
        r.iterations++;
    }
    r.final = fx;
    if (rep) *rep = r;
    rc = 0;
out:
    free(g);
    free(d);
    free(xn);
    free(gn);
    free(S);
    free(Y);
    free(rho);
    free(alpha);
    return rc;
}
