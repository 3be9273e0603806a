/* The one sparse Cholesky (fem.h, rk_chol): the caller's matrix wrapped (no copy) as a symmetric
 * upper matrix; the fill-reducing ordering and symbolic factorization computed once per pattern
 * (the Newton solver: at init and again only when contact changes which vertices the matrix
 * couples); each refactorization numeric into the same L; solves with cholmod_solve2, which reuses
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
 * OpenBLAS's threads (rk_threads()) from RK_CHOL_THREADED_FLOPS on, one below. Two threads against
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
#include "fem/fem.h"

#include <string.h>

#include "util/util.h"

static void set_policy(rk_chol *c)
{
    c->cc.print = 0; /* errors come back through rk_error, not stderr */
    c->cc.error_handler = NULL;
    c->cc.supernodal = CHOLMOD_SUPERNODAL;
    c->cc.nmethods = 2; /* both, the one with the sparser factor kept (above) */
    c->cc.method[0].ordering = CHOLMOD_AMD;
    c->cc.method[1].ordering = CHOLMOD_NESDIS;
    c->cc.postorder = 1;
}

int rk_chol_analyze(rk_chol *c, const rk_sparse *S, rk_error *err)
{
    if (!c->started) {
        memset(c, 0, sizeof *c);
        rk_threads(); /* the thread counts set before CHOLMOD starts any (util.h) */
        cholmod_start(&c->cc);
        c->started = 1;
        set_policy(c);
    }
    if (c->L) cholmod_free_factor(&c->L, &c->cc);
    c->S = S;
    c->n = S->n;
    rk_cholmod_sparse_view(S, &c->A);
    c->L = cholmod_analyze(&c->A, &c->cc);
    if (!c->L || c->cc.status < CHOLMOD_OK)
        return rk_fail(err, "CHOLMOD symbolic analysis failed (status %d) on %d unknowns, %d nonzeros", c->cc.status,
                       S->n, S->nnz);
    c->blas_threads = c->cc.fl >= RK_CHOL_THREADED_FLOPS ? rk_threads() : 1;
    return 0;
}

int rk_chol_factor(rk_chol *c, rk_error *err)
{
    rk_cholmod_sparse_view(c->S, &c->A); /* the values may have moved (a pattern rebuilt in place) */
    int before = rk_threads_blas(c->blas_threads);
    int ok = cholmod_factorize(&c->A, c->L, &c->cc);
    rk_threads_blas(before);
    if (c->cc.status == CHOLMOD_NOT_POSDEF && !c->indefinite) {
        rk_fail(err, "not positive definite (CHOLMOD stopped at column %d of %d)", (int)c->L->minor, c->n);
        return RK_CHOL_NOT_POSDEF;
    }
    if (!ok || c->cc.status < CHOLMOD_OK) return rk_fail(err, "CHOLMOD factorization failed (status %d)", c->cc.status);
    return 0;
}

int rk_chol_indefinite(rk_chol *c, rk_error *err)
{
    c->indefinite = 1;
    c->cc.supernodal = CHOLMOD_SIMPLICIAL;
    c->cc.final_ll = 0;
    return rk_chol_analyze(c, c->S, err) || rk_chol_factor(c, err) ? -1 : 0;
}

int rk_chol_solve(rk_chol *c, const double *b, double *x, rk_error *err)
{
    cholmod_dense B;
    rk_cholmod_dense_view(b, c->n, &B);
    int before = rk_threads_blas(c->blas_threads);
    int ok = cholmod_solve2(CHOLMOD_A, c->L, &B, NULL, &c->sol, NULL, &c->Y, &c->E, &c->cc);
    rk_threads_blas(before);
    if (!ok) return rk_fail(err, "CHOLMOD solve failed (status %d)", c->cc.status);
    memmove(x, c->sol->x, sizeof(double) * (size_t)c->n);
    return 0;
}

double rk_chol_rcond(rk_chol *c)
{
    return c->L ? cholmod_rcond(c->L, &c->cc) : 0;
}

int rk_chol_minor(const rk_chol *c)
{
    return c->L ? (int)c->L->minor : -1;
}

void rk_chol_free(rk_chol *c)
{
    if (!c->started) return;
    cholmod_free_factor(&c->L, &c->cc);
    cholmod_free_dense(&c->sol, &c->cc);
    cholmod_free_dense(&c->Y, &c->cc);
    cholmod_free_dense(&c->E, &c->cc);
    cholmod_finish(&c->cc);
    memset(c, 0, sizeof *c);
}
