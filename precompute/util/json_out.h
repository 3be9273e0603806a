/* JSON reports: written atomically, numbers with full precision. */
#ifndef RK_JSON_OUT_H
#define RK_JSON_OUT_H

#include <cjson/cJSON.h>

#include "util/error.h"

int rk_json_write_file(const char *path, const cJSON *root, rk_error *err);
/* cJSON array from n doubles. */
cJSON *rk_json_array(const double *v, int n);

#endif
