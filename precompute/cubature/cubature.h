/* precompute/cubature: the reduced elastic energy, integrated exactly (every element) or by a
 * cubature (a few weighted elements), and the training that picks the cubature.
 *
 * In a subspace x = X + U q the deformation gradient of every P1 tet (and of every RKPM
 * integration sample under linear blend skinning) is affine in q: F_i = I + G_i q, with G_i a
 * 9 x r matrix fixed at precompute time. The reduced energy is then a weighted sum over points,
 *
 *   E(q) = sum_i w_i Psi_i(I + G_i q),  f(q) = -sum_i w_i G_i^T P_i,  K(q) = sum_i w_i G_i^T dP/dF_i G_i,
 *
 * exact when the points are all the elements with w_i their rest volumes, and approximate (An et
 * al. 2008, "Optimizing cubature for efficient integration of subspace deformations") when they
 * are a few elements with trained non-negative weights. Neither costs anything per vertex. */
#ifndef RK_CUBATURE_H
#define RK_CUBATURE_H

#include "cubature/select.h"
#include "fem/fem.h"
#include "util/error.h"

typedef struct {
    int r;                     /* reduced coordinates */
    int count;                 /* points */
    double *G;                 /* count blocks of 9 x r, row-major: row 3a+b of block i is dF_ab/dq */
    double *weight;            /* count: rest volume (m^3) times the cubature weight */
    rk_material_model *model;  /* count */
    double *mu, *lambda;       /* count, Lame parameters */
    int *source;               /* count: the element (or integration sample) each point is */
    double *scratch;           /* F, P (9 count each) and w dP/dF G (9 r count) */
} rk_quadrature;

/* The points of `count` elements of f (elements NULL: all nt, in order) in the subspace U (3 nv x r,
 * column-major), each weighted by its rest volume times weights[k] (NULL: 1). */
int rk_quadrature_elements(const rk_fem *f, const double *U, int r, int count, const int *elements,
                           const double *weights, rk_quadrature *Q, rk_error *err);
void rk_quadrature_free(rk_quadrature *Q);

/* Elastic energy at q; with g, adds its gradient; with H (r x r, column-major), adds its Hessian
 * (each point's dP/dF projected to PSD when project != 0, like the full-order model). Returns
 * +INFINITY when a value is not finite. Uses Q->scratch, so one call at a time per Q. */
double rk_quadrature_eval(rk_quadrature *Q, const double *q, double *g, double *H, int project);

/* One point's reduced internal force contribution -w_i G_i^T P_i(I + G_i q) is
 * rk_quadrature_point_force(Q, i, F, out) with F = I + G_i q precomputed: out (r) = w_i G_i^T P. */
void rk_quadrature_point_force(const rk_quadrature *Q, int i, const double F[9], double *out);
/* F (9) of point i at q. */
void rk_quadrature_point_F(const rk_quadrature *Q, int i, const double *q, double F[9]);

typedef struct {
    double tolerance;     /* relative force error over the training poses (default 0.01) */
    int max_points;       /* 0: no limit but the element count */
    int poses;            /* training poses (default 100): up to half from snapshots, the rest random */
    int sample;           /* candidates scored per greedy iteration (default 1000; 0: all) */
    double amplitude;     /* RMS displacement (m) of the random poses; 0: the largest snapshot's */
    unsigned long long seed;
} rk_cubature_options;

void rk_cubature_default_options(rk_cubature_options *o);

/* Trains a cubature for the exact quadrature `exact` (all elements, rk_quadrature_elements with
 * weights NULL): poses from the reduced snapshots (r x nsnapshots, column-major; may be 0) and
 * random ones (An et al. 2008, Sec. 3), the exact reduced forces there as targets, then greedy
 * NNLS selection (select.h) until the relative force error is under o->tolerance. Mr = U^T M U and
 * the total mass measure pose sizes. out->index are element numbers and out->weight multiply
 * their rest volumes (rk_quadrature_elements takes both as they are). Not reaching the
 * tolerance within max_points is not an error: out->reached = 0. */
int rk_cubature_train(rk_quadrature *exact, const double *Mr, double mass, const double *snapshots,
                      int nsnapshots, const rk_cubature_options *o, rk_cubature_set *out, int *poses_used,
                      rk_error *err);

#endif
