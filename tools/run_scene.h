/* romkit run --scene SCENE.json: the scene the asset was built from, built again, and which scene
 * vertex each of the asset's shown vertices is (VMAP), for the measures that need the scene
 * (run_contact.h: contact; run_stress.h: stresses from its materials). */
#ifndef ROMKIT_RUN_SCENE_H
#define ROMKIT_RUN_SCENE_H

#include <stddef.h>
#include <stdint.h>

#include "pipeline/pipeline.h"
#include "runtime/romrt.h"

typedef struct {
    const char *path;
    rk_scene scene;
    rk_scene_sim sim;
    int have_scene, have_sim;
    int shown;
    uint32_t *source;      /* shown vertex -> scene mesh vertex (the asset's VMAP); from the mesh's
                            * vertex count on, a caged object's embedded surface vertex (mesh.cage:
                            * source - nv into sim.embedded) */
    int ncollision;        /* the asset's collision vertices (CVTX), when VMAP names their scene vertices */
    uint32_t *collision_source; /* collision vertex (CVTX order) -> scene mesh vertex, or NULL */
} run_scene;

/* Builds the scene; fails, saying why, when the asset has no VMAP or its shown vertices are not the
 * scene's (another scene, or moved). */
int run_scene_open(run_scene *o, const char *scene_path, const unsigned char *asset, size_t bytes, const romrt_model *m,
                   rk_error *err);
/* Where shown vertex i is when the scene's mesh vertices are at x (3 nv): x's own, or for an embedded
 * surface vertex its rest position plus its cage tet's displacement at its barycentric coordinates. */
void run_scene_shown_at(const run_scene *o, const double *x, int i, double out[3]);
/* The object scene vertex v belongs to. */
int run_scene_object_of(const run_scene *o, int v);
void run_scene_close(run_scene *o);

#endif
