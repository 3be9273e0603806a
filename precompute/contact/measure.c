/* A run's contact measures (contact.h): each frame measured by the exact crossing test and the
 * smallest surface distance (intersect.c), tallied over the frames. `romkit fom` and `romkit run`
 * report this one tally as contact.*, so the full-order run and the runtime are judged alike. */
#include "contact/contact.h"

#include <math.h>

void rk_contact_tally_init(rk_contact_tally *t)
{
    t->frames = t->intersections = t->intersecting_frames = 0;
    t->min_distance = INFINITY;
}

void rk_contact_tally_add(rk_contact_tally *t, int intersections, double min_distance)
{
    t->frames++;
    t->intersections += intersections;
    t->intersecting_frames += intersections > 0;
    /* fmin would drop a NaN; a frame that could not be measured must show */
    if (isnan(min_distance) || min_distance < t->min_distance) t->min_distance = min_distance;
}

int rk_contact_measure(rk_contact *c, const double *x, int *intersections, double *min_distance, rk_error *err)
{
    *min_distance = INFINITY;
    *intersections = rk_contact_intersections(c, x, err);
    if (*intersections < 0) return -1;
    *min_distance = rk_contact_min_distance(c, x, err);
    return isnan(*min_distance) ? -1 : 0;
}
