/* precompute/fom: prescribed vertices (fixed, twist, translate) sit exactly on their targets in
 * dynamics and in static solves; a linear static solve satisfies K0 u = f on the free dofs. */
#include "fom/fom.h"
#include "testlib.h"
#include "fem_body.h"

typedef struct {
    fem_body body;
    int *left, nleft, *right, nright; /* vertices on the faces x = 0 and x = L */
} beam;

static const double L = 1.0, W = 0.2;

static int make_beam(beam *b, rk_material_model model, double young, rk_error *err)
{
    int rc = fem_body_box(&b->body, L, W, W, 6, 2, 2, (rk_material){model, young, 0.3, 1000.0}, err);
    if (rc) return rc;
    b->left = calloc((size_t)b->body.f.nv, sizeof(int));
    b->right = calloc((size_t)b->body.f.nv, sizeof(int));
    b->nleft = b->nright = 0;
    for (int v = 0; v < b->body.f.nv; v++) {
        if (b->body.f.X[3 * v] < 1e-9) b->left[b->nleft++] = v;
        if (b->body.f.X[3 * v] > L - 1e-9) b->right[b->nright++] = v;
    }
    return rc;
}

static void free_beam(beam *b)
{
    free(b->left), free(b->right);
    fem_body_free(&b->body);
}

/* Target of rest point X under a twist of `angle` about the x axis through (., W/2, W/2). */
static void twisted(const double *X, double angle, double out[3])
{
    double y = X[1] - W / 2, z = X[2] - W / 2;
    out[0] = X[0];
    out[1] = W / 2 + cos(angle) * y - sin(angle) * z;
    out[2] = W / 2 + sin(angle) * y + cos(angle) * z;
}

TEST(twisted_and_fixed_vertices_sit_on_their_targets)
{
    rk_error err;
    beam b;
    CHECK_OK(make_beam(&b, RK_MAT_NEOHOOKEAN, 1e5, &err));
    for (int integ = 0; integ < 2; integ++) {
        rk_prescribed groups[2] = {
            {.kind = RK_MOTION_FIXED, .count = b.nleft, .verts = b.left},
            {.kind = RK_MOTION_TWIST, .count = b.nright, .verts = b.right, .axis = {2, 0, 0}, /* not unit */
             .center = {L, W / 2, W / 2}, .rate = 2.0},
        };
        rk_fom_options opt;
        rk_fom_default_options(&opt);
        opt.integrator = (rk_integrator)integ;
        opt.h = 0.02;
        opt.gravity[2] = -9.81;
        opt.nprescribed = 2;
        opt.prescribed = groups;
        rk_fom s;
        CHECK_OK(rk_fom_init(&s, &b.body.f, &opt, &err));
        for (int k = 1; k <= 40; k++) { /* 1.6 rad at the end */
            CHECK_OK(rk_fom_step(&s, &err));
            for (int j = 0; j < b.nright; j++) {
                int v = b.right[j];
                double want[3];
                twisted(&b.body.f.X[3 * v], 2.0 * s.t, want);
                for (int i = 0; i < 3; i++)
                    CHECK(fabs(s.x[3 * v + i] - want[i]) <= 1e-12, "step %d: twisted vertex %d off by %g", k,
                          v, s.x[3 * v + i] - want[i]);
            }
            for (int j = 0; j < b.nleft; j++)
                for (int i = 0; i < 3; i++)
                    CHECK(s.x[3 * b.left[j] + i] == b.body.f.X[3 * b.left[j] + i], "step %d: fixed vertex %d moved", k,
                          b.left[j]);
        }
        CHECK(s.stats.unconverged_steps == 0, "%ld unconverged steps", s.stats.unconverged_steps);
        /* The twist reaches into the beam: the mid-span corners turned by a fraction of 1.6 rad. */
        int mid = -1;
        for (int v = 0; v < b.body.f.nv; v++)
            if (fabs(b.body.f.X[3 * v] - L / 2) < 1e-9 && b.body.f.X[3 * v + 1] > W - 1e-9 && b.body.f.X[3 * v + 2] > W - 1e-9) mid = v;
        CHECK(mid >= 0, "no mid-span corner");
        double y = s.x[3 * mid + 1] - W / 2, z = s.x[3 * mid + 2] - W / 2;
        double turned = atan2(z, y) - atan2(W / 2, W / 2);
        CHECK(turned > 0.3 && turned < 1.3, "mid-span turned by %g rad", turned);
        rk_fom_free(&s);
    }
    free_beam(&b);
}

TEST(translated_vertices_follow_their_velocity)
{
    rk_error err;
    beam b;
    CHECK_OK(make_beam(&b, RK_MAT_COROTATED, 1e5, &err));
    rk_prescribed group = {.kind = RK_MOTION_TRANSLATE, .count = b.nright, .verts = b.right, .velocity = {0.1, 0, -0.05}};
    rk_fom_options opt;
    rk_fom_default_options(&opt);
    opt.nprescribed = 1;
    opt.prescribed = &group;
    rk_fom s;
    CHECK_OK(rk_fom_init(&s, &b.body.f, &opt, &err));
    for (int k = 1; k <= 30; k++) {
        CHECK_OK(rk_fom_step(&s, &err));
        for (int j = 0; j < b.nright; j++)
            for (int i = 0; i < 3; i++) {
                int v = b.right[j];
                double want = b.body.f.X[3 * v + i] + group.velocity[i] * s.t;
                CHECK(fabs(s.x[3 * v + i] - want) <= 1e-12, "step %d vertex %d axis %d: %g, want %g", k, v, i,
                      s.x[3 * v + i], want);
            }
    }
    /* The free rest of the beam is dragged along: its centre moved in +x. */
    double cx = 0;
    for (int v = 0; v < b.body.f.nv; v++) cx += s.x[3 * v] - b.body.f.X[3 * v];
    CHECK(cx > 0, "beam not dragged");
    rk_fom_free(&s);
    free_beam(&b);
}

/* Linear material: the static problem is quadratic, K0 u = f on free dofs, u = 0 on fixed. */
TEST(linear_static_cantilever_solves_the_rest_stiffness_system)
{
    rk_error err;
    beam b;
    CHECK_OK(make_beam(&b, RK_MAT_LINEAR, 1e7, &err));
    rk_prescribed group = {.kind = RK_MOTION_FIXED, .count = b.nleft, .verts = b.left};
    rk_fom_options opt;
    rk_fom_default_options(&opt);
    opt.gravity[2] = -9.81;
    opt.nprescribed = 1;
    opt.prescribed = &group;
    opt.newton_tol = 1e-12; /* metres, static */
    rk_fom s;
    CHECK_OK(rk_fom_init(&s, &b.body.f, &opt, &err));
    CHECK_OK(rk_fom_static(&s, &err));
    int n = 3 * b.body.f.nv;
    rk_sparse K;
    CHECK_OK(rk_sparse_alloc_pattern(&b.body.f, &K, &err));
    rk_fem_add_rest_stiffness(&b.body.f, 1.0, &K);
    double *u = malloc((size_t)n * sizeof *u), *Ku = malloc((size_t)n * sizeof *Ku);
    for (int i = 0; i < n; i++) u[i] = s.x[i] - b.body.f.X[i];
    rk_sparse_mul(&K, u, Ku);
    char *fixed = calloc((size_t)b.body.f.nv, 1);
    for (int j = 0; j < b.nleft; j++) fixed[b.left[j]] = 1;
    double worst = 0, fmax_ = 0, tip = 0;
    for (int v = 0; v < b.body.f.nv; v++) {
        double fz = -9.81 * b.body.f.vertex_mass[v];
        fmax_ = fmax(fmax_, fabs(fz));
        if (fixed[v]) {
            CHECK(u[3 * v] == 0 && u[3 * v + 1] == 0 && u[3 * v + 2] == 0, "fixed vertex %d moved", v);
            continue;
        }
        for (int i = 0; i < 3; i++) worst = fmax(worst, fabs(Ku[3 * v + i] - (i == 2 ? fz : 0)));
        tip = fmin(tip, u[3 * v + 2]);
    }
    printf("# cantilever tip deflection %.4g m, residual %.3g N (max load %.3g N), %ld Newton iterations\n", tip,
           worst, fmax_, s.stats.newton_iterations);
    CHECK(worst <= 1e-6 * fmax_, "K0 u - f = %g on free dofs (load %g)", worst, fmax_);
    CHECK(tip < 0, "beam did not sag");
    for (int i = 0; i < n; i++) CHECK(s.v[i] == 0, "velocity not zero after a static solve");
    free(u), free(Ku), free(fixed);
    rk_sparse_free(&K);
    rk_fom_free(&s);
    free_beam(&b);
}

/* Static solve of a large twist (prescribed at time steps * h) on a soft Neo-Hookean beam: the
 * targets are met exactly and the result is an equilibrium of the nonlinear problem. */
TEST(static_twist_reaches_equilibrium)
{
    rk_error err;
    beam b;
    CHECK_OK(make_beam(&b, RK_MAT_NEOHOOKEAN, 1e5, &err));
    rk_prescribed groups[2] = {
        {.kind = RK_MOTION_FIXED, .count = b.nleft, .verts = b.left},
        {.kind = RK_MOTION_TWIST, .count = b.nright, .verts = b.right, .axis = {1, 0, 0},
         .center = {L, W / 2, W / 2}, .rate = 1.0},
    };
    rk_fom_options opt;
    rk_fom_default_options(&opt);
    opt.h = 0.01;
    opt.steps = 150; /* 1.5 rad */
    opt.newton_tol = 1e-10; /* metres, static */
    opt.nprescribed = 2;
    opt.prescribed = groups;
    rk_fom s;
    CHECK_OK(rk_fom_init(&s, &b.body.f, &opt, &err));
    CHECK_OK(rk_fom_static(&s, &err));
    for (int j = 0; j < b.nright; j++) {
        int v = b.right[j];
        double want[3];
        twisted(&b.body.f.X[3 * v], 1.5, want);
        for (int i = 0; i < 3; i++)
            CHECK(fabs(s.x[3 * v + i] - want[i]) <= 1e-12, "twisted vertex %d off by %g", v, s.x[3 * v + i] - want[i]);
    }
    /* Equilibrium: elastic forces vanish on the free vertices (relative to the largest force). */
    int n = 3 * b.body.f.nv;
    double *g = calloc((size_t)n, sizeof *g);
    rk_fem_add_gradient(&b.body.f, s.x, 1.0, g);
    char *pres = calloc((size_t)b.body.f.nv, 1);
    for (int j = 0; j < b.nleft; j++) pres[b.left[j]] = 1;
    for (int j = 0; j < b.nright; j++) pres[b.right[j]] = 1;
    double free_force = 0, reaction = 0;
    for (int v = 0; v < b.body.f.nv; v++)
        for (int i = 0; i < 3; i++) {
            if (pres[v]) reaction = fmax(reaction, fabs(g[3 * v + i]));
            else free_force = fmax(free_force, fabs(g[3 * v + i]));
        }
    printf("# static twist: residual %.3g N, reactions up to %.3g N, %ld Newton iterations\n", free_force, reaction,
           s.stats.newton_iterations);
    CHECK(free_force <= 1e-6 * reaction, "residual force %g vs reactions %g", free_force, reaction);
    free(g), free(pres);
    rk_fom_free(&s);
    free_beam(&b);
}

int main(void)
{
    RUN(twisted_and_fixed_vertices_sit_on_their_targets);
    RUN(translated_vertices_follow_their_velocity);
    RUN(linear_static_cantilever_solves_the_rest_stiffness_system);
    RUN(static_twist_reaches_equilibrium);
    return test_finish();
}
