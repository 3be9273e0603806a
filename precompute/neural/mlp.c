/* The network (neural.h): sizes and the one parameter array, seeded initialisation, ELU, the
 * workspace and the batched forward pass, one dgemm per layer. */
#include "neural/neural_impl.h"

#include <cblas.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Far beyond any network here; keeps every count and dgemm dimension inside an int. */
#define MLP_MAX_UNITS (1 << 24)
#define MLP_MAX_PARAMS (1L << 40)

void rk_mlp_free(rk_mlp *m)
{
    free(m->sizes);
    free(m->offset);
    free(m->params);
    memset(m, 0, sizeof *m);
}

long rk_mlp_params(const rk_mlp *m)
{
    return m->offset ? m->offset[m->nlayers] : 0;
}

int rk_mlp_init(rk_mlp *m, int nsizes, const int *sizes, unsigned long long seed, rk_error *err)
{
    memset(m, 0, sizeof *m);
    if (!sizes || nsizes < 2) return rk_fail(err, "mlp: %d layer sizes given; need at least 2 (inputs, outputs)", nsizes);
    for (int l = 0; l < nsizes; l++)
        if (sizes[l] < 1 || sizes[l] > MLP_MAX_UNITS)
            return rk_fail(err, "mlp: layer size %d is %d; must be 1 to %d", l, sizes[l], MLP_MAX_UNITS);
    int L = nsizes - 1;
    m->nlayers = L;
    m->sizes = rk_calloc((size_t)nsizes, sizeof(int), err);
    m->offset = rk_calloc((size_t)nsizes, sizeof(long), err);
    if (!m->sizes || !m->offset) goto fail;
    memcpy(m->sizes, sizes, sizeof(int) * (size_t)nsizes);
    for (int l = 0; l < L; l++) {
        long in = sizes[l], out = sizes[l + 1];
        m->offset[l + 1] = m->offset[l] + out * in + out;
        if (m->offset[l + 1] > MLP_MAX_PARAMS) {
            rk_fail(err, "mlp: more than %ld parameters by layer %d", MLP_MAX_PARAMS, l);
            goto fail;
        }
    }
    m->params = rk_calloc((size_t)m->offset[L], sizeof(double), err);
    if (!m->params) goto fail;
    uint64_t state = seed;
    for (int l = 0; l < L; l++) {
        long in = sizes[l], out = sizes[l + 1];
        /* uniform on [-c, c] has variance c^2 / 3: He's 2 / n_in before an ELU, Glorot's
         * 2 / (n_in + n_out) on the linear output layer */
        double c = l + 1 < L ? sqrt(6.0 / (double)in) : sqrt(6.0 / (double)(in + out));
        double *W = m->params + m->offset[l];
        for (long i = 0; i < out * in; i++) W[i] = c * (2.0 * rk_uniform(&state) - 1.0);
        /* the biases (W + out in, out values) stay 0 */
    }
    return 0;
fail:
    rk_mlp_free(m);
    return -1;
}

double rk_elu(double z)
{
    return elu(z);
}

double rk_elu_grad(double z)
{
    return z > 0 ? 1.0 : exp(z);
}

void rk_mlp_work_free(rk_mlp_work *w)
{
    free(w->sizes);
    free(w->aoff);
    free(w->act);
    for (int i = 0; i < 2; i++) {
        free(w->delta[i]);
        free(w->tan[i]);
    }
    memset(w, 0, sizeof *w);
}

int rk_mlp_work_init(rk_mlp_work *w, const rk_mlp *m, int batch, int tangents, rk_error *err)
{
    memset(w, 0, sizeof *w);
    if (!m->sizes) return rk_fail(err, "mlp workspace: the network is not initialised");
    if (batch < 1) return rk_fail(err, "mlp workspace: batch %d; must be at least 1", batch);
    if (tangents < 0) return rk_fail(err, "mlp workspace: tangents %d; must be at least 0", tangents);
    int L = m->nlayers, width = 0;
    long units = 0;
    for (int l = 0; l <= L; l++) {
        units += m->sizes[l];
        if (m->sizes[l] > width) width = m->sizes[l];
    }
    if ((long)batch * tangents > INT_MAX || (long)batch * width > INT_MAX / 2)
        return rk_fail(err, "mlp workspace: batch %d x tangents %d x width %d is too large", batch, tangents, width);
    w->nlayers = L;
    w->batch = batch;
    w->tangents = tangents;
    w->width = width;
    w->sizes = rk_calloc((size_t)L + 1, sizeof(int), err);
    w->aoff = rk_calloc((size_t)L + 1, sizeof(long), err);
    w->act = rk_calloc((size_t)batch * (size_t)units, sizeof(double), err);
    for (int i = 0; i < 2 && w->act; i++) {
        w->delta[i] = rk_calloc((size_t)batch * (size_t)width, sizeof(double), err);
        if (!w->delta[i]) break;
        if (tangents > 0) {
            w->tan[i] = rk_calloc((size_t)batch * (size_t)tangents * (size_t)width, sizeof(double), err);
            if (!w->tan[i]) break;
        }
    }
    if (!w->sizes || !w->aoff || !w->act || !w->delta[0] || !w->delta[1] || (tangents > 0 && (!w->tan[0] || !w->tan[1]))) {
        rk_mlp_work_free(w);
        return -1;
    }
    memcpy(w->sizes, m->sizes, sizeof(int) * ((size_t)L + 1));
    for (int l = 0; l < L; l++) w->aoff[l + 1] = w->aoff[l] + (long)batch * m->sizes[l];
    return 0;
}

int mlp_work_check(const rk_mlp *m, const rk_mlp_work *w, rk_error *err)
{
    if (!m->params) return rk_fail(err, "mlp: the network is not initialised");
    if (!w->act) return rk_fail(err, "mlp: the workspace is not initialised");
    int same = w->nlayers == m->nlayers;
    for (int l = 0; same && l <= m->nlayers; l++) same = w->sizes[l] == m->sizes[l];
    if (!same) return rk_fail(err, "mlp: the workspace was made for a network of another shape");
    return 0;
}

int rk_mlp_forward(const rk_mlp *m, rk_mlp_work *w, int B, const double *X, double *Y, rk_error *err)
{
    if (mlp_work_check(m, w, err)) return -1;
    if (B < 1 || B > w->batch) return rk_fail(err, "mlp forward: %d rows; the workspace holds 1 to %d", B, w->batch);
    int L = m->nlayers;
    w->rows = 0; /* no valid pass until this one completes */
    memcpy(w->act, X, sizeof(double) * (size_t)B * (size_t)m->sizes[0]);
    for (int l = 0; l < L; l++) {
        int in = m->sizes[l], out = m->sizes[l + 1];
        const double *W = m->params + m->offset[l], *b = W + (long)out * in;
        const double *A = w->act + w->aoff[l];
        double *C = w->act + w->aoff[l + 1];
        for (int r = 0; r < B; r++) memcpy(C + (long)r * out, b, sizeof(double) * (size_t)out);
        /* C (B x out) += A (B x in) W^T */
        cblas_dgemm(CblasRowMajor, CblasNoTrans, CblasTrans, B, out, in, 1.0, A, in, W, in, 1.0, C, out);
        if (l + 1 < L)
            for (long i = 0; i < (long)B * out; i++) C[i] = elu(C[i]);
    }
    w->rows = B;
    if (Y) memcpy(Y, w->act + w->aoff[L], sizeof(double) * (size_t)B * (size_t)m->sizes[L]);
    return 0;
}
