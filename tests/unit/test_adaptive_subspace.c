/* precompute/adaptive: the adaptive subspace simulator against full order on small contact scenes:
 * with every vertex enriched it takes the full-order steps and its Schur-complement direction is
 * full Newton's; the thresholds control enrichment (a whole METIS part at a time), a stiff object is
 * not enriched where a soft one is; BFGS and exact subspace Hessians converge to the same step;
 * downdating drops what a free fall does not need; bad options are named. */
#include "adaptive/adaptive_impl.h"
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
    return rk_basis_skinning(&s->body.f, NULL, 0, m, &s->basis, err);
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
    o.full_fraction = 1;    /* the Schur solve over everything, not full order's Newton in its place */
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

static int init_adaptive(rk_adaptive *ad, scene *s, double eps_g, double eps_e, int downdate, rk_error *err)
{
    rk_adaptive_options o;
    rk_adaptive_default_options(&o);
    o.eps_g_nodal = o.eps_g_modal = eps_g;
    o.paper_units = 1;      /* the paper's oracle on its own: its G, no enrichment by the residual */
    o.residual_rounds = 0;
    o.eps_e = eps_e;
    o.downdate = downdate;
    o.subdomains = 6;
    o.full_fraction = 1; /* the oracle's enrichment as it is, however far it goes */
    return rk_adaptive_init(ad, &s->body.f, &s->opt, s->basis.U, s->basis.r, &o, err);
}

TEST(schur_direction_is_full_newtons_when_everything_is_enriched)
{
    rk_error err;
    scene s;
    CHECK_OK(make_scene(&s, 1e5, 4, &err));
    rk_adaptive ad;
    CHECK_OK(init_adaptive(&ad, &s, 1e-300, 1e300, 0, &err));
    ad.opt.pcg_tol = 1e-10;
    CHECK_OK(rk_adaptive_step(&ad, &err)); /* everything enriched from the first iteration */
    ad.opt.probe = 1;
    CHECK_OK(rk_adaptive_step(&ad, &err));
    const rk_adaptive_probe *p = &ad.stats.probe;
    CHECK(p->done, "the probe did not run");
    CHECK(p->enriched_dofs == 3 * s.body.f.nv, "%d of %d dofs enriched", p->enriched_dofs, 3 * s.body.f.nv);
    CHECK(p->direction_difference < 1e-6, "Schur direction differs from CHOLMOD's by %g (relative)",
          p->direction_difference);
    CHECK(p->bjcg_iterations > 0 && p->bjcg_iterations < 10000, "block-Jacobi CG took %d iterations", p->bjcg_iterations);
    rk_adaptive_free(&ad);
    free_scene(&s);
}

TEST(thresholds_control_enrichment_part_by_part)
{
    rk_error err;
    scene s;
    CHECK_OK(make_scene(&s, 1e5, 4, &err));
    int nv = s.body.f.nv;
    /* no progress ever small enough, or no error ever large enough: nothing enriched */
    double none[2][2] = {{1e-300, -1e300}, {1e300, 1e300}};
    for (int k = 0; k < 2; k++) {
        rk_adaptive ad;
        CHECK_OK(init_adaptive(&ad, &s, none[k][0], none[k][1], 0, &err));
        for (int t = 0; t < 4; t++) CHECK_OK(rk_adaptive_step(&ad, &err));
        CHECK(ad.stats.max_nodes == 0 && ad.stats.max_modes == 12, "eps_g %g eps_e %g: %d vertices, %d columns",
              none[k][0], none[k][1], ad.stats.max_nodes, ad.stats.max_modes);
        rk_adaptive_free(&ad);
    }
    /* in between: the contact enriches some parts, each one whole (no downdating), not all */
    rk_adaptive ad;
    CHECK_OK(init_adaptive(&ad, &s, 1e-2, 1e-4, 0, &err));
    for (int t = 0; t < 4; t++) CHECK_OK(rk_adaptive_step(&ad, &err));
    CHECK(ad.nodes > 0 && ad.nodes < nv, "%d of %d vertices enriched", ad.nodes, nv);
    const rk_adaptive_impl *im = ad.impl;
    for (int l = 0; l < im->L; l++) {
        int in = 0, count = im->part_first[l + 1] - im->part_first[l];
        for (int k = im->part_first[l]; k < im->part_first[l + 1]; k++) in += ad.enriched[im->part_vert[k]];
        CHECK(in == 0 || in == count, "part %d: %d of its %d vertices enriched", l, in, count);
    }
    int lowest = 0; /* the vertex nearest the sphere's top, where the beam lands */
    for (int v = 0; v < nv; v++) {
        double dv = hypot(s.body.m.X[3 * v], s.body.m.X[3 * v + 1]) + fabs(s.body.m.X[3 * v + 2]);
        double dl = hypot(s.body.m.X[3 * lowest], s.body.m.X[3 * lowest + 1]) + fabs(s.body.m.X[3 * lowest + 2]);
        if (dv < dl) lowest = v;
    }
    CHECK(ad.enriched[lowest], "the landing vertex %d is not enriched", lowest);
    rk_adaptive_free(&ad);
    free_scene(&s);
}

TEST(stiff_object_is_not_enriched_where_a_soft_one_is)
{
    rk_error err;
    int nodes[2];
    double young[2] = {1e5, 1e9};
    for (int k = 0; k < 2; k++) {
        scene s;
        CHECK_OK(make_scene(&s, young[k], 4, &err));
        rk_adaptive ad;
        CHECK_OK(init_adaptive(&ad, &s, 1e-2, 1e-4, 1, &err));
        for (int t = 0; t < 5; t++) CHECK_OK(rk_adaptive_step(&ad, &err));
        nodes[k] = ad.stats.max_nodes;
        rk_adaptive_free(&ad);
        free_scene(&s);
    }
    CHECK(nodes[0] > 0 && nodes[1] == 0, "enriched vertices: %d at E = 1e5, %d at E = 1e9", nodes[0], nodes[1]);
}

TEST(bfgs_and_exact_subspace_hessians_find_the_same_steps)
{
    rk_error err;
    scene s;
    CHECK_OK(make_scene(&s, 1e5, 4, &err));
    s.opt.newton_tol = 1e-7;
    int n = 3 * s.body.f.nv;
    double *x[2];
    long updates = 0;
    for (int exact = 0; exact < 2; exact++) {
        rk_adaptive_options o;
        rk_adaptive_default_options(&o);
        o.modal = o.nodal = 0;
        o.initial_blocks = s.basis.r / 12; /* every candidate, fixed: the minimiser over one subspace */
        o.exact_hessian = exact;
        o.subdomains = 6;
        o.full_fraction = 1;
        rk_adaptive ad;
        CHECK_OK(rk_adaptive_init(&ad, &s.body.f, &s.opt, s.basis.U, s.basis.r, &o, &err));
        for (int t = 0; t < 5; t++) CHECK_OK(rk_adaptive_step(&ad, &err));
        CHECK(ad.fom.stats.unconverged_steps == 0, "%s: %ld steps did not converge", exact ? "exact" : "bfgs",
              ad.fom.stats.unconverged_steps);
        x[exact] = malloc(sizeof(double) * n);
        memcpy(x[exact], ad.fom.x, sizeof(double) * n);
        if (!exact) updates = ad.stats.bfgs_updates;
        rk_adaptive_free(&ad);
    }
    double d = max_diff(x[0], x[1], n);
    free(x[0]);
    free(x[1]);
    CHECK(updates > 0, "BFGS never updated");
    CHECK(d < 1e-6, "BFGS and exact subspace Hessians end %g m apart", d);
    free_scene(&s);
}

TEST(downdating_drops_what_a_free_fall_does_not_need)
{
    rk_error err;
    scene s;
    CHECK_OK(make_scene(&s, 1e5, 4, &err));
    s.opt.nobstacles = 0; /* falling freely: every displacement is the affine block's */
    for (int downdate = 0; downdate < 2; downdate++) {
        rk_adaptive ad;
        CHECK_OK(init_adaptive(&ad, &s, 1e300, 1e300, downdate, &err)); /* the oracle adds nothing */
        rk_adaptive_impl *im = ad.impl;
        for (int b = 0; b < im->nblocks; b++) im->block_on[b] = 1; /* every block active, one part enriched */
        rk_adaptive_enrich_part(&ad, 0);
        CHECK_OK(rk_adaptive_set_columns(&ad, &err));
        int part = im->part_first[1] - im->part_first[0];
        CHECK(ad.nodes == part && ad.modes == s.basis.r, "set up: %d vertices, %d columns", ad.nodes, ad.modes);
        CHECK_OK(rk_adaptive_step(&ad, &err));
        CHECK_OK(rk_adaptive_step(&ad, &err)); /* starts from the model the first step's downdating left */
        if (downdate)
            CHECK(ad.nodes == 0 && ad.modes == 12, "downdated to %d vertices and %d columns, expected 0 and 12",
                  ad.nodes, ad.modes);
        else
            CHECK(ad.nodes == part && ad.modes == s.basis.r, "without downdating: %d vertices, %d columns", ad.nodes,
                  ad.modes);
        rk_adaptive_free(&ad);
    }
    free_scene(&s);
}

/* The oracle told to add nothing (eps_g huge): the full-space residual |d_full|_inf / h the
 * subspace leaves exceeds the method's tolerance, is counted and left so with residual_rounds 0,
 * and with the default rounds the parts where it is are enriched until every step ends below it. */
TEST(residual_above_the_tolerance_enriches_until_it_is_not)
{
    rk_error err;
    scene s;
    CHECK_OK(make_scene(&s, 1e5, 4, &err));
    long over[2], rounds[2];
    int nodes[2];
    for (int k = 0; k < 2; k++) {
        rk_adaptive_options o;
        rk_adaptive_default_options(&o);
        o.eps_g_nodal = o.eps_g_modal = 1e300;
        o.downdate = 0;
        o.subdomains = 6;
        o.full_fraction = 1; /* the residual's rounds enrich everything here (checked below) */
        if (k == 0) o.residual_rounds = 0;
        rk_adaptive ad;
        CHECK_OK(rk_adaptive_init(&ad, &s.body.f, &s.opt, s.basis.U, s.basis.r, &o, &err));
        for (int t = 0; t < 4; t++) {
            CHECK_OK(rk_adaptive_step(&ad, &err));
            printf("# rounds %d step %d: residual %.3g m/s (tolerance %g), %d vertices enriched\n", o.residual_rounds,
                   t, ad.stats.residual_last, ad.tolerance, ad.nodes);
        }
        over[k] = ad.stats.residual_over;
        rounds[k] = ad.stats.residual_rounds;
        nodes[k] = ad.stats.max_nodes;
        rk_adaptive_free(&ad);
    }
    CHECK(over[0] > 0 && rounds[0] == 0 && nodes[0] == 0, "report only: %ld steps over, %ld rounds, %d vertices",
          over[0], rounds[0], nodes[0]);
    CHECK(over[1] == 0 && rounds[1] > 0 && nodes[1] > 0, /* all of this small beam bends: all enriched */
          "enriching: %ld steps over, %ld rounds, %d of %d vertices", over[1], rounds[1], nodes[1], s.body.f.nv);
    free_scene(&s);
}

TEST(bad_options_are_named)
{
    rk_error err;
    scene s;
    CHECK_OK(make_scene(&s, 1e5, 4, &err));
    static const struct {
        const char *what, *expect;
    } cases[] = {{"nodal 0", "eps_g_nodal"}, {"modal -1", "eps_g_modal"}, {"eps_d 0", "eps_d"},
                 {"subdomains", "subdomains"}, {"block", "whole number of blocks"}, {"nan", "non-finite"},
                 {"static", "dynamics only"}, {"initial", "initial_blocks"}, {"rounds", "residual_rounds"},
                 {"accuracy", "accuracy"}, {"full", "full_fraction"}};
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
        rk_adaptive_options o;
        rk_adaptive_default_options(&o);
        rk_fom_options fo = s.opt;
        int r = s.basis.r;
        double keep = s.basis.U[5];
        if (k == 0) o.eps_g_nodal = 0;
        if (k == 1) o.eps_g_modal = -1;
        if (k == 2) o.eps_d = 0;
        if (k == 3) o.subdomains = s.body.f.nv + 1;
        if (k == 4) r = 13;
        if (k == 5) s.basis.U[5] = NAN;
        if (k == 6) fo.is_static = 1;
        if (k == 7) o.initial_blocks = 100;
        if (k == 8) o.residual_rounds = -1;
        if (k == 9) o.accuracy = -1;
        if (k == 10) o.full_fraction = 0;
        rk_adaptive ad;
        err.msg[0] = 0;
        int rc = rk_adaptive_init(&ad, &s.body.f, &fo, s.basis.U, r, &o, &err);
        s.basis.U[5] = keep;
        CHECK(rc != 0, "%s was accepted", cases[k].what);
        CHECK(strstr(err.msg, cases[k].expect), "%s: \"%s\" does not say %s", cases[k].what, err.msg, cases[k].expect);
    }
    free_scene(&s);
}

int main(void)
{
    RUN(everything_enriched_takes_the_full_order_steps);
    RUN(schur_direction_is_full_newtons_when_everything_is_enriched);
    RUN(thresholds_control_enrichment_part_by_part);
    RUN(stiff_object_is_not_enriched_where_a_soft_one_is);
    RUN(bfgs_and_exact_subspace_hessians_find_the_same_steps);
    RUN(downdating_drops_what_a_free_fall_does_not_need);
    RUN(residual_above_the_tolerance_enriches_until_it_is_not);
    RUN(bad_options_are_named);
    return test_finish();
}
