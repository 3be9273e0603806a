/* precompute/rom: the mesh-free reduced model (rk_rom_model_init with integration points, freeform
 * paper Eq. 22): the mass and gravity come from the points, not from the mesh's vertices,
 *   M_r = sum_p rho_p v_p U_p^T U_p,   f_r = sum_p rho_p v_p U_p^T g + U^T f_ext,
 * with U_p the 3 x 12H linear-blend-skinning rows of point p (row a, column 12 j + 4 a + c =
 * W_j(X_p) X̄_c, as rk_skinning_to_U), checked against dense products formed here; and with
 * Rayleigh damping C_r = a M_r + b K_r(0), K_r(0) the points' Hessian at rest. The vertices carry
 * other weights than the points, so a mass taken from the vertices would show. And a cloud
 * without elements holds its fixed points. */
#include "rom/rom.h"
#include "testlib.h"
#include "fem_body.h"
#include "util/util.h"

static uint64_t rng = 4242;
static double uni(void) { return rk_uniform(&rng); }

#define NH 3

/* The LBS basis of vertex weights W (nv x NH) at X, built here (rk_skinning_to_U's layout):
 * U[3 v + a, 12 j + 4 a + c] = W[v, j] X̄_c. */
static double *lbs_basis(const double *W, int nv, const double *X)
{
    int ndof = 3 * nv, r = 12 * NH;
    double *U = calloc((size_t)ndof * r, sizeof *U);
    for (int v = 0; v < nv; v++)
        for (int j = 0; j < NH; j++)
            for (int a = 0; a < 3; a++)
                for (int c = 0; c < 4; c++)
                    U[3 * v + a + (size_t)ndof * (12 * j + 4 * a + c)] = W[v + (size_t)nv * j] * (c < 3 ? X[3 * v + c] : 1.0);
    return U;
}

/* n points in the box [0, L] with weights unrelated to the vertices', varied densities and volumes. */
static void make_points(rk_skin_points *P, int n, const double L[3])
{
    memset(P, 0, sizeof *P);
    P->n = n, P->H = NH;
    P->X = calloc(3 * (size_t)n, sizeof(double));
    P->W = calloc((size_t)n * NH, sizeof(double));
    P->dW = calloc(3 * (size_t)n * NH, sizeof(double));
    P->volume = calloc((size_t)n, sizeof(double));
    P->density = calloc((size_t)n, sizeof(double));
    P->model = calloc((size_t)n, sizeof *P->model);
    P->mu = calloc((size_t)n, sizeof(double));
    P->lambda = calloc((size_t)n, sizeof(double));
    for (int i = 0; i < n; i++) {
        for (int d = 0; d < 3; d++) P->X[3 * i + d] = L[d] * uni();
        for (int j = 0; j < NH; j++) {
            P->W[i + (size_t)n * j] = j == 0 ? 1 + 0.2 * uni() : 2 * uni() - 1;
            for (int b = 0; b < 3; b++) P->dW[3 * (size_t)i + b + 3 * (size_t)n * j] = 2 * uni() - 1;
        }
        P->volume[i] = 1e-3 * (0.5 + uni());
        P->density[i] = 500 + 1000 * uni();
        P->model[i] = i % 2 ? RK_MAT_NEOHOOKEAN : RK_MAT_STVK;
        P->mu[i] = 2e4 * (1 + uni());
        P->lambda[i] = 4e4;
    }
}

/* max |a - b| / max |b| over n entries */
static double rel_diff(const double *a, const double *b, size_t n)
{
    double d = 0, s = 0;
    for (size_t k = 0; k < n; k++) d = fmax(d, fabs(a[k] - b[k])), s = fmax(s, fabs(b[k]));
    return d / s;
}

typedef struct {
    fem_body b;
    double *U, *force;
    rk_skin_points P;
    rk_fom_options opt;
} setup;

static int setup_init(setup *s, rk_error *err)
{
    const double L[3] = {1.0, 0.4, 0.3};
    memset(s, 0, sizeof *s);
    if (fem_body_box(&s->b, L[0], L[1], L[2], 3, 2, 2, (rk_material){RK_MAT_NEOHOOKEAN, 1e5, 0.3, 2000.0}, err)) return -1;
    int nv = s->b.f.nv;
    double *W = calloc((size_t)nv * NH, sizeof *W);
    for (int v = 0; v < nv; v++) {
        const double *X = &s->b.m.X[3 * v];
        W[v] = 1, W[v + nv] = X[0], W[v + 2 * (size_t)nv] = X[1] * X[2] + 0.5;
    }
    s->U = lbs_basis(W, nv, s->b.m.X);
    free(W);
    s->force = calloc(3 * (size_t)nv, sizeof *s->force);
    for (int k = 0; k < 3 * nv; k++) s->force[k] = uni() - 0.5;
    make_points(&s->P, 40, L);
    rk_fom_default_options(&s->opt);
    s->opt.gravity[0] = 1.5, s->opt.gravity[1] = -9.81, s->opt.gravity[2] = 0.7;
    s->opt.force = s->force;
    return 0;
}

static void setup_free(setup *s)
{
    free(s->U);
    free(s->force);
    rk_skin_points_free(&s->P);
    fem_body_free(&s->b);
}

/* The dense references: M (r x r) and f (r). */
static void dense_reference(const setup *s, double *M, double *f, double *mass)
{
    int r = 12 * NH, n = s->P.n, ndof = 3 * s->b.f.nv;
    double *Up = calloc(3 * (size_t)r, sizeof *Up); /* 3 x r, row-major */
    memset(M, 0, sizeof(double) * r * r);
    memset(f, 0, sizeof(double) * r);
    *mass = 0;
    for (int p = 0; p < n; p++) {
        const double *X = &s->P.X[3 * p];
        double mp = s->P.density[p] * s->P.volume[p];
        memset(Up, 0, sizeof(double) * 3 * r);
        for (int j = 0; j < NH; j++)
            for (int a = 0; a < 3; a++)
                for (int c = 0; c < 4; c++) Up[a * r + 12 * j + 4 * a + c] = s->P.W[p + (size_t)n * j] * (c < 3 ? X[c] : 1.0);
        for (int i = 0; i < r; i++) {
            for (int k = 0; k < r; k++)
                for (int a = 0; a < 3; a++) M[i + (size_t)r * k] += mp * Up[a * r + i] * Up[a * r + k];
            for (int a = 0; a < 3; a++) f[i] += mp * Up[a * r + i] * s->opt.gravity[a];
        }
        *mass += mp;
    }
    for (int i = 0; i < r; i++) /* + U^T f_ext: the vertices' loads */
        for (int k = 0; k < ndof; k++) f[i] += s->U[k + (size_t)ndof * i] * s->force[k];
    free(Up);
}

TEST(mass_and_gravity_come_from_the_points)
{
    rk_error err;
    setup s;
    CHECK_OK(setup_init(&s, &err));
    int r = 12 * NH;
    rk_quadrature Q;
    rk_rom_model m;
    CHECK_OK(rk_quadrature_points(&s.P, s.P.n, NULL, NULL, &Q, &err));
    CHECK_OK(rk_rom_model_init(&m, &s.b.f, &s.opt, s.U, r, &Q, &s.P, &err));
    double *M = calloc((size_t)r * r, sizeof *M), f[12 * NH], mass;
    dense_reference(&s, M, f, &mass);
    double eM = rel_diff(m.M, M, (size_t)r * r), ef = rel_diff(m.f, f, (size_t)r);
    printf("# %d points, r = %d: M_r %.3g, f_r %.3g relative to the dense sums; mass %.6g kg (the vertices' %.6g)\n",
           s.P.n, r, eM, ef, m.mass, 2000.0 * 1.0 * 0.4 * 0.3);
    CHECK(eM < 1e-12, "M_r differs from sum rho v U_p^T U_p by %.3g", eM);
    CHECK(ef < 1e-12, "f_r differs from sum rho v U_p^T g + U^T f_ext by %.3g", ef);
    CHECK_CLOSE(m.mass / mass, 1.0, 1e-12);
    CHECK(m.C == NULL, "no damping asked, C built");
    /* the vertices' mass would be another matrix: the check above could tell */
    rk_sparse S = {0};
    CHECK_OK(rk_sparse_alloc_pattern(&s.b.f, &S, &err));
    rk_fem_add_mass(&s.b.f, 0, 1.0, &S);
    int ndof = 3 * s.b.f.nv;
    double *SU = calloc((size_t)ndof, sizeof *SU), *Mv = calloc((size_t)r * r, sizeof *Mv);
    for (int k = 0; k < r; k++) {
        rk_sparse_mul(&S, s.U + (size_t)ndof * k, SU);
        for (int i = 0; i < r; i++)
            for (int e = 0; e < ndof; e++) Mv[i + (size_t)r * k] += s.U[e + (size_t)ndof * i] * SU[e];
    }
    CHECK(rel_diff(Mv, M, (size_t)r * r) > 1e-2, "the vertices' U^T M U is the points' mass too: the test cannot tell them apart");
    rk_sparse_free(&S);
    free(SU), free(Mv), free(M);
    rk_rom_model_free(&m);
    setup_free(&s);
}

TEST(damping_is_rayleigh_on_the_points)
{
    rk_error err;
    setup s;
    CHECK_OK(setup_init(&s, &err));
    int r = 12 * NH;
    double a = 0.3, b = 2e-3;
    s.opt.rayleigh_mass = a, s.opt.rayleigh_stiffness = b;
    rk_quadrature Q, Qref;
    rk_rom_model m;
    CHECK_OK(rk_quadrature_points(&s.P, s.P.n, NULL, NULL, &Q, &err));
    CHECK_OK(rk_quadrature_points(&s.P, s.P.n, NULL, NULL, &Qref, &err));
    CHECK_OK(rk_rom_model_init(&m, &s.b.f, &s.opt, s.U, r, &Q, &s.P, &err));
    CHECK(m.C != NULL, "damping asked, no C");
    double *M = calloc((size_t)r * r, sizeof *M), *K = calloc((size_t)r * r, sizeof *K), *C = calloc((size_t)r * r, sizeof *C);
    double f[12 * NH], mass, q0[12 * NH] = {0};
    dense_reference(&s, M, f, &mass);
    rk_quadrature_eval(&Qref, q0, NULL, K, 0);
    for (int k = 0; k < r * r; k++) C[k] = a * M[k] + b * K[k];
    double eC = rel_diff(m.C, C, (size_t)r * r), bM = 0, bK = 0;
    for (int k = 0; k < r * r; k++) bM = fmax(bM, fabs(a * M[k])), bK = fmax(bK, fabs(b * K[k]));
    printf("# C_r against a M_r + b K_r(0): %.3g (largest a M %.3g, b K %.3g)\n", eC, bM, bK);
    CHECK(bM > 1e-3 * bK && bK > 1e-3 * bM, "one of a M and b K swamps the other: the check is blind to it");
    CHECK(eC < 1e-12, "C_r differs from a M_r + b K_r(0) by %.3g", eC);
    free(M), free(K), free(C);
    rk_quadrature_free(&Qref);
    rk_rom_model_free(&m);
    setup_free(&s);
}

TEST(points_must_match_the_basis)
{
    rk_error err;
    setup s;
    CHECK_OK(setup_init(&s, &err));
    rk_quadrature Q;
    rk_rom_model m;
    CHECK_OK(rk_quadrature_points(&s.P, s.P.n, NULL, NULL, &Q, &err));
    s.P.H = 2; /* 24 columns' worth of handles for a 36-column basis */
    CHECK(rk_rom_model_init(&m, &s.b.f, &s.opt, s.U, 12 * NH, &Q, &s.P, &err) != 0 && strstr(err.msg, "handles"),
          "2 handles for 36 columns: %s", err.msg);
    CHECK(Q.G == NULL, "the model did not take over the quadrature");
    s.P.H = NH;
    setup_free(&s);
}

/* A point cloud's model has no element (rk_fem_init_points): the vertices are the points, each
 * weighing rho v, and the material lives at the integration points only. Its fixed vertices must
 * still be held: the penalty's stiffness (rom.h, k ~ (lambda + 2 mu) / (rho L^2)) comes from the
 * points' material when there is no element to take it from. Ten steps under gravity: the fixed
 * vertices stay within a small fraction of free fall (0.054 m) while the free ones sag. */
TEST(pins_hold_a_cloud_without_elements)
{
    rk_error err;
    const double L[3] = {1.0, 0.2, 0.2};
    rk_skin_points P;
    const int n = 60;
    make_points(&P, n, L);
    for (int i = 0; i < n; i++) { /* smooth weights, and one material */
        const double *X = &P.X[3 * i];
        P.W[i] = 1, P.W[i + n] = sin(3 * X[0]), P.W[i + 2 * (size_t)n] = cos(2 * X[0]) + 0.5;
        for (int b = 0; b < 3; b++) {
            P.dW[3 * i + b] = 0;
            P.dW[3 * i + b + 3 * (size_t)n] = b == 0 ? 3 * cos(3 * X[0]) : 0;
            P.dW[3 * i + b + 6 * (size_t)n] = b == 0 ? -2 * sin(2 * X[0]) : 0;
        }
        P.density[i] = 1000, P.model[i] = RK_MAT_NEOHOOKEAN, P.mu[i] = 7e3, P.lambda[i] = 3e4;
        P.volume[i] = L[0] * L[1] * L[2] / P.n;
    }
    rk_mesh cloud = {0};
    cloud.nv = P.n, cloud.X = P.X;
    double *vm = calloc((size_t)n, sizeof *vm);
    for (int i = 0; i < P.n; i++) vm[i] = P.density[i] * P.volume[i];
    rk_fem fem;
    CHECK_OK(rk_fem_init_points(&fem, &cloud, NULL, vm, &err));
    int nfixed = 0, *fixed = calloc((size_t)n, sizeof *fixed);
    for (int i = 0; i < P.n; i++)
        if (P.X[3 * i] < 0.15) fixed[nfixed++] = i;
    CHECK(nfixed >= 3, "only %d fixed points", nfixed);
    rk_prescribed group = {RK_MOTION_FIXED, nfixed, fixed, {0}, {0}, 0, {0}};
    rk_fom_options opt;
    rk_fom_default_options(&opt);
    opt.gravity[1] = -9.81;
    opt.nprescribed = 1;
    opt.prescribed = &group;
    double *U = lbs_basis(P.W, P.n, P.X);
    rk_quadrature Q;
    rk_rom_model m;
    rk_rom s;
    CHECK_OK(rk_quadrature_points(&P, P.n, NULL, NULL, &Q, &err));
    CHECK_OK(rk_rom_model_init(&m, &fem, &opt, U, 12 * NH, &Q, &P, &err));
    CHECK_OK(rk_rom_init(&s, &m, NULL, NULL, &err));
    for (int k = 0; k < 10; k++) CHECK_OK(rk_rom_step(&s, &err));
    double *x = calloc(3 * (size_t)n, sizeof *x), held = 0, sag = 0;
    rk_rom_positions(U, 3 * P.n, 12 * NH, P.X, s.q, x);
    for (int i = 0; i < P.n; i++) {
        double d = 0;
        for (int a = 0; a < 3; a++) d += (x[3 * i + a] - P.X[3 * i + a]) * (x[3 * i + a] - P.X[3 * i + a]);
        if (P.X[3 * i] < 0.15) held = fmax(held, sqrt(d));
        else sag = fmax(sag, sqrt(d));
    }
    printf("# a cloud without elements, pin stiffness %.3g: fixed points moved %.3g m, free ones up to %.3g m (free fall 0.054)\n",
           m.pin_k, held, sag);
    CHECK(m.pin_k > 0, "the pins' penalty stiffness is %g", m.pin_k);
    CHECK(held < 0.1 * 0.054, "the fixed points fell %.3g m in 0.1 s (free fall 0.054 m)", held);
    free(x), free(U), free(fixed), free(vm);
    rk_rom_free(&s);
    rk_rom_model_free(&m);
    rk_fem_free(&fem);
    rk_skin_points_free(&P);
}

int main(void)
{
    RUN(mass_and_gravity_come_from_the_points);
    RUN(damping_is_rayleigh_on_the_points);
    RUN(points_must_match_the_basis);
    RUN(pins_hold_a_cloud_without_elements);
    return test_finish();
}
