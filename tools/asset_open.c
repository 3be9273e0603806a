/* tool_asset_open (asset_open.h): read, inflate, ask for the arena, open in place. */
#include "asset_open.h"

#include <stdlib.h>
#include <string.h>

#include "formats/rombin_write.h"

int tool_asset_open(tool_asset *a, const char *path, int koopman, romrt_error *rerr, rk_error *err)
{
    int inflated;
    memset(a, 0, sizeof *a);
    rerr->status = ROMRT_OK;
    if (rombin_read_file(path, &a->data, &a->bytes, err)) return -1;
    a->file_bytes = a->bytes;
    if (rombin_inflate_in_place(&a->data, &a->bytes, &inflated, err)) return -1;
    if ((koopman ? romrt_arena_size_kind(a->data, a->bytes, ROMRT_KIND_KOOPMAN, &a->arena_bytes, rerr)
                 : romrt_arena_size(a->data, a->bytes, &a->arena_bytes, rerr)) != ROMRT_OK)
        return rk_fail(err, "%s: %s: %s", path, romrt_status_string(rerr->status), rerr->message);
    a->arena = aligned_alloc(16, (a->arena_bytes + 15) / 16 * 16);
    if (!a->arena) return rk_fail(err, "out of memory for a %zu-byte arena", a->arena_bytes);
    if ((koopman ? romrt_open_kind(a->data, a->bytes, ROMRT_KIND_KOOPMAN, a->arena, a->arena_bytes, &a->m, rerr)
                 : romrt_open(a->data, a->bytes, a->arena, a->arena_bytes, &a->m, rerr)) != ROMRT_OK)
        return rk_fail(err, "%s: %s: %s", path, romrt_status_string(rerr->status), rerr->message);
    return 0;
}

void tool_asset_close(tool_asset *a)
{
    free(a->data);
    free(a->arena);
    memset(a, 0, sizeof *a);
}
