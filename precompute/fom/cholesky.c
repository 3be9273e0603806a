/* CHOLMOD behind the Newton solver: impl->N.A is wrapped (no copy) as a symmetric upper matrix;
 * the fill-reducing ordering and symbolic factorization are computed at init and again only when
 * contact changes which vertices the matrix couples (never without contact); each Newton
 * iteration refactorizes numerically into the same L and solves with cholmod_solve2, which reuses
 * its dense workspaces (no per-iteration allocation).
 *
 * Supernodal, ordered by AMD and by CHOLMOD's nested dissection (NESDIS: METIS on the graph, then
 * CAMD on the separators), keeping the one whose factor has fewer nonzeros: NESDIS on every mesh
 * measured but the beam, where AMD's is 5% faster. Numeric factorizations of the projected
 * Hessian's pattern (M/h^2 + K), median of 9 (3 at 102k), one thread, 2-core AMD EPYC:
 *
 *   mesh (tets)          AMD                METIS              NESDIS             default (AMD or METIS)
 *   beam 40x8x8 (15k)    0.026 s  0.82 GF   0.026 s  0.82 GF   0.027 s  0.87 GF   AMD
 *   bunny_19k            0.030 s  0.85 GF   0.026 s  0.62 GF   0.024 s  0.59 GF   AMD
 *   dinosaur (50k)       0.066 s  1.47 GF   0.089 s  1.40 GF   0.064 s  1.37 GF   AMD
 *   box 50x20x17 (102k)  1.80 s   79 GF     1.29 s   43 GF     0.95 s   41 GF     METIS
 *
 * (GF: CHOLMOD's flop count.) CHOLMOD's default (nmethods 0) keeps AMD unless its fill is large,
 * which left the bunny 25% slower. NESDIS's analysis costs more (0.03 s against AMD's 0.01 s on
 * the bunny, 0.14 s against 0.03 s at 102k) and is done once without contact. bench_fom measures
 * them all again (bench/results/fom_orderings.csv, where "AMD|NESDIS" is this choice).
 *
 * OpenBLAS's threads (rk_threads()) from RK_FOM_THREADED_FLOPS on, one below. Two threads against
 * one, median of 5 to 15 factorizations, with the other core mostly free: 7.6e6 flops (box_1k)
 * 1.00, 1.7e7 (armadillo) 0.99, 4.6e8 (box_10k) 1.05, 5.9e8 (bunny) 0.87 to 1.07, 8.7e8 (beam)
 * 0.80, 1.3e9 0.78, 3.1e9 0.75 to 0.87, 1.1e10 (box_50k) 0.69, 4.1e10 (box_100k) 0.72; with two
 * other jobs on the machine: bunny 0.89, box_50k 1.29, box_100k 1.07, and in whole runs the
 * bunny's factorization took 0.097 s on two threads against 0.026 s on one. Threaded OpenBLAS
 * also rounds differently for each thread count (the beam's positions after 20 steps differ
 * between 1, 2 and 3 threads), while everything else here is bit-identical for any count. So the
 * meshes most runs use factor on one thread, identical and safe on a shared machine, and only
 * factorizations of 1e10 flops and more (box_50k and up) take the threads: there two are 30%
 * faster on a free machine, and results are the same for the same ROMKIT_THREADS. */
#include "fom/fom_impl.h"

#include "fem/fem.h"

#include "util/util.h"

#include <string.h>

int rk_fom_chol_analyze(rk_fom_impl *im, rk_error *err)
{
    rk_threads(); /* the thread counts set before CHOLMOD starts any (util.h) */
    cholmod_start(&im->cc);
    im->cc_started = 1;
    im->cc.print = 0; /* errors come back through rk_error, not stderr */
    im->cc.error_handler = NULL;
    im->cc.supernodal = CHOLMOD_SUPERNODAL;
    im->cc.nmethods = 2; /* both, the one with the sparser factor kept (header) */
    im->cc.method[0].ordering = CHOLMOD_AMD;
    im->cc.method[1].ordering = CHOLMOD_NESDIS;
    im->cc.postorder = 1;
    return rk_fom_chol_reanalyze(im, err);
}

int rk_fom_chol_reanalyze(rk_fom_impl *im, rk_error *err)
{
    double t0 = rk_now();
    if (im->L) cholmod_free_factor(&im->L, &im->cc);
    rk_cholmod_sparse_view(&im->N.A, &im->A);
    im->L = cholmod_analyze(&im->A, &im->cc);
    im->seconds_analyze += rk_now() - t0;
    im->analyses++;
    if (!im->L || im->cc.status < CHOLMOD_OK)
        return rk_fail(err, "CHOLMOD symbolic analysis failed (status %d) on %d dofs, %d nonzeros",
                       im->cc.status, im->N.A.n, im->N.A.nnz);
    im->blas_threads = im->cc.fl >= RK_FOM_THREADED_FLOPS ? rk_threads() : 1;
    return 0;
}

int rk_fom_chol_factor(rk_fom *s, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    double t0 = rk_now();
    int before = rk_threads_blas(im->blas_threads);
    int ok = cholmod_factorize(&im->A, im->L, &im->cc);
    rk_threads_blas(before);
    double dt = rk_now() - t0;
    s->stats.seconds_factor += dt;
    rk_fom_iteration_factor(im, dt);
    if (im->cc.status == CHOLMOD_NOT_POSDEF && im->exact_elastic) return RK_FOM_NOT_POSDEF;
    if (im->cc.status == CHOLMOD_NOT_POSDEF) /* impossible with projected Hessians unless a bug */
        return rk_fail(err, "Newton matrix is not positive definite (CHOLMOD stopped at column %d of %d)",
                       (int)im->L->minor, im->ndof);
    if (!ok || im->cc.status < CHOLMOD_OK)
        return rk_fail(err, "CHOLMOD factorization failed (status %d)", im->cc.status);
    return 0;
}

int rk_fom_chol_solve(rk_fom *s, const double *g, double *d, rk_error *err)
{
    rk_fom_impl *im = s->impl;
    double t0 = rk_now();
    cholmod_dense B;
    rk_cholmod_dense_view(g, im->ndof, &B);
    int before = rk_threads_blas(im->blas_threads);
    int ok = cholmod_solve2(CHOLMOD_A, im->L, &B, NULL, &im->sol, NULL, &im->Y, &im->E, &im->cc);
    rk_threads_blas(before);
    if (ok) {
        const double *y = im->sol->x;
        for (int i = 0; i < im->ndof; i++) d[i] = -y[i];
    }
    s->stats.seconds_solve += rk_now() - t0;
    return ok ? 0 : rk_fail(err, "CHOLMOD solve failed (status %d)", im->cc.status);
}

void rk_fom_chol_free(rk_fom_impl *im)
{
    if (!im->cc_started) return;
    cholmod_free_factor(&im->L, &im->cc);
    cholmod_free_dense(&im->sol, &im->cc);
    cholmod_free_dense(&im->Y, &im->cc);
    cholmod_free_dense(&im->E, &im->cc);
    cholmod_finish(&im->cc);
    im->cc_started = 0;
}
