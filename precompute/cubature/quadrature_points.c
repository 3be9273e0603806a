/* Mesh-free integration points (cubature.h, rk_skin_points): each point's G from the skinning
 * weights and their gradients (freeform paper Eq. 21), no element anywhere. */
#include "cubature/cubature.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void rk_skin_points_free(rk_skin_points *P)
{
    free(P->X);
    free(P->W);
    free(P->dW);
    free(P->volume);
    free(P->density);
    free(P->model);
    free(P->mu);
    free(P->lambda);
    memset(P, 0, sizeof *P);
}

void rk_skin_points_G(const rk_skin_points *P, int i, double *G)
{
    int H = P->H, r = 12 * H;
    const double *X = P->X + 3 * (size_t)i;
    memset(G, 0, sizeof(double) * 9 * (size_t)r);
    for (int j = 0; j < H; j++) {
        double w = P->W[(size_t)i + (size_t)P->n * j];
        const double *d = P->dW + 3 * (size_t)i + 3 * (size_t)P->n * j;
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) {
                double *row = G + (size_t)(3 * a + b) * r + 12 * j + 4 * a;
                for (int c = 0; c < 3; c++) row[c] = X[c] * d[b] + (c == b ? w : 0);
                row[3] = d[b];
            }
    }
}

int rk_quadrature_points(const rk_skin_points *P, int count, const int *index, const double *weights,
                         rk_quadrature *Q, rk_error *err)
{
    memset(Q, 0, sizeof *Q);
    int r = 12 * P->H;
    if (P->H < 1 || count < 0) return rk_fail(err, "quadrature: %d handles, %d points", P->H, count);
    if (rk_quadrature_alloc(Q, r, count, P->H, "integration points", err)) return -1;
    for (int k = 0; k < count; k++) {
        int i = index ? index[k] : k;
        if (i < 0 || i >= P->n) {
            rk_quadrature_free(Q);
            return rk_fail(err, "quadrature: integration point %d out of range (there are %d)", i, P->n);
        }
        double w = weights ? weights[k] : 1.0;
        if (!(isfinite(w) && w >= 0)) {
            rk_quadrature_free(Q);
            return rk_fail(err, "quadrature: weight %g of integration point %d is not a non-negative number", w, i);
        }
        rk_skin_points_G(P, i, Q->G + (size_t)k * 9 * r);
        /* N: row (a = 0, b) of G holds N[(j, c), b] at columns 12 j + c */
        for (int b = 0; b < 3; b++)
            for (int j = 0; j < P->H; j++)
                for (int c = 0; c < 4; c++)
                    Q->N[((size_t)k * 3 + b) * 4 * P->H + 4 * j + c] = Q->G[(size_t)k * 9 * r + (size_t)b * r + 12 * j + c];
        Q->weight[k] = P->volume[i] * w;
        Q->model[k] = P->model[i];
        Q->mu[k] = P->mu[i];
        Q->lambda[k] = P->lambda[i];
        Q->source[k] = i;
    }
    return 0;
}
