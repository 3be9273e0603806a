/* precompute/pipeline: what family.c and family_keys.c share (not public: family.h is). */
#ifndef RK_PIPELINE_FAMILY_IMPL_H
#define RK_PIPELINE_FAMILY_IMPL_H

#include "pipeline/family.h"
#include "pipeline/parse_impl.h"

/* "shape.keys" (sh: the shape object at path p) into f->keys, each key resolved in f->shape_text
 * (a number there), its per_gamma g finite numbers and its value inside "range" over the members'
 * codes. Messages name the key and what is wrong with it. */
int rk_family_parse_keys(const rk_json_ctx *c, const cJSON *sh, const char *p, rk_family *f);
/* Sets each key of root (the shape scene's JSON) to its value at gamma. */
int rk_family_apply_keys(const rk_family *f, const double *gamma, cJSON *root, rk_error *err);

#endif
