/* Minibatch MSE training (neural.h, rk_mlp_train): shuffle, forward, backward, Adam, with the
 * phased learning rate; everything that decides a bit of the result (the permutation, the
 * summation order, OpenBLAS's thread count) is fixed, so a seed names one outcome. */
#include "neural/neural_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void rk_mlp_train_default_options(rk_mlp_train_options *o)
{
    o->epochs = 400;
    o->batch = 64;
    o->base_lr = RK_LR_BASE_DEFAULT;
    o->seed = 1;
}

static int check_input(const rk_mlp *m, const double *X, const double *Y, int N, const rk_mlp_train_options *o,
                       rk_error *err)
{
    if (!m->params) return rk_fail(err, "mlp training: the network is not initialised");
    if (N < 1) return rk_fail(err, "mlp training: %d training pairs; need at least 1", N);
    if (!X || !Y) return rk_fail(err, "mlp training: no %s given", !X ? "inputs X" : "targets Y");
    if (o->epochs < 1) return rk_fail(err, "mlp training: epochs %d; must be at least 1", o->epochs);
    if (o->batch < 1) return rk_fail(err, "mlp training: batch %d; must be at least 1", o->batch);
    if (!(o->base_lr > 0) || !isfinite(o->base_lr))
        return rk_fail(err, "mlp training: learning rate base_lr %g; must be finite and above 0", o->base_lr);
    int n0 = m->sizes[0], nL = m->sizes[m->nlayers];
    for (long r = 0; r < N; r++) {
        for (int c = 0; c < n0; c++)
            if (!isfinite(X[r * n0 + c]))
                return rk_fail(err, "mlp training: input X row %ld column %d is %g", r, c, X[r * n0 + c]);
        for (int c = 0; c < nL; c++)
            if (!isfinite(Y[r * nL + c]))
                return rk_fail(err, "mlp training: target Y row %ld column %d is %g", r, c, Y[r * nL + c]);
    }
    return 0;
}

/* The MSE over all N pairs, `batch` rows per forward pass, summed in row order. */
static int dataset_mse(const rk_mlp *m, rk_mlp_work *w, const double *X, const double *Y, int N, double *out,
                       rk_error *err)
{
    int n0 = m->sizes[0], nL = m->sizes[m->nlayers];
    double sum = 0;
    for (int r0 = 0; r0 < N; r0 += w->batch) {
        int nb = N - r0 < w->batch ? N - r0 : w->batch;
        if (rk_mlp_forward(m, w, nb, X + (long)r0 * n0, NULL, err)) return -1;
        const double *P = w->act + w->aoff[m->nlayers], *T = Y + (long)r0 * nL;
        for (long i = 0; i < (long)nb * nL; i++) sum += (P[i] - T[i]) * (P[i] - T[i]);
    }
    *out = sum / ((double)N * nL);
    return 0;
}

typedef struct {
    rk_mlp_work w;
    rk_adam adam;
    double *grad, *start, *xb, *yb, *dy;
    int *perm;
} train_buffers;

static void buffers_free(train_buffers *t)
{
    rk_mlp_work_free(&t->w);
    rk_adam_free(&t->adam);
    free(t->grad);
    free(t->start);
    free(t->xb);
    free(t->yb);
    free(t->dy);
    free(t->perm);
}

static int buffers_init(train_buffers *t, const rk_mlp *m, int N, int batch, rk_error *err)
{
    memset(t, 0, sizeof *t);
    long P = rk_mlp_params(m);
    int n0 = m->sizes[0], nL = m->sizes[m->nlayers];
    if (rk_mlp_work_init(&t->w, m, batch, 0, err) || rk_adam_init(&t->adam, P, err)) return -1;
    t->grad = rk_calloc((size_t)P, sizeof(double), err);
    t->start = rk_calloc((size_t)P, sizeof(double), err);
    t->xb = rk_calloc((size_t)batch * n0, sizeof(double), err);
    t->yb = rk_calloc((size_t)batch * nL, sizeof(double), err);
    t->dy = rk_calloc((size_t)batch * nL, sizeof(double), err);
    t->perm = rk_calloc((size_t)N, sizeof(int), err);
    if (!t->grad || !t->start || !t->xb || !t->yb || !t->dy || !t->perm) return -1;
    for (int i = 0; i < N; i++) t->perm[i] = i;
    return 0;
}

/* One epoch: a fresh shuffle of t->perm, then one Adam step per minibatch. *loss gets the mean of
 * the minibatches' losses (weighted by their rows). */
static int train_epoch(rk_mlp *m, train_buffers *t, const double *X, const double *Y, int N, double lr,
                       uint64_t *state, double *loss, rk_error *err)
{
    int n0 = m->sizes[0], nL = m->sizes[m->nlayers], batch = t->w.batch;
    long P = rk_mlp_params(m);
    for (int i = N - 1; i > 0; i--) { /* Fisher-Yates; the modulo's bias is below N / 2^64 */
        int j = (int)(rk_splitmix64(state) % (uint64_t)(i + 1)), tmp = t->perm[i];
        t->perm[i] = t->perm[j];
        t->perm[j] = tmp;
    }
    double sum = 0;
    for (int r0 = 0; r0 < N; r0 += batch) {
        int nb = N - r0 < batch ? N - r0 : batch;
        for (int r = 0; r < nb; r++) {
            long src = t->perm[r0 + r];
            memcpy(t->xb + (long)r * n0, X + src * n0, sizeof(double) * (size_t)n0);
            memcpy(t->yb + (long)r * nL, Y + src * nL, sizeof(double) * (size_t)nL);
        }
        if (rk_mlp_forward(m, &t->w, nb, t->xb, NULL, err)) return -1;
        /* L = (1 / (nb nL)) sum (p - y)^2, dL/dp = 2 (p - y) / (nb nL) */
        const double *p = t->w.act + t->w.aoff[m->nlayers];
        double scale = 1.0 / ((double)nb * nL);
        for (long i = 0; i < (long)nb * nL; i++) {
            double d = p[i] - t->yb[i];
            sum += d * d;
            t->dy[i] = 2.0 * d * scale;
        }
        memset(t->grad, 0, sizeof(double) * (size_t)P);
        if (rk_mlp_backward(m, &t->w, t->dy, t->grad, NULL, err)) return -1;
        if (rk_adam_step(&t->adam, m->params, t->grad, lr, err)) return -1;
    }
    *loss = sum / ((double)N * nL);
    return 0;
}

int rk_mlp_train(rk_mlp *m, const double *X, const double *Y, int N, const rk_mlp_train_options *o,
                 rk_mlp_train_report *report, rk_error *err)
{
    rk_mlp_train_options defaults;
    if (!o) {
        rk_mlp_train_default_options(&defaults);
        o = &defaults;
    }
    if (check_input(m, X, Y, N, o, err)) return -1;
    double t0 = rk_now();
    int batch = o->batch < N ? o->batch : N;
    long P = rk_mlp_params(m);
    train_buffers t;
    if (buffers_init(&t, m, N, batch, err)) {
        buffers_free(&t);
        return rk_error_prefix(err, "mlp training");
    }
    memcpy(t.start, m->params, sizeof(double) * (size_t)P);
    /* one BLAS thread: a threaded dgemm may split its sums differently on another thread count,
     * and these products (batch x 128) are too small to gain from threads anyway */
    int blas_before = rk_threads_blas(1);
    uint64_t state = o->seed;
    double initial = 0, final = 0, loss = 0;
    long steps = 0;
    int rc = dataset_mse(m, &t.w, X, Y, N, &initial, err);
    for (int e = 0; rc == 0 && e < o->epochs; e++) {
        double lr = rk_lr_phased(o->base_lr, e, o->epochs);
        rc = train_epoch(m, &t, X, Y, N, lr, &state, &loss, err);
        if (rc == 0 && !isfinite(loss))
            rc = rk_fail(err, "diverged at epoch %d (loss %g at learning rate %g); lower base_lr", e, loss, lr);
        else if (rc)
            rk_error_prefix(err, "epoch %d (learning rate %g)", e, lr);
        steps += (N + batch - 1) / batch;
        rk_progress("mlp training", e + 1, o->epochs);
    }
    rk_progress_done("mlp training");
    if (rc == 0) rc = dataset_mse(m, &t.w, X, Y, N, &final, err);
    if (rc == 0 && !isfinite(final)) rc = rk_fail(err, "diverged: final loss %g; lower base_lr", final);
    rk_threads_blas(blas_before);
    if (rc) {
        memcpy(m->params, t.start, sizeof(double) * (size_t)P); /* a failed run changes nothing */
        rk_error_prefix(err, "mlp training");
    } else if (report) {
        report->initial_loss = initial;
        report->final_loss = final;
        report->seconds = rk_now() - t0;
        report->steps = steps;
    }
    buffers_free(&t);
    return rc;
}
