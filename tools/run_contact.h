/* romkit run --scene SCENE.json: the runtime's frames measured for contact exactly as romkit fom
 * measures its own (precompute/contact's rk_contact_measure over the scene's collision surface and
 * obstacles), for the report's contact.* keys. */
#ifndef ROMKIT_RUN_CONTACT_H
#define ROMKIT_RUN_CONTACT_H

#include <stddef.h>
#include <stdint.h>

#include "contact/contact.h"
#include "pipeline/pipeline.h"
#include "runtime/romrt.h"

typedef struct {
    rk_scene scene;
    rk_scene_sim sim;
    rk_contact contact;
    int have_scene, have_sim, have_contact;
    int shown;
    uint32_t *source;      /* shown vertex -> scene mesh vertex (the asset's VMAP) */
    double *x;             /* 3 nv of the scene mesh: at rest, its shown vertices where the runtime has them */
    rk_contact_tally tally;
} run_contact;

/* Builds the scene the asset was baked from and its contact model; fails, saying why, when the
 * scene has nothing to collide with, when the asset has no VMAP, when the asset's shown vertices
 * are not the scene's (another scene, or moved) or leave out a vertex of the collision surface. */
int run_contact_open(run_contact *o, const char *scene_path, const unsigned char *asset, size_t bytes,
                     const romrt_model *m, rk_error *err);
/* One frame: the shown positions xyz at time t (obstacles on their paths to t), measured and
 * tallied. */
int run_contact_frame(run_contact *o, double t, const romrt_real *xyz, rk_error *err);
void run_contact_close(run_contact *o);

#endif
