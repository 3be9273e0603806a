/* The freeform paper's beam (5 x 1 x 1 m, its first 0.5 m fixed, E = 5e6 Pa, rho = 1000, a tenth
 * of gravity) as Timoshenko theory bends it: tip deflection q L^4 / (8 E I) + q L^2 / (2 kappa G A)
 * over the free length L = 4.5 m (q = rho g A, kappa = 10 (1 + nu) / (12 + 11 nu)); and the 3D
 * solid's static sag by quadratic tets (fem/p2.c). Shared by the tests and bench/bench_p2_beam.c. */
#ifndef RK_TESTS_FREEFORM_BEAM_H
#define RK_TESTS_FREEFORM_BEAM_H

#include <math.h>
#include <stdlib.h>

#include "fem/fem.h"

#define BEAM_YOUNG 5e6
#define BEAM_DENSITY 1000.0
#define BEAM_GRAVITY 0.981
#define BEAM_FREE_LENGTH 4.5

static inline double beam_timoshenko_tip(double nu)
{
    double area = 1, inertia = 1.0 / 12, q = BEAM_DENSITY * BEAM_GRAVITY * area; /* (I is complex.h's) */
    double G = BEAM_YOUNG / (2 * (1 + nu)), kappa = 10 * (1 + nu) / (12 + 11 * nu);
    return q * pow(BEAM_FREE_LENGTH, 4) / (8 * BEAM_YOUNG * inertia) +
           q * BEAM_FREE_LENGTH * BEAM_FREE_LENGTH / (2 * kappa * G * area);
}

/* The freeform beam (5 x 1 x 1 m, first 0.5 m fixed, rho 1000, E 5e6, a tenth of gravity), the box
 * mesh of 20 x 4 x 4 cells (1,920 tets, the Table-1 scenes') refined `levels` times 1:8: the tip sag
 * (mean downward displacement of the mesh vertices at x = 5). */
static inline double beam_p2_sag(double nu, int levels, int *nodes, rk_error *err)
{
    const double size[3] = {5, 1, 1};
    const int cells[3] = {20, 4, 4};
    rk_mesh m;
    rk_p2_mesh p;
    double sag = NAN;
    if (rk_mesh_box(size, cells, &m, err)) return NAN;
    if (levels > 0) {
        rk_mesh fine;
        int rc = rk_mesh_refine(&m, levels, &fine, err);
        rk_mesh_free(&m);
        if (rc) return NAN;
        m = fine;
    }
    if (rk_p2_mesh_init(&p, &m, err)) goto no_p2;
    unsigned char *fixed = calloc((size_t)p.nn, 1);
    double *u = calloc((size_t)3 * p.nn, sizeof(double)), body[3] = {0, -BEAM_DENSITY * BEAM_GRAVITY, 0};
    for (int i = 0; fixed && i < p.nn; i++) fixed[i] = p.X[3 * i] <= 0.5 + 1e-9;
    if (fixed && u && !rk_p2_static_linear(&p, BEAM_YOUNG, nu, body, fixed, NULL, u, err)) {
        double sum = 0;
        int count = 0;
        for (int v = 0; v < p.nv; v++)
            if (p.X[3 * v] > 5 - 1e-9) {
                sum -= u[3 * v + 1];
                count++;
            }
        sag = sum / count;
    }
    *nodes = p.nn;
    free(fixed);
    free(u);
    rk_p2_mesh_free(&p);
no_p2:
    rk_mesh_free(&m);
    return sag;
}

#endif
