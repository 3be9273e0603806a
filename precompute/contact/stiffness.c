/* Adaptive barrier stiffness (contact.h; IPC supplement Sec. 3.3). */
#include "contact/contact.h"

#include <math.h>

/* kappa doubles while the closest pair keeps closing below this fraction of the bounding-box
 * diagonal: the barrier is losing against what pushes the surfaces together. */
#define KAPPA_GROW_BELOW 1e-9

void rk_contact_adapt_kappa(rk_contact *c, const double *ge, const double *gb, int n, double min_distance)
{
    if (c->opt.kappa > 0 || !isfinite(min_distance)) return; /* fixed, or no pair */
    if (!c->kappa_set) {
        /* the first contact: kappa that balances the barrier's push against the rest, along it */
        double num = 0, den = 0;
        for (int i = 0; i < n; i++) {
            num += ge[i] * gb[i];
            den += gb[i] * gb[i];
        }
        double k = den > 0 ? -c->kappa * num / den : c->kappa_min; /* gb is at the current kappa */
        c->kappa = fmin(fmax(k, c->kappa_min), c->kappa_max);
        c->kappa_set = 1;
    } else {
        double eps = KAPPA_GROW_BELOW * c->bbox_diagonal;
        if (min_distance < eps && c->min_distance_last < eps && min_distance < c->min_distance_last)
            c->kappa = fmin(2 * c->kappa, c->kappa_max);
    }
    c->min_distance_last = min_distance;
}

double rk_contact_holding_kappa(double dhat, double weight)
{
    double f1;
    rk_barrier_distance(0.5 * dhat, dhat, &f1, NULL);
    return 10 * weight / fabs(f1);
}
