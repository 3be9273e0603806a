/* The contact model (precompute/contact): every kind of pair gathered on a scene built for it (two
 * objects, a plane, a sphere, a capsule, a box), the barrier's gradient against central
 * differences of its energy and its (unprojected) Hessian against differences of the gradient,
 * the projected Hessian PSD, and the feasible step of CCD against the exact intersection test. */
#include "contact/contact.h"
#include "testlib.h"
#include "two_boxes.h"
#include "util/util.h"

/* Two 1 m cubes of 2 x 2 x 2 cells, B 0.02 m above A and shifted; obstacles 0.02 to 0.03 m from
 * the surfaces: a plane left of A, a sphere below A, a box right of A, a capsule over B. */
typedef struct {
    rk_mesh mesh;
    int first[3];
    rk_obstacle obs[4];
    rk_contact c;
    double *x;
} scene;

static int make_scene(scene *s, rk_error *err)
{
    memset(s, 0, sizeof *s);
    double size[3] = {1, 1, 1}, shift[3] = {0.2, 0.3, 1.02};
    int cells[3] = {2, 2, 2};
    if (two_boxes(size, cells, shift, 1, &s->mesh, s->first, err)) return -1;
    s->obs[0] = (rk_obstacle){.kind = RK_OBSTACLE_PLANE, .point = {-0.03, 0, 0}, .normal = {1, 0, 0}};
    s->obs[1] = (rk_obstacle){.kind = RK_OBSTACLE_SPHERE, .center = {0.5, 0.4, -0.13}, .radius = 0.1};
    s->obs[2] = (rk_obstacle){.kind = RK_OBSTACLE_BOX, .min = {1.03, 0.2, 0.2}, .max = {1.5, 0.8, 0.8}};
    s->obs[3] = (rk_obstacle){.kind = RK_OBSTACLE_CAPSULE, .center = {0.3, 0.45, 2.06}, .end = {1.1, 0.55, 2.06}, .radius = 0.02};
    rk_contact_options o;
    rk_contact_default_options(&o);
    o.dhat = 0.05;
    o.kappa = 1e3;
    if (rk_contact_init(&s->c, &s->mesh, s->first, 2, s->obs, 4, &o, 1.0, err)) return -1;
    s->x = calloc(3 * (size_t)s->mesh.nv, sizeof(double));
    uint64_t seed = 5;
    for (int i = 0; i < 3 * s->mesh.nv; i++) s->x[i] = s->mesh.X[i] + 0.003 * (2 * rk_uniform(&seed) - 1);
    return 0;
}

static void free_scene(scene *s)
{
    rk_contact_free(&s->c);
    rk_mesh_free(&s->mesh);
    free(s->x);
}

/* A dense Hessian from the blocks. */
typedef struct {
    int n;
    double *H;
    int not_psd;
} dense;

static void collect(void *ctx, const int *id, int np, const double *B)
{
    dense *d = ctx;
    int dim = 3 * np;
    double w[12], V[144];
    rk_sym_eig(dim, B, w, V);
    for (int k = 0; k < dim; k++) d->not_psd += w[k] < -1e-9 * fabs(w[dim - 1]);
    for (int i = 0; i < np; i++)
        for (int j = 0; j < np; j++)
            if (id[i] >= 0 && id[j] >= 0)
                for (int a = 0; a < 3; a++)
                    for (int b = 0; b < 3; b++) d->H[(size_t)d->n * (3 * id[i] + a) + 3 * id[j] + b] += B[dim * (3 * i + a) + 3 * j + b];
}

TEST(every_kind_of_pair_is_gathered)
{
    rk_error err;
    scene s;
    CHECK_OK(make_scene(&s, &err));
    rk_contact_set set = {0};
    CHECK_OK(rk_contact_gather(&s.c, s.x, &set, &err));
    int kinds[3] = {0}, obstacle_points = 0, thick = 0, object_object = 0;
    for (int i = 0; i < set.n; i++) {
        const rk_contact_pair *p = &set.pairs[i];
        kinds[p->kind]++;
        thick += p->xi > 0;
        obstacle_points += p->kind != RK_PAIR_POINT_PLANE && (p->id[0] < 0 || p->id[3] < 0);
        object_object += p->kind != RK_PAIR_POINT_PLANE && p->id[0] >= 0 && p->id[1] >= 0 && p->id[2] >= 0 && p->id[3] >= 0;
    }
    printf("# %d pairs: %d point-triangle, %d edge-edge, %d point-plane; %d between the objects, %d with an "
           "obstacle's points, %d thick (sphere, capsule)\n", set.n, kinds[0], kinds[1], kinds[2], object_object,
           obstacle_points, thick);
    CHECK(kinds[0] && kinds[1] && kinds[2] && object_object && obstacle_points && thick, "a kind of pair is missing");
    rk_contact_set_free(&set);
    free_scene(&s);
}

TEST(barrier_gradient_and_hessian_match_finite_differences)
{
    rk_error err;
    scene s;
    CHECK_OK(make_scene(&s, &err));
    s.c.exact_hessian = 1;
    int n = 3 * s.mesh.nv;
    rk_contact_set set = {0};
    CHECK_OK(rk_contact_gather(&s.c, s.x, &set, &err));
    size_t nn = n > 0 ? (size_t)n : 1; /* (gcc -O1 with sanitizers cannot see n > 0 and warns) */
    double *g = calloc(nn, sizeof(double)), *gp = calloc(nn, sizeof(double)), *gm = calloc(nn, sizeof(double));
    dense d = {n, calloc(nn * nn, sizeof(double)), 0};
    double E = rk_contact_energy(&s.c, &set, s.x, g, NULL, collect, &d, NULL);
    CHECK(isfinite(E) && E > 0, "energy %g", E);
    double worst_g = 0, worst_H = 0, h = 1e-7, gscale = 0, Hscale = 0;
    for (int i = 0; i < n; i++) gscale = fmax(gscale, fabs(g[i]));
    for (int i = 0; i < n * n; i++) Hscale = fmax(Hscale, fabs(d.H[i]));
    for (int i = 0; i < n; i++) {
        double keep = s.x[i];
        memset(gp, 0, n * sizeof(double)), memset(gm, 0, n * sizeof(double));
        s.x[i] = keep + h;
        double Ep = rk_contact_energy(&s.c, &set, s.x, gp, NULL, NULL, NULL, NULL);
        s.x[i] = keep - h;
        double Em = rk_contact_energy(&s.c, &set, s.x, gm, NULL, NULL, NULL, NULL);
        s.x[i] = keep;
        worst_g = fmax(worst_g, fabs((Ep - Em) / (2 * h) - g[i]) / gscale);
        for (int j = 0; j < n; j++) worst_H = fmax(worst_H, fabs((gp[j] - gm[j]) / (2 * h) - d.H[(size_t)n * j + i]) / Hscale);
    }
    printf("# %d pairs, energy %.4g: gradient off by %.2e, Hessian by %.2e (relative to their largest entries)\n", set.n,
           E, worst_g, worst_H);
    CHECK(worst_g < 1e-6 && worst_H < 1e-5, "gradient %g, Hessian %g", worst_g, worst_H);
    /* projected, every block is PSD */
    s.c.exact_hessian = 0;
    memset(d.H, 0, sizeof(double) * (size_t)n * n);
    d.not_psd = 0;
    rk_contact_energy(&s.c, &set, s.x, NULL, NULL, collect, &d, NULL);
    CHECK(d.not_psd == 0, "%d negative eigenvalues in projected blocks", d.not_psd);
    free(g), free(gp), free(gm), free(d.H);
    rk_contact_set_free(&set);
    free_scene(&s);
}

TEST(friction_gradient_and_hessian_match_finite_differences)
{
    rk_error err;
    scene s;
    CHECK_OK(make_scene(&s, &err));
    s.c.opt.friction = 0.4;
    int n = 3 * s.mesh.nv;
    double step = 0.01, eps = s.c.opt.eps_v * step; /* slips below eps are static */
    CHECK_OK(rk_contact_friction_start(&s.c, s.x, &err));
    CHECK_OK(rk_contact_friction_lag(&s.c, s.x, &err));
    int planes = 0;
    for (int k = 0; k < s.c.nfriction; k++) planes += s.c.friction[k].np == 1;
    /* slide every vertex by up to 3 eps: pairs on both sides of the smoothing */
    uint64_t rng = 11;
    for (int i = 0; i < n; i++) s.x[i] += 3 * eps * (2 * rk_uniform(&rng) - 1);
    size_t nn = n > 0 ? (size_t)n : 1; /* (gcc -O1 with sanitizers cannot see n > 0 and warns) */
    double *g = calloc(nn, sizeof(double)), *gp = calloc(nn, sizeof(double)), *gm = calloc(nn, sizeof(double));
    dense d = {n, calloc(nn * nn, sizeof(double)), 0};
    double E = rk_contact_friction_energy(&s.c, s.x, step, g, NULL, collect, &d);
    double worst_g = 0, worst_H = 0, h = 1e-10, gscale = 0, Hscale = 0;
    for (int i = 0; i < n; i++) gscale = fmax(gscale, fabs(g[i]));
    for (int i = 0; i < n * n; i++) Hscale = fmax(Hscale, fabs(d.H[i]));
    for (int i = 0; i < n; i++) {
        double keep = s.x[i];
        memset(gp, 0, n * sizeof(double)), memset(gm, 0, n * sizeof(double));
        s.x[i] = keep + h;
        double Ep = rk_contact_friction_energy(&s.c, s.x, step, gp, NULL, NULL, NULL);
        s.x[i] = keep - h;
        double Em = rk_contact_friction_energy(&s.c, s.x, step, gm, NULL, NULL, NULL);
        s.x[i] = keep;
        worst_g = fmax(worst_g, fabs((Ep - Em) / (2 * h) - g[i]) / gscale);
        for (int j = 0; j < n; j++) worst_H = fmax(worst_H, fabs((gp[j] - gm[j]) / (2 * h) - d.H[(size_t)n * j + i]) / Hscale);
    }
    printf("# friction: %d lagged pairs (%d against a plane), energy %.4g: gradient off by %.2e, Hessian by %.2e\n",
           s.c.nfriction, planes, E, worst_g, worst_H);
    CHECK(s.c.nfriction > 0 && planes > 0 && planes < s.c.nfriction, "pairs %d, plane pairs %d", s.c.nfriction, planes);
    CHECK(worst_g < 1e-6 && worst_H < 1e-4, "gradient %g, Hessian %g", worst_g, worst_H);
    CHECK(d.not_psd == 0, "%d negative eigenvalues in friction blocks", d.not_psd);
    free(g), free(gp), free(gm), free(d.H);
    free_scene(&s);
}

TEST(ccd_step_keeps_every_surface_apart)
{
    rk_error err;
    scene s;
    CHECK_OK(make_scene(&s, &err));
    int n = 3 * s.mesh.nv;
    CHECK(rk_contact_intersections(&s.c, s.x, &err) == 0, "the scene starts intersecting");
    double *dx = calloc(n, sizeof(double)), *y = calloc(n, sizeof(double));
    uint64_t seed = 9;
    int stopped = 0;
    for (int trial = 0; trial < 20; trial++) {
        /* B falls through A, A shoots into the obstacles: big random motions */
        for (int v = 0; v < s.mesh.nv; v++)
            for (int a = 0; a < 3; a++) dx[3 * v + a] = (v < s.first[1] ? -0.5 : 0) * (a == 0) + (v >= s.first[1] ? -1.5 : 0) * (a == 2) +
                                                        0.2 * (2 * rk_uniform(&seed) - 1);
        double alpha = rk_contact_max_step(&s.c, s.x, dx, NULL, &err);
        CHECK(alpha >= 0 && alpha <= 1, "alpha %g", alpha);
        stopped += alpha < 1;
        for (int i = 0; i < n; i++) y[i] = s.x[i] + alpha * dx[i];
        int crossings = rk_contact_intersections(&s.c, y, &err);
        CHECK(crossings == 0, "trial %d: %d crossings after a step of %g", trial, crossings, alpha);
        double d = rk_contact_min_distance(&s.c, y, &err);
        CHECK(d > 0, "trial %d: touching after the step (%g)", trial, d);
    }
    CHECK(stopped == 20, "CCD let %d of 20 colliding motions through whole", 20 - stopped);
    free(dx), free(y);
    free_scene(&s);
}

int main(void)
{
    RUN(every_kind_of_pair_is_gathered);
    RUN(barrier_gradient_and_hessian_match_finite_differences);
    RUN(friction_gradient_and_hessian_match_finite_differences);
    RUN(ccd_step_keeps_every_surface_apart);
    return test_finish();
}
