/* Private to rkpm_chunks.c and rkpm_assemble.c: the integration points walked in spatial chunks
 * (grid cells of about the median kernel radius, at most max_points points each), with the
 * kernels covering each point. */
#ifndef RK_RKPM_CHUNKS_H
#define RK_RKPM_CHUNKS_H

#include "basis/rkpm_impl.h"

typedef struct {
    const rk_rkpm *k;
    const double *X;
    int n;
    rk_rkpm_grid grid;  /* over the integration points */
    int max_points;     /* per chunk */
    int cell, offset;   /* traversal state */
    /* The current chunk: */
    int np;             /* points */
    int *pts;           /* np point indices */
    int u;              /* kernels covering at least one of them */
    int *U;             /* u kernel indices, ascending */
    int *cover_start;   /* np + 1 */
    int *cover;         /* point t's covering kernels: positions in U, ascending,
                         * cover[cover_start[t] .. cover_start[t + 1]) */
    int *cand, *used;   /* scratch */
} rkpm_chunks;

int rkpm_chunks_init(rkpm_chunks *c, const rk_rkpm *k, const double *X, int n, rk_error *err);
/* Advances to the next chunk: 1, or 0 at the end (then the traversal restarts), or -1 with err. */
int rkpm_chunks_next(rkpm_chunks *c, rk_error *err);
void rkpm_chunks_free(rkpm_chunks *c);

#endif
