/* Shared by the scene-level physics tests: build a scene from JSON text and run it. */
#ifndef RK_TEST_SCENE_RUN_H
#define RK_TEST_SCENE_RUN_H

#include "testlib.h"
#include "fom/fom.h"
#include "pipeline/method_fixed.h"

int rk_fem_inverted(const rk_fem *f, const double *x, double *min_J);

typedef struct {
    rk_scene scene;
    rk_scene_sim sim;
    rk_fom fom;
    int ready;
} scene_run;

/* Parses and builds the scene and initialises the simulator. 0 on success. */
static inline int scene_run_open(scene_run *r, const char *json, rk_error *err)
{
    memset(r, 0, sizeof *r);
    if (rk_scene_parse(json, "test.json", &r->scene, err)) return -1;
    if (rk_scene_build(&r->scene, &r->sim, err)) {
        rk_scene_free(&r->scene);
        return -1;
    }
    if (rk_fom_init(&r->fom, &r->sim.fem, &r->sim.options, err)) {
        rk_scene_sim_free(&r->sim);
        rk_scene_free(&r->scene);
        return -1;
    }
    r->ready = 1;
    return 0;
}

static inline void scene_run_close(scene_run *r)
{
    if (!r->ready) return;
    rk_fom_free(&r->fom);
    rk_scene_sim_free(&r->sim);
    rk_scene_free(&r->scene);
    r->ready = 0;
}

/* All positions and velocities finite. */
static inline int scene_run_finite(const scene_run *r)
{
    for (int i = 0; i < 3 * r->sim.mesh.nv; i++)
        if (!isfinite(r->fom.x[i]) || !isfinite(r->fom.v[i])) return 0;
    return 1;
}

#endif
