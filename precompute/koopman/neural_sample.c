/* A training mesh's vertices sampled (koopman.h, rk_koopman_neural_sample): what keeps the neural
 * DMD's training bounded at the paper's resolutions (koopman-dmd-log-linear, Sec. 5 and Fig. 3:
 * one model on 2.5k, 10k and 500k vertices). The loss (Eq. 22-23) holds each mesh's lifted
 * snapshot pairs as dense 6 nv x M matrices and runs the modes network over every vertex every
 * step, so time and memory grow with nv. The modes are a field of the rest position, phi(gamma, x),
 * and the loss is a sum over vertices: a uniform sample of a mesh's vertices is a discretization of
 * the same field with fewer points, which is the paper's own discretization-agnostic argument.
 * The sample is fixed for the whole training (drawn once from the seed), not redrawn each step:
 * its pairs are then gathered once (6 S x M), the projection y = Phi^* X of Eq. 22 is one
 * least-squares problem throughout (a new sample each step would change the projection itself,
 * not only add noise to the gradient), and the full snapshots need not be revisited. */
#include "koopman/koopman.h"

#include <stdlib.h>
#include <string.h>

static int by_index(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* dst (3 S) = the 3-vectors of src at the S vertices index[0 .. S-1]. */
static void gather(double *dst, const double *src, const int *index, int S)
{
    for (int i = 0; i < S; i++) memcpy(dst + 3 * (size_t)i, src + 3 * (size_t)index[i], sizeof(double) * 3);
}

void rk_koopman_neural_sample_free(rk_koopman_neural_sample *s)
{
    for (int k = 0; s->traj && k < s->mesh.ntraj; k++) {
        free((double *)s->traj[k].u);
        free((double *)s->traj[k].accel);
    }
    free(s->traj);
    free(s->X);
    free(s->index);
    memset(s, 0, sizeof *s);
}

int rk_koopman_neural_sample_init(const rk_koopman_neural_mesh *m, int count, unsigned long long seed,
                                  rk_koopman_neural_sample *s, rk_error *err)
{
    memset(s, 0, sizeof *s);
    if (m->nv < 1 || m->ntraj < 1) return rk_fail(err, "sampling a mesh of %d vertices and %d trajectories", m->nv, m->ntraj);
    int S = count > 0 && count < m->nv ? count : m->nv, nv = m->nv;
    s->index = rk_calloc((size_t)nv, sizeof(int), err);
    if (!s->index) return -1;
    /* the first S of a partial Fisher-Yates shuffle: S distinct vertices, uniformly; sorted, so that
     * a sample keeps the mesh's vertex order (and all vertices, S = nv, are the mesh itself) */
    for (int p = 0; p < nv; p++) s->index[p] = p;
    uint64_t state = (uint64_t)seed ^ 0x5A3D1E0F2B4C6978ULL;
    for (int p = 0; S < nv && p < S; p++) {
        int q = p + (int)(rk_uniform(&state) * (nv - p));
        int t = s->index[p];
        s->index[p] = s->index[q];
        s->index[q] = t;
    }
    qsort(s->index, (size_t)S, sizeof(int), by_index);
    int *shrunk = realloc(s->index, sizeof(int) * (size_t)S);
    if (shrunk) s->index = shrunk;
    s->X = rk_calloc(3 * (size_t)S, sizeof(double), err);
    s->traj = rk_calloc((size_t)m->ntraj, sizeof *s->traj, err);
    if (!s->X || !s->traj) goto fail;
    s->mesh = *m;
    s->mesh.nv = S;
    s->mesh.X = s->X;
    s->mesh.traj = s->traj;
    gather(s->X, m->X, s->index, S);
    size_t d = 3 * (size_t)nv, ds = 3 * (size_t)S;
    for (int k = 0; k < m->ntraj; k++) {
        const rk_koopman_trajectory *t = &m->traj[k];
        double *u = rk_calloc(ds * (size_t)t->frames, sizeof(double), err), *a = NULL;
        s->traj[k].u = u;
        s->traj[k].frames = t->frames;
        if (!u) goto fail;
        for (int f = 0; f < t->frames; f++) gather(u + ds * f, t->u + d * f, s->index, S);
        if (t->accel) {
            if (!(a = rk_calloc(ds, sizeof(double), err))) goto fail;
            gather(a, t->accel, s->index, S);
            s->traj[k].accel = a;
        }
    }
    return 0;
fail:
    rk_koopman_neural_sample_free(s);
    return -1;
}
