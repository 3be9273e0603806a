/* An adaptive linear ROM entry into an asset (pipeline.h, rk_scene_bake_alrom): the decoder (a
 * quadratic one's parts, or a trained CROM's networks), the cubature the runtime integrates every
 * step's basis with (trained for the moving basis as rk_scene_alrom_cubature trains it for romkit
 * compare, or every element), a reduced model on the decoder's linear part (a CROM's Jacobian at p = 0) for the
 * chunks a reduced model has (its pin penalty left out: the runtime moves the prescribed vertices
 * itself), and the adaptive chunks beside them. */
#include "pipeline/method_adaptive_linear.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* the entry's own options (the caller checked its method) */
#define AL(e) rk_adaptive_linear_of(e)

/* The vertices the cubature's elements touch: the rows the runtime forms each step. */
static int cubature_vertices(const rk_scene_sim *sim, const rk_rom_model *model)
{
    unsigned char *seen = calloc((size_t)sim->mesh.nv + 1, 1);
    int count = 0;
    for (int k = 0; seen && k < model->quad.count; k++)
        for (int a = 0; a < 4; a++) {
            int v = sim->fem.tets[4 * model->quad.source[k] + a];
            count += !seen[v];
            seen[v] = 1;
        }
    free(seen);
    return seen ? count : -1;
}

static void report(rk_baked *out, const rk_scene_sim *sim, const rk_rom_entry *e, const rk_rom_model *model,
                   const rk_moving_fit *fit, const rk_asset_summary *sum, double seconds)
{
    cJSON *b = cJSON_AddObjectToObject(out->report, "basis");
    cJSON_AddStringToObject(b, "type", AL(e)->crom ? "crom" : AL(e)->quadratic_pod ? "quadratic_pod" : "quadratic_manifold");
    cJSON_AddNumberToObject(b, "size", model->r);
    cJSON_AddNumberToObject(b, "columns", model->r);
    cJSON *c = cJSON_AddObjectToObject(out->report, "cubature");
    cJSON_AddNumberToObject(c, "elements", model->quad.count);
    cJSON_AddNumberToObject(c, "vertices", cubature_vertices(sim, model));
    if (e->cubature) { /* trained for the moving basis (rk_scene_alrom_cubature) */
        cJSON_AddNumberToObject(c, "poses", fit->poses);
        cJSON_AddNumberToObject(c, "relative_error", fit->train_error);
        cJSON_AddNumberToObject(c, "heldout_poses", fit->heldout_poses);
        if (isfinite(fit->heldout_error)) cJSON_AddNumberToObject(c, "heldout_error", fit->heldout_error);
    }
    cJSON *a = cJSON_AddObjectToObject(out->report, "adaptive_linear");
    cJSON_AddNumberToObject(a, "history", AL(e)->opt.history);
    cJSON_AddNumberToObject(a, "lambda", AL(e)->opt.lambda);
    cJSON_AddNumberToObject(a, "cadence", AL(e)->opt.cadence);
    cJSON_AddNumberToObject(a, "encoder_iterations", AL(e)->opt.encoder_iterations);
    cJSON_AddStringToObject(a, "decoder", AL(e)->crom ? "crom" : AL(e)->quadratic_pod ? "quadratic_pod" : "quadratic");
    rk_asset_report(cJSON_AddObjectToObject(out->report, "asset"), out->data, out->bytes, sum);
    cJSON_AddNumberToObject(out->report, "vertices", sim->mesh.nv);
    cJSON_AddNumberToObject(out->report, "tets", sim->mesh.nt);
    cJSON_AddNumberToObject(cJSON_AddObjectToObject(out->report, "seconds"), "total", seconds);
    snprintf(out->summary, sizeof out->summary, "%s (adaptive linear ROM, %s decoder), r = %d, history %d, "
             "lambda %g, %d cubature elements, %d of %d vertices stored (%d shown), %zu bytes", e->name,
             AL(e)->crom ? "CROM" : AL(e)->quadratic_pod ? "fitted quadratic" : "quadratic", model->r,
             AL(e)->opt.history, AL(e)->opt.lambda, model->quad.count, sum->vertices, sim->mesh.nv, sum->shown, out->bytes);
    /* the adaptive model's runtime state (history, encoder) starts at rest: VEL0 is the fixed-basis
     * models' only, so a thrown object is said, not silently dropped */
    for (int i = 0; sim->options.velocity0 && i < 3 * sim->mesh.nv; i++)
        if (sim->options.velocity0[i] != 0) {
            snprintf(out->summary + strlen(out->summary), sizeof out->summary - strlen(out->summary),
                     "\n  warning: the initial velocities are not baked for the adaptive linear ROM: the runtime "
                     "starts it at rest");
            break;
        }
}

int rk_scene_bake_alrom(const rk_scene *scene, const rk_rom_entry *e, const rk_asset_options *ao,
                        const char *const *training_runs, int n, rk_baked *out, rk_error *err)
{
    if (!AL(e)) return rk_fail(err, "%s is not method adaptive_linear", e->path);
    if (n && n != e->ntraining)
        return rk_fail(err, "%d training run files given for %s's %d training runs", n, e->path, e->ntraining);
    double t0 = rk_now();
    rk_scene_sim sim;
    if (rk_scene_build(scene, &sim, err)) return -1;
    double *D = NULL, *Phi = NULL, *Psi = NULL, *cub_weight = NULL;
    int *cub_element = NULL, ncub = 0, T = 0, r = e->basis.size, rc = -1, have_model = 0;
    rk_rom_model model;
    rk_quadrature quad = {0};
    rk_decoder dec = {0};
    rk_crom_parts crom;
    rk_moving_fit fit = {0};
    if (sim.options.is_static) {
        rk_fail(err, "%s: an adaptive linear ROM steps dynamics; the scene asks for a static solve", e->path);
        goto out;
    }
    if ((e->cubature || AL(e)->quadratic_pod || AL(e)->crom) && (e->ntraining ? rk_scene_training_set_from(scene, &sim, e, n ? training_runs : NULL, &D, &T, err)
                                                           : rk_scene_training_frames(&sim, &D, &T, err)))
        goto out;
    /* the decoder first: the cubature trains on its bases at the frames */
    if (((e->cubature || AL(e)->crom) && rk_scene_alrom_decoder(scene, &sim, e, D, T, &dec, err)) ||
        rk_scene_alrom_cubature(&sim, e, &dec, D, T, &cub_element, &cub_weight, &ncub, &fit, err))
        goto out;
    if (AL(e)->crom) { /* the trained CROM; its Jacobian at p = 0 stands as the model's rows */
        size_t nr = (size_t)3 * sim.mesh.nv * r;
        double *p0 = NULL;
        int bad = rk_crom_parts_of(&dec, &crom) || !(p0 = rk_calloc((size_t)r, sizeof(double), err)) ||
                  !(Phi = rk_calloc(nr, sizeof(double), err)) || dec.jacobian(dec.ctx, p0, Phi, err);
        free(p0);
        if (bad) goto out;
    } else if (rk_scene_quadratic_parts(&sim, e, D, T, &Phi, &Psi, err)) {
        rk_error_prefix(err, "%s: the decoder", e->path);
        goto out;
    }
    if (rk_quadrature_elements(&sim.fem, Phi, r, ncub ? ncub : sim.mesh.nt, ncub ? cub_element : NULL,
                               ncub ? cub_weight : NULL, &quad, err) ||
        rk_rom_model_init(&model, &sim.fem, &sim.options, Phi, r, &quad, NULL, err)) {
        rk_error_prefix(err, "%s: the reduced model on the decoder's linear part", e->path);
        goto out;
    }
    have_model = 1;
    rk_asset_alrom A = {AL(e)->opt.history, AL(e)->opt.lambda, AL(e)->opt.reg, AL(e)->opt.ridge, AL(e)->opt.budget, Psi, AL(e)->crom ? &crom : NULL, &sim.options,
                         AL(e)->opt.cadence, AL(e)->opt.encoder_iterations};
    rk_asset_rom R = {&sim.mesh, &sim.fem, Phi, &model, 0, NULL, 0, NULL, NULL, &A, NULL, NULL, NULL};
    rk_asset_summary sum = {0};
    rombin_writer w;
    rombin_writer_init(&w, ao->real_type, ao->compress);
    const char *slash = strrchr(scene->path, '/');
    cJSON *ij = cJSON_CreateObject();
    cJSON_AddStringToObject(ij, "scene", slash ? slash + 1 : scene->path);
    cJSON_AddStringToObject(ij, "method", e->name);
    cJSON_AddStringToObject(ij, "basis", AL(e)->crom ? "crom" : AL(e)->quadratic_pod ? "quadratic_pod" : "quadratic_manifold");
    cJSON_AddNumberToObject(ij, "columns", r);
    cJSON_AddNumberToObject(ij, "cubature_elements", model.quad.count);
    char *info = cJSON_PrintUnformatted(ij);
    cJSON_Delete(ij);
    rc = rk_asset_bake(&R, NULL, NULL, ao, info, &w, &sum, err) || rombin_serialize(&w, &out->data, &out->bytes, err)
             ? -1 : 0;
    rombin_writer_free(&w);
    free(info);
    if (!rc) {
        out->report = cJSON_CreateObject();
        report(out, &sim, e, &model, &fit, &sum, rk_now() - t0);
    } else {
        rk_error_prefix(err, "%s", e->path);
    }
out:
    if (have_model) rk_rom_model_free(&model);
    rk_decoder_free(&dec);
    free(D);
    free(Phi);
    free(Psi);
    free(cub_element);
    free(cub_weight);
    rk_scene_sim_free(&sim);
    return rc;
}
