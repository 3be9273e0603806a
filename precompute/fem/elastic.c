/* Elastic energy, gradient and Hessian assembled from the physics/ tet kernels.
 *
 * In parallel and bit-identical to one thread, whatever the thread count: the elements go in
 * blocks of ELASTIC_BLOCK; each block's per-element terms (energies, 12-entry gradients, the 78
 * upper entries of the Hessians) are computed on rk_parallel_for's threads into a buffer, then
 * added into the global vector or matrix by one thread in element order, so every sum is taken
 * in the same order as a plain loop over the elements. The adding is the cheap part (15k tets:
 * 0.4 ms of a 17 ms Hessian), and it overlaps the next block's computing. */
#include "fem/element_impl.h"

#include <math.h>
#include <stdlib.h>

/* Elements per block: a block's Hessian entries (2.5 MB) stay in cache until they are added. */
#define ELASTIC_BLOCK 4096
/* Elements per scheduled chunk: enough work (about 0.1 ms of Hessians) to pay for handing it out. */
#define ELASTIC_CHUNK 128
/* The block when the buffer cannot be allocated: a stack buffer, the same results. */
#define ELASTIC_SMALL_BLOCK 16

typedef enum { TERM_ENERGY = 1, TERM_GRADIENT = 12, TERM_HESSIAN = RK_TET_SLOTS } term;

typedef struct {
    const rk_fem *f;
    const double *x;
    term kind;          /* also the doubles per element in buf */
    int project;
    long first;         /* the block's first element */
    double *buf;
} elastic_job;

static void compute_range(void *ctx, long begin, long end)
{
    const elastic_job *j = ctx;
    const rk_fem *f = j->f;
    for (long k = begin; k < end; k++) {
        int t = (int)(j->first + k);
        double xe[12], *out = j->buf + (size_t)k * j->kind;
        rk_fem_gather(f, t, j->x, xe);
        if (j->kind == TERM_ENERGY) {
            *out = rk_tet_energy(f->model[t], f->mu[t], f->lambda[t], xe, &f->Dm_inv[9 * t], f->vol[t]);
        } else if (j->kind == TERM_GRADIENT) {
            for (int i = 0; i < 12; i++) out[i] = 0;
            rk_tet_gradient(f->model[t], f->mu[t], f->lambda[t], xe, &f->Dm_inv[9 * t], f->vol[t], out);
        } else {
            double He[144];
            rk_tet_hessian(f->model[t], f->mu[t], f->lambda[t], xe, &f->Dm_inv[9 * t], f->vol[t], He, j->project);
            for (int p = 0; p < 12; p++) /* the upper entries, in rk_fem_scatter_block's order */
                for (int q = p; q < 12; q++) *out++ = He[12 * p + q];
        }
    }
}

/* The block buffers, kept between calls (one pair per calling thread, grown as needed, never
 * freed): a fresh 2.5 MB buffer per call cost its page faults every Newton iteration. */
static _Thread_local double *kept[2];
static _Thread_local size_t kept_size[2];

static double *block_buffer(int which, size_t doubles)
{
    if (kept_size[which] < doubles) {
        double *grown = realloc(kept[which], sizeof(double) * doubles);
        if (!grown) return NULL;
        kept[which] = grown;
        kept_size[which] = doubles;
    }
    return kept[which];
}

/* Adding a computed block into the global vector or matrix, in element order. */
typedef struct {
    const rk_fem *f;
    term kind;
    double scale, *g, *val, E;
    long first, count;
    const double *buf;
} elastic_add;

static void add_block(void *ctx)
{
    elastic_add *a = ctx;
    const rk_fem *f = a->f;
    for (long k = 0; k < a->count; k++) {
        int t = (int)(a->first + k);
        const double *term_k = a->buf + (size_t)k * a->kind;
        if (a->kind == TERM_ENERGY) {
            a->E += *term_k;
        } else if (a->kind == TERM_GRADIENT) {
            rk_fem_scatter_vector(f, t, term_k, a->scale, a->g);
        } else {
            const int *s = &f->slot[RK_TET_SLOTS * (size_t)t];
            for (int i = 0; i < RK_TET_SLOTS; i++) a->val[s[i]] += a->scale * term_k[i];
        }
    }
    a->count = 0;
}

/* Every element's term of the given kind, block by block: block b + 1 is computed on the workers
 * while the calling thread adds block b (two buffers), so the adding, always in element order,
 * costs no time of its own on two threads or more. */
static double run(const rk_fem *f, const double *x, term kind, int project, double scale, double *g, double *val)
{
    double small[2][ELASTIC_SMALL_BLOCK * RK_TET_SLOTS];
    long block = f->nt < ELASTIC_BLOCK ? f->nt : ELASTIC_BLOCK;
    double *buf[2] = {block_buffer(0, (size_t)block * kind), block_buffer(1, (size_t)block * kind)};
    if (!buf[0] || !buf[1] || block <= ELASTIC_SMALL_BLOCK) {
        buf[0] = small[0];
        buf[1] = small[1];
        block = ELASTIC_SMALL_BLOCK;
    }
    elastic_add add = {f, kind, scale, g, val, 0, 0, 0, NULL};
    int b = 0;
    for (long first = 0; first < f->nt; first += block, b ^= 1) {
        long count = f->nt - first < block ? f->nt - first : block;
        elastic_job job = {f, x, kind, project, first, buf[b]};
        rk_parallel_for_beside(count, ELASTIC_CHUNK, compute_range, &job, add_block, &add); /* adds the previous block */
        add.first = first;
        add.count = count;
        add.buf = buf[b];
    }
    add_block(&add);
    return add.E;
}

double rk_fem_energy(const rk_fem *f, const double *x)
{
    double E = run(f, x, TERM_ENERGY, 0, 1.0, NULL, NULL);
    return isfinite(E) ? E : INFINITY; /* a NaN or infinite term poisons the sum */
}

void rk_fem_add_gradient(const rk_fem *f, const double *x, double scale, double *g)
{
    run(f, x, TERM_GRADIENT, 0, scale, g, NULL);
}

void rk_fem_add_hessian(const rk_fem *f, const double *x, double scale, int project, rk_sparse *H)
{
    run(f, x, TERM_HESSIAN, project, scale, NULL, H->val);
}

void rk_fem_add_rest_stiffness(const rk_fem *f, double scale, rk_sparse *K)
{
    rk_fem_add_hessian(f, f->X, scale, 0, K);
}
