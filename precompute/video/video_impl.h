/* precompute/video's internals shared between its files (not part of video.h). */
#ifndef RK_VIDEO_IMPL_H
#define RK_VIDEO_IMPL_H

#include <cjson/cJSON.h>

#include "video/video.h"

/* A JSON file parsed (NULL and err set when unreadable or not JSON). tracks.c. */
cJSON *rk_video_json_load(const char *path, rk_error *err);

#endif
