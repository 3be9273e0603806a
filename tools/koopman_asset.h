/* Shared by romkit build (a scene's rom.koopman) and romkit dmd (outside snapshots): bake a
 * Koopman operator into an asset, save it, and report it. */
#ifndef ROMKIT_KOOPMAN_ASSET_H
#define ROMKIT_KOOPMAN_ASSET_H

#include <cjson/cJSON.h>

#include "asset/asset.h"

/* The report's "koopman" object: rank, max_abs_eigenvalue, eigenvalues ([[re, im], ...],
 * discrete-time), residuals (per eigenvalue: how far the data is from following the mode),
 * clamped, singular_values, h. */
cJSON *koopman_report(const rk_koopman *k);

/* Bakes k over g into `out` (atomically). With report_out, writes `report` (the caller's keys)
 * with "koopman" and "asset" added. Prints a one-line summary. 0 or -1 with err set. */
int koopman_asset_write(const rk_koopman *k, rk_koopman_geometry *g, const rk_asset_options *ao, const char *info,
                        const char *out, const char *report_out, cJSON *report, rk_error *err);

/* "--precision float32|float64" and "--compress" over the asset options; -1 on a bad value. */
int asset_flags(const char *cmd, const char *precision, int compress, rk_asset_options *ao);

#endif
