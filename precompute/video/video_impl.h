/* precompute/video's internals shared between its files (not part of video.h). */
#ifndef RK_VIDEO_IMPL_H
#define RK_VIDEO_IMPL_H

#include <cjson/cJSON.h>

#include "video/video.h"

/* A JSON file parsed (NULL and err set when unreadable or not JSON). tracks.c. */
cJSON *rk_video_json_load(const char *path, rk_error *err);
/* The cameras of a parsed {"views": [...]} object, and back (cameras.c): a tracks file carries them. */
int rk_cameras_from_json(const cJSON *root, rk_cameras *c, rk_error *err);
cJSON *rk_cameras_to_json(const rk_cameras *c);

#endif
