/* Where a full-order step's time goes (fom.h, rk_fom_stats and rk_fom_iterations): each Newton
 * iteration's seconds beside its numeric factorization's, so that the cost of an iteration can be
 * set against the factorization alone (issue 16). */
#include "fom/fom_impl.h"

#include <stdlib.h>

#include "util/util.h"

void rk_fom_iteration_start(rk_fom_impl *im, double t0)
{
    if (im->iter_open) rk_fom_iteration_end(im);
    if (im->niter == im->capiter) {
        long cap = im->capiter ? 2 * im->capiter : 256;
        double *a = realloc(im->iter_seconds, sizeof(double) * (size_t)cap);
        if (a) im->iter_seconds = a;
        double *b = a ? realloc(im->iter_factor, sizeof(double) * (size_t)cap) : NULL;
        if (b) im->iter_factor = b;
        if (!a || !b) return; /* timing only: the run goes on unrecorded */
        im->capiter = cap;
    }
    im->iter_open = 1;
    im->iter_start = t0;
    im->iter_seconds[im->niter] = 0;
    im->iter_factor[im->niter] = 0;
}

void rk_fom_iteration_factor(rk_fom_impl *im, double seconds)
{
    if (im->iter_open) im->iter_factor[im->niter] += seconds;
}

void rk_fom_iteration_end(rk_fom_impl *im)
{
    if (!im->iter_open) return;
    im->iter_seconds[im->niter++] = rk_now() - im->iter_start;
    im->iter_open = 0;
}

void rk_fom_sync_stats(rk_fom *s)
{
    rk_fom_impl *im = s->impl;
    if (im->analyses == 1 && s->stats.analyses == 0) im->seconds_analyze_init = im->seconds_analyze; /* init's */
    s->stats.analyses = im->analyses;
    s->stats.seconds_analyze_init = im->seconds_analyze_init;
    s->stats.seconds_analyze = im->seconds_analyze - im->seconds_analyze_init;
}

long rk_fom_iterations(const rk_fom *s, const double **seconds, const double **factor_seconds)
{
    if (seconds) *seconds = s->impl->iter_seconds;
    if (factor_seconds) *factor_seconds = s->impl->iter_factor;
    return s->impl->niter;
}
