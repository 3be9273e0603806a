/* precompute/rom and the exact quadrature: the reduced energy is the full-order energy restricted
 * to the subspace (values, gradients, Hessians against the fem and finite differences), a full
 * basis reproduces the full-order trajectory, rigid motion and free fall are exact, pins hold
 * prescribed vertices, projection inverts reconstruction. */
#include "rom/rom.h"
#include "testlib.h"
#include "fem_body.h"
#include "util/util.h"

#include <cblas.h>

static uint64_t rng_state = 12345;
static double rnd(void) { return 2 * rk_uniform(&rng_state) - 1; } /* uniform in [-1, 1), util/util.h */

static rk_material steel_ish(rk_material_model model) { return (rk_material){model, 1e5, 0.35, 1000.0}; }

/* A full basis: one column per dof not in `fixed` (unit vectors). */
static double *identity_basis(int nv, const unsigned char *fixed, int *r)
{
    int n = 0;
    for (int v = 0; v < nv; v++) n += fixed && fixed[v] ? 0 : 3;
    double *U = calloc((size_t)3 * nv * n, sizeof *U);
    int j = 0;
    for (int v = 0; v < nv; v++)
        for (int a = 0; a < 3 && !(fixed && fixed[v]); a++, j++) U[(size_t)3 * nv * j + 3 * v + a] = 1;
    *r = n;
    return U;
}

TEST(exact_quadrature_is_the_fem_energy_in_the_subspace)
{
    rk_error err;
    fem_body b;
    for (int model = 0; model < 4; model++) {
        CHECK_OK(fem_body_box(&b, 1.0, 0.5, 0.4, 3, 2, 2, steel_ish((rk_material_model)model), &err));
        int nv = b.f.nv, ndof = 3 * nv, r = 5;
        double *U = calloc((size_t)ndof * r, sizeof *U), q[5], x[1024], gq[5] = {0}, H[25] = {0};
        double *gx = calloc((size_t)ndof, sizeof *gx);
        for (int i = 0; i < ndof * r; i++) U[i] = 0.1 * rnd();
        for (int j = 0; j < r; j++) q[j] = 0.5 * rnd();
        rk_quadrature Q;
        CHECK_OK(rk_quadrature_elements(&b.f, U, r, b.f.nt, NULL, NULL, &Q, &err));
        rk_rom_positions(U, ndof, r, b.f.X, q, x);
        double E = rk_quadrature_eval(&Q, q, gq, H, 0), Ef = rk_fem_energy(&b.f, x);
        CHECK(fabs(E - Ef) <= 1e-12 * fabs(Ef), "model %d: reduced energy %.15g, fem %.15g", model, E, Ef);
        rk_fem_add_gradient(&b.f, x, 1.0, gx);
        for (int j = 0; j < r; j++) {
            double ref = cblas_ddot(ndof, U + (size_t)ndof * j, 1, gx, 1);
            CHECK(fabs(gq[j] - ref) <= 1e-10 * (fabs(ref) + 1e-8), "model %d: g[%d] = %g, U^T grad = %g", model, j, gq[j], ref);
        }
        /* Hessian column k against central differences of the gradient. */
        for (int k = 0; k < r; k++) {
            double step = 1e-6, qp[5], qm[5], gp[5] = {0}, gm[5] = {0};
            memcpy(qp, q, sizeof q);
            memcpy(qm, q, sizeof q);
            qp[k] += step;
            qm[k] -= step;
            rk_quadrature_eval(&Q, qp, gp, NULL, 0);
            rk_quadrature_eval(&Q, qm, gm, NULL, 0);
            for (int j = 0; j < r; j++) {
                double fd = (gp[j] - gm[j]) / (2 * step);
                CHECK(fabs(H[j + 5 * k] - fd) <= 1e-6 * (fabs(fd) + 1.0), "model %d: H[%d][%d] = %.10g, FD %.10g",
                      model, j, k, H[j + 5 * k], fd);
            }
        }
        rk_quadrature_free(&Q);
        free(U);
        free(gx);
        fem_body_free(&b);
    }
}

/* Runs the full-order model and the reduced model with a full basis side by side; they minimise
 * the same potential over the same space, so they agree to the Newton tolerance. is_static: one
 * static equilibrium each (both through the solver's load stepping) instead of steps. */
static double full_basis_gap(rk_integrator integ, double damping, int steps, int is_static, rk_error *err, int *fail)
{
    fem_body b;
    *fail = 1;
    if (fem_body_box(&b, 1.0, 0.3, 0.3, 4, 1, 1, (rk_material){RK_MAT_NEOHOOKEAN, 2e4, 0.3, 1000.0}, err)) return NAN;
    unsigned char *fixed = fem_body_fix_x_below(&b, 0.01);
    int nfixed = 0, *verts = calloc((size_t)b.f.nv, sizeof(int));
    for (int v = 0; v < b.f.nv; v++)
        if (fixed[v]) verts[nfixed++] = v;
    rk_prescribed group = {RK_MOTION_FIXED, nfixed, verts, {0}, {0}, 0, {0}};
    rk_fom_options opt;
    rk_fom_default_options(&opt);
    opt.integrator = integ;
    opt.gravity[1] = -9.81;
    opt.rayleigh_stiffness = damping;
    opt.nprescribed = 1;
    opt.prescribed = &group;
    opt.newton_tol = 1e-9;
    opt.is_static = is_static;
    if (is_static) opt.steps = steps = 1;
    int r, ndof = 3 * b.f.nv;
    double *U = identity_basis(b.f.nv, fixed, &r), gap = NAN;
    double *x = calloc((size_t)ndof, sizeof *x);
    rk_fom fom;
    rk_quadrature Q;
    rk_rom_model m;
    rk_rom rom;
    if (!rk_fom_init(&fom, &b.f, &opt, err)) {
        if (!rk_quadrature_elements(&b.f, U, r, b.f.nt, NULL, NULL, &Q, err) &&
            !rk_rom_model_init(&m, &b.f, &opt, U, r, &Q, NULL, err)) {
            if (!rk_rom_init(&rom, &m, NULL, NULL, err)) {
                gap = 0;
                *fail = 0;
                for (int k = 0; k < steps && !*fail; k++) {
                    *fail = (is_static ? rk_fom_static(&fom, err) : rk_fom_step(&fom, err)) || rk_rom_step(&rom, err);
                    *fail = *fail || rom.stats.unconverged_steps > 0;
                    rk_rom_positions(U, ndof, r, b.f.X, rom.q, x);
                    for (int i = 0; i < ndof; i++) gap = fmax(gap, fabs(x[i] - fom.x[i]));
                }
                rk_rom_free(&rom);
            }
            rk_rom_model_free(&m);
        }
        rk_fom_free(&fom);
    }
    free(x);
    free(U);
    free(fixed);
    free(verts);
    fem_body_free(&b);
    return gap;
}

TEST(full_basis_reproduces_the_full_order_model)
{
    rk_error err;
    int fail;
    for (int integ = 0; integ < 2; integ++)
        for (int damped = 0; damped < 2; damped++) {
            double gap = full_basis_gap(integ ? RK_BDF2 : RK_BACKWARD_EULER, damped ? 0.01 : 0, 30, 0, &err, &fail);
            CHECK(!fail, "run failed: %s", err.msg);
            /* Sagging by ~0.1 m; both solve to 1e-9 m/s * h. */
            CHECK(gap < 1e-8, "integrator %d damping %d: largest gap to the full-order model %g m", integ, damped, gap);
            printf("# full basis, integrator %d, damping %d: gap to the full-order model %.2e m\n", integ, damped, gap);
        }
    /* The static equilibrium under gravity: both minimise Psi - f.x to 1e-9 m. */
    double gap = full_basis_gap(RK_BACKWARD_EULER, 0, 1, 1, &err, &fail);
    CHECK(!fail, "static solve failed: %s", err.msg);
    CHECK(gap < 1e-8, "static: largest gap to the full-order equilibrium %g m", gap);
    printf("# full basis, static equilibrium: gap to the full-order one %.2e m\n", gap);
}

/* A free body in a basis of its 3 translations falls as backward Euler says: v_k = k g h,
 * x_k = k (k + 1)/2 g h^2, exactly (no elastic forces in a translation). */
TEST(free_fall_in_a_translation_basis_is_exact)
{
    rk_error err;
    fem_body b;
    CHECK_OK(fem_body_box(&b, 1.0, 0.5, 0.4, 2, 2, 2, steel_ish(RK_MAT_STVK), &err));
    int nv = b.f.nv, ndof = 3 * nv, r = 3;
    double *U = calloc((size_t)ndof * r, sizeof *U);
    for (int v = 0; v < nv; v++)
        for (int a = 0; a < 3; a++) U[(size_t)ndof * a + 3 * v + a] = 1;
    rk_fom_options opt;
    rk_fom_default_options(&opt);
    opt.gravity[2] = -9.81;
    rk_quadrature Q;
    rk_rom_model m;
    rk_rom rom;
    CHECK_OK(rk_quadrature_elements(&b.f, U, r, b.f.nt, NULL, NULL, &Q, &err));
    CHECK_OK(rk_rom_model_init(&m, &b.f, &opt, U, r, &Q, NULL, &err));
    CHECK_OK(rk_rom_init(&rom, &m, NULL, NULL, &err));
    double h = opt.h;
    for (int k = 1; k <= 20; k++) {
        CHECK_OK(rk_rom_step(&rom, &err));
        double z = -9.81 * h * h * k * (k + 1) / 2.0;
        CHECK(fabs(rom.q[2] - z) <= 1e-10 * fabs(z), "step %d: z = %.15g, expected %.15g", k, rom.q[2], z);
        CHECK(fabs(rom.q[0]) < 1e-14 && fabs(rom.q[1]) < 1e-14, "drifted sideways");
    }
    rk_rom_free(&rom);
    rk_rom_model_free(&m);
    free(U);
    fem_body_free(&b);
}

/* Pins: a twisted end in a full basis follows its targets up to the penalty's compliance, and
 * the vertex the basis cannot move is refused when it must move. */
TEST(pins_hold_moving_vertices)
{
    rk_error err;
    fem_body b;
    CHECK_OK(fem_body_box(&b, 1.0, 0.3, 0.3, 4, 1, 1, (rk_material){RK_MAT_NEOHOOKEAN, 2e4, 0.3, 1000.0}, &err));
    int nv = b.f.nv, ndof = 3 * nv, r, nend = 0, *end = calloc((size_t)nv, sizeof(int));
    unsigned char *fixed = fem_body_fix_x_below(&b, 0.01);
    for (int v = 0; v < nv; v++)
        if (b.f.X[3 * v] > 0.99) end[nend++] = v;
    double *U = identity_basis(nv, fixed, &r), *x = calloc((size_t)ndof, sizeof *x);
    int nfix = 0, *fv = calloc((size_t)nv, sizeof(int));
    for (int v = 0; v < nv; v++)
        if (fixed[v]) fv[nfix++] = v;
    rk_prescribed groups[2] = {{RK_MOTION_FIXED, nfix, fv, {0}, {0}, 0, {0}},
                               {RK_MOTION_TWIST, nend, end, {1, 0, 0}, {1, 0.15, 0.15}, M_PI, {0}}};
    rk_fom_options opt;
    rk_fom_default_options(&opt);
    opt.nprescribed = 2;
    opt.prescribed = groups;
    rk_quadrature Q;
    rk_rom_model m;
    rk_rom rom;
    CHECK_OK(rk_quadrature_elements(&b.f, U, r, b.f.nt, NULL, NULL, &Q, &err));
    CHECK_OK(rk_rom_model_init(&m, &b.f, &opt, U, r, &Q, NULL, &err));
    CHECK(m.pinned_vertices == nend, "%d vertices pinned, expected the %d moving ones", m.pinned_vertices, nend);
    CHECK_OK(rk_rom_init(&rom, &m, NULL, NULL, &err));
    double worst = 0;
    for (int k = 0; k < 50; k++) {
        CHECK_OK(rk_rom_step(&rom, &err));
        rk_rom_positions(U, ndof, r, b.f.X, rom.q, x);
        double R[9], s[3];
        rk_prescribed_transform(&groups[1], rom.t, R, s);
        for (int j = 0; j < nend; j++) {
            const double *X = &b.f.X[3 * end[j]];
            for (int a = 0; a < 3; a++)
                worst = fmax(worst, fabs(x[3 * end[j] + a] - (R[3 * a] * X[0] + R[3 * a + 1] * X[1] + R[3 * a + 2] * X[2] + s[a])));
        }
    }
    printf("# twisted end (90 deg/0.5 s): largest miss of a pinned vertex %.2e m\n", worst);
    CHECK(worst < 1e-3, "pinned vertices miss their targets by %g m", worst);
    rk_rom_free(&rom);
    rk_rom_model_free(&m);
    /* The same with the moving end left out of the basis: refused, naming the group. */
    unsigned char *both = calloc((size_t)nv, 1);
    for (int v = 0; v < nv; v++) both[v] = fixed[v] || b.f.X[3 * v] > 0.99;
    int r2;
    double *U2 = identity_basis(nv, both, &r2);
    CHECK_OK(rk_quadrature_elements(&b.f, U2, r2, b.f.nt, NULL, NULL, &Q, &err));
    CHECK(rk_rom_model_init(&m, &b.f, &opt, U2, r2, &Q, NULL, &err) != 0, "a basis that cannot move the twisted end was taken");
    CHECK(strstr(err.msg, "group 1") && strstr(err.msg, "must move"), "message: %s", err.msg);
    free(both);
    free(U2);
    free(U);
    free(x);
    free(fv);
    free(end);
    free(fixed);
    fem_body_free(&b);
}

TEST(projection_inverts_reconstruction)
{
    rk_error err;
    fem_body b;
    CHECK_OK(fem_body_box(&b, 1.0, 0.5, 0.4, 2, 2, 2, steel_ish(RK_MAT_LINEAR), &err));
    int nv = b.f.nv, ndof = 3 * nv, r = 7;
    double *U = calloc((size_t)ndof * r, sizeof *U), q[7], q2[7], *x = calloc((size_t)ndof, sizeof *x);
    for (int i = 0; i < ndof * r; i++) U[i] = rnd();
    for (int j = 0; j < r; j++) q[j] = rnd();
    rk_fom_options opt;
    rk_fom_default_options(&opt);
    rk_quadrature Q;
    rk_rom_model m;
    rk_sparse M;
    CHECK_OK(rk_quadrature_elements(&b.f, U, r, b.f.nt, NULL, NULL, &Q, &err));
    CHECK_OK(rk_rom_model_init(&m, &b.f, &opt, U, r, &Q, NULL, &err));
    CHECK_OK(rk_sparse_alloc_pattern(&b.f, &M, &err));
    rk_fem_add_mass(&b.f, 0, 1.0, &M);
    rk_rom_positions(U, ndof, r, b.f.X, q, x);
    CHECK_OK(rk_rom_project(&m, &M, U, ndof, b.f.X, x, q2, &err));
    for (int j = 0; j < r; j++) CHECK(fabs(q2[j] - q[j]) < 1e-10, "q[%d] = %g, projected back %g", j, q[j], q2[j]);
    rk_sparse_free(&M);
    rk_rom_model_free(&m);
    free(U);
    free(x);
    fem_body_free(&b);
}

TEST(bad_input_is_refused)
{
    rk_error err;
    fem_body b;
    CHECK_OK(fem_body_box(&b, 1.0, 0.5, 0.4, 1, 1, 1, steel_ish(RK_MAT_LINEAR), &err));
    int ndof = 3 * b.f.nv, r = 2;
    double *U = calloc((size_t)ndof * r, sizeof *U);
    for (int i = 0; i < ndof * r; i++) U[i] = rnd();
    rk_fom_options opt;
    rk_fom_default_options(&opt);
    rk_quadrature Q;
    rk_rom_model m;
    U[5] = NAN;
    CHECK_OK(rk_quadrature_elements(&b.f, U, r, b.f.nt, NULL, NULL, &Q, &err));
    CHECK(rk_rom_model_init(&m, &b.f, &opt, U, r, &Q, NULL, &err) != 0 && strstr(err.msg, "not finite"), "NaN basis: %s", err.msg);
    U[5] = 0.5;
    opt.h = -1;
    CHECK_OK(rk_quadrature_elements(&b.f, U, r, b.f.nt, NULL, NULL, &Q, &err));
    CHECK(rk_rom_model_init(&m, &b.f, &opt, U, r, &Q, NULL, &err) != 0 && strstr(err.msg, "time step"), "h < 0: %s", err.msg);
    int bad = b.f.nt;
    CHECK(rk_quadrature_elements(&b.f, U, r, 1, &bad, NULL, &Q, &err) != 0 && strstr(err.msg, "out of range"),
          "element out of range: %s", err.msg);
    free(U);
    fem_body_free(&b);
}

int main(void)
{
    RUN(exact_quadrature_is_the_fem_energy_in_the_subspace);
    RUN(full_basis_reproduces_the_full_order_model);
    RUN(free_fall_in_a_translation_basis_is_exact);
    RUN(pins_hold_moving_vertices);
    RUN(projection_inverts_reconstruction);
    RUN(bad_input_is_refused);
    return test_finish();
}
