/* precompute/adaptive: the oracle's measures (adaptive-subspace paper, Eq. 5-17) against hand-worked
 * cases and finite differences, and the per-vertex potential against the whole potential. */
#include "adaptive/adaptive_impl.h"
#include "testlib.h"
#include "fem_body.h"

/* The unit right tet (0,0,0), (1,0,0), (0,1,0), (0,0,1). */
static int one_tet(fem_body *b, double young, double poisson, rk_error *err)
{
    memset(b, 0, sizeof *b);
    static const double X[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    static const int T[4] = {0, 1, 2, 3};
    b->m.nv = 4;
    b->m.nt = 1;
    b->m.X = malloc(sizeof X);
    b->m.tets = malloc(sizeof T);
    memcpy(b->m.X, X, sizeof X);
    memcpy(b->m.tets, T, sizeof T);
    return fem_body_init(b, (rk_material){RK_MAT_NEOHOOKEAN, young, poisson, 1000.0}, err);
}

TEST(vertex_scales_of_one_tet_by_hand)
{
    rk_error err;
    fem_body b;
    CHECK_OK(one_tet(&b, 1e6, 0.3, &err));
    double psi[4], area[4], vol[4];
    rk_adaptive_vertex_scales(&b.f, psi, area, vol);
    double mu = 1e6 / (2 * 1.3), lambda = 1e6 * 0.3 / (1.3 * 0.4);
    for (int v = 0; v < 4; v++) {
        CHECK_CLOSE(psi[v], 2 * mu + 3 * lambda, 1e-12);
        CHECK_CLOSE(vol[v], 1.0 / 24, 1e-14);
    }
    CHECK_CLOSE(area[0], sqrt(3.0) / 2, 1e-14); /* the slanted face opposite the corner */
    for (int v = 1; v < 4; v++) CHECK_CLOSE(area[v], 0.5, 1e-14);
    fem_body_free(&b);
}

/* psi_bar is the 2-norm of d2W/dF2 at rest: its largest eigenvalue, along the dilation F = I + e I/sqrt(3),
 * is 2 mu + 3 lambda, and along a deviatoric stretch 2 mu. Both by central differences of the
 * element energy (vol W), for every material model. */
TEST(rest_hessian_norm_matches_finite_differences_of_the_energy)
{
    rk_error err;
    fem_body b;
    CHECK_OK(one_tet(&b, 2e5, 0.4, &err));
    double psi[4], area[4], vol[4];
    rk_adaptive_vertex_scales(&b.f, psi, area, vol);
    double mu = b.f.mu[0], lambda = b.f.lambda[0];
    static const rk_material_model models[] = {RK_MAT_LINEAR, RK_MAT_COROTATED, RK_MAT_STVK, RK_MAT_NEOHOOKEAN};
    for (int k = 0; k < 4; k++) {
        double dil[9] = {1 / sqrt(3.0), 0, 0, 0, 1 / sqrt(3.0), 0, 0, 0, 1 / sqrt(3.0)};
        double dev[9] = {1 / sqrt(2.0), 0, 0, 0, -1 / sqrt(2.0), 0, 0, 0, 0};
        const double *dirs[2] = {dil, dev};
        double expect[2] = {psi[0], 2 * mu};
        for (int d = 0; d < 2; d++) {
            double e = 1e-4, W[3];
            for (int s = -1; s <= 1; s++) {
                double x[12];
                for (int v = 0; v < 4; v++)
                    for (int i = 0; i < 3; i++) {
                        x[3 * v + i] = b.m.X[3 * v + i];
                        for (int j = 0; j < 3; j++) x[3 * v + i] += s * e * dirs[d][3 * i + j] * b.m.X[3 * v + j];
                    }
                W[s + 1] = rk_tet_energy(models[k], mu, lambda, x, b.f.Dm_inv, b.f.vol[0]) / b.f.vol[0];
            }
            double second = (W[0] - 2 * W[1] + W[2]) / (e * e);
            CHECK(fabs(second - expect[d]) < 1e-4 * expect[d], "model %d direction %d: %g, expected %g", k, d, second,
                  expect[d]);
        }
    }
    CHECK_CLOSE(psi[0], 2 * mu + 3 * lambda, 1e-12);
    fem_body_free(&b);
}

TEST(nodal_and_modal_measures_by_hand)
{
    /* two vertices; scales A psi = (10, 5), V psi = (2, 4) */
    double area[2] = {2, 1}, volume[2] = {0.4, 0.8}, psi[2] = {5, 5}, G[2], work[6];
    double g[6] = {3, 4, 0, 0, 0, 0};
    rk_adaptive_nodal_error(2, g, area, psi, 0.5, G);
    CHECK_CLOSE(G[0], 0.5 * 5 / 10, 1e-15);
    CHECK_CLOSE(G[1], 0, 1e-15);
    /* one column u = (1,0,0, 1,0,0): g projects to (u.g / u.u) u = u, so each vertex's part has norm 1 */
    double u[6] = {1, 0, 0, 1, 0, 0}, g2[6] = {2, 0, 0, 0, 0, 0};
    CHECK_CLOSE(rk_adaptive_modal_error(2, u, 1, g2, area, psi, 0.5, work), 0.5 * 1 / 5, 1e-15); /* the larger: vertex 1 */
    /* a block of two columns spanning x at vertex 0 and y at vertex 1: the projection is g itself */
    double U2[12] = {1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0}, g3[6] = {7, 0, 0, 0, 2, 0};
    CHECK_CLOSE(rk_adaptive_modal_error(2, U2, 2, g3, area, psi, 1, work), 7.0 / 10, 1e-15);
    /* progress: ubar = (1, 1) (the average of (3,0,0) and (0,3,0)); dE = (2, 4) projects to (3, 3) */
    double w[6] = {3, 0, 0, 0, 3, 0}, dE[2] = {2, 4};
    CHECK_CLOSE(rk_adaptive_modal_progress(2, w, 1, dE, volume, psi, 0.5), 0.5 * (3.0 / 2 + 3.0 / 4), 1e-15);
}

/* The method's own tolerance (rk_adaptive_own_tolerance): the accumulation bound by hand, its
 * scaling with the diagonal and the run's length, and the floor at full order's tolerance. */
TEST(own_tolerance_from_the_accuracy_target)
{
    /* a = 1e-3 of L = 2 m over N = 10 steps of h = 0.01 s: 2 a L / (h N (N + 1)) */
    double v = rk_adaptive_own_tolerance(1e-3, 2, 0.01, 10, 1e-5);
    CHECK_CLOSE(v, 2 * 1e-3 * 2 / (0.01 * 10 * 11), 1e-15);
    /* the bound it stands for: N steps each leaving h v, each carried on by every later step */
    double e = 0;
    for (int k = 1; k <= 10; k++) e += 0.01 * v * (10 - k + 1);
    CHECK_CLOSE(e, 1e-3 * 2, 1e-15);
    CHECK_CLOSE(rk_adaptive_own_tolerance(1e-3, 4, 0.01, 10, 1e-5), 2 * v, 1e-15);  /* linear in L */
    CHECK_CLOSE(rk_adaptive_own_tolerance(1e-3, 2, 0.01, 1, 1e-5), 1e-3 * 2 / 0.01, 1e-12); /* one step: a L / h */
    CHECK(rk_adaptive_own_tolerance(1e-3, 2, 0.01, 1000, 1e-5) == 1e-5, "a long run is floored at full order's");
    CHECK(rk_adaptive_own_tolerance(0, 2, 0.01, 10, 1e-5) == 1e-5, "accuracy 0 is full order's tolerance");
}

/* The per-vertex potential (energy.c) adds up to the whole incremental potential the solver
 * minimises, inertia, damping, gravity and contact included, at a state pressed into a sphere. */
TEST(vertex_energies_add_up_to_the_potential)
{
    rk_error err;
    fem_body b;
    double size[3] = {0.2, 0.1, 0.1}, shift[3] = {-0.1, -0.05, 0.0004};
    int cells[3] = {4, 2, 2};
    CHECK_OK(rk_mesh_box(size, cells, &b.m, &err));
    rk_mesh_transform(&b.m, 1.0, shift);
    CHECK_OK(fem_body_init(&b, (rk_material){RK_MAT_NEOHOOKEAN, 1e5, 0.4, 1000.0}, &err));
    rk_obstacle sphere = {.kind = RK_OBSTACLE_SPHERE, .center = {0, 0, -0.05}, .radius = 0.05};
    rk_fom_options fo;
    rk_fom_default_options(&fo);
    fo.gravity[2] = -9.81;
    fo.obstacles = &sphere;
    fo.nobstacles = 1;
    fo.contact.dhat = 1e-3;
    fo.rayleigh_mass = 0.5;
    fo.rayleigh_stiffness = 1e-3;
    int n = 3 * b.m.nv;
    double *U = calloc((size_t)n * 3, sizeof(double));
    for (int v = 0; v < b.m.nv; v++)
        for (int c = 0; c < 3; c++) U[(size_t)c * n + 3 * v + c] = 1; /* translations */
    rk_adaptive_options o;
    rk_adaptive_default_options(&o);
    o.block = 1;
    rk_adaptive ad;
    CHECK_OK(rk_adaptive_init(&ad, &b.f, &fo, U, 3, &o, &err));
    double *x = malloc(sizeof(double) * n), *xt = malloc(sizeof(double) * n), *xtilde = malloc(sizeof(double) * n);
    for (int i = 0; i < n; i++) { /* a wavy state just above the sphere, and a step's start and prediction */
        x[i] = b.m.X[i] + 1e-4 * sin(7.0 * i);
        xt[i] = b.m.X[i] + 2e-4 * cos(3.0 * i);
        xtilde[i] = xt[i] - 1e-3 * (i % 3 == 2);
    }
    rk_fom_terms T = {.w_inertia = 1e4, .xtilde = xtilde, .w_damping = 100, .xt = xt, .load = 1};
    double E = rk_fom_potential(&ad.fom, &T, x, NULL, RK_FOM_NO_HESSIAN, NULL, &err);
    rk_fom_view_get(&ad.fom, &ad.impl->view);
    double *e = malloc(sizeof(double) * b.m.nv), sum = 0;
    CHECK(rk_adaptive_vertex_energy(&ad, &T, x, NULL, e, &err) == 0, "vertex energies failed: %s", err.msg);
    for (int v = 0; v < b.m.nv; v++) sum += e[v];
    CHECK(ad.impl->pairs.n > 0, "the state should be in contact (%d pairs)", ad.impl->pairs.n);
    CHECK(fabs(sum - E) <= 1e-10 * fabs(E), "vertex energies sum to %.15g, the potential is %.15g", sum, E);
    /* the elastic terms element by element: the fem's energy and gradient, and the same shares */
    double *g1 = calloc((size_t)n, sizeof(double)), *g2 = calloc((size_t)n, sizeof(double));
    double psi = rk_adaptive_elastic(&ad, x, g1);
    rk_fem_add_gradient(&b.f, x, 1.0, g2);
    CHECK_CLOSE(psi, rk_fem_energy(&b.f, x), 1e-13);
    for (int i = 0; i < n; i++) CHECK(fabs(g1[i] - g2[i]) <= 1e-12 * (1 + fabs(g2[i])), "gradient %d: %g vs %g", i, g1[i], g2[i]);
    double sum2 = 0;
    CHECK(rk_adaptive_vertex_energy(&ad, &T, x, ad.impl->elem_psi, e, &err) == 0, "vertex energies failed: %s", err.msg);
    for (int v = 0; v < b.m.nv; v++) sum2 += e[v];
    CHECK(fabs(sum2 - sum) <= 1e-13 * fabs(E), "with the kept element energies: %.15g, computed: %.15g", sum2, sum);
    free(g1);
    free(g2);
    free(e);
    free(x);
    free(xt);
    free(xtilde);
    free(U);
    rk_adaptive_free(&ad);
    fem_body_free(&b);
}

int main(void)
{
    RUN(vertex_scales_of_one_tet_by_hand);
    RUN(rest_hessian_norm_matches_finite_differences_of_the_energy);
    RUN(nodal_and_modal_measures_by_hand);
    RUN(vertex_energies_add_up_to_the_potential);
    RUN(own_tolerance_from_the_accuracy_target);
    return test_finish();
}
