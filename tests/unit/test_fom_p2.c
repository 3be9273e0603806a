/* precompute/fom: full order on quadratic tets (p2_fom.c), the converged dynamic reference of
 * issue 37. Checked against what it must reproduce exactly: a body falling freely under backward
 * Euler (no strain, the consistent load on the consistent mass: x_n = X + g h^2 n (n + 1) / 2 at every
 * node), a twisted group's nodes on their rigid path, and the static linear P2 solve (p2.c, an
 * independent assembly) as the limit of one step with an enormous time step; and it refuses what it
 * does not model. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fem/fem.h"
#include "fom/fom.h"
#include "testlib.h"

typedef struct {
    int nv, steps;
    double *x; /* (steps + 1) x 3 nv: the mesh vertices' positions */
} frames;

static int keep(void *ctx, int step, const double *x, const double *v, double seconds, rk_error *err)
{
    frames *f = ctx;
    if (step > f->steps) return rk_fail(err, "step %d past %d", step, f->steps);
    memcpy(f->x + (size_t)3 * f->nv * step, x, (size_t)3 * f->nv * sizeof(double));
    return 0;
}

static void make_beam(rk_material_model model, double poisson, rk_mesh *m, rk_fem *f)
{
    rk_error err;
    const double size[3] = {1.0, 0.25, 0.25};
    const int cells[3] = {4, 1, 1};
    rk_material mat = {model, 1e6, poisson, 1000};
    if (rk_mesh_box(size, cells, m, &err)) abort();
    rk_material *mats = malloc((size_t)m->nt * sizeof *mats);
    for (int t = 0; t < m->nt; t++) mats[t] = mat;
    if (rk_fem_init(f, m, mats, &err)) abort();
    free(mats);
}

TEST(p2_free_fall_is_exact)
{
    rk_error err;
    rk_mesh m;
    rk_fem f;
    make_beam(RK_MAT_NEOHOOKEAN, 0.45, &m, &f);
    rk_fom_options o;
    rk_fom_default_options(&o);
    o.steps = 5;
    o.h = 0.01;
    o.gravity[1] = -9.81;
    frames F = {m.nv, o.steps, calloc((size_t)3 * m.nv * (o.steps + 1), sizeof(double))};
    rk_fom_stats st;
    CHECK_OK(rk_p2_fom_run(&f, &o, keep, &F, &st, &err));
    double worst = 0;
    for (int n = 0; n <= o.steps; n++)
        for (int v = 0; v < m.nv; v++) {
            double want = m.X[3 * v + 1] - 9.81 * o.h * o.h * n * (n + 1) / 2;
            worst = fmax(worst, fabs(F.x[(size_t)3 * m.nv * n + 3 * v + 1] - want));
            worst = fmax(worst, fabs(F.x[(size_t)3 * m.nv * n + 3 * v] - m.X[3 * v]));
        }
    printf("# P2 free fall: %ld steps, %ld Newton iterations, largest error %.2e m\n", st.steps, st.newton_iterations,
           worst);
    CHECK(worst < 1e-12, "free fall off by %g m", worst);
    free(F.x);
    rk_fem_free(&f);
    rk_mesh_free(&m);
}

/* One backward Euler step of h = 1e4 s from rest is the static equilibrium up to inertia's weight
 * 1/h^2 (relative 1e-8 here): the linear material against rk_p2_static_linear, clamped at x = 0. */
TEST(p2_long_step_is_the_static_linear_solve)
{
    rk_error err;
    rk_mesh m;
    rk_fem f;
    make_beam(RK_MAT_LINEAR, 0.3, &m, &f);
    int *clamp = malloc((size_t)m.nv * sizeof(int)), nclamp = 0;
    for (int v = 0; v < m.nv; v++)
        if (m.X[3 * v] < 1e-9) clamp[nclamp++] = v;
    rk_prescribed g = {.kind = RK_MOTION_FIXED, .count = nclamp, .verts = clamp};
    rk_fom_options o;
    rk_fom_default_options(&o);
    o.steps = 1;
    o.h = 1e4;
    o.gravity[1] = -9.81;
    o.nprescribed = 1;
    o.prescribed = &g;
    o.newton_tol = 1e-14; /* m/s: a linear problem converges in one Newton step anyway */
    frames F = {m.nv, 1, calloc((size_t)3 * m.nv * 2, sizeof(double))};
    CHECK_OK(rk_p2_fom_run(&f, &o, keep, &F, NULL, &err));
    rk_p2_mesh p;
    CHECK_OK(rk_p2_mesh_init(&p, &m, &err));
    unsigned char *fixed = calloc((size_t)p.nn, 1);
    double *u = calloc((size_t)3 * p.nn, sizeof(double)), body[3] = {0, -9.81 * 1000, 0};
    for (int i = 0; i < p.nn; i++) fixed[i] = p.X[3 * i] < 1e-9;
    CHECK_OK(rk_p2_static_linear(&p, 1e6, 0.3, body, fixed, NULL, u, &err));
    double worst = 0, sag = 0;
    for (int v = 0; v < m.nv; v++)
        for (int c = 0; c < 3; c++) {
            worst = fmax(worst, fabs(F.x[(size_t)3 * m.nv + 3 * v + c] - m.X[3 * v + c] - u[3 * v + c]));
            sag = fmax(sag, fabs(u[3 * v + c]));
        }
    printf("# P2 long step against the static solve: sag %.4e m, largest difference %.2e m\n", sag, worst);
    CHECK(sag > 1e-3 && worst < 1e-6 * sag, "difference %g m of a sag of %g m", worst, sag);
    free(fixed);
    free(u);
    free(clamp);
    rk_p2_mesh_free(&p);
    free(F.x);
    rk_fem_free(&f);
    rk_mesh_free(&m);
}

/* The whole end face twisted about the beam's axis: its vertices are on the rigid path (edge nodes
 * too, or the face would tear: checked through the vertices' distances staying rigid). */
TEST(p2_twisted_group_follows_its_path)
{
    rk_error err;
    rk_mesh m;
    rk_fem f;
    make_beam(RK_MAT_NEOHOOKEAN, 0.45, &m, &f);
    int *clamp = malloc((size_t)m.nv * sizeof(int)), *end = malloc((size_t)m.nv * sizeof(int)), nc = 0, ne = 0;
    for (int v = 0; v < m.nv; v++) {
        if (m.X[3 * v] < 1e-9) clamp[nc++] = v;
        if (m.X[3 * v] > 1 - 1e-9) end[ne++] = v;
    }
    rk_prescribed g[2] = {{.kind = RK_MOTION_FIXED, .count = nc, .verts = clamp},
                          {.kind = RK_MOTION_TWIST, .count = ne, .verts = end, .axis = {1, 0, 0},
                           .center = {1, 0.125, 0.125}, .rate = 3.0}};
    rk_fom_options o;
    rk_fom_default_options(&o);
    o.steps = 10;
    o.h = 0.01;
    o.integrator = RK_BDF2;
    o.nprescribed = 2;
    o.prescribed = g;
    frames F = {m.nv, o.steps, calloc((size_t)3 * m.nv * (o.steps + 1), sizeof(double))};
    rk_fom_stats st;
    CHECK_OK(rk_p2_fom_run(&f, &o, keep, &F, &st, &err));
    double worst = 0, R[9], shift[3];
    rk_prescribed_transform(&g[1], o.steps * o.h, R, shift);
    for (int k = 0; k < ne; k++) {
        const double *X = &m.X[3 * end[k]], *x = &F.x[(size_t)3 * m.nv * o.steps + 3 * end[k]];
        for (int c = 0; c < 3; c++)
            worst = fmax(worst, fabs(x[c] - (R[3 * c] * X[0] + R[3 * c + 1] * X[1] + R[3 * c + 2] * X[2] + shift[c])));
    }
    printf("# P2 twist, BDF2: %ld Newton iterations in %ld steps (%ld unconverged), end face off its path by %.2e m\n",
           st.newton_iterations, st.steps, st.unconverged_steps, worst);
    CHECK(worst < 1e-14, "end face off its path by %g m", worst);
    CHECK(st.unconverged_steps == 0, "%ld steps did not converge", st.unconverged_steps);
    free(clamp);
    free(end);
    free(F.x);
    rk_fem_free(&f);
    rk_mesh_free(&m);
}

TEST(p2_refuses_what_it_does_not_model)
{
    rk_error err;
    rk_mesh m;
    rk_fem f;
    make_beam(RK_MAT_NEOHOOKEAN, 0.3, &m, &f);
    rk_fom_options o;
    rk_fom_default_options(&o);
    o.steps = 1;
    o.contact.self = 1;
    CHECK(rk_p2_fom_run(&f, &o, NULL, NULL, NULL, &err) != 0 && strstr(err.msg, "self-contact"),
          "self-contact: '%s'", err.msg);
    rk_fom_default_options(&o);
    o.lumped_mass = 1;
    CHECK(rk_p2_fom_run(&f, &o, NULL, NULL, NULL, &err) != 0 && strstr(err.msg, "lumped"), "lumped: '%s'", err.msg);
    rk_fom_default_options(&o);
    o.h = -1;
    CHECK(rk_p2_fom_run(&f, &o, NULL, NULL, NULL, &err) != 0, "a negative step was taken");
    rk_fem_free(&f);
    rk_mesh_free(&m);
}

int main(void)
{
    RUN(p2_free_fall_is_exact);
    RUN(p2_long_step_is_the_static_linear_solve);
    RUN(p2_twisted_group_follows_its_path);
    RUN(p2_refuses_what_it_does_not_model);
    return test_finish();
}
