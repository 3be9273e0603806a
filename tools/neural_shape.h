/* romkit neural-dmd --objective (koopman-dmd-log-linear paper, Sec. 7.4): the shape code for which
 * one value of a vertex's position after N steps from rest reaches a target, through the trained
 * model's closed-form jump (rk_koopman_shape_optimize), each code's mesh built from the family's
 * "shape" (rk_family_shape_scene); or (--lift) the code that maximises the mean vertical
 * displacement of a region after N steps (rk_koopman_shape_maximize, Fig. 16's lift). */
#ifndef ROMKIT_NEURAL_SHAPE_H
#define ROMKIT_NEURAL_SHAPE_H

#include "pipeline/family.h"

typedef struct {
    const char *objective, *target, *steps, *start; /* "VERTEX,AXIS", m, N, "G1,G2,..." (NULL: mid-range) */
    const char *lift;       /* "X0,Y0,Z0,X1,Y1,Z1": maximise the mean y displacement of the rest box's vertices */
    const char *scene_out;  /* write the optimum's scene (JSON) there */
} neural_shape_args;

/* --objective or --lift: a shape optimisation instead of --scene and --gamma. */
int neural_shape_wanted(const neural_shape_args *a);

/* text (option opt's value): exactly g comma-separated finite numbers, each inside the members'
 * range, into gamma. */
int neural_gamma(const char *opt, const char *text, const rk_family *f, double *gamma, rk_error *err);
/* Checks the arguments against the family (a "shape", the vertex inside its mesh, the start inside
 * the members' range) before any training: 0, or -1 with err naming the option. */
int neural_shape_check(const neural_shape_args *a, const rk_family *f, rk_error *err);
/* gamma (g values) out: the optimum; its numbers into report (an object). */
int neural_shape_optimize(const neural_shape_args *a, const rk_koopman_neural *nk, const rk_family *f, double *gamma,
                          cJSON *report, rk_error *err);
/* With --lift: each member's lift, the model's against its own full-order run's at step N, into
 * report ("members", and "held_out_lift_error": the largest |model - full order| over the held-out
 * members, the model's own error on shapes it was not trained on, and
 * "held_out_lift_relative_error", the largest |model - full order| / |full order|; null without any). */
int neural_shape_members(const neural_shape_args *a, const rk_koopman_neural *nk, const rk_family *f, cJSON *report,
                         int quiet, rk_error *err);

#endif
