/* The contact.* keys of a report (contact_report.h). */
#include "contact_report.h"

void contact_tally_report(cJSON *obj, const rk_contact_tally *t)
{
    cJSON_AddNumberToObject(obj, "min_distance", t->min_distance);
    cJSON_AddNumberToObject(obj, "intersections", (double)t->intersections);
    cJSON_AddNumberToObject(obj, "intersecting_frames", (double)t->intersecting_frames);
    cJSON_AddNumberToObject(obj, "frames", (double)t->frames);
}
