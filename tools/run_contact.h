/* romkit run --scene SCENE.json: the runtime's frames measured for contact exactly as romkit fom
 * measures its own (precompute/contact's rk_contact_measure over the scene's collision surface and
 * obstacles), for the report's contact.* keys. */
#ifndef ROMKIT_RUN_CONTACT_H
#define ROMKIT_RUN_CONTACT_H

#include <stddef.h>
#include <stdint.h>

#include "contact/contact.h"
#include "run_scene.h"

typedef struct {
    const run_scene *S;
    rk_contact contact;
    int have_contact;
    double *x;             /* 3 nv of the scene mesh: at rest, its shown and collision vertices where the runtime has them */
    romrt_real *cxyz;      /* 3 S->ncollision: the runtime's collision vertices */
    rk_contact_tally tally;
} run_contact;

/* Whether the scene has contact to measure: obstacles, several objects or self-contact. */
int run_contact_wanted(const run_scene *S);
/* The scene's contact model; fails, saying why, when the scene has nothing to collide with or the
 * asset's shown and collision vertices leave out a vertex of the collision surface. */
int run_contact_open(run_contact *o, const run_scene *S, rk_error *err);
/* One frame of m: the shown positions xyz and m's collision vertices at time t (obstacles on their
 * paths to t), measured and tallied. */
int run_contact_frame(run_contact *o, const romrt_model *m, double t, const romrt_real *xyz, rk_error *err);
void run_contact_close(run_contact *o);

#endif
