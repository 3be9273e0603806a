/* The gather's candidate cache (a Verlet list grown by 2 dhat) serving CCD and the smallest-distance
 * measure (precompute/contact/pairs.c): whenever it serves a step, its candidates are exactly the
 * broad phase's (the same pairs in the same order), so CCD's step is the same to the bit; whenever
 * it decides the smallest distance, that is the broad phase's to the bit. Two boxes of 3 x 3 x 3
 * cells, one 0.4 dhat over the other (lifted and tilted to gaps of every size near the cache's
 * reach), self-contact on, a sphere (a thick obstacle point) and a box obstacle beside them, at
 * jittered positions and steps from a tenth of dhat to ten dhat. */
#include "contact/contact.h"
#include "contact/pairs_impl.h"
#include "testlib.h"
#include "two_boxes.h"
#include "util/util.h"

static uint64_t seed = 11;
static double rnd(void) { return 2 * rk_uniform(&seed) - 1; }

#define DHAT 1e-3

typedef struct {
    rk_mesh mesh;
    int first[3];
    rk_contact c;
} boxes;

static int make_boxes(boxes *s, rk_error *err)
{
    memset(s, 0, sizeof *s);
    double size[3] = {0.1, 0.1, 0.1}, shift[3] = {0.013, 0.021, 0.1 + 0.4 * DHAT};
    int cells[3] = {3, 3, 3};
    if (two_boxes(size, cells, shift, 1, &s->mesh, s->first, err)) return -1;
    rk_obstacle obs[2] = {{.kind = RK_OBSTACLE_SPHERE, .center = {0.05, -0.02 - 0.5 * DHAT, 0.05}, .radius = 0.02},
                          {.kind = RK_OBSTACLE_BOX, .min = {0.1 + 0.3 * DHAT, 0, 0}, .max = {0.2, 0.1, 0.1}}};
    rk_contact_options o;
    rk_contact_default_options(&o);
    o.dhat = DHAT;
    o.kappa = 1;
    o.self = 1;
    return rk_contact_init(&s->c, &s->mesh, s->first, 2, obs, 2, &o, 1.0, err);
}

static int same_sets(const rk_contact_set *a, const rk_contact_set *b)
{
    if (a->n != b->n) return 0;
    for (int i = 0; i < a->n; i++)
        if (a->pairs[i].kind != b->pairs[i].kind || memcmp(a->pairs[i].id, b->pairs[i].id, sizeof a->pairs[i].id) ||
            a->pairs[i].xi != b->pairs[i].xi || a->pairs[i].eps != b->pairs[i].eps)
            return 0;
    return 1;
}

TEST(the_cache_serves_ccd_with_the_broad_phases_own_pairs)
{
    rk_error err;
    boxes s;
    CHECK_OK(make_boxes(&s, &err));
    int n = 3 * s.mesh.nv, served = 0, refused = 0, trials = 60, differ = 0, alpha_differ = 0;
    double *x = malloc(sizeof(double) * n), *dx = malloc(sizeof(double) * n);
    rk_contact_set gathered = {0}, cached = {0}, fresh = {0};
    long most = 0;
    for (int t = 0; t < trials; t++) {
        for (int i = 0; i < n; i++) x[i] = s.mesh.X[i] + 0.2 * DHAT * rnd();
        /* the upper box lifted by up to 6 dhat and tilted by 3 dhat across: gaps of every size
         * around the cache's reach, so a cache that served past it would miss pairs */
        double lift = 6 * DHAT * (t % 7) / 6.0;
        for (int v = s.first[1]; v < s.first[2]; v++) x[3 * v + 2] += lift + 3 * DHAT * x[3 * v] / 0.1;
        CHECK_OK(rk_contact_gather(&s.c, x, &gathered, &err));
        /* move a little after the gather (as a line search does), then a step of 0.1 to 10 dhat */
        for (int i = 0; i < n; i++) x[i] += 0.1 * DHAT * rnd();
        double scale = DHAT * pow(10, -1 + 2 * (t % 10) / 9.0);
        for (int i = 0; i < n; i++) dx[i] = scale * rnd();
        rk_motion_frame f = {x, dx, s.c.ox, NULL};
        int rc = rk_contact_step_candidates_cached(&s.c, &f, &cached, &err);
        CHECK(rc >= 0, "trial %d: %s", t, err.msg);
        CHECK_OK(rk_contact_candidates(&s.c, &f, 0, &fresh, &err));
        if (rc == 1) {
            served++;
            differ += !same_sets(&cached, &fresh);
            most = fresh.n > most ? fresh.n : most;
            /* CCD through the cache, then with the cache dropped (the broad phase) */
            double a1 = rk_contact_max_step(&s.c, x, dx, NULL, &err);
            s.c.cache_valid = 0;
            double a2 = rk_contact_max_step(&s.c, x, dx, NULL, &err);
            alpha_differ += a1 != a2;
        } else {
            refused++;
        }
    }
    printf("# %d of %d steps served from the cache (up to %ld candidate pairs), %d left to the broad phase\n",
           served, trials, most, refused);
    CHECK(served >= 20 && refused >= 10, "served %d, refused %d: both paths must be exercised", served, refused);
    CHECK(most >= 50, "at most %ld candidates: the scene must touch", most);
    CHECK(differ == 0, "%d served steps listed other pairs than the broad phase", differ);
    CHECK(alpha_differ == 0, "%d served steps' CCD differed from the broad phase's", alpha_differ);
    rk_contact_set_free(&gathered), rk_contact_set_free(&cached), rk_contact_set_free(&fresh);
    free(x), free(dx);
    rk_contact_free(&s.c);
    rk_mesh_free(&s.mesh);
}

TEST(the_cache_decides_the_smallest_distance_only_when_it_is_the_broad_phases)
{
    rk_error err;
    boxes s;
    CHECK_OK(make_boxes(&s, &err));
    int n = 3 * s.mesh.nv, decided = 0, trials = 40, differ = 0;
    double *x = malloc(sizeof(double) * n);
    rk_contact_set gathered = {0};
    for (int t = 0; t < trials; t++) {
        for (int i = 0; i < n; i++) x[i] = s.mesh.X[i] + 0.2 * DHAT * rnd();
        CHECK_OK(rk_contact_gather(&s.c, x, &gathered, &err));
        /* lift the upper box by 0 to 4 dhat: from touching to beyond what the cache can decide */
        double lift = 4 * DHAT * (t % 8) / 7.0;
        for (int v = s.first[1]; v < s.first[2]; v++) x[3 * v + 2] += lift;
        double mine = rk_contact_cached_closest(&s.c, x, fmax(DHAT, 1e-2 * s.c.bbox_diagonal));
        double through = rk_contact_min_distance(&s.c, x, &err); /* the cache's when it decides */
        s.c.cache_valid = 0;
        double fresh = rk_contact_min_distance(&s.c, x, &err);
        if (!isnan(mine)) decided++;
        differ += through != fresh;
    }
    printf("# the cache decided the smallest distance in %d of %d frames\n", decided, trials);
    CHECK(decided >= 10 && decided < trials, "decided %d of %d: both paths must be exercised", decided, trials);
    CHECK(differ == 0, "%d frames measured another smallest distance than the broad phase's", differ);
    rk_contact_set_free(&gathered);
    free(x);
    rk_contact_free(&s.c);
    rk_mesh_free(&s.mesh);
}

int main(void)
{
    RUN(the_cache_serves_ccd_with_the_broad_phases_own_pairs);
    RUN(the_cache_decides_the_smallest_distance_only_when_it_is_the_broad_phases);
    return test_finish();
}
