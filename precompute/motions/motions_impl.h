/* precompute/motions: what the template's object measures, shared by the scene writer (motions.c)
 * and the environments built around it (environment.c). */
#ifndef RK_MOTIONS_IMPL_H
#define RK_MOTIONS_IMPL_H

#include <cjson/cJSON.h>

#include "mesh/mesh.h"
#include "motions/motions.h"

/* The object in the frame gravity sets: up u = -g / |g|, a horizontal a (along the board; the
 * world axis least aligned with u, made perpendicular) and b = a x u (across the board, the
 * drum's axis). c is the centre of the object's bounding box in that frame, ext its extents along
 * a, u, b, L the largest and D the box's diagonal. */
typedef struct {
    double u[3], a[3], b[3], c[3];
    double ext[3], L, D;
    double g;               /* |gravity| */
} rk_motions_frame;

/* The pegs' spacing along the board (m): a draw starts the object within half of it of the middle. */
double rk_motions_peg_spacing(const rk_motions_frame *F);
/* The drum's inner radius (m): the object's half diagonal and a clearance, so it can turn over. */
double rk_motions_drum_radius(const rk_motions_frame *F);

/* c + alpha a + upsilon u + beta b */
void rk_motions_point(const rk_motions_frame *F, double alpha, double upsilon, double beta, double out[3]);

/* The board's obstacles (planes and capsules; rk_motions_report.pegs set), the same for every
 * scene: a new JSON array. */
cJSON *rk_motions_board(const rk_motions_frame *F, rk_motions_report *rep);
/* The drum's closed octagonal prism around the object (rk_motions_report.drum_radius set). */
int rk_motions_drum_surface(const rk_motions_frame *F, rk_surface *s, rk_motions_report *rep, rk_error *err);
/* The drum as the scene's one obstacle: mesh file `file` (relative to the scene), turning about b
 * through c at spin deg/s. A new JSON array. */
cJSON *rk_motions_drum(const rk_motions_frame *F, const char *file, double spin);

#endif
