/* precompute/fom: free-body dynamics. Momentum conservation, the exact discrete free fall of
 * backward Euler, energy decay of BE and BDF2 with and without Rayleigh damping. */
#include "fom/fom.h"
#include "testlib.h"
#include "fem_body.h"

typedef fem_body body;

static int make_body(body *b, rk_material_model model, double young, int cells_per_axis, rk_error *err)
{
    int n = cells_per_axis;
    return fem_body_box(b, 1.0, 0.6, 0.4, n, n, n, (rk_material){model, young, 0.3, 1000.0}, err);
}

static void free_body(body *b) { fem_body_free(b); }

/* Linear momentum sum_v m_v v_v: the consistent mass has the lumped masses as row sums, so this
 * is 1^T M v for either mass. */
static void momentum(const rk_fem *f, const double *v, double p[3])
{
    p[0] = p[1] = p[2] = 0;
    for (int i = 0; i < f->nv; i++)
        for (int k = 0; k < 3; k++) p[k] += f->vertex_mass[i] * v[3 * i + k];
}

static double total_energy(const rk_fom *s) { return rk_fom_kinetic_energy(s) + rk_fom_elastic_energy(s); }

TEST(translation_and_spin_conserve_linear_momentum)
{
    rk_error err;
    body b;
    CHECK_OK(make_body(&b, RK_MAT_NEOHOOKEAN, 1e5, 2, &err));
    int n = 3 * b.f.nv;
    double *v0 = calloc((size_t)n, sizeof *v0), vt[3] = {0.3, -0.2, 0.5}, w[3] = {0.4, 1.5, -0.7};
    for (int integ = 0; integ < 2; integ++)
        for (int spin = 0; spin < 2; spin++) {
            for (int v = 0; v < b.f.nv; v++) {
                const double *X = &b.f.X[3 * v];
                double r[3] = {X[0] - 0.5, X[1] - 0.3, X[2] - 0.2};
                double wr[3] = {w[1] * r[2] - w[2] * r[1], w[2] * r[0] - w[0] * r[2], w[0] * r[1] - w[1] * r[0]};
                for (int i = 0; i < 3; i++) v0[3 * v + i] = vt[i] + (spin ? wr[i] : 0);
            }
            rk_fom_options opt;
            rk_fom_default_options(&opt);
            opt.integrator = integ ? RK_BDF2 : RK_BACKWARD_EULER;
            opt.velocity0 = v0;
            rk_fom s;
            CHECK_OK(rk_fom_init(&s, &b.f, &opt, &err));
            double p0[3], p[3], ke0 = rk_fom_kinetic_energy(&s);
            momentum(&b.f, s.v, p0);
            double pnorm = sqrt(p0[0] * p0[0] + p0[1] * p0[1] + p0[2] * p0[2]);
            for (int k = 0; k < 100; k++) {
                CHECK_OK(rk_fom_step(&s, &err));
                momentum(&b.f, s.v, p);
                for (int i = 0; i < 3; i++)
                    CHECK(fabs(p[i] - p0[i]) <= 1e-9 * pnorm, "integrator %d spin %d step %d: p[%d] = %.15g, was %.15g",
                          integ, spin, k + 1, i, p[i], p0[i]);
                if (!spin)
                    CHECK(rk_fom_elastic_energy(&s) <= 1e-12 * ke0, "translating body gained elastic energy %g",
                          rk_fom_elastic_energy(&s));
            }
            CHECK(s.stats.unconverged_steps == 0, "%ld unconverged steps", s.stats.unconverged_steps);
            if (spin) {
                /* The spinning body keeps turning: its kinetic energy stays within numerical
                 * dissipation, and the centre of mass moves with the initial translation. */
                CHECK(rk_fom_kinetic_energy(&s) > 0.5 * ke0, "spin lost %g of %g kinetic energy",
                      ke0 - rk_fom_kinetic_energy(&s), ke0);
            }
            double com[3] = {0, 0, 0}, com0[3] = {0, 0, 0}, mass = 0;
            for (int v = 0; v < b.f.nv; v++) {
                mass += b.f.vertex_mass[v];
                for (int i = 0; i < 3; i++) {
                    com[i] += b.f.vertex_mass[v] * s.x[3 * v + i];
                    com0[i] += b.f.vertex_mass[v] * b.f.X[3 * v + i];
                }
            }
            for (int i = 0; i < 3; i++)
                CHECK(fabs((com[i] - com0[i]) / mass - vt[i] * s.t) <= 1e-9, "centre of mass off by %g on axis %d",
                      (com[i] - com0[i]) / mass - vt[i] * s.t, i);
            rk_fom_free(&s);
        }
    free(v0);
    free_body(&b);
}

/* Angular momentum sum_v m_v x_v x v_v (lumped masses). Neither integrator conserves it exactly:
 * backward Euler loses O(h) per step, BDF2 far less. */
static void angular_momentum(const rk_fom *s, double L[3])
{
    L[0] = L[1] = L[2] = 0;
    for (int v = 0; v < s->fem->nv; v++) {
        const double *x = &s->x[3 * v], *u = &s->v[3 * v];
        double m = s->fem->vertex_mass[v];
        L[0] += m * (x[1] * u[2] - x[2] * u[1]);
        L[1] += m * (x[2] * u[0] - x[0] * u[2]);
        L[2] += m * (x[0] * u[1] - x[1] * u[0]);
    }
}

TEST(bdf2_nearly_conserves_angular_momentum_of_a_spinning_body)
{
    rk_error err;
    body b;
    CHECK_OK(make_body(&b, RK_MAT_NEOHOOKEAN, 1e5, 2, &err));
    int n = 3 * b.f.nv;
    double *v0 = calloc((size_t)n, sizeof *v0), w[3] = {0.4, 1.5, -0.7}, drift[2];
    for (int v = 0; v < b.f.nv; v++) {
        const double *X = &b.f.X[3 * v];
        double r[3] = {X[0] - 0.5, X[1] - 0.3, X[2] - 0.2};
        v0[3 * v] = w[1] * r[2] - w[2] * r[1];
        v0[3 * v + 1] = w[2] * r[0] - w[0] * r[2];
        v0[3 * v + 2] = w[0] * r[1] - w[1] * r[0];
    }
    for (int integ = 0; integ < 2; integ++) {
        rk_fom_options opt;
        rk_fom_default_options(&opt);
        opt.integrator = (rk_integrator)integ;
        opt.lumped_mass = 1;
        opt.velocity0 = v0;
        rk_fom s;
        CHECK_OK(rk_fom_init(&s, &b.f, &opt, &err));
        double L0[3], L[3];
        angular_momentum(&s, L0);
        for (int k = 0; k < 100; k++) CHECK_OK(rk_fom_step(&s, &err));
        angular_momentum(&s, L);
        drift[integ] = sqrt(((L[0] - L0[0]) * (L[0] - L0[0]) + (L[1] - L0[1]) * (L[1] - L0[1]) +
                             (L[2] - L0[2]) * (L[2] - L0[2])) /
                            (L0[0] * L0[0] + L0[1] * L0[1] + L0[2] * L0[2]));
        rk_fom_free(&s);
    }
    printf("# relative angular momentum drift over 100 steps: BE %.3g, BDF2 %.3g\n", drift[0], drift[1]);
    CHECK(drift[1] < 1e-3, "BDF2 angular momentum drifted by %g", drift[1]);
    CHECK(drift[0] < 0.1 && drift[1] < drift[0], "BE drift %g, BDF2 drift %g", drift[0], drift[1]);
    free(v0);
    free_body(&b);
}

/* Backward Euler with a constant force and no internal forces: M (x1 - x0 - h v0) / h^2 = M g, so
 * v_n = v0 + n h g and x_n = x0 + n h v0 + h^2 g n (n + 1) / 2 exactly. */
TEST(backward_euler_free_fall_is_exact)
{
    rk_error err;
    body b;
    CHECK_OK(make_body(&b, RK_MAT_STVK, 1e6, 2, &err));
    int n = 3 * b.f.nv;
    double g[3] = {0.5, -9.81, 0.2}, v0[3] = {1.0, 2.0, -0.5}, *vel = calloc((size_t)n, sizeof *vel);
    for (int i = 0; i < n; i++) vel[i] = v0[i % 3];
    for (int lumped = 0; lumped < 2; lumped++) {
        rk_fom_options opt;
        rk_fom_default_options(&opt);
        opt.h = 0.02;
        opt.lumped_mass = lumped;
        opt.velocity0 = vel;
        memcpy(opt.gravity, g, sizeof g);
        rk_fom s;
        CHECK_OK(rk_fom_init(&s, &b.f, &opt, &err));
        double h = opt.h;
        for (int k = 1; k <= 50; k++) {
            CHECK_OK(rk_fom_step(&s, &err));
            for (int i = 0; i < n; i++) {
                double x = b.f.X[i] + k * h * v0[i % 3] + h * h * g[i % 3] * k * (k + 1) / 2.0;
                double v = v0[i % 3] + k * h * g[i % 3];
                CHECK(fabs(s.x[i] - x) <= 1e-9 * fmax(1.0, fabs(x)), "lumped %d step %d dof %d: x = %.15g, want %.15g",
                      lumped, k, i, s.x[i], x);
                CHECK(fabs(s.v[i] - v) <= 1e-9 * fmax(1.0, fabs(v)), "lumped %d step %d dof %d: v = %.15g, want %.15g",
                      lumped, k, i, s.v[i], v);
            }
        }
        CHECK(fabs(s.t - 50 * h) < 1e-12, "t = %g after 50 steps", s.t);
        CHECK(s.stats.steps == 50 && s.stats.newton_iterations <= 100, "%ld steps, %ld Newton iterations",
              s.stats.steps, s.stats.newton_iterations);
        rk_fom_free(&s);
    }
    free(vel);
    free_body(&b);
}

/* A box released from a stretched state oscillates; both integrators dissipate energy, backward
 * Euler more than BDF2, Rayleigh damping more still; with a linear material backward Euler's
 * energy never increases. */
static int run_oscillation(const rk_fem *f, rk_integrator integ, rk_material_model model, double damping, int steps,
                           double *e0, double *e_end, int *monotone, rk_error *err)
{
    rk_fom_options opt;
    rk_fom_default_options(&opt);
    opt.integrator = integ;
    opt.h = 0.01;
    opt.rayleigh_mass = damping;
    opt.rayleigh_stiffness = damping * 1e-3;
    rk_fom s;
    if (rk_fom_init(&s, f, &opt, err)) return -1;
    for (int v = 0; v < f->nv; v++) s.x[3 * v] = 1.15 * f->X[3 * v]; /* 15% stretch along x */
    *e0 = total_energy(&s);
    *monotone = 1;
    double prev = *e0;
    for (int k = 0; k < steps; k++) {
        if (rk_fom_step(&s, err)) {
            rk_fom_free(&s);
            return -1;
        }
        double e = total_energy(&s);
        if (e > prev * (1 + 1e-9)) *monotone = 0;
        prev = e;
    }
    *e_end = prev;
    rk_fom_free(&s);
    return 0;
}

TEST(oscillation_energy_decays_more_with_backward_euler)
{
    rk_error err;
    body b;
    CHECK_OK(make_body(&b, RK_MAT_NEOHOOKEAN, 1e5, 2, &err));
    double e0, e_be, e_bdf2, e_damped;
    int mono;
    CHECK_OK(run_oscillation(&b.f, RK_BACKWARD_EULER, RK_MAT_NEOHOOKEAN, 0, 100, &e0, &e_be, &mono, &err));
    CHECK_OK(run_oscillation(&b.f, RK_BDF2, RK_MAT_NEOHOOKEAN, 0, 100, &e0, &e_bdf2, &mono, &err));
    CHECK_OK(run_oscillation(&b.f, RK_BDF2, RK_MAT_NEOHOOKEAN, 2.0, 100, &e0, &e_damped, &mono, &err));
    printf("# energy after 100 steps: start %g, BE %g, BDF2 %g, BDF2 damped %g\n", e0, e_be, e_bdf2, e_damped);
    CHECK(e0 > 0, "no initial energy");
    CHECK(e_bdf2 < e0 && e_bdf2 > 0.05 * e0, "BDF2 energy %g from %g", e_bdf2, e0);
    CHECK(e_be < 0.5 * e_bdf2, "BE energy %g not well below BDF2's %g", e_be, e_bdf2);
    CHECK(e_damped < 0.5 * e_bdf2, "damped BDF2 energy %g not below undamped %g", e_damped, e_bdf2);
    free_body(&b);

    CHECK_OK(make_body(&b, RK_MAT_LINEAR, 1e5, 2, &err));
    CHECK_OK(run_oscillation(&b.f, RK_BACKWARD_EULER, RK_MAT_LINEAR, 0, 60, &e0, &e_be, &mono, &err));
    CHECK(mono, "backward Euler on a linear material increased the energy");
    CHECK(e_be < e0, "no decay");
    free_body(&b);
}

/* Each Newton iteration factors the exact matrix first (the elements' dP/dF unprojected) and
 * projects only where CHOLMOD finds it is not positive definite (fom/newton.c). A stiff box spun
 * at h = 10 ms never needs the projection; a soft one (E = 300 Pa) stretched and released at
 * h = 0.1 s compresses far enough that some exact matrices are indefinite: those iterations fall
 * back to the projected matrix and every step still converges, with the momentum exact. */
TEST(newton_projects_only_where_the_exact_matrix_is_indefinite)
{
    const double young[2] = {1e5, 1e4}, h[2] = {0.01, 0.5};
    for (int c = 0; c < 2; c++) {
        rk_error err;
        body b;
        CHECK_OK(make_body(&b, RK_MAT_NEOHOOKEAN, young[c], 3, &err));
        int n = 3 * b.f.nv;
        double *x0 = malloc(sizeof(double) * (size_t)n), *v0 = calloc((size_t)n, sizeof *v0);
        for (int v = 0; v < b.f.nv; v++) /* squashed to 30% along x, spun about z */
            for (int i = 0; i < 3; i++) {
                x0[3 * v + i] = b.f.X[3 * v + i] * (i == 0 ? 0.3 : 1.0);
                v0[3 * v + i] = i == 0 ? -3 * (b.f.X[3 * v + 1] - 0.3) : i == 1 ? 3 * (b.f.X[3 * v] - 0.5) : 0;
            }
        rk_fom_options opt;
        rk_fom_default_options(&opt);
        opt.h = h[c];
        opt.position0 = x0;
        opt.velocity0 = v0;
        rk_fom s;
        CHECK_OK(rk_fom_init(&s, &b.f, &opt, &err));
        double p0[3], p[3];
        momentum(&b.f, s.v, p0);
        for (int k = 0; k < 30; k++) CHECK_OK(rk_fom_step(&s, &err));
        momentum(&b.f, s.v, p);
        printf("# E = %g Pa, h = %g s: %ld of %ld Newton iterations projected, %ld steps unconverged\n", young[c], h[c],
               s.stats.projected_hessians, s.stats.newton_iterations, s.stats.unconverged_steps);
        CHECK(s.stats.unconverged_steps == 0, "%ld steps unconverged", s.stats.unconverged_steps);
        CHECK(c == 0 ? s.stats.projected_hessians == 0
                     : s.stats.projected_hessians > 0 && s.stats.projected_hessians < s.stats.newton_iterations,
              "E = %g: %ld of %ld iterations projected", young[c], s.stats.projected_hessians, s.stats.newton_iterations);
        for (int i = 0; i < 3; i++) CHECK(fabs(p[i] - p0[i]) <= 1e-8 * (1 + fabs(p0[i])), "momentum %d moved", i);
        rk_fom_free(&s);
        free(x0);
        free(v0);
        free_body(&b);
    }
}

int main(void)
{
    RUN(translation_and_spin_conserve_linear_momentum);
    RUN(bdf2_nearly_conserves_angular_momentum_of_a_spinning_body);
    RUN(backward_euler_free_fall_is_exact);
    RUN(oscillation_energy_decays_more_with_backward_euler);
    RUN(newton_projects_only_where_the_exact_matrix_is_indefinite);
    return test_finish();
}
