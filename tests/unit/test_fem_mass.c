/* precompute/fem: mass matrices (totals, row sums), the rest stiffness (rigid motions in its
 * null space, one linear tangent shared by all models), and the symmetric sparse products. */
#include "fem/fem.h"
#include "testlib.h"

static double rnd(unsigned *state)
{
    *state = *state * 1664525u + 1013904223u;
    return (double)(*state >> 8) / (double)(1u << 23) - 1.0;
}

static const double SIZE[3] = {1.0, 0.8, 0.6};

static int make_fem(rk_material_model model, rk_mesh *m, rk_fem *f, rk_error *err)
{
    int cells[3] = {3, 3, 2};
    if (rk_mesh_box(SIZE, cells, m, err)) return -1;
    rk_material *mats = calloc((size_t)m->nt, sizeof *mats);
    for (int t = 0; t < m->nt; t++) mats[t] = (rk_material){model, 2e6, 0.35, 1200.0};
    int rc = rk_fem_init(f, m, mats, err);
    free(mats);
    return rc;
}

TEST(consistent_and_lumped_mass_have_the_body_mass)
{
    rk_error err;
    rk_mesh m;
    rk_fem f;
    CHECK_OK(make_fem(RK_MAT_LINEAR, &m, &f, &err));
    double total = 1200.0 * SIZE[0] * SIZE[1] * SIZE[2];
    int n = 3 * f.nv;
    double *ones = calloc((size_t)n, sizeof *ones), *Mo = calloc((size_t)n, sizeof *Mo);
    for (int lumped = 0; lumped < 2; lumped++) {
        rk_sparse M;
        CHECK_OK(rk_sparse_alloc_pattern(&f, &M, &err));
        rk_fem_add_mass(&f, lumped, 1.0, &M);
        for (int axis = 0; axis < 3; axis++) {
            for (int i = 0; i < n; i++) ones[i] = i % 3 == axis;
            CHECK_CLOSE(rk_sparse_dot(&M, ones, ones), total, 1e-12);
            /* Row sums of M are the lumped masses: M 1_axis = m_v on that axis, 0 elsewhere. */
            rk_sparse_mul(&M, ones, Mo);
            for (int v = 0; v < f.nv; v++)
                for (int i = 0; i < 3; i++)
                    CHECK(fabs(Mo[3 * v + i] - (i == axis ? f.vertex_mass[v] : 0.0)) <= 1e-12 * total,
                          "lumped=%d: row sum of dof %d is %g, vertex mass %g", lumped, 3 * v + i, Mo[3 * v + i],
                          f.vertex_mass[v]);
        }
        unsigned seed = 3u;
        for (int trial = 0; trial < 10; trial++) {
            for (int i = 0; i < n; i++) ones[i] = rnd(&seed);
            CHECK(rk_sparse_dot(&M, ones, ones) > 0, "mass matrix not positive definite");
        }
        rk_sparse_free(&M);
    }
    double sum = 0;
    for (int v = 0; v < f.nv; v++) sum += f.vertex_mass[v];
    CHECK_CLOSE(sum, total, 1e-12);
    free(ones), free(Mo);
    rk_fem_free(&f);
    rk_mesh_free(&m);
}

/* The six rigid motions: three translations, three infinitesimal rotations w x (X - c). */
static void rigid_mode(const rk_fem *f, int k, double *u)
{
    for (int v = 0; v < f->nv; v++) {
        const double *X = &f->X[3 * v];
        double r[3] = {X[0] - 0.5, X[1] - 0.4, X[2] - 0.3}, w[3] = {0, 0, 0};
        if (k < 3) {
            for (int i = 0; i < 3; i++) u[3 * v + i] = i == k;
            continue;
        }
        w[k - 3] = 1;
        u[3 * v] = w[1] * r[2] - w[2] * r[1];
        u[3 * v + 1] = w[2] * r[0] - w[0] * r[2];
        u[3 * v + 2] = w[0] * r[1] - w[1] * r[0];
    }
}

TEST(rest_stiffness_annihilates_rigid_motions_and_is_shared_by_all_models)
{
    rk_error err;
    rk_mesh m;
    rk_fem f;
    rk_sparse K[4];
    for (int model = 0; model < 4; model++) {
        CHECK_OK(make_fem((rk_material_model)model, &m, &f, &err));
        int n = 3 * f.nv;
        CHECK_OK(rk_sparse_alloc_pattern(&f, &K[model], &err));
        rk_fem_add_rest_stiffness(&f, 1.0, &K[model]);
        double *u = calloc((size_t)n, sizeof *u), *Ku = calloc((size_t)n, sizeof *Ku);
        /* The scale of K: |K r| / |r| for a random r. */
        unsigned seed = 17u;
        for (int i = 0; i < n; i++) u[i] = rnd(&seed);
        rk_sparse_mul(&K[model], u, Ku);
        double scale = test_norm(Ku, n) / test_norm(u, n);
        for (int k = 0; k < 6; k++) {
            rigid_mode(&f, k, u);
            rk_sparse_mul(&K[model], u, Ku);
            double rel = test_norm(Ku, n) / test_norm(u, n) / scale;
            CHECK(rel <= 1e-9, "model %d: |K0 r| / |r| = %g of the scale for rigid mode %d", model, rel, k);
        }
        free(u), free(Ku);
        rk_fem_free(&f);
        rk_mesh_free(&m);
    }
    /* At F = I every model has the linear tangent, so the four K0 coincide. */
    double big = 0;
    for (int k = 0; k < K[0].nnz; k++) big = fmax(big, fabs(K[0].val[k]));
    for (int model = 1; model < 4; model++) {
        double worst = 0;
        for (int k = 0; k < K[0].nnz; k++) worst = fmax(worst, fabs(K[model].val[k] - K[0].val[k]));
        CHECK(worst <= 1e-9 * big, "model %d: rest stiffness differs from linear by %g (scale %g)", model, worst, big);
    }
    for (int model = 0; model < 4; model++) rk_sparse_free(&K[model]);
}

/* rk_sparse_mul and rk_sparse_dot against a dense symmetric reference. */
TEST(symmetric_products_match_a_dense_reference)
{
    rk_error err;
    rk_mesh m;
    rk_fem f;
    CHECK_OK(make_fem(RK_MAT_STVK, &m, &f, &err));
    int n = 3 * f.nv;
    rk_sparse S;
    CHECK_OK(rk_sparse_alloc_pattern(&f, &S, &err));
    unsigned seed = 23u;
    for (int k = 0; k < S.nnz; k++) S.val[k] = rnd(&seed);
    double *A = calloc((size_t)n * (size_t)n, sizeof *A);
    for (int j = 0; j < n; j++)
        for (int k = S.colptr[j]; k < S.colptr[j + 1]; k++)
            A[(size_t)S.rowind[k] * (size_t)n + (size_t)j] = A[(size_t)j * (size_t)n + (size_t)S.rowind[k]] = S.val[k];
    double *x = malloc((size_t)n * sizeof *x), *y = malloc((size_t)n * sizeof *y), *z = malloc((size_t)n * sizeof *z);
    for (int i = 0; i < n; i++) x[i] = rnd(&seed), z[i] = rnd(&seed);
    rk_sparse_mul(&S, x, y);
    double dot = 0, ref_dot = 0;
    for (int i = 0; i < n; i++) {
        double ref = 0;
        for (int j = 0; j < n; j++) ref += A[(size_t)i * (size_t)n + (size_t)j] * x[j];
        CHECK(fabs(ref - y[i]) <= 1e-12 * (1 + fabs(ref)), "row %d: %g vs %g", i, y[i], ref);
        ref_dot += z[i] * ref;
        dot += z[i] * y[i];
    }
    CHECK_CLOSE(rk_sparse_dot(&S, z, x), ref_dot, 1e-12);
    CHECK_CLOSE(dot, ref_dot, 1e-12);
    CHECK(rk_sparse_find(&S, 0, n - 1) == -1 && rk_sparse_find(&S, 5, 3) == -1, "find outside pattern");
    free(A), free(x), free(y), free(z);
    rk_sparse_free(&S);
    rk_fem_free(&f);
    rk_mesh_free(&m);
}

int main(void)
{
    RUN(consistent_and_lumped_mass_have_the_body_mass);
    RUN(rest_stiffness_annihilates_rigid_motions_and_is_shared_by_all_models);
    RUN(symmetric_products_match_a_dense_reference);
    return test_finish();
}
