/* The contact.* keys of a report (romkit fom, romkit run): one tally (precompute/contact's
 * rk_contact_tally), one wording, whichever simulator ran. */
#ifndef ROMKIT_CONTACT_REPORT_H
#define ROMKIT_CONTACT_REPORT_H

#include <cjson/cJSON.h>

#include "contact/contact.h"

/* min_distance (m; null when nothing could touch), intersections (exact crossings summed over the
 * frames), intersecting_frames, frames: added to obj. */
void contact_tally_report(cJSON *obj, const rk_contact_tally *t);

#endif
