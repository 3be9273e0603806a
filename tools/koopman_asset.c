/* Koopman assets for romkit build and romkit dmd (koopman_asset.h). */
#include "koopman_asset.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/json_out.h"
#include "util/metrics.h"

cJSON *koopman_report(const rk_koopman *k)
{
    cJSON *j = cJSON_CreateObject(), *eig = cJSON_CreateArray();
    for (int i = 0; i < k->r; i++) {
        double pair[2] = {k->lambda_re[i], k->lambda_im[i]};
        cJSON_AddItemToArray(eig, rk_json_array(pair, 2));
    }
    cJSON_AddNumberToObject(j, "rank", k->r);
    cJSON_AddNumberToObject(j, "max_abs_eigenvalue", rk_max_abs_eigenvalue(k->lambda_re, k->lambda_im, k->r));
    cJSON_AddItemToObject(j, "eigenvalues", eig);
    cJSON_AddItemToObject(j, "residuals", rk_json_array(k->residual, k->r));
    cJSON_AddNumberToObject(j, "clamped", k->clamped);
    cJSON_AddItemToObject(j, "singular_values", rk_json_array(k->singular, k->nsingular < 200 ? k->nsingular : 200));
    cJSON_AddNumberToObject(j, "observables", k->d);
    cJSON_AddNumberToObject(j, "h", k->h);
    return j;
}

int asset_flags(const char *cmd, const char *precision, int compress, rk_asset_options *ao)
{
    if (precision) {
        if (strcmp(precision, "float32") == 0) ao->real_type = ROMBIN_REAL_F32;
        else if (strcmp(precision, "float64") == 0) ao->real_type = ROMBIN_REAL_F64;
        else {
            fprintf(stderr, "romkit %s: --precision must be float32 or float64, got '%s'\n", cmd, precision);
            return -1;
        }
    }
    if (compress) ao->compress = 1;
    return 0;
}

int koopman_asset_write(const rk_koopman *k, rk_koopman_geometry *g, const rk_asset_options *ao, const char *info,
                        const char *out, const char *report_out, cJSON *report, rk_error *err)
{
    rombin_writer w;
    rk_asset_summary sum;
    unsigned char *data = NULL;
    size_t bytes = 0;
    int rc = -1;
    rombin_writer_init(&w, ao->real_type, ao->compress);
    if (!rk_asset_bake_koopman(k, g, ao, info, &w, &sum, err) && !rombin_serialize(&w, &data, &bytes, err) &&
        !rombin_save(out, data, bytes, err))
        rc = 0;
    rombin_writer_free(&w);
    if (!rc && report_out) {
        cJSON_AddItemToObject(report, "koopman", koopman_report(k));
        cJSON *a = cJSON_AddObjectToObject(report, "asset");
        cJSON_AddNumberToObject(a, "bytes", (double)bytes);
        cJSON_AddNumberToObject(a, "stored_vertices", sum.vertices);
        cJSON_AddNumberToObject(a, "shown_vertices", sum.shown);
        cJSON_AddNumberToObject(a, "triangles", sum.triangles);
        cJSON_AddNumberToObject(a, "groups", sum.groups);
        cJSON_AddStringToObject(a, "precision", ao->real_type == ROMBIN_REAL_F32 ? "float32" : "float64");
        rc = rk_json_write_file(report_out, report, err);
    }
    if (!rc) {
        double top = rk_max_abs_eigenvalue(k->lambda_re, k->lambda_im, k->r);
        printf("%s: Koopman operator, rank %d over %d observables, max |lambda| %.9f%s, %d of %d vertices stored "
               "(%d shown), %zu bytes\n",
               out, k->r, k->d, top, k->clamped ? " (clamped)" : "", sum.vertices, g->nv, sum.shown, bytes);
    }
    free(data);
    return rc;
}
