/* JSON reports (pipeline.h): written atomically, numbers with full precision. */
#include "pipeline/pipeline.h"

#include <stdlib.h>
#include <string.h>

#include "util/util.h"

void rk_contact_tally_report(cJSON *obj, const rk_contact_tally *t)
{
    cJSON_AddNumberToObject(obj, "min_distance", t->min_distance);
    cJSON_AddNumberToObject(obj, "intersections", (double)t->intersections);
    cJSON_AddNumberToObject(obj, "intersecting_frames", (double)t->intersecting_frames);
    cJSON_AddNumberToObject(obj, "frames", (double)t->frames);
}

int rk_json_write_file(const char *path, const cJSON *root, rk_error *err)
{
    char *text = cJSON_Print(root);
    if (!text) return rk_fail(err, "%s: out of memory formatting the report", path);
    rk_atomic_file f;
    if (rk_atomic_open(&f, path, err)) {
        free(text);
        return -1;
    }
    fputs(text, f.fp);
    fputc('\n', f.fp);
    free(text);
    return rk_atomic_commit(&f, err);
}

cJSON *rk_json_array(const double *v, int n) { return cJSON_CreateDoubleArray(v, n); }
