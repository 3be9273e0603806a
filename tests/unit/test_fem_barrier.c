/* precompute/fem: the ground-plane log barrier (energy, gradient, Hessian against finite
 * differences, PSD, infinite past the plane) and the step filter. */
#include "fem/fem.h"
#include "testlib.h"

static double rnd(unsigned *state)
{
    *state = *state * 1664525u + 1013904223u;
    return (double)(*state >> 8) / (double)(1u << 23) - 1.0;
}

/* A 2x2x2-cell unit box, its bottom at height z0 above the plane z = 0, and a second, tilted
 * plane below the -x face; dhat large enough that many vertices are inside the band. */
typedef struct {
    rk_mesh m;
    rk_fem f;
    rk_plane planes[2];
    rk_obstacles o;
} scene;

static int make_scene(scene *s, double z0, rk_error *err)
{
    double size[3] = {1, 1, 1}, shift[3] = {0, 0, z0};
    int cells[3] = {2, 2, 2};
    if (rk_mesh_box(size, cells, &s->m, err)) return -1;
    rk_mesh_transform(&s->m, 1.0, shift);
    rk_material *mats = calloc((size_t)s->m.nt, sizeof *mats);
    for (int t = 0; t < s->m.nt; t++) mats[t] = (rk_material){RK_MAT_LINEAR, 1e6, 0.3, 1000};
    int rc = rk_fem_init(&s->f, &s->m, mats, err);
    free(mats);
    double c = 1 / sqrt(2.0);
    s->planes[0] = (rk_plane){{0, 0, 0}, {0, 0, 1}};
    s->planes[1] = (rk_plane){{-0.05, 0, 0}, {c, 0, c}};
    s->o = (rk_obstacles){2, s->planes, 0.6, 50.0};
    return rc;
}

static void free_scene(scene *s)
{
    rk_fem_free(&s->f);
    rk_mesh_free(&s->m);
}

TEST(barrier_derivatives_match_finite_differences)
{
    rk_error err;
    scene s;
    CHECK_OK(make_scene(&s, 0.02, &err));
    int n = 3 * s.f.nv;
    double *x = malloc((size_t)n * sizeof *x), *g = calloc((size_t)n, sizeof *g);
    unsigned seed = 41u;
    for (int i = 0; i < n; i++) x[i] = s.f.X[i] + 0.005 * rnd(&seed);
    double E = rk_barrier_energy(&s.f, &s.o, x);
    CHECK(E > 0 && isfinite(E), "barrier energy %g with vertices inside dhat", E);
    rk_barrier_add_gradient(&s.f, &s.o, x, 1.0, g);
    double worst = 0, scale = 0;
    for (int i = 0; i < n; i++) {
        double h = 1e-7, keep = x[i];
        x[i] = keep + h;
        double ep = rk_barrier_energy(&s.f, &s.o, x);
        x[i] = keep - h;
        double em = rk_barrier_energy(&s.f, &s.o, x);
        x[i] = keep;
        worst = fmax(worst, fabs((ep - em) / (2 * h) - g[i]));
        scale = fmax(scale, fabs(g[i]));
    }
    CHECK(scale > 0 && worst <= 1e-6 * scale, "gradient differs from FD by %g (scale %g)", worst, scale);

    rk_sparse H;
    CHECK_OK(rk_sparse_alloc_pattern(&s.f, &H, &err));
    rk_barrier_add_hessian(&s.f, &s.o, x, 1.0, &H);
    double *u = malloc((size_t)n * sizeof *u), *Hu = malloc((size_t)n * sizeof *Hu);
    double *gp = calloc((size_t)n, sizeof *gp), *gm = calloc((size_t)n, sizeof *gm);
    for (int i = 0; i < n; i++) u[i] = rnd(&seed);
    rk_sparse_mul(&H, u, Hu);
    double h = 1e-7;
    for (int i = 0; i < n; i++) x[i] += h * u[i];
    rk_barrier_add_gradient(&s.f, &s.o, x, 1.0, gp);
    for (int i = 0; i < n; i++) x[i] -= 2 * h * u[i];
    rk_barrier_add_gradient(&s.f, &s.o, x, 1.0, gm);
    for (int i = 0; i < n; i++) x[i] += h * u[i];
    worst = scale = 0;
    for (int i = 0; i < n; i++) {
        worst = fmax(worst, fabs((gp[i] - gm[i]) / (2 * h) - Hu[i]));
        scale = fmax(scale, fabs(Hu[i]));
    }
    CHECK(scale > 0 && worst <= 1e-5 * scale, "H u differs from FD by %g (scale %g)", worst, scale);
    for (int trial = 0; trial < 20; trial++) {
        for (int i = 0; i < n; i++) u[i] = rnd(&seed);
        CHECK(rk_sparse_dot(&H, u, u) >= 0, "barrier Hessian is not PSD");
    }
    /* Past the plane the energy is infinite; beyond dhat it is zero. */
    double keep = x[2];
    x[2] = -1e-9;
    CHECK(rk_barrier_energy(&s.f, &s.o, x) == INFINITY, "vertex behind the plane gives finite energy");
    x[2] = keep;
    s.o.dhat = 1e-3;
    CHECK(rk_barrier_energy(&s.f, &s.o, x) == 0, "no vertex within dhat, yet energy %g",
          rk_barrier_energy(&s.f, &s.o, x));
    free(x), free(g), free(u), free(Hu), free(gp), free(gm);
    rk_sparse_free(&H);
    free_scene(&s);
}

static double min_distance(const rk_obstacles *o, int nv, const double *x, const double *d0, int *bad)
{
    double worst_ratio = INFINITY;
    *bad = 0;
    for (int k = 0; k < o->count; k++)
        for (int v = 0; v < nv; v++) {
            const rk_plane *p = &o->planes[k];
            double d = 0;
            for (int i = 0; i < 3; i++) d += p->normal[i] * (x[3 * v + i] - p->point[i]);
            double ratio = d / d0[k * nv + v];
            if (ratio < worst_ratio) worst_ratio = ratio;
            if (!(d > 0)) *bad = 1;
        }
    return worst_ratio;
}

TEST(max_step_never_lets_a_vertex_cross)
{
    rk_error err;
    scene s;
    CHECK_OK(make_scene(&s, 0.01, &err));
    int nv = s.f.nv, n = 3 * nv;
    double *x = malloc((size_t)n * sizeof *x), *dx = malloc((size_t)n * sizeof *dx);
    double *y = malloc((size_t)n * sizeof *y), *d0 = malloc(2 * (size_t)nv * sizeof *d0);
    unsigned seed = 5u;
    int binding = 0;
    for (int trial = 0; trial < 200; trial++) {
        for (int i = 0; i < n; i++) x[i] = s.f.X[i] + 0.004 * rnd(&seed);
        double amp = trial % 2 ? 0.05 : 3.0; /* small steps are often unconstrained */
        for (int i = 0; i < n; i++) dx[i] = amp * rnd(&seed);
        int bad;
        for (int k = 0; k < 2; k++)
            for (int v = 0; v < nv; v++) {
                const rk_plane *p = &s.planes[k];
                d0[k * nv + v] = 0;
                for (int i = 0; i < 3; i++) d0[k * nv + v] += p->normal[i] * (x[3 * v + i] - p->point[i]);
            }
        double alpha = rk_planes_max_step(&s.o, nv, x, dx);
        CHECK(alpha > 0 && alpha <= 1, "alpha = %g", alpha);
        if (alpha < 1) binding++;
        /* Anywhere along [0, alpha] (linear motion: the end is the worst) distances stay >= 10%. */
        for (int i = 0; i < n; i++) y[i] = x[i] + alpha * dx[i];
        double ratio = min_distance(&s.o, nv, y, d0, &bad);
        CHECK(!bad && ratio >= 0.1 - 1e-12, "trial %d: a vertex ends at %g of its distance", trial, ratio);
        /* And the bound is tight: a bit further, some vertex gets closer than 10%. */
        if (alpha < 1) {
            for (int i = 0; i < n; i++) y[i] = x[i] + 1.01 * alpha * dx[i];
            CHECK(min_distance(&s.o, nv, y, d0, &bad) < 0.1, "trial %d: alpha %g not tight", trial, alpha);
        }
    }
    CHECK(binding > 50, "only %d of 200 trials constrained the step", binding);
    /* Moving away from every plane is never limited. */
    for (int i = 0; i < n; i++) dx[i] = i % 3 == 2 ? 10.0 : 10.0 * (i % 3 == 0);
    CHECK(rk_planes_max_step(&s.o, nv, s.f.X, dx) == 1.0, "step away from the planes limited");
    free(x), free(dx), free(y), free(d0);
    free_scene(&s);
}

int main(void)
{
    RUN(barrier_derivatives_match_finite_differences);
    RUN(max_step_never_lets_a_vertex_cross);
    return test_finish();
}
