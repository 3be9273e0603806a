/* precompute/fem: assembled elastic energy, gradient and Hessian against finite differences for
 * every material model, per-element materials, material and volume errors, the pattern and the
 * slot map, and the same bits on any number of threads. */
#include "fem/fem.h"
#include "testlib.h"

static double rnd(unsigned *state) /* uniform in [-1, 1), deterministic */
{
    *state = *state * 1664525u + 1013904223u;
    return (double)(*state >> 8) / (double)(1u << 23) - 1.0;
}

static int make_box(int nx, int ny, int nz, rk_mesh *m, rk_error *err)
{
    double size[3] = {1.0, 0.8, 0.6};
    int cells[3] = {nx, ny, nz};
    return rk_mesh_box(size, cells, m, err);
}

static rk_material *uniform(int nt, rk_material_model model, double young, double poisson)
{
    rk_material *mats = calloc((size_t)nt, sizeof *mats);
    for (int t = 0; t < nt; t++) mats[t] = (rk_material){model, young, poisson, 1000.0};
    return mats;
}

/* Rest positions moved by up to amp in each coordinate. */
static double *perturbed(const rk_fem *f, double amp, unsigned seed)
{
    double *x = malloc(3 * (size_t)f->nv * sizeof *x);
    for (int i = 0; i < 3 * f->nv; i++) x[i] = f->X[i] + amp * rnd(&seed);
    return x;
}

static double max_abs(const double *a, int n)
{
    double m = 0;
    for (int i = 0; i < n; i++) m = fmax(m, fabs(a[i]));
    return m;
}

static const char *model_name[] = {"linear", "corotated", "stvk", "neohookean"};

TEST(gradient_matches_finite_differences_for_every_model)
{
    rk_error err;
    rk_mesh m;
    CHECK_OK(make_box(4, 3, 3, &m, &err)); /* 80 vertices, 240 dofs */
    for (int model = 0; model < 4; model++) {
        rk_material *mats = uniform(m.nt, (rk_material_model)model, 1e6, 0.3);
        rk_fem f;
        CHECK_OK(rk_fem_init(&f, &m, mats, &err));
        int n = 3 * f.nv;
        double *x = perturbed(&f, 0.04, 7u + (unsigned)model), *g = calloc((size_t)n, sizeof *g);
        rk_fem_add_gradient(&f, x, 2.0, g); /* scale honoured */
        double scale = max_abs(g, n) / 2.0, worst = 0;
        CHECK(scale > 0, "%s: zero gradient on a deformed mesh", model_name[model]);
        for (int i = 0; i < n; i++) {
            double h = 1e-6, keep = x[i];
            x[i] = keep + h;
            double ep = rk_fem_energy(&f, x);
            x[i] = keep - h;
            double em = rk_fem_energy(&f, x);
            x[i] = keep;
            worst = fmax(worst, fabs((ep - em) / (2 * h) - g[i] / 2.0));
        }
        CHECK(worst <= 1e-6 * scale, "%s: gradient differs from FD by %g (scale %g)", model_name[model], worst, scale);
        free(x), free(g), free(mats);
        rk_fem_free(&f);
    }
    rk_mesh_free(&m);
}

TEST(hessian_vector_products_match_finite_differences_of_the_gradient)
{
    rk_error err;
    rk_mesh m;
    CHECK_OK(make_box(4, 3, 3, &m, &err));
    for (int model = 0; model < 4; model++) {
        rk_material *mats = uniform(m.nt, (rk_material_model)model, 1e6, 0.3);
        rk_fem f;
        CHECK_OK(rk_fem_init(&f, &m, mats, &err));
        int n = 3 * f.nv;
        rk_sparse H;
        CHECK_OK(rk_sparse_alloc_pattern(&f, &H, &err));
        double *x = perturbed(&f, 0.04, 11u + (unsigned)model);
        rk_fem_add_hessian(&f, x, 1.0, 0, &H);
        double *u = malloc((size_t)n * sizeof *u), *Hu = malloc((size_t)n * sizeof *Hu);
        double *gp = calloc((size_t)n, sizeof *gp), *gm = calloc((size_t)n, sizeof *gm);
        unsigned seed = 99u;
        for (int i = 0; i < n; i++) u[i] = rnd(&seed);
        rk_sparse_mul(&H, u, Hu);
        double h = 1e-6;
        for (int i = 0; i < n; i++) x[i] += h * u[i];
        rk_fem_add_gradient(&f, x, 1.0, gp);
        for (int i = 0; i < n; i++) x[i] -= 2 * h * u[i];
        rk_fem_add_gradient(&f, x, 1.0, gm);
        double worst = 0, scale = max_abs(Hu, n);
        for (int i = 0; i < n; i++) worst = fmax(worst, fabs((gp[i] - gm[i]) / (2 * h) - Hu[i]));
        CHECK(worst <= 1e-6 * scale, "%s: H u differs from FD by %g (scale %g)", model_name[model], worst, scale);
        /* The projected Hessian is positive semi-definite: u^T H u >= 0 for random u. */
        rk_sparse_zero(&H);
        for (int i = 0; i < n; i++) x[i] += h * u[i];
        for (int i = 0; i < n; i++) x[i] += 0.2 * u[i] * 0.3; /* a harder, partly compressed state */
        rk_fem_add_hessian(&f, x, 1.0, 1, &H);
        for (int trial = 0; trial < 20; trial++) {
            for (int i = 0; i < n; i++) u[i] = rnd(&seed);
            double q = rk_sparse_dot(&H, u, u);
            CHECK(q >= -1e-9 * scale, "%s: projected Hessian has u^T H u = %g", model_name[model], q);
        }
        free(x), free(u), free(Hu), free(gp), free(gm), free(mats);
        rk_sparse_free(&H);
        rk_fem_free(&f);
    }
    rk_mesh_free(&m);
}

TEST(materials_are_honoured_per_element)
{
    rk_error err;
    rk_mesh m;
    CHECK_OK(make_box(3, 2, 2, &m, &err));
    rk_material *mats = calloc((size_t)m.nt, sizeof *mats);
    for (int t = 0; t < m.nt; t++) /* every model, stiffness over four decades, two densities */
        mats[t] = (rk_material){(rk_material_model)(t % 4), 1e5 * pow(10.0, t % 5), 0.2 + 0.05 * (t % 3),
                                t % 2 ? 500.0 : 2000.0};
    rk_fem f;
    CHECK_OK(rk_fem_init(&f, &m, mats, &err));
    double *x = perturbed(&f, 0.03, 5u), expect = 0, mass = 0;
    for (int t = 0; t < f.nt; t++) {
        double mu, lambda, xe[12], Dm_inv[9];
        rk_lame(mats[t].young, mats[t].poisson, &mu, &lambda);
        CHECK(f.model[t] == mats[t].model && f.mu[t] == mu && f.lambda[t] == lambda &&
                  f.density[t] == mats[t].density,
              "element %d: material not stored as given", t);
        for (int a = 0; a < 4; a++)
            for (int i = 0; i < 3; i++) xe[3 * a + i] = x[3 * m.tets[4 * t + a] + i];
        double Xe[12];
        for (int a = 0; a < 4; a++)
            for (int i = 0; i < 3; i++) Xe[3 * a + i] = m.X[3 * m.tets[4 * t + a] + i];
        double vol = rk_tet_rest(Xe, Dm_inv);
        expect += rk_tet_energy(mats[t].model, mu, lambda, xe, Dm_inv, vol);
        mass += mats[t].density * vol;
    }
    CHECK_CLOSE(rk_fem_energy(&f, x), expect, 1e-12);
    double lumped = 0;
    for (int v = 0; v < f.nv; v++) lumped += f.vertex_mass[v];
    CHECK_CLOSE(lumped, mass, 1e-12);
    free(x), free(mats);
    rk_fem_free(&f);
    rk_mesh_free(&m);
}

/* rk_fem_init on the 2x2x2 box with element `bad` given material `mat` must fail naming both. */
static int fails_naming(rk_material mat, int bad, const char *want1, const char *want2, char *msg)
{
    rk_error err;
    rk_mesh m;
    if (make_box(2, 2, 2, &m, &err)) return 0;
    rk_material *mats = uniform(m.nt, RK_MAT_NEOHOOKEAN, 1e6, 0.3);
    mats[bad] = mat;
    rk_fem f;
    int rc = rk_fem_init(&f, &m, mats, &err);
    snprintf(msg, 1024, "%s", rc ? err.msg : "(no error)");
    free(mats);
    rk_mesh_free(&m);
    return rc != 0 && strstr(err.msg, want1) && strstr(err.msg, want2);
}

TEST(bad_materials_are_named)
{
    char msg[1024];
    CHECK(fails_naming((rk_material){RK_MAT_LINEAR, -5, 0.3, 1000}, 5, "element 5", "-5", msg), "%s", msg);
    CHECK(fails_naming((rk_material){RK_MAT_LINEAR, NAN, 0.3, 1000}, 2, "element 2", "Young", msg), "%s", msg);
    CHECK(fails_naming((rk_material){RK_MAT_STVK, 1e6, 0.5, 1000}, 7, "element 7", "0.5", msg), "%s", msg);
    CHECK(fails_naming((rk_material){RK_MAT_STVK, 1e6, -1.0, 1000}, 1, "element 1", "Poisson", msg), "%s", msg);
    CHECK(fails_naming((rk_material){RK_MAT_COROTATED, 1e6, 0.3, 0}, 11, "element 11", "density", msg), "%s", msg);
    CHECK(fails_naming((rk_material){(rk_material_model)9, 1e6, 0.3, 10}, 3, "element 3", "model", msg), "%s", msg);
}

TEST(inverted_element_is_named)
{
    rk_error err;
    rk_mesh m;
    CHECK_OK(make_box(2, 2, 2, &m, &err));
    int tmp = m.tets[4 * 13 + 1];
    m.tets[4 * 13 + 1] = m.tets[4 * 13 + 2];
    m.tets[4 * 13 + 2] = tmp;
    rk_material *mats = uniform(m.nt, RK_MAT_LINEAR, 1e6, 0.3);
    rk_fem f;
    int rc = rk_fem_init(&f, &m, mats, &err);
    free(mats);
    rk_mesh_free(&m);
    CHECK(rc != 0 && strstr(err.msg, "element 13 has non-positive volume"), "got: %s", rc ? err.msg : "no error");
}

/* Every slot lands on the entry (min, max) of the two global dofs; columns sorted, closed by
 * their diagonal; every vertex's diagonal block present. */
TEST(slot_map_points_at_the_right_entries)
{
    rk_error err;
    rk_mesh m;
    CHECK_OK(make_box(3, 3, 2, &m, &err));
    rk_material *mats = uniform(m.nt, RK_MAT_LINEAR, 1e6, 0.3);
    rk_fem f;
    CHECK_OK(rk_fem_init(&f, &m, mats, &err));
    const rk_sparse *P = &f.pattern;
    CHECK(P->n == 3 * f.nv && P->colptr[P->n] == P->nnz, "pattern size %d, nnz %d", P->n, P->nnz);
    int *col_of = malloc((size_t)P->nnz * sizeof *col_of);
    for (int j = 0; j < P->n; j++) {
        CHECK(P->colptr[j + 1] > P->colptr[j] && P->rowind[P->colptr[j + 1] - 1] == j, "column %d has no diagonal", j);
        for (int k = P->colptr[j]; k < P->colptr[j + 1]; k++) {
            col_of[k] = j;
            CHECK(k == P->colptr[j] || P->rowind[k] > P->rowind[k - 1], "column %d unsorted", j);
        }
    }
    for (int t = 0; t < f.nt; t++) {
        int k = 0;
        for (int p = 0; p < 12; p++)
            for (int q = p; q < 12; q++, k++) {
                int gp = 3 * f.tets[4 * t + p / 3] + p % 3, gq = 3 * f.tets[4 * t + q / 3] + q % 3;
                int lo = gp < gq ? gp : gq, hi = gp < gq ? gq : gp, s = f.slot[78 * t + k];
                CHECK(P->rowind[s] == lo && col_of[s] == hi, "tet %d entry %d -> (%d, %d), want (%d, %d)", t, k,
                      P->rowind[s], col_of[s], lo, hi);
                CHECK(rk_sparse_find(P, lo, hi) == s, "rk_sparse_find disagrees at tet %d entry %d", t, k);
            }
    }
    /* 3x3x2 cells: vertex 0's lower-neighbour list is empty, so its columns hold just its block. */
    CHECK(P->colptr[1] - P->colptr[0] == 1 && P->colptr[3] - P->colptr[2] == 3, "vertex 0 columns wrong");
    free(col_of), free(mats);
    rk_fem_free(&f);
    rk_mesh_free(&m);
}

/* Energy, gradient and Hessian are assembled in parallel (elastic.c): every sum in element order,
 * so the results are the same bits on any number of threads. 7,200 tets: two blocks, the second
 * added while nothing else runs, the first beside the second's computing. */
TEST(assembly_is_bit_identical_on_any_thread_count)
{
    rk_error err;
    rk_mesh m;
    CHECK_OK(make_box(12, 10, 10, &m, &err));
    rk_material *mats = uniform(m.nt, RK_MAT_NEOHOOKEAN, 1e6, 0.45);
    rk_fem f;
    CHECK_OK(rk_fem_init(&f, &m, mats, &err));
    int n = 3 * f.nv;
    double *x = perturbed(&f, 0.03, 11u), E[4];
    double *g[4], *H[4];
    const int counts[4] = {1, 2, 3, 8};
    for (int k = 0; k < 4; k++) {
        char v[8];
        snprintf(v, sizeof v, "%d", counts[k]);
        setenv("ROMKIT_THREADS", v, 1);
        CHECK_OK(rk_threads_init(&err));
        CHECK(rk_threads() == counts[k], "rk_threads() = %d with ROMKIT_THREADS=%s", rk_threads(), v);
        rk_sparse S;
        CHECK_OK(rk_sparse_alloc_pattern(&f, &S, &err));
        g[k] = calloc((size_t)n, sizeof(double));
        E[k] = rk_fem_energy(&f, x);
        rk_fem_add_gradient(&f, x, 1.5, g[k]);
        rk_fem_add_hessian(&f, x, 0.5, 1, &S);
        H[k] = S.val;
        S.val = NULL;
        rk_sparse_free(&S);
    }
    for (int k = 1; k < 4; k++) {
        CHECK(memcmp(&E[k], &E[0], sizeof E[0]) == 0, "energy on %d threads %.17g, on one %.17g", counts[k], E[k], E[0]);
        CHECK(memcmp(g[k], g[0], sizeof(double) * (size_t)n) == 0, "gradient on %d threads differs", counts[k]);
        CHECK(memcmp(H[k], H[0], sizeof(double) * (size_t)f.pattern.nnz) == 0, "Hessian on %d threads differs", counts[k]);
    }
    CHECK(setenv("ROMKIT_THREADS", "0", 1) == 0 && rk_threads_init(&err) != 0 && strstr(err.msg, "ROMKIT_THREADS"),
          "ROMKIT_THREADS=0 accepted (%s)", err.msg);
    unsetenv("ROMKIT_THREADS");
    CHECK_OK(rk_threads_init(&err));
    for (int k = 0; k < 4; k++) free(g[k]), free(H[k]);
    free(x), free(mats);
    rk_fem_free(&f);
    rk_mesh_free(&m);
}

/* A 200k-tet mesh initializes with the right sizes. How long it takes is make bench's to say
 * (bench/bench_fom.c: fem_init_s, the median of repeated rk_fem_init on every bench mesh). */
TEST(init_handles_200k_tets)
{
    rk_error err;
    rk_mesh m;
    CHECK_OK(make_box(20, 20, 84, &m, &err)); /* 20 x 20 x 84 cells of 6 tets: 201,600 tets */
    rk_material *mats = uniform(m.nt, RK_MAT_NEOHOOKEAN, 1e6, 0.3);
    rk_fem f;
    CHECK_OK(rk_fem_init(&f, &m, mats, &err));
    int nt = f.nt, nv = f.nv, nnz = f.pattern.nnz;
    free(mats);
    rk_fem_free(&f);
    rk_mesh_free(&m);
    printf("# rk_fem_init on %d tets, %d dofs, %d nonzeros\n", nt, 3 * nv, nnz);
    CHECK(nt == 6 * 20 * 20 * 84 && nv == 21 * 21 * 85, "%d tets, %d vertices", nt, nv);
    /* Interior vertex of a Kuhn box has 14 neighbours: nnz ~ 9 * 7 nv + 6 nv. */
    CHECK(nnz < 70 * nv, "pattern has %d nonzeros for %d vertices", nnz, nv);
}

int main(void)
{
    RUN(gradient_matches_finite_differences_for_every_model);
    RUN(hessian_vector_products_match_finite_differences_of_the_gradient);
    RUN(materials_are_honoured_per_element);
    RUN(bad_materials_are_named);
    RUN(inverted_element_is_named);
    RUN(slot_map_points_at_the_right_entries);
    RUN(assembly_is_bit_identical_on_any_thread_count);
    RUN(init_handles_200k_tets);
    return test_finish();
}
