/* The asset options' defaults (asset.h); the scene's rom.asset keys are read by the pipeline. */
#include "asset/asset.h"

#include <string.h>

void rk_asset_default_options(rk_asset_options *o)
{
    memset(o, 0, sizeof *o);
    o->real_type = ROMBIN_REAL_F32;
    o->show = RK_SHOW_SURFACE;
    o->colliders = RK_COLLIDERS_SURFACE;
}
