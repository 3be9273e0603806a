/* Cubature training (An et al. 2008, Sec. 3-4): training poses, the exact reduced forces there,
 * and the greedy NNLS selection of elements whose weighted forces reproduce them. */
#include "cubature/cubature.h"

#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/util.h"

void rk_cubature_default_options(rk_cubature_options *o)
{
    o->tolerance = 0.01;
    o->max_points = 0;
    o->poses = 100;
    o->sample = 1000;
    o->amplitude = 0;
    o->seed = 0x5eed;
    o->prune = 0;
    o->vertex_cost = 8;
}

static double uniform(uint64_t *s) { return ((double)(rk_splitmix64(s) >> 11) + 0.5) / 9007199254740992.0; }

static double gaussian(uint64_t *s) /* Box-Muller */
{
    return sqrt(-2 * log(uniform(s))) * cos(2 * M_PI * uniform(s));
}

static double rms_displacement(const double *Mr, int r, const double *q, double mass, double *tmp)
{
    cblas_dsymv(CblasColMajor, CblasUpper, r, 1.0, Mr, r, q, 1, 0.0, tmp, 1);
    return sqrt(fmax(cblas_ddot(r, q, 1, tmp, 1), 0.0) / mass);
}

/* Random poses in the spirit of An et al. Sec. 3: each reduced vibration mode (K_r v = w^2 M_r v at
 * rest) with a normal amplitude proportional to 1/w, so soft modes dominate as they do in motion,
 * the whole pose scaled to an RMS displacement uniform in [0.1, 1] x amplitude. */
static int random_poses(rk_quadrature *Q, const double *Mr, double mass, double amplitude, int count,
                        uint64_t seed, double *poses, rk_error *err)
{
    int r = Q->r;
    double *K = rk_calloc((size_t)r * r, sizeof(double), err), *B = rk_calloc((size_t)r * r, sizeof(double), err);
    double *w2 = rk_calloc((size_t)r, sizeof(double), err), *zero = rk_calloc((size_t)r, sizeof(double), err);
    double *tmp = rk_calloc((size_t)r, sizeof(double), err);
    int rc = -1;
    if (!K || !B || !w2 || !zero || !tmp) goto out;
    rk_quadrature_eval(Q, zero, NULL, K, 0);
    memcpy(B, Mr, sizeof(double) * r * r);
    if (LAPACKE_dsygv(LAPACK_COL_MAJOR, 1, 'V', 'U', r, K, r, B, r, w2) != 0) {
        rk_fail(err, "cubature training: the reduced vibration modes failed (U^T M U not positive definite?)");
        goto out;
    }
    /* Rigid and near-rigid modes (w^2 tiny) get the amplitude of the softest elastic one. */
    double floor_w2 = 0;
    for (int i = 0; i < r && floor_w2 == 0; i++)
        if (w2[i] > 1e-8 * w2[r - 1]) floor_w2 = w2[i];
    if (floor_w2 == 0) floor_w2 = 1;
    for (int p = 0; p < count; p++) {
        double *q = poses + (size_t)r * p;
        memset(q, 0, sizeof(double) * r);
        for (int i = 0; i < r; i++)
            cblas_daxpy(r, gaussian(&seed) / sqrt(fmax(w2[i], floor_w2)), K + (size_t)r * i, 1, q, 1);
        double rms = rms_displacement(Mr, r, q, mass, tmp);
        double target = amplitude * (0.1 + 0.9 * uniform(&seed));
        if (rms > 0) cblas_dscal(r, target / rms, q, 1);
    }
    rc = 0;
out:
    free(K);
    free(B);
    free(w2);
    free(zero);
    free(tmp);
    return rc;
}

/* Column c of the training matrix: point c's force at every pose, each pose's block divided by
 * the norm of its exact total force so that every pose counts the same (An et al. Eq. 5). */
typedef struct {
    const rk_quadrature *Q;
    const double *poses;
    const double *inv_norm;
    int count;
    double *cache;     /* every column (rows x candidates) when it fits in RK_CUBATURE_CACHE bytes */
} training;

/* Columns are cheap to keep and costly to recompute (one stress per pose): the greedy asks for
 * `sample` of them per pick, so small and mid-size problems keep them all. */
#define RK_CUBATURE_CACHE (512.0 * 1024 * 1024)

static int compute_column(const training *T, int c, double *col, rk_error *err)
{
    int r = T->Q->r;
    for (int p = 0; p < T->count; p++) {
        double F[9];
        rk_quadrature_point_F(T->Q, c, T->poses + (size_t)r * p, F);
        rk_quadrature_point_force(T->Q, c, F, col + (size_t)r * p);
        cblas_dscal(r, T->inv_norm[p], col + (size_t)r * p, 1);
        for (int i = 0; i < r; i++)
            if (!isfinite(col[(size_t)r * p + i]))
                return rk_fail(err, "element %d: force not finite at training pose %d", T->Q->source[c], p);
    }
    return 0;
}

static int column(void *ctx, int c, double *col, rk_error *err)
{
    const training *T = ctx;
    size_t rows = (size_t)T->Q->r * T->count;
    if (!T->cache) return compute_column(T, c, col, err);
    memcpy(col, T->cache + rows * c, sizeof(double) * rows);
    return 0;
}

static void fill_cache(training *T)
{
    size_t rows = (size_t)T->Q->r * T->count;
    if ((double)rows * T->Q->count * sizeof(double) > RK_CUBATURE_CACHE) return;
    T->cache = malloc(rows * T->Q->count * sizeof(double));
    rk_error ignored;
    for (int c = 0; T->cache && c < T->Q->count; c++) {
        if (compute_column(T, c, T->cache + rows * c, &ignored)) { /* recomputed, and reported, on demand */
            free(T->cache);
            T->cache = NULL;
        }
        rk_progress("cubature training", c + 1, T->Q->count);
    }
    rk_progress_done("cubature training");
}

/* Exact total forces b at every pose (normalised); poses whose force vanishes (the rest pose, a
 * rigid motion) carry no information and are dropped. Returns the poses kept. */
static int targets(training *T, double *poses, int count, double *inv_norm, double *b, rk_error *err)
{
    int r = T->Q->r, kept = 0;
    double *col = rk_calloc((size_t)r, sizeof(double), err);
    if (!col) return -1;
    for (int p = 0; p < count; p++) {
        double *f = b + (size_t)r * kept;
        memset(f, 0, sizeof(double) * r);
        for (int c = 0; c < T->Q->count; c++) {
            double F[9];
            rk_quadrature_point_F(T->Q, c, poses + (size_t)r * p, F);
            rk_quadrature_point_force(T->Q, c, F, col);
            cblas_daxpy(r, 1.0, col, 1, f, 1);
        }
        double norm = cblas_dnrm2(r, f, 1);
        if (!isfinite(norm)) {
            free(col);
            return rk_fail(err, "cubature training: the exact force at pose %d is not finite", p);
        }
        if (norm == 0) continue;
        cblas_dscal(r, 1.0 / norm, f, 1);
        inv_norm[kept] = 1.0 / norm;
        memmove(poses + (size_t)r * kept, poses + (size_t)r * p, sizeof(double) * r);
        kept++;
    }
    free(col);
    return kept;
}

int rk_cubature_train(rk_quadrature *exact, const double *Mr, double mass, const double *snapshots,
                      int nsnapshots, const rk_cubature_options *o, rk_cubature_set *out, int *poses_used,
                      rk_error *err)
{
    memset(out, 0, sizeof *out);
    int r = exact->r;
    if (!(o->tolerance > 0 && o->tolerance < 1))
        return rk_fail(err, "cubature: tolerance %g must be in (0, 1)", o->tolerance);
    if (o->poses < 1 || o->max_points < 0 || o->sample < 0)
        return rk_fail(err, "cubature: poses %d, max_points %d, sample %d", o->poses, o->max_points, o->sample);
    /* Up to half the poses from the full-order snapshots (evenly spaced), the rest random. */
    int nsnap = nsnapshots < o->poses / 2 ? nsnapshots : o->poses / 2;
    int total = nsnap + (o->poses - nsnap);
    double *poses = rk_calloc((size_t)r * total, sizeof(double), err);
    double *inv_norm = rk_calloc((size_t)total, sizeof(double), err);
    double *b = rk_calloc((size_t)r * total, sizeof(double), err);
    double *tmp = rk_calloc((size_t)r, sizeof(double), err);
    int rc = -1;
    if (!poses || !inv_norm || !b || !tmp) goto out;
    double amplitude = o->amplitude;
    for (int p = 0; p < nsnap; p++) {
        int s = nsnapshots == 1 ? 0 : (int)((long)p * (nsnapshots - 1) / (nsnap > 1 ? nsnap - 1 : 1));
        memcpy(poses + (size_t)r * p, snapshots + (size_t)r * s, sizeof(double) * r);
    }
    for (int s = 0; s < nsnapshots && o->amplitude <= 0; s++)
        amplitude = fmax(amplitude, rms_displacement(Mr, r, snapshots + (size_t)r * s, mass, tmp));
    if (!(amplitude > 0)) {
        rk_fail(err, "cubature: no training amplitude (no snapshot moves, and none was given)");
        goto out;
    }
    if (random_poses(exact, Mr, mass, amplitude, total - nsnap, o->seed, poses + (size_t)r * nsnap, err)) goto out;
    training T = {exact, poses, inv_norm, 0, NULL};
    int kept = targets(&T, poses, total, inv_norm, b, err);
    if (kept < 0) goto out;
    if (kept == 0) {
        rk_fail(err, "cubature: every training pose has zero force");
        goto out;
    }
    T.count = kept;
    fill_cache(&T);
    rk_cubature_problem P = {0};
    P.rows = r * kept;
    P.candidates = exact->count;
    P.column = column;
    P.ctx = &T;
    P.b = b;
    P.tolerance = o->tolerance;
    P.max_points = o->max_points > 0 ? o->max_points : exact->count;
    P.sample = o->sample;
    P.seed = o->seed;
    P.prune = o->prune;
    rc = rk_cubature_greedy(&P, out, err);
    /* The greedy's indices are positions in the exact quadrature: make them element numbers. */
    for (int k = 0; !rc && k < out->count; k++) out->index[k] = exact->source[out->index[k]];
    *poses_used = kept;
    free(T.cache);
out:
    free(poses);
    free(inv_norm);
    free(b);
    free(tmp);
    return rc;
}
