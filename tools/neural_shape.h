/* romkit neural-dmd --objective (koopman-dmd-log-linear paper, Sec. 7.4): the shape code for which
 * one value of a vertex's position after N steps from rest reaches a target, through the trained
 * model's closed-form jump (rk_koopman_shape_optimize), each code's mesh built from the family's
 * "shape" (rk_family_shape_scene). */
#ifndef ROMKIT_NEURAL_SHAPE_H
#define ROMKIT_NEURAL_SHAPE_H

#include "pipeline/family.h"

typedef struct {
    const char *objective, *target, *steps, *start; /* "VERTEX,AXIS", m, N, "G1,G2,..." (NULL: mid-range) */
} neural_shape_args;

/* text (option opt's value): exactly g comma-separated finite numbers, each inside the members'
 * range, into gamma. */
int neural_gamma(const char *opt, const char *text, const rk_family *f, double *gamma, rk_error *err);
/* Checks the arguments against the family (a "shape", the vertex inside its mesh, the start inside
 * the members' range) before any training: 0, or -1 with err naming the option. */
int neural_shape_check(const neural_shape_args *a, const rk_family *f, rk_error *err);
/* gamma (g values) out: the optimum; its numbers into report (an object). */
int neural_shape_optimize(const neural_shape_args *a, const rk_koopman_neural *nk, const rk_family *f, double *gamma,
                          cJSON *report, rk_error *err);

#endif
