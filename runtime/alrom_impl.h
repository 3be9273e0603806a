/* Private to the runtime's adaptive linear ROM (alrom*.c): what its files share. */
#ifndef ROMRT_ALROM_IMPL_H
#define ROMRT_ALROM_IMPL_H

#include <string.h>

#include "runtime/romrt_impl.h"

/* A QR diagonal below this fraction of the largest is rank loss, the precompute's rk_thin_q floor
 * (precompute/grassmann/interpolate.c: the history's missing directions are amplified round-off
 * above 1e-12, so the data decides only from well above it). */
#define RT_ALROM_RANK_TOL 1e-6

/* The quadratic decoder's encoder: Gauss-Newton iterations at most (ALRH's encoder field may lower it). */
#define RT_ALROM_ENCODE_ITERATIONS 20u

/* Pair (i, j) of QDRV's r (r + 1) / 2, row-major over i <= j (the precompute's rk_quadratic_pairs). */
static inline int rt_alrom_pair(int r, int i, int j)
{
    if (i > j) {
        int t = i;
        i = j;
        j = t;
    }
    return i * r - i * (i - 1) / 2 + (j - i);
}
/* The quadratic decoder (alrom_decoder.c), B = [ROWS | QDRV] (n x R, R = r + pairs) and U = B C(p):
 * at open, B^T W B into al->gram and B^T B over the free rows into al->gram_free; */
void rt_alrom_gram(romrt_model *m);
/* the vertices a step reads rows of into al->sv (al->ns, al->s_of): the cubature elements', the
 * collision vertices and the plane contacts' (at open, the quadratic decoder); */
void rt_alrom_used(romrt_model *m);
/* B_i . c (R) for row i, and out = G v for G R x R; */
double rt_alrom_b_dot(const romrt_model *m, int i, const double *c);
void rt_alrom_gram_times(int R, const double *G, const double *v, double *out);
/* C(p)^T v (r) for v an R-vector, and C(p)^T S C(p) (r x r, column-major) for S R x R (al->gram_c
 * as scratch); */
void rt_alrom_c_apply(const romrt_model *m, const double *p, const double *v, double *out);
/* S C(p) (R x r, column-major) for S R x R; */
void rt_alrom_s_c(const romrt_model *m, const double *S, const double *p, double *SC);
void rt_alrom_c_gram(const romrt_model *m, const double *S, const double *p, double *out);
/* row i of U at al->p. */
void rt_alrom_jacobian_row(const romrt_model *m, int i, double *Ui);
/* rows 3v..3v+2 of U at al->p, side by side (J: r x 4, lane a row 3v + a, lane 3 zero). */
void rt_alrom_jacobian_vertex(const romrt_model *m, int v, double *J);
/* Whether the quadratic decoder's state holds vertex v's displacement in u_t (a used or a
 * prescribed vertex), or leaves it to B c (alrom.c). */
static inline int rt_alrom_held(const rt_alrom *al, int v)
{
    return al->decoder || al->s_of[v] < (uint32_t)al->ns_on || al->motion_of[v] != ROMBIN_NO_MOTION;
}
/* Held vertex k of al->ns_on + al->npv (the used vertices now, then the prescribed; one of both is
 * visited twice): the quadratic decoder's step passes over these rather than every stored vertex
 * (issue 33: five passes over the stored rows were a twentieth of the step, and they grow with the
 * mesh while the work they do does not). */
static inline int rt_alrom_held_vertex(const rt_alrom *al, int k)
{
    return (int)(k < al->ns_on ? al->sv[k] : al->pv[k - al->ns_on]);
}
/* dst = src over every stored row (CROM) or the held vertices' rows (the quadratic decoder: the
 * others are B c, never read). */
static inline void rt_alrom_copy_held(const romrt_model *m, double *dst, const double *src)
{
    const rt_alrom *al = &m->al;
    int k, a;
    if (al->decoder) {
        memcpy(dst, src, sizeof(double) * 3 * (size_t)m->nv);
        return;
    }
    for (k = 0; k < al->ns_on + al->npv; k++) {
        size_t i = 3 * (size_t)rt_alrom_held_vertex(al, k);
        for (a = 0; a < 3; a++) dst[i + (size_t)a] = src[i + (size_t)a];
    }
}
/* The ring's value of entry slot on used row k (3 s + a for used vertex s, axis a): a used row's
 * m + 1 entries contiguous, so a step's gather of them (form_used) reads a cache line or three
 * rather than one line per entry at a stride of the whole ring's row count (issue 33: the strided
 * gather was 14% of the step). */
static inline double *rt_alrom_ds(const rt_alrom *al, int slot, int k) { return al->ds + (size_t)k * (size_t)(al->m + 1) + (size_t)slot; }
/* Whether row (a dof) of the stored vertices is prescribed (its basis row is zero). */
static inline int rt_alrom_prescribed(const rt_alrom *al, int row) { return al->motion_of[row / 3] != ROMBIN_NO_MOTION; }
/* The prescribed rows of A (n x r, a row's r doubles contiguous) zeroed. */
void rt_alrom_zero_prescribed(const romrt_model *m, double *A);
/* p = e(u) of al->u into al->p (alrom_decoder.c); with a CROM decoder also U = dg/dp at p into
 * al->U (the quadratic's rows are formed where used). */
romrt_status rt_alrom_encode(romrt_model *m, romrt_error *err);
/* The step's basis into al->rows (alrom_basis.c, Algorithm 3 lines 3-6): the code of the state,
 * the decoder's basis there, the history written and, when it has rank r, the Grassmann point. */
romrt_status rt_alrom_step_basis(romrt_model *m, romrt_error *err);

/* A Newton matrix kept across steps (alrom_keep.c): the step's W_F C and M_r noted at its commit,
 * and m->H's kept factor carried into the new step's basis (0), or not (-1: none to carry, too old,
 * another inertia weight, or one that would not factor; a fresh one is built). */
void rt_alrom_keep_note(romrt_model *m);
int rt_alrom_keep_carry(romrt_model *m, romrt_real w_inertia);

#endif
