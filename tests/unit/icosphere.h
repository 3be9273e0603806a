/* An icosphere surface for the cage tests (test_cage_build, test_pipeline_cage). */
#ifndef RK_TEST_ICOSPHERE_H
#define RK_TEST_ICOSPHERE_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/mesh.h"

/* An icosphere of radius R: the icosahedron split `levels` times (each triangle into four, midpoints
 * pushed to the sphere), outward. */
static inline int icosphere(int levels, double R, rk_surface *s, rk_error *err)
{
    double t = (1 + sqrt(5.0)) / 2;
    double V[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                       {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    int F[20][3] = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                    {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    int nf = 20 << (2 * levels), nv = 12, cap = 10 * nf + 12;
    s->X = malloc(sizeof(double) * 3 * (size_t)cap);
    s->tris = malloc(sizeof(int) * 3 * (size_t)nf);
    int *tmp = malloc(sizeof(int) * 3 * (size_t)nf);
    int *key = malloc(sizeof(int) * 3 * (size_t)cap); /* (a, b, midpoint), linear search per level */
    if (!s->X || !s->tris || !tmp || !key) return rk_fail(err, "out of memory");
    memcpy(s->X, V, sizeof V);
    memcpy(s->tris, F, sizeof F);
    int cur = 20;
    for (int l = 0; l < levels; l++) {
        int nkeys = 0, out = 0;
        for (int f = 0; f < cur; f++) {
            int m[3];
            for (int e = 0; e < 3; e++) {
                int a = s->tris[3 * f + e], b = s->tris[3 * f + (e + 1) % 3], lo = a < b ? a : b, hi = a < b ? b : a;
                m[e] = -1;
                for (int k = 0; k < nkeys && m[e] < 0; k++)
                    if (key[3 * k] == lo && key[3 * k + 1] == hi) m[e] = key[3 * k + 2];
                if (m[e] < 0) {
                    for (int i = 0; i < 3; i++) s->X[3 * nv + i] = 0.5 * (s->X[3 * a + i] + s->X[3 * b + i]);
                    key[3 * nkeys] = lo, key[3 * nkeys + 1] = hi, key[3 * nkeys + 2] = nv;
                    m[e] = nv++, nkeys++;
                }
            }
            const int *v = s->tris + 3 * f;
            int kids[4][3] = {{v[0], m[0], m[2]}, {v[1], m[1], m[0]}, {v[2], m[2], m[1]}, {m[0], m[1], m[2]}};
            memcpy(tmp + 3 * out, kids, sizeof kids);
            out += 4;
        }
        memcpy(s->tris, tmp, sizeof(int) * 3 * (size_t)out);
        cur = out;
    }
    for (int v = 0; v < nv; v++) {
        double *x = s->X + 3 * v, len = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        for (int i = 0; i < 3; i++) x[i] *= R / len;
    }
    s->nv = nv;
    s->nf = cur;
    free(tmp);
    free(key);
    int flipped;
    return rk_surface_check_and_orient(s, "icosphere", &flipped, err);
}

#endif
