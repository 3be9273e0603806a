/* An asset file opened as the runtime opens it (tools/asset_open.c), for the commands that step
 * one (romkit run, romkit export). */
#ifndef ROMKIT_ASSET_OPEN_H
#define ROMKIT_ASSET_OPEN_H

#include <stddef.h>

#include "runtime/romrt.h"
#include "util/util.h"

typedef struct {
    unsigned char *data;        /* the asset in memory, deflated chunks inflated */
    size_t bytes, file_bytes;   /* its size, and its file's */
    void *arena;                /* the model's arena (16-byte aligned) */
    size_t arena_bytes;
    romrt_model *m;
} tool_asset;

/* Reads path and opens its reduced model, or with koopman its Koopman operator (romrt_open_kind).
 * -1 on failure: err says why (the runtime's refusals as "PATH: status: message"), and
 * rerr->status is the runtime's status (ROMRT_OK when the failure was not the runtime's). The
 * caller frees a with tool_asset_close, also after a failure. */
int tool_asset_open(tool_asset *a, const char *path, int koopman, romrt_error *rerr, rk_error *err);
void tool_asset_close(tool_asset *a);

#endif
