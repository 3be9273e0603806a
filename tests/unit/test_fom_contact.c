/* precompute/fom: a box dropped on a ground plane never passes through it and comes to rest on
 * it; the static solve finds the same resting state. */
#include "fom/fom.h"
#include "testlib.h"
#include "fem_body.h"

typedef struct {
    fem_body body;
    rk_obstacle ground;
    rk_fom_options opt;
} drop;

/* A 0.2 m soft cube, 5 cm above the plane z = 0 (tilted slightly so it lands on an edge first),
 * under gravity; barrier as the scene builder sets it (dhat = 1e-3 diagonal, adaptive kappa). */
static int make_drop(drop *d, rk_integrator integ, rk_error *err)
{
    double size[3] = {0.2, 0.2, 0.2}, shift[3] = {0, 0, 0.05};
    int cells[3] = {3, 3, 3};
    rk_mesh *m = &d->body.m;
    if (rk_mesh_box(size, cells, m, err)) return -1;
    for (int v = 0; v < m->nv; v++) m->X[3 * v + 2] += 0.1 * m->X[3 * v]; /* tilt */
    rk_mesh_transform(m, 1.0, shift);
    int rc = fem_body_init(&d->body, (rk_material){RK_MAT_NEOHOOKEAN, 2e5, 0.35, 1000.0}, err);
    d->ground = (rk_obstacle){.kind = RK_OBSTACLE_PLANE, .normal = {0, 0, 1}};
    rk_fom_default_options(&d->opt);
    d->opt.integrator = integ;
    d->opt.h = 0.01;
    d->opt.gravity[2] = -9.81;
    d->opt.obstacles = &d->ground;
    d->opt.nobstacles = 1;
    d->opt.contact.dhat = 1e-3 * 0.35;
    return rc;
}

static double lowest(const rk_fom *s)
{
    double z = INFINITY;
    for (int v = 0; v < s->fem->nv; v++) z = fmin(z, s->x[3 * v + 2]);
    return z;
}

static double fastest(const rk_fom *s)
{
    double m = 0;
    for (int i = 0; i < 3 * s->fem->nv; i++) m = fmax(m, fabs(s->v[i]));
    return m;
}

TEST(dropped_box_never_crosses_the_ground_and_comes_to_rest)
{
    for (int integ = 0; integ < 2; integ++) {
        rk_error err;
        drop d;
        CHECK_OK(make_drop(&d, (rk_integrator)integ, &err));
        rk_fom s;
        CHECK_OK(rk_fom_init(&s, &d.body.f, &d.opt, &err));
        int touched = 0;
        for (int k = 1; k <= 200; k++) {
            CHECK_OK(rk_fom_step(&s, &err));
            double z = lowest(&s);
            CHECK(z > 0, "integrator %d step %d: a vertex is at height %g", integ, k, z);
            if (z < d.opt.contact.dhat) touched = 1;
        }
        CHECK(touched, "integrator %d: the box never reached the ground", integ);
        double z = lowest(&s), vmax = fastest(&s);
        printf("# integrator %d: lowest vertex %.3g m (dhat %.3g), fastest %.3g m/s, %ld Newton iterations, "
               "%ld halvings, %ld unconverged\n",
               integ, z, d.opt.contact.dhat, vmax, s.stats.newton_iterations, s.stats.line_search_halvings,
               s.stats.unconverged_steps);
        CHECK(z > 0 && z < d.opt.contact.dhat, "integrator %d: resting height %g outside (0, dhat)", integ, z);
        CHECK(vmax < 0.02, "integrator %d: still moving at %g m/s after 2 s", integ, vmax);
        CHECK(s.stats.unconverged_steps == 0, "%ld unconverged steps", s.stats.unconverged_steps);
        rk_fom_free(&s);
        fem_body_free(&d.body);
    }
}

TEST(static_solve_rests_the_box_on_the_ground)
{
    rk_error err;
    drop d;
    CHECK_OK(make_drop(&d, RK_BACKWARD_EULER, &err));
    /* Start just above the ground, flat, so the rest state is near. */
    for (int v = 0; v < d.body.m.nv; v++) d.body.m.X[3 * v + 2] -= 0.1 * d.body.m.X[3 * v] + 0.05 - 2e-4;
    rk_fem_free(&d.body.f);
    CHECK_OK(fem_body_init(&d.body, (rk_material){RK_MAT_NEOHOOKEAN, 2e5, 0.35, 1000.0}, &err));
    rk_fom s;
    CHECK_OK(rk_fom_init(&s, &d.body.f, &d.opt, &err));
    CHECK_OK(rk_fom_static(&s, &err));
    double z = lowest(&s);
    CHECK(z > 0 && z < d.opt.contact.dhat, "resting height %g outside (0, dhat)", z);
    double top = -INFINITY, top0 = -INFINITY;
    for (int v = 0; v < d.body.f.nv; v++) {
        top = fmax(top, s.x[3 * v + 2]);
        top0 = fmax(top0, d.body.f.X[3 * v + 2]);
    }
    CHECK(top < top0, "the box did not settle (top %g, was %g)", top, top0);
    /* A dynamic run from the same start ends at the same state. */
    double *xs = malloc(3 * (size_t)d.body.f.nv * sizeof *xs);
    memcpy(xs, s.x, 3 * (size_t)d.body.f.nv * sizeof *xs);
    rk_fom_free(&s);
    d.opt.rayleigh_mass = 5.0; /* settle fast */
    CHECK_OK(rk_fom_init(&s, &d.body.f, &d.opt, &err));
    for (int k = 0; k < 300; k++) CHECK_OK(rk_fom_step(&s, &err));
    double worst = 0;
    for (int i = 2; i < 3 * d.body.f.nv; i += 3) worst = fmax(worst, fabs(s.x[i] - xs[i]));
    CHECK(worst < 1e-5, "static and settled dynamic heights differ by %g m", worst);
    free(xs);
    rk_fom_free(&s);
    fem_body_free(&d.body);
}

int main(void)
{
    RUN(dropped_box_never_crosses_the_ground_and_comes_to_rest);
    RUN(static_solve_rests_the_box_on_the_ground);
    return test_finish();
}
