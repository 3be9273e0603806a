/* Test fixture of the pressure tests (test_fom_pressure.c, test_fom_lame.c): a box with a carved
 * cubic void whose walls are a chamber, and a static solve under chambers. */
#ifndef RK_TEST_CHAMBER_BOX_H
#define RK_TEST_CHAMBER_BOX_H

#include <stdlib.h>
#include <string.h>

#include "fom/fom.h"
#include "mesh/mesh.h"
#include "fem_body.h"

/* A box of n^3 cells, size s, with the middle cells inside [lo, hi]^3 carved out; the chamber is
 * the boundary faces whose centroid lies inside the box [lo - eps, hi + eps]^3. */
typedef struct {
    rk_mesh m;
    rk_chamber c;
} carved;

static inline int carve_box(carved *cv, int n, double s, double lo, double hi, rk_error *err)
{
    double size[3] = {s, s, s};
    int cells[3] = {n, n, n};
    memset(cv, 0, sizeof *cv);
    rk_box b = {{lo, lo, lo}, {hi, hi, hi}};
    if (rk_mesh_box(size, cells, &cv->m, err) || rk_mesh_carve(&cv->m, &b, 1, err)) return -1;
    int *tris, nf;
    if (rk_mesh_boundary(&cv->m, &tris, &nf, err)) return -1;
    cv->c.tris = calloc(3 * (size_t)nf, sizeof(int));
    double eps = 1e-9 * s;
    rk_box g = {{lo - eps, lo - eps, lo - eps}, {hi + eps, hi + eps, hi + eps}};
    for (int t = 0; t < nf; t++) {
        double c[3] = {0, 0, 0};
        for (int k = 0; k < 3; k++)
            for (int i = 0; i < 3; i++) c[i] += cv->m.X[3 * tris[3 * t + k] + i] / 3;
        if (rk_box_contains(&g, c, 0)) memcpy(&cv->c.tris[3 * cv->c.nf++], &tris[3 * t], 3 * sizeof(int));
    }
    free(tris);
    return 0;
}

static inline void carved_free(carved *cv)
{
    free(cv->c.tris);
    rk_mesh_free(&cv->m);
}

/* Static equilibrium of body under its chambers (neo-Hookean, tolerance tol metres): x in fom. */
static inline int solve_static(fem_body *body, const rk_chamber *c, double tol, rk_fom *fom, rk_error *err)
{
    rk_fom_options opt;
    rk_fom_default_options(&opt);
    opt.is_static = 1;
    opt.nchambers = 1;
    opt.chambers = c;
    opt.newton_tol = tol;
    if (rk_fom_init(fom, &body->f, &opt, err)) return -1;
    if (rk_fom_static(fom, err)) {
        rk_fom_free(fom);
        return -1;
    }
    return 0;
}

#endif
