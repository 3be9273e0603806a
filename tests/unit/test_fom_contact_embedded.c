/* Full order's contact on a surface embedded in its elements (fom.h, rk_fom_contact_surface;
 * precompute/fom/contact_view.c), as a point cloud's march surface is in its full-order body: two
 * bodies (2 x 2 x 2-cell boxes) each carry a small box surface embedded in their tets, partly
 * outside them (rest offsets), 0.02 m apart and an obstacle box beside one (dhat 0.05). The
 * potential's contact part, pulled back through y = W x + o:
 *  - equals the contact stage's barrier evaluated on y built by hand;
 *  - its gradient matches central differences of its energy and its Hessian (exact per-pair blocks,
 *    expanded to the tets' vertices and split into 4-vertex blocks) differences of its gradient;
 *  - projected per pair (the default), the assembled Hessian is PSD;
 *  - CCD along a step of x keeps the embedded surfaces apart (exact test at the step's end);
 *  - a bad embedding is refused by name. */
#include "cage/cage.h"
#include "fom/fom.h"
#include "testlib.h"

typedef struct {
    rk_mesh mesh;          /* the two bodies */
    rk_fem fem;
    rk_fom_contact_surface cs;
    int first[3], cfirst[3];
    int *vertex;
    double *weight, *offset;
    rk_obstacle box;
    rk_fom_options opt;
    rk_fom fom;
} scene;

/* Appends b's vertices and tets (or ghost-free tets of a contact mesh) to a. */
static void append(rk_mesh *a, const rk_mesh *b)
{
    a->X = realloc(a->X, sizeof(double) * 3 * (size_t)(a->nv + b->nv));
    a->tets = realloc(a->tets, sizeof(int) * 4 * (size_t)(a->nt + b->nt));
    memcpy(a->X + 3 * (size_t)a->nv, b->X, sizeof(double) * 3 * (size_t)b->nv);
    for (int i = 0; i < 4 * b->nt; i++) a->tets[4 * (size_t)a->nt + i] = b->tets[i] + a->nv;
    a->nv += b->nv;
    a->nt += b->nt;
}

static int make_scene(scene *s, rk_error *err)
{
    memset(s, 0, sizeof *s);
    double one[3] = {1, 1, 1}, small[3] = {0.6, 0.4, 0.6};
    int cells[3] = {2, 2, 2}, scells[3] = {2, 1, 2};
    double body_at[2][3] = {{0, 0, 0}, {0, 1.05, 0}};
    double surface_at[2][3] = {{0.2, 0.61, 0.2}, {0.25, 1.03, 0.27}}; /* tops at 1.01 and bottoms at 1.03: each
                                                                       * 0.01 to 0.02 outside its body */
    rk_mesh contact = {0};
    for (int k = 0; k < 2; k++) {
        rk_mesh body, surf;
        if (rk_mesh_box(one, cells, &body, err) || rk_mesh_box(small, scells, &surf, err)) return -1;
        rk_mesh_transform(&body, 1, body_at[k]);
        rk_mesh_transform(&surf, 1, surface_at[k]);
        rk_embedding e;
        if (rk_cage_embed(&body, surf.X, surf.nv, &e, err)) return -1;
        if (e.outside == 0) return rk_fail(err, "object %d: no embedded vertex outside its body", k);
        int v0 = s->mesh.nv, c0 = contact.nv;
        s->vertex = realloc(s->vertex, sizeof(int) * 4 * (size_t)(c0 + surf.nv));
        s->weight = realloc(s->weight, sizeof(double) * 4 * (size_t)(c0 + surf.nv));
        s->offset = realloc(s->offset, sizeof(double) * 3 * (size_t)(c0 + surf.nv));
        for (int p = 0; p < surf.nv; p++) {
            double at[3] = {0, 0, 0};
            for (int a = 0; a < 4; a++) {
                int v = body.tets[4 * e.tet[p] + a];
                s->vertex[4 * (c0 + p) + a] = v0 + v;
                s->weight[4 * (c0 + p) + a] = e.bary[4 * p + a];
                for (int d = 0; d < 3; d++) at[d] += e.bary[4 * p + a] * body.X[3 * v + d];
            }
            for (int d = 0; d < 3; d++) s->offset[3 * (c0 + p) + d] = surf.X[3 * p + d] - at[d];
        }
        rk_embedding_free(&e);
        append(&s->mesh, &body);
        append(&contact, &surf);
        s->first[k + 1] = s->mesh.nv;
        s->cfirst[k + 1] = contact.nv;
        rk_mesh_free(&body), rk_mesh_free(&surf);
    }
    rk_material *mats = calloc((size_t)s->mesh.nt, sizeof *mats);
    for (int t = 0; t < s->mesh.nt; t++) mats[t] = (rk_material){RK_MAT_NEOHOOKEAN, 1e5, 0.3, 1000};
    int rc = rk_fem_init(&s->fem, &s->mesh, mats, err);
    free(mats);
    if (rc) return -1;
    s->cs = (rk_fom_contact_surface){.mesh = contact, .vertex = s->vertex, .weight = s->weight, .offset = s->offset,
                                     .object_first_vertex = s->cfirst};
    /* beside the second surface's face x = 0.85, inside its body (which does not collide) */
    s->box = (rk_obstacle){.kind = RK_OBSTACLE_BOX, .min = {0.87, 1.1, 0.3}, .max = {1.3, 1.3, 0.6}};
    rk_fom_default_options(&s->opt);
    s->opt.nobjects = 2;
    s->opt.object_first_vertex = s->first;
    s->opt.obstacles = &s->box;
    s->opt.nobstacles = 1;
    s->opt.contact.dhat = 0.05;
    s->opt.contact.kappa = 1e3;
    s->opt.contact_surface = &s->cs;
    if (rk_fom_init(&s->fom, &s->fem, &s->opt, err)) return -1;
    uint64_t seed = 5;
    for (int i = 0; i < 3 * s->mesh.nv; i++) s->fom.x[i] = s->mesh.X[i] + 0.003 * (2 * rk_uniform(&seed) - 1);
    return 0;
}

static void free_scene(scene *s)
{
    rk_fom_free(&s->fom);
    rk_fem_free(&s->fem);
    rk_mesh_free(&s->mesh);
    rk_mesh_free(&s->cs.mesh);
    free(s->vertex), free(s->weight), free(s->offset);
}

/* The contact part alone: no elastic energy, inertia or load. */
static const rk_fom_terms contact_only = {.no_elastic = 1};

/* The contact blocks of the last evaluation with a Hessian, assembled densely (n x n). */
static void assemble(const rk_fom *fom, int n, double *H)
{
    rk_fom_view v;
    rk_fom_view_get(fom, &v);
    memset(H, 0, sizeof(double) * (size_t)n * n);
    for (int b = 0; b < v.nblocks; b++) {
        const rk_contact_block *blk = &v.blocks[b];
        int dim = 3 * blk->np;
        for (int i = 0; i < blk->np; i++)
            for (int j = 0; j < blk->np; j++)
                if (blk->id[i] >= 0 && blk->id[j] >= 0)
                    for (int a = 0; a < 3; a++)
                        for (int c = 0; c < 3; c++)
                            H[(size_t)n * (3 * blk->id[i] + a) + 3 * blk->id[j] + c] += blk->H[dim * (3 * i + a) + 3 * j + c];
    }
}

/* Whether H + shift I has a Cholesky factor (dense, in place on a copy). */
static int positive_definite(const double *H, int n, double shift)
{
    double *L = malloc(sizeof(double) * (size_t)n * n);
    memcpy(L, H, sizeof(double) * (size_t)n * n);
    int ok = 1;
    for (int j = 0; j < n && ok; j++) {
        double d = L[(size_t)n * j + j] + shift;
        for (int k = 0; k < j; k++) d -= L[(size_t)n * j + k] * L[(size_t)n * j + k];
        if (!(d > 0)) {
            ok = 0;
            break;
        }
        d = sqrt(d);
        L[(size_t)n * j + j] = d;
        for (int i = j + 1; i < n; i++) {
            double s = L[(size_t)n * i + j];
            for (int k = 0; k < j; k++) s -= L[(size_t)n * i + k] * L[(size_t)n * j + k];
            L[(size_t)n * i + j] = s / d;
        }
    }
    free(L);
    return ok;
}

TEST(pulled_back_barrier_matches_the_contact_stage_and_finite_differences)
{
    rk_error err = {{0}};
    scene s;
    CHECK_OK(make_scene(&s, &err));
    int n = 3 * s.mesh.nv, ny = s.cs.mesh.nv;
    rk_fom_view v;
    rk_fom_view_get(&s.fom, &v);
    v.contact->exact_hessian = 1;
    double *g = calloc((size_t)n, sizeof(double)), *gp = calloc((size_t)n, sizeof(double));
    double *gm = calloc((size_t)n, sizeof(double)), *H = calloc((size_t)n * n, sizeof(double));
    double E = rk_fom_potential(&s.fom, &contact_only, s.fom.x, g, RK_FOM_CONTACT_BLOCKS, NULL, &err);
    CHECK(isfinite(E) && E > 0, "energy %g: %s", E, err.msg);
    assemble(&s.fom, n, H);
    /* y by hand, and the contact stage's own barrier on it */
    double *y = calloc(3 * (size_t)ny, sizeof(double));
    for (int j = 0; j < ny; j++)
        for (int d = 0; d < 3; d++) {
            y[3 * j + d] = s.offset[3 * j + d];
            for (int a = 0; a < 4; a++) y[3 * j + d] += s.weight[4 * j + a] * s.fom.x[3 * s.vertex[4 * j + a] + d];
        }
    rk_contact_set set = {0};
    CHECK_OK(rk_contact_gather(v.contact, y, &set, &err));
    int wide = 0, obstacle = 0; /* pairs over 2+ embedded points (more than 4 of the bodies' vertices: split
                                 * blocks); pairs with the obstacle's points (ids < 0, kept as they are) */
    for (int k = 0; k < set.n; k++) {
        int points = 0;
        for (int a = 0; a < 4; a++) points += set.pairs[k].id[a] >= 0;
        wide += points >= 2;
        obstacle += points < 4;
    }
    double Ey = rk_contact_energy(v.contact, &set, y, NULL, NULL, NULL, NULL, NULL);
    CHECK(fabs(Ey - E) <= 1e-12 * E, "pulled back %.17g, on y by hand %.17g", E, Ey);
    double worst_g = 0, worst_H = 0, h = 1e-7, gscale = 0, Hscale = 0;
    for (int i = 0; i < n; i++) gscale = fmax(gscale, fabs(g[i]));
    for (size_t i = 0; i < (size_t)n * n; i++) Hscale = fmax(Hscale, fabs(H[i]));
    for (int i = 0; i < n; i++) {
        double keep = s.fom.x[i];
        s.fom.x[i] = keep + h;
        double Ep = rk_fom_potential(&s.fom, &contact_only, s.fom.x, gp, RK_FOM_NO_HESSIAN, NULL, &err);
        s.fom.x[i] = keep - h;
        double Em = rk_fom_potential(&s.fom, &contact_only, s.fom.x, gm, RK_FOM_NO_HESSIAN, NULL, &err);
        s.fom.x[i] = keep;
        worst_g = fmax(worst_g, fabs((Ep - Em) / (2 * h) - g[i]) / gscale);
        for (int j = 0; j < n; j++) worst_H = fmax(worst_H, fabs((gp[j] - gm[j]) / (2 * h) - H[(size_t)n * j + i]) / Hscale);
    }
    printf("# %d pairs (%d over 2+ embedded points, %d with the obstacle), energy %.4g: gradient off by %.2e, Hessian "
           "by %.2e\n", set.n, wide, obstacle, E, worst_g, worst_H);
    CHECK(wide > 0 && obstacle > 0, "%d pairs, %d over several embedded points, %d with the obstacle", set.n, wide,
          obstacle);
    CHECK(worst_g < 1e-6 && worst_H < 1e-5, "gradient %g, Hessian %g", worst_g, worst_H);
    /* projected per pair: the sum of the split blocks is PSD; the exact one is not */
    int exact_pd = positive_definite(H, n, 1e-9 * Hscale);
    v.contact->exact_hessian = 0;
    rk_fom_potential(&s.fom, &contact_only, s.fom.x, g, RK_FOM_CONTACT_BLOCKS, NULL, &err);
    assemble(&s.fom, n, H);
    CHECK(positive_definite(H, n, 1e-9 * Hscale), "the projected contact Hessian is not PSD");
    printf("# the exact Hessian %s PSD, the projected one is\n", exact_pd ? "is also" : "is not");
    free(g), free(gp), free(gm), free(H), free(y);
    rk_contact_set_free(&set);
    free_scene(&s);
}

TEST(ccd_along_a_step_keeps_the_embedded_surfaces_apart)
{
    rk_error err = {{0}};
    scene s;
    CHECK_OK(make_scene(&s, &err));
    int n = 3 * s.mesh.nv;
    double *dx = calloc((size_t)n, sizeof(double)), *x0 = malloc(sizeof(double) * (size_t)n);
    memcpy(x0, s.fom.x, sizeof(double) * (size_t)n);
    /* the second body down through the first and into the obstacle's side: far past touching */
    for (int v = s.first[1]; v < s.first[2]; v++) dx[3 * v] = 0.1, dx[3 * v + 1] = -0.3;
    double alpha = rk_fom_max_step(&s.fom, s.fom.x, dx, &err);
    CHECK(alpha > 0 && alpha < 1, "alpha %g", alpha);
    for (int i = 0; i < n; i++) s.fom.x[i] = x0[i] + alpha * dx[i];
    int crossings;
    double d;
    CHECK_OK(rk_fom_contact_measure(&s.fom, &crossings, &d, &err));
    printf("# CCD: alpha %.4g, then %d crossings, the surfaces %.3g m apart\n", alpha, crossings, d);
    CHECK(crossings == 0 && d > 0, "%d crossings, distance %g", crossings, d);
    /* the whole step would cross */
    for (int i = 0; i < n; i++) s.fom.x[i] = x0[i] + dx[i];
    CHECK_OK(rk_fom_contact_measure(&s.fom, &crossings, &d, &err));
    CHECK(crossings > 0, "the full step does not cross (%d): the test shows nothing", crossings);
    free(dx), free(x0);
    free_scene(&s);
}

/* Bad embeddings are refused by name: a vertex naming no mesh vertex, an offset not finite,
 * object ranges that do not tile the contact surface. */
TEST(a_bad_embedding_is_named)
{
    rk_error err = {{0}};
    scene s;
    CHECK_OK(make_scene(&s, &err));
    rk_fom_free(&s.fom);
    s.vertex[4 * 5 + 2] = s.mesh.nv;
    CHECK(rk_fom_init(&s.fom, &s.fem, &s.opt, &err) != 0 && strstr(err.msg, "vertex 5's embedding names mesh vertex"),
          "out of range: %s", err.msg);
    s.vertex[4 * 5 + 2] = 0;
    s.offset[3 * 7 + 1] = NAN;
    CHECK(rk_fom_init(&s.fom, &s.fem, &s.opt, &err) != 0 && strstr(err.msg, "vertex 7's offset is not finite"),
          "NaN offset: %s", err.msg);
    s.offset[3 * 7 + 1] = 0;
    s.cfirst[1] = s.cfirst[2] + 1;
    CHECK(rk_fom_init(&s.fom, &s.fem, &s.opt, &err) != 0 && strstr(err.msg, "vertices [37, 36) do not tile its 36"),
          "ranges: %s", err.msg);
    free_scene(&s);
}

int main(void)
{
    RUN(pulled_back_barrier_matches_the_contact_stage_and_finite_differences);
    RUN(ccd_along_a_step_keeps_the_embedded_surfaces_apart);
    RUN(a_bad_embedding_is_named);
    return test_finish();
}
