/* Fields on the RKPM kernels evaluated at any points, u(X) = sum_k phi_k(X) c_k (freeform paper
 * Eq. 6): the skinning weights W^j at mesh vertices, splat centres or integration points, and their
 * gradients (Eq. 21: what F at a mesh-free integration point is made of). The points
 * are walked in spatial chunks (rkpm_chunks.c), so each is tested only against the kernels near
 * its chunk. */
#include "basis/rkpm_chunks_impl.h"

#include <math.h>
#include <stdlib.h>

int rk_rkpm_interpolate(const rk_rkpm *k, const double *X, int n, const double *c, int m, double *W,
                        double *dW, int *regularized, rk_error *err)
{
    if (regularized) *regularized = 0;
    if (n <= 0) return 0;
    int bad = rkpm_first_nonfinite(X, n);
    if (bad >= 0)
        return rk_fail(err, "RKPM interpolation: point %d is not finite (%g, %g, %g)", bad, X[3 * bad], X[3 * bad + 1],
                       X[3 * bad + 2]);
    int cap = k->max_support, rc = -1, more;
    int *kid = rk_calloc((size_t)cap, sizeof *kid, err);
    double *phi = rk_calloc((size_t)cap, sizeof *phi, err);
    double *grad = dW ? rk_calloc(3 * (size_t)cap, sizeof *grad, err) : NULL;
    rkpm_chunks ch;
    if (!kid || !phi || (dW && !grad) || rkpm_chunks_init(&ch, k, X, n, err)) {
        free(kid);
        free(phi);
        free(grad);
        return -1;
    }
    while ((more = rkpm_chunks_next(&ch, err)) == 1)
        for (int t = 0; t < ch.np; t++) {
            int i = ch.pts[t], cnt = ch.cover_start[t + 1] - ch.cover_start[t];
            for (int q = 0; q < cnt; q++) kid[q] = ch.U[ch.cover[ch.cover_start[t] + q]];
            int damped = 0;
            if (rkpm_shape_at(k, &X[3 * i], i, cnt, kid, phi, grad, regularized ? &damped : NULL, err)) goto done;
            if (regularized) *regularized += damped;
            for (int j = 0; j < m; j++) {
                const double *cj = &c[(size_t)k->K * j];
                double s = 0;
                for (int q = 0; q < cnt; q++) s += phi[q] * cj[kid[q]];
                double gl[3] = {0, 0, 0}; /* the lifting handle's field (rkpm_lift.c), added to its column */
                if (j == k->lift_column - 1) s += rk_lift_at(&k->lift, &X[3 * i], gl);
                W[i + (size_t)n * j] = s;
                for (int b = 0; dW && b < 3; b++) {
                    double g = gl[b];
                    for (int q = 0; q < cnt; q++) g += grad[3 * q + b] * cj[kid[q]];
                    dW[3 * (size_t)i + b + 3 * (size_t)n * j] = g;
                }
            }
        }
    if (more == 0) rc = 0;
done:
    rkpm_chunks_free(&ch);
    free(kid);
    free(phi);
    free(grad);
    return rc;
}
