/* Threads, set once and on purpose (util.h, "threads"). The libraries romkit links start threads
 * of their own, and on a 2-core machine their defaults oversubscribe it:
 *  - CHOLMOD 3.0 (SuiteSparse 5.12, Debian 12) wraps the memory-bound loops of its supernodal
 *    factorization (clearing and assembling supernodes, the relative map) in OpenMP regions with a
 *    fixed num_threads(4) clause, which OMP_NUM_THREADS does not cap. Its threads spin while
 *    OpenBLAS's run the supernodes' dense kernels: on the 15k-tet beam (romkit fom, 20 steps, 2
 *    cores) 0.27 s/step with the defaults, 0.11-0.14 s/step with CHOLMOD's OpenMP on one thread,
 *    and 0.5-2.0 s/step with two OpenMP and two OpenBLAS threads. Those loops gain nothing from a
 *    second thread (0.13-0.17 s/step with two OpenMP threads and one OpenBLAS thread), so every
 *    OpenMP region runs on one thread: max-active-levels is 0 (OpenMP 5: no region is active).
 *  - OpenBLAS (its pthreads build) gets its count through openblas_set_num_threads; CHOLMOD's
 *    parallelism is OpenBLAS's, inside the supernodes' BLAS calls (rk_threads_blas).
 *  - romkit's own loops (element assembly) run on the workers below: plain threads that block
 *    between jobs. OpenMP threads were tried first and lost: libgomp's workers spin after each
 *    region (its default wait policy, settable only by OMP_WAIT_POLICY before the program starts)
 *    beside OpenBLAS's, and the beam's assembly took 4.7 s on 2 threads against 1.15 s on one. */
#define _GNU_SOURCE /* sched_getaffinity, CPU_COUNT */
#include "util/util.h"

#include <errno.h>
#include <omp.h>
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* OpenBLAS's setter (cblas-openblas.h declares it; util includes no BLAS header). */
void openblas_set_num_threads(int num_threads);

static int threads_count = 0; /* 0: not set yet */
static int blas_count = 0;

/* CPUs this process may run on: its affinity mask, capped by a cgroup v2 CPU quota. */
static int available_cpus(void)
{
    int n = 1;
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) == 0) n = CPU_COUNT(&set);
    FILE *fp = fopen("/sys/fs/cgroup/cpu.max", "r");
    if (fp) {
        char quota[32];
        long period;
        if (fscanf(fp, "%31s %ld", quota, &period) == 2 && strcmp(quota, "max") != 0 && period > 0) {
            long q = atol(quota), cap = (q + period - 1) / period;
            if (cap >= 1 && cap < n) n = (int)cap;
        }
        fclose(fp);
    }
    return n < 1 ? 1 : n;
}

static void apply(int n)
{
    threads_count = n;
    blas_count = n;
    openblas_set_num_threads(n);
    omp_set_max_active_levels(0); /* CHOLMOD's OpenMP regions on one thread (header) */
}

int rk_threads_init(rk_error *err)
{
    int def = available_cpus();
    if (def > RK_THREADS_DEFAULT_MAX) def = RK_THREADS_DEFAULT_MAX;
    const char *s = getenv("ROMKIT_THREADS");
    if (!s || !*s) {
        apply(def);
        return 0;
    }
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || *end || v < 1 || v > RK_THREADS_MAX) {
        apply(def);
        return rk_fail(err, "ROMKIT_THREADS=%s: expected a whole number from 1 to %d (unset: %d here, the CPUs available)",
                       s, RK_THREADS_MAX, def);
    }
    apply((int)v);
    return 0;
}

int rk_threads(void)
{
    if (!threads_count) {
        rk_error ignored;
        rk_threads_init(&ignored); /* a bad ROMKIT_THREADS falls back to the default */
    }
    return threads_count;
}

int rk_threads_blas(int n)
{
    int all = rk_threads(), before = blas_count;
    if (n < 1) n = 1;
    if (n > all) n = all;
    if (n != blas_count) {
        openblas_set_num_threads(n);
        blas_count = n;
    }
    return before;
}

/* ---- the workers: rk_threads() - 1 of them, started at the first parallel loop; the calling
 * thread is one more. A job hands out chunks through an atomic counter; workers sleep on a
 * condition variable between jobs (no spinning: the machine may be shared). ---- */

typedef struct {
    pthread_mutex_t lock;
    pthread_cond_t wake, done;
    long generation;       /* bumped for each job */
    int started, nworkers; /* workers running */
    int active;            /* workers still on the current job */
    int helpers;           /* workers the current job may use */
    /* the job */
    rk_range_fn body;
    void *ctx;
    long n, chunk, chunks;
    atomic_long next;
} pool_t;

static pool_t pool = {.lock = PTHREAD_MUTEX_INITIALIZER, .wake = PTHREAD_COND_INITIALIZER, .done = PTHREAD_COND_INITIALIZER};

static void run_chunks(void)
{
    for (;;) {
        long c = atomic_fetch_add(&pool.next, 1);
        if (c >= pool.chunks) return;
        long begin = c * pool.chunk, end = begin + pool.chunk < pool.n ? begin + pool.chunk : pool.n;
        pool.body(pool.ctx, begin, end);
    }
}

static void *worker(void *arg)
{
    int id = (int)(long)arg;
    long seen = 0;
    pthread_mutex_lock(&pool.lock);
    for (;;) {
        while (pool.generation == seen) pthread_cond_wait(&pool.wake, &pool.lock);
        seen = pool.generation;
        if (id >= pool.helpers) continue; /* not needed for this one */
        pthread_mutex_unlock(&pool.lock);
        run_chunks();
        pthread_mutex_lock(&pool.lock);
        if (--pool.active == 0) pthread_cond_signal(&pool.done);
    }
    return NULL;
}

/* Starts workers up to `want`; returns how many run (fewer when a thread cannot be created). */
static int start_workers(int want)
{
    while (pool.nworkers < want) {
        pthread_t t;
        pthread_attr_t attr;
        pthread_attr_init(&attr);
        pthread_attr_setdetachstate(&attr, PTHREAD_CREATE_DETACHED);
        int rc = pthread_create(&t, &attr, worker, (void *)(long)pool.nworkers);
        pthread_attr_destroy(&attr);
        if (rc) break;
        pool.nworkers++;
    }
    return pool.nworkers;
}

void rk_parallel_for(long n, long chunk, rk_range_fn body, void *ctx)
{
    rk_parallel_for_beside(n, chunk, body, ctx, NULL, NULL);
}

void rk_parallel_for_beside(long n, long chunk, rk_range_fn body, void *ctx, void (*first)(void *), void *first_ctx)
{
    /* one job at a time: a loop started while another runs (from a body, or from another thread
     * of the program) runs on its caller's thread */
    static pthread_mutex_t job = PTHREAD_MUTEX_INITIALIZER;
    if (n <= 0) {
        if (first) first(first_ctx);
        return;
    }
    if (chunk < 1) chunk = 1;
    long chunks = (n + chunk - 1) / chunk;
    int nt = rk_threads();
    if (nt > chunks) nt = (int)chunks;
    if (nt <= 1 || pthread_mutex_trylock(&job) != 0) {
        if (first) first(first_ctx);
        body(ctx, 0, n);
        return;
    }
    pthread_mutex_lock(&pool.lock);
    int helpers = start_workers(nt - 1);
    if (helpers > nt - 1) helpers = nt - 1;
    pool.body = body;
    pool.ctx = ctx;
    pool.n = n;
    pool.chunk = chunk;
    pool.chunks = chunks;
    atomic_store(&pool.next, 0);
    pool.helpers = helpers;
    pool.active = helpers;
    pool.generation++;
    pthread_cond_broadcast(&pool.wake);
    pthread_mutex_unlock(&pool.lock);
    if (first) first(first_ctx);
    run_chunks();
    pthread_mutex_lock(&pool.lock);
    while (pool.active > 0) pthread_cond_wait(&pool.done, &pool.lock);
    pthread_mutex_unlock(&pool.lock);
    pthread_mutex_unlock(&job);
}
