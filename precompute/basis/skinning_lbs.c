/* Linear blend skinning (freeform paper Eq. 1): x = X + sum_j W_j(X) Z_j Xbar with Z_j a 3x4
 * affine handle, so each weight gives 12 displacement columns. */
#include "basis/basis.h"

#include <string.h>

void rk_skinning_to_U(const double *W, int n, int m, const double *X, double *U)
{
    size_t rows = 3 * (size_t)n;
    memset(U, 0, rows * 12 * (size_t)m * sizeof(double));
    for (int j = 0; j < m; j++)
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 4; b++) {
                double *col = U + rows * (size_t)(12 * j + 4 * a + b);
                for (int i = 0; i < n; i++) {
                    double xb = b < 3 ? X[3 * i + b] : 1.0;
                    col[3 * i + a] = W[(size_t)j * n + i] * xb;
                }
            }
}
