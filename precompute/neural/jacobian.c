/* Forward mode (neural.h, rk_mlp_jacobian): k tangents per input pushed up through the layers
 * beside the activations. Row (b, j) of the tangent block T (B k rows, one column per unit) is
 * d a / d x_b[first + j] at the current layer; a layer maps it by T <- (T W^T) (.) ELU'(z), the
 * transpose of J_l = diag(act'(z_l)) W_l J_{l-1}, so all B k tangents take one dgemm. Forward
 * rather than reverse mode because k (a latent size) is far below n_L for a decoder of many
 * outputs, and the x-inputs the Jacobian skips never enter. */
#include "neural/neural_impl.h"

#include <cblas.h>

int rk_mlp_jacobian(const rk_mlp *m, rk_mlp_work *w, int B, const double *X, int first, int k, double *Y, double *J,
                    rk_error *err)
{
    if (mlp_work_check(m, w, err)) return -1;
    int L = m->nlayers, n0 = m->sizes[0], nL = m->sizes[L];
    if (k < 1 || k > w->tangents)
        return rk_fail(err, "mlp jacobian: %d columns; the workspace holds 1 to %d", k, w->tangents);
    if (first < 0 || first > n0 - k)
        return rk_fail(err, "mlp jacobian: inputs %d to %d are outside the network's %d inputs", first, first + k - 1, n0);
    if (rk_mlp_forward(m, w, B, X, Y, err)) return rk_error_prefix(err, "mlp jacobian");
    long rows = (long)B * k;
    const double *T = NULL;
    for (int l = 0; l < L; l++) {
        int in = m->sizes[l], out = m->sizes[l + 1];
        const double *W = m->params + m->offset[l];
        double *Tn = w->tan[l & 1];
        if (l == 0) {
            /* the input tangents are unit vectors: T W^T picks W's columns first .. first + k */
            for (int b = 0; b < B; b++)
                for (int j = 0; j < k; j++)
                    for (int o = 0; o < out; o++) Tn[((long)b * k + j) * out + o] = W[(long)o * in + first + j];
        } else {
            cblas_dgemm(CblasRowMajor, CblasNoTrans, CblasTrans, (int)rows, out, in, 1.0, T, in, W, in, 0.0, Tn, out);
        }
        if (l + 1 < L) {
            const double *A = w->act + w->aoff[l + 1]; /* this layer's ELU outputs, B x out */
            for (int b = 0; b < B; b++)
                for (int j = 0; j < k; j++) {
                    double *t = Tn + ((long)b * k + j) * out;
                    for (int o = 0; o < out; o++) t[o] *= elu_grad_from_value(A[(long)b * out + o]);
                }
        }
        T = Tn;
    }
    /* row (b, j) of T is column j of input b's n_L x k Jacobian */
    for (int b = 0; b < B; b++)
        for (int j = 0; j < k; j++)
            for (int i = 0; i < nL; i++) J[((long)b * nL + i) * k + j] = T[((long)b * k + j) * nL + i];
    return 0;
}
