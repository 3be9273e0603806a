/* Reverse mode (neural.h, rk_mlp_backward): the chain rule from the output layer down, on the
 * activations the forward pass left in the workspace. With delta_l = dL/dz_l (rows x n_{l+1}):
 *   dW_l += delta_l^T a_l,   db_l += the column sums of delta_l,
 *   dL/da_l = delta_l W_l,   delta_{l-1} = dL/da_l (.) ELU'(z_{l-1}),
 * and dL/dX = dL/da_0. One dgemm for each product. */
#include "neural/neural_impl.h"

#include <cblas.h>
#include <string.h>

int rk_mlp_backward(const rk_mlp *m, rk_mlp_work *w, const double *dY, double *dparams, double *dX, rk_error *err)
{
    if (mlp_work_check(m, w, err)) return -1;
    int B = w->rows, L = m->nlayers;
    if (B < 1) return rk_fail(err, "mlp backward: no forward pass in the workspace to differentiate");
    /* the output layer is the identity: delta_{L-1} = dY */
    const double *delta = dY;
    int next = 0;
    for (int l = L - 1; l >= 0; l--) {
        int in = m->sizes[l], out = m->sizes[l + 1];
        const double *W = m->params + m->offset[l];
        const double *A = w->act + w->aoff[l];
        double *dW = dparams + m->offset[l], *db = dW + (long)out * in;
        /* dW (out x in) += delta^T (out x B) A (B x in) */
        cblas_dgemm(CblasRowMajor, CblasTrans, CblasNoTrans, out, in, B, 1.0, delta, out, A, in, 1.0, dW, in);
        /* row by row, in order: the same sum whatever BLAS would do with a gemv */
        for (int r = 0; r < B; r++)
            for (int o = 0; o < out; o++) db[o] += delta[(long)r * out + o];
        if (l == 0 && !dX) break;
        /* g (B x in) = delta (B x out) W (out x in): dL/da_l, into dX at the input layer */
        double *g = l == 0 ? dX : w->delta[next];
        cblas_dgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, B, in, out, 1.0, delta, out, W, in, 0.0, g, in);
        if (l == 0) break;
        /* a_l is a hidden layer's ELU output: delta_{l-1} = g (.) ELU'(z) */
        for (long i = 0; i < (long)B * in; i++) g[i] *= elu_grad_from_value(A[i]);
        delta = g;
        next ^= 1;
    }
    return 0;
}
