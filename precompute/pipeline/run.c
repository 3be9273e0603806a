/* Full-order runs of a built scene (pipeline.h): one loop for romkit fom, the comparisons, and the
 * training frames of bases, cubature and Koopman fits. */
#include "pipeline/pipeline.h"

#include <stdlib.h>
#include <string.h>

#include "util/util.h"

int rk_scene_fom_run(const rk_scene_sim *sim, const rk_fom_options *opt, const char *label, rk_frame_fn frame,
                     void *ctx, rk_fom_stats *stats, rk_error *err)
{
    rk_fom fom;
    if (sim->cloud_points > 0)
        return rk_fail(err, "%s: a point cloud runs at full order on its body (romkit fom and romkit compare: "
                       "rk_scene_build_full_order), but nothing trains on that run yet (a data-driven basis, "
                       "cubature or Koopman fit of a scene with a point cloud); a mesh-free rom entry simulates the "
                       "cloud", label);
    if (rk_fom_init(&fom, &sim->fem, opt ? opt : &sim->options, err)) return rk_error_prefix(err, "%s", label);
    int steps = fom.opt.is_static ? 1 : sim->steps;
    int rc = frame ? frame(ctx, 0, &fom, 0, err) : 0;
    for (int s = 0; !rc && s < steps; s++) {
        double t0 = rk_now();
        rc = fom.opt.is_static ? rk_fom_static(&fom, err) : rk_fom_step(&fom, err);
        if (!rc && frame) rc = frame(ctx, s + 1, &fom, rk_now() - t0, err);
        rk_progress(label, s + 1, steps);
    }
    rk_progress_done(label);
    if (stats) *stats = fom.stats;
    rk_fom_free(&fom);
    return rc ? rk_error_prefix(err, "%s", label) : 0;
}

typedef struct {
    const rk_scene_sim *sim;
    double *D;
} training;

static int keep_displacement(void *ctx, int step, rk_fom *fom, double seconds, rk_error *err)
{
    const training *t = ctx;
    int n3 = 3 * t->sim->mesh.nv;
    if (step > 0)
        for (int i = 0; i < n3; i++) t->D[(size_t)(step - 1) * n3 + i] = fom->x[i] - t->sim->mesh.X[i];
    return 0;
}

int rk_scene_training_frames(const rk_scene_sim *sim, double **D, int *T, rk_error *err)
{
    int steps = sim->options.is_static ? 1 : sim->steps;
    training t = {sim, rk_calloc((size_t)3 * sim->mesh.nv * (steps > 0 ? steps : 1), sizeof(double), err)};
    if (!t.D) return -1;
    if (rk_scene_fom_run(sim, NULL, "full-order training run", keep_displacement, &t, NULL, err)) {
        free(t.D);
        return -1;
    }
    *D = t.D;
    *T = steps;
    return 0;
}
