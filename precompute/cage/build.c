/* rk_cage_build (cage.h): simplify, tetrahedralize, move the boundary out until every original
 * vertex is inside (inflate.c), with the tet count held to max_tets.
 *
 * The tet count: TetGen fills a closed surface of T triangles under its quality bound with a number
 * of tets that grows with T and with how fine the surface's smallest features are. Measured on
 * spot.obj's simplifications (TetGen 1.6): at radius-edge 2 (-pq2), 3332 triangles gave 45,007 tets,
 * 1874 gave 25,482, 1052 gave 15,728 (about 15 a triangle, growing as T^0.9); at romkit mesh's 1.4,
 * twice as many (51,064 from 1874), so a cage uses 2 (RK_CAGE_QUALITY). The simplification target
 * starts at T = max_tets / RK_CAGE_TETS_PER_TRIANGLE (at most the surface's own count); a cage over
 * max_tets sets T to 0.95 T (max_tets / tets)^1.5, a step a little past the mark, and tries again.
 * A cage under 80% of the budget is refined with TetGen's volume bound (fill_budget). A
 * simplification TetGen cannot mesh (meshopt can pinch two sheets of a surface together at a low
 * target: an edge of four faces) is retried an eighth finer, or an eighth coarser when that one
 * would reach a target already over the budget. */
#include "cage/cage_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define RK_CAGE_TETS_PER_TRIANGLE 15
#define RK_CAGE_QUALITY 2.0
#define MAX_RUNS 16
#define RK_CAGE_FILL 2.5
#define FILL_RUNS 5

static double diagonal(const rk_surface *s)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, d = 0;
    for (int v = 0; v < s->nv; v++)
        for (int i = 0; i < 3; i++) lo[i] = fmin(lo[i], s->X[3 * v + i]), hi[i] = fmax(hi[i], s->X[3 * v + i]);
    for (int i = 0; i < 3; i++) d += (hi[i] - lo[i]) * (hi[i] - lo[i]);
    return sqrt(d);
}

/* A cage under 80% of its budget (a surface simplified to few triangles fills with few, large tets:
 * a box beam's 1,344 triangles gave 1,300 tets whatever the budget) is made again under TetGen's
 * volume bound V_max = RK_CAGE_FILL V / max_tets (V the cage's volume: tets under a bound average a
 * third to a half of it), raised by the overshoot (x 1.3) while over max_tets; the first within the
 * budget (the finest tried) replaces the cage, which stays as it was if none is. Returns the runs
 * so far. */
static int fill_budget(const rk_surface *c, double quality, int max_tets, int run, rk_mesh *cage, double *vmax_used)
{
    double vmax = RK_CAGE_FILL * rk_surface_volume(c) / max_tets;
    for (int k = 0; k < FILL_RUNS && run < MAX_RUNS; k++) {
        rk_mesh finer;
        rk_error terr;
        run++;
        if (rk_tetrahedralize(c, quality, vmax, &finer, &terr)) return run;
        if (finer.nt <= max_tets) {
            rk_mesh_free(cage);
            *cage = finer;
            *vmax_used = vmax;
            return run;
        }
        vmax *= 1.3 * finer.nt / max_tets;
        rk_mesh_free(&finer);
    }
    return run;
}

int rk_cage_build(const rk_surface *s, const rk_cage_options *o, rk_mesh *cage, rk_cage_report *rep, rk_error *err)
{
    memset(cage, 0, sizeof *cage);
    if (o->max_tets < RK_CAGE_MIN_TETS)
        return rk_fail(err, "cage: max_tets must be at least %d, got %d", RK_CAGE_MIN_TETS, o->max_tets);
    if (!(o->margin >= 0) || o->margin >= 1) return rk_fail(err, "cage: margin %g is not in [0, 1)", o->margin);
    double margin = (o->margin > 0 ? o->margin : RK_CAGE_MARGIN) * diagonal(s);
    double quality = o->quality > 0 ? o->quality : RK_CAGE_QUALITY;
    int target = o->max_tets / RK_CAGE_TETS_PER_TRIANGLE;
    if (target > s->nf) target = s->nf;
    char last[512] = "nothing tried";
    int over = s->nf + 1; /* the smallest target that gave too many tets */
    rk_cage_report r = {0};
    for (int run = 1; run <= MAX_RUNS && target >= 4; run++) {
        rk_surface c;
        double serr;
        if (rk_cage_simplify(s, target, &c, &serr, err)) return -1;
        rk_error terr;
        int rc = rk_tetrahedralize(&c, quality, 0, cage, &terr);
        r = (rk_cage_report){.triangles = c.nf, .simplify_error = serr, .tetgen_runs = run};
        if (rc == 0 && cage->nt < 0.8 * o->max_tets) run = fill_budget(&c, quality, o->max_tets, run, cage, &r.max_volume);
        r.tetgen_runs = run;
        rk_surface_free(&c);
        if (rc) {
            /* a simplification TetGen cannot mesh (meshopt may pinch two sheets of the surface
             * together along an edge): a finer one next, but not as fine as one known to be over
             * the budget (then a coarser one) */
            snprintf(last, sizeof last, "%d triangles: %s", r.triangles, terr.msg);
            int finer = target * 9 / 8 + 1 < s->nf ? target * 9 / 8 + 1 : s->nf;
            target = finer < over ? finer : target * 7 / 8;
            continue;
        }
        if (cage->nt > o->max_tets) {
            snprintf(last, sizeof last, "%d triangles gave %d tets", r.triangles, cage->nt);
            if (target < over) over = target;
            target = (int)(0.95 * target * pow((double)o->max_tets / cage->nt, 1.5));
            rk_mesh_free(cage);
            continue;
        }
        r.tets = cage->nt;
        r.vertices = cage->nv;
        if (rk_cage_inflate(cage, s, margin, &r, err)) {
            rk_mesh_free(cage);
            return -1;
        }
        if (rep) *rep = r;
        return 0;
    }
    return rk_fail(err, "cage: no cage of at most %d tets after %d TetGen runs (last: %s)", o->max_tets, r.tetgen_runs,
                   last);
}
