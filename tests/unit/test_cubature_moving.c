/* A cubature for a moving basis (cubature.h, rk_cubature_train_moving), on a small box whose
 * every pose has its own random basis U_t and a displacement u_t = U_t q_t in it, so that the
 * reduced forces are the gradients of the quadrature's energy in U_t (rk_quadrature_eval, a path
 * the trainer does not take): the errors the trainer reports, over the fitted and the held-out
 * poses (every fourth), recomputed that way; the weights positive on distinct elements; the
 * tolerance met; the vertex cost choosing elements on fewer vertices; bad input and a failing pose. */
#include "cubature/cubature.h"
#include "fem_body.h"
#include "testlib.h"
#include "util/util.h"

#define R 3
#define POSES 8

typedef struct {
    int n;
    int fail_at;
} poses_ctx;

static void pose_basis(const poses_ctx *c, int t, double *U, double *q)
{
    uint64_t s = 1000 + (uint64_t)t;
    for (int i = 0; i < c->n * R; i++) U[i] = (rk_uniform(&s) - 0.5) * 0.02;
    s = 77 + (uint64_t)t;
    for (int k = 0; k < R; k++) q[k] = rk_uniform(&s) - 0.5;
}

static int pose(void *ctx, int t, double *u, double *U, rk_error *err)
{
    const poses_ctx *c = ctx;
    double q[R];
    if (t == c->fail_at) return rk_fail(err, "no such frame");
    pose_basis(c, t, U, q);
    for (int i = 0; i < c->n; i++) {
        u[i] = 0;
        for (int k = 0; k < R; k++) u[i] += U[(size_t)c->n * k + i] * q[k];
    }
    return 0;
}

/* The relative force error of the cubature `set` over the fitted (held = 0) or held-out poses,
 * each pose's error over its exact force's norm (An et al. Eq. 5), from the quadratures'
 * gradients in U_t at q_t. */
static double recomputed(const rk_fem *f, const poses_ctx *c, const rk_cubature_set *set, int held, rk_error *err)
{
    double num = 0, den = 0, *U = malloc(sizeof(double) * (size_t)c->n * R), q[R];
    for (int t = 0; t < POSES; t++) {
        if ((t % 4 == 3) != held) continue;
        rk_quadrature all = {0}, cub = {0};
        double ga[R] = {0}, gc[R] = {0}, na = 0;
        pose_basis(c, t, U, q);
        if (rk_quadrature_elements(f, U, R, f->nt, NULL, NULL, &all, err) ||
            rk_quadrature_elements(f, U, R, set->count, set->index, set->weight, &cub, err))
            return -1;
        rk_quadrature_eval(&all, q, ga, NULL, 0);
        rk_quadrature_eval(&cub, q, gc, NULL, 0);
        for (int k = 0; k < R; k++) na += ga[k] * ga[k];
        for (int k = 0; k < R; k++) {
            num += (gc[k] - ga[k]) * (gc[k] - ga[k]) / na;
            den += ga[k] * ga[k] / na;
        }
        rk_quadrature_free(&all);
        rk_quadrature_free(&cub);
    }
    free(U);
    return sqrt(num / den);
}

static int box(fem_body *b, rk_error *err)
{
    return fem_body_box(b, 0.3, 0.1, 0.1, 3, 2, 2, (rk_material){RK_MAT_NEOHOOKEAN, 1e5, 0.3, 1000.0}, err);
}

TEST(reported_errors_match_the_quadratures_forces)
{
    rk_error err;
    fem_body b;
    CHECK_OK(box(&b, &err));
    poses_ctx c = {3 * b.m.nv, -1};
    rk_moving_poses P = {POSES, pose, &c};
    rk_cubature_options o;
    rk_cubature_default_options(&o);
    o.tolerance = 0.02;
    o.sample = 0;
    rk_cubature_set set;
    rk_moving_fit fit;
    CHECK_OK(rk_cubature_train_moving(&b.f, R, &P, &o, &set, &fit, &err));
    CHECK(fit.poses == 6 && fit.heldout_poses == 2, "%d fitted, %d held out", fit.poses, fit.heldout_poses);
    CHECK(set.reached && fit.train_error <= o.tolerance, "train error %g", fit.train_error);
    CHECK(set.count > 0 && set.count < b.f.nt, "%d of %d elements", set.count, b.f.nt);
    for (int k = 0; k < set.count; k++) {
        CHECK(set.weight[k] > 0 && set.index[k] >= 0 && set.index[k] < b.f.nt, "point %d", k);
        CHECK(k == 0 || set.index[k] > set.index[k - 1], "indices not ascending at %d", k);
    }
    double train = recomputed(&b.f, &c, &set, 0, &err), held = recomputed(&b.f, &c, &set, 1, &err);
    CHECK_CLOSE(train, fit.train_error, 1e-6);
    CHECK_CLOSE(held, fit.heldout_error, 1e-6);
    /* each pose moves its basis: the fitted poses' weights do not carry over exactly */
    CHECK(fit.heldout_error > fit.train_error, "held out %g, fitted %g", fit.heldout_error, fit.train_error);
    rk_cubature_set_free(&set);
    fem_body_free(&b);
}

static int vertices_of(const rk_fem *f, const rk_cubature_set *set)
{
    unsigned char *seen = calloc((size_t)f->nv, 1);
    int count = 0;
    for (int k = 0; k < set->count; k++)
        for (int a = 0; a < 4; a++) {
            count += !seen[f->tets[4 * set->index[k] + a]];
            seen[f->tets[4 * set->index[k] + a]] = 1;
        }
    free(seen);
    return count;
}

TEST(vertex_cost_picks_elements_on_fewer_vertices)
{
    rk_error err;
    fem_body b;
    CHECK_OK(box(&b, &err));
    poses_ctx c = {3 * b.m.nv, -1};
    rk_moving_poses P = {POSES, pose, &c};
    rk_cubature_options o;
    rk_cubature_default_options(&o);
    o.tolerance = 0.02;
    o.sample = 0;
    rk_cubature_set set[2];
    rk_moving_fit fit[2];
    int v[2];
    for (int k = 0; k < 2; k++) {
        o.vertex_cost = k ? 32 : 0;
        CHECK_OK(rk_cubature_train_moving(&b.f, R, &P, &o, &set[k], &fit[k], &err));
        CHECK(set[k].reached, "vertex cost %g: error %g", o.vertex_cost, fit[k].train_error);
        v[k] = vertices_of(&b.f, &set[k]);
    }
    printf("# %d elements on %d vertices without the vertex cost, %d on %d with 32\n", set[0].count, v[0],
           set[1].count, v[1]);
    CHECK(v[1] < v[0], "%d vertices with the cost, %d without", v[1], v[0]);
    rk_cubature_set_free(&set[0]);
    rk_cubature_set_free(&set[1]);
    fem_body_free(&b);
}

TEST(bad_input_and_a_failing_pose_are_errors)
{
    rk_error err;
    fem_body b;
    CHECK_OK(box(&b, &err));
    poses_ctx c = {3 * b.m.nv, 5};
    rk_moving_poses P = {POSES, pose, &c};
    rk_cubature_options o;
    rk_cubature_default_options(&o);
    rk_cubature_set set;
    rk_moving_fit fit;
    CHECK(rk_cubature_train_moving(&b.f, R, &P, &o, &set, &fit, &err) != 0, "a failing pose passed");
    CHECK(strstr(err.msg, "pose 5") && strstr(err.msg, "no such frame"), "message: %s", err.msg);
    c.fail_at = -1;
    o.tolerance = 0;
    CHECK(rk_cubature_train_moving(&b.f, R, &P, &o, &set, &fit, &err) != 0 && strstr(err.msg, "tolerance"),
          "tolerance 0: %s", err.msg);
    o.tolerance = 0.01;
    P.poses = 0;
    CHECK(rk_cubature_train_moving(&b.f, R, &P, &o, &set, &fit, &err) != 0 && strstr(err.msg, "0 poses"),
          "no poses: %s", err.msg);
    fem_body_free(&b);
}

int main(void)
{
    RUN(reported_errors_match_the_quadratures_forces);
    RUN(vertex_cost_picks_elements_on_fewer_vertices);
    RUN(bad_input_and_a_failing_pose_are_errors);
    return test_finish();
}
