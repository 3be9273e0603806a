/* make bench, contact part: full-order IPC step time against tet count and contact pairs, with
 * the share of the step spent in the broad phase, CCD, the barrier and CHOLMOD (issue 15).
 *
 * Scene: two soft neo-Hookean boxes (E = 5e5 Pa, nu = 0.4, 1000 kg/m^3). The lower one,
 * 1 x 0.5 x 1 m, is held at its base; the upper one, 0.8 x 0.5 x 0.8 m, starts GAP above it
 * falling at DROP_SPEED, comes within dhat in the first step and lands in the next, so every timed
 * step has a contact front over the face it rests on (point-triangle and edge-edge pairs between
 * meshes that do not match). Each box is a rk_mesh_box of cells [2n, n, 2n] (24 n^3 tets), so a
 * case has 48 n^3 tets. Gravity, backward Euler at h = 0.01 s, dhat 1.7 mm (the scene default,
 * 1e-3 of the bounding-box diagonal, written out). The _dhat_x4 row takes four times dhat at 3k
 * tets: the pairs at a fixed tet count. (Sliding the upper box off-centre, or narrowing the lower
 * one, to get fewer pairs at the same tets was tried: it tips the box or presses an edge into a
 * face, and the Newton iterations, not the pairs, then set the step time.)
 *
 * Timing: warm-up steps until a step has gathered contact pairs (kappa is set there and CHOLMOD
 * re-analyses the coupled pattern), at most WARMUP_MAX, then case.steps single steps of one run,
 * each timed: 10 up to 3k tets, then 6, 4, 3, and 2 at 105k (a step there takes one to two
 * minutes; the median of 2 is their mean). The whole bench takes about 5.5 minutes. Spread (bench_cases.h): s_per_step is the median over those
 * steps, _min and _max the fastest and slowest; the spread is over the steps of one run (and
 * Newton iterations per step vary a lot under contact), not over repeated runs.
 *
 * Shares are of the timed steps' summed step time, all measured in this one process: broad
 * (contact.seconds_broad: the Verlet list rebuilds and the CCD's swept-box broad phase), ccd
 * (additive CCD of the candidates), barrier (contact energy, gradient and projected Hessian
 * blocks), factor (CHOLMOD numeric factorization) and solve (triangular solves); the rest is the
 * elastic energy and its PSD-projected Hessian, CHOLMOD re-analysis when contact changes the
 * pattern, the line search and bookkeeping. pairs_mean is pairs per gather (per potential
 * evaluation) over the timed steps; pairs_max the largest gather over the whole run (warm-up
 * included: the counter cannot be reset). After every step (untimed) the state is checked
 * exactly: any intersection aborts the bench; min_distance is the smallest surface distance of
 * those states.
 *
 * Threads: one each. OpenBLAS and OpenMP read their settings when the libraries load, before
 * main, so when OPENBLAS_NUM_THREADS, OMP_NUM_THREADS or OMP_THREAD_LIMIT is unset the bench sets
 * it to 1 and re-executes itself; set them to measure otherwise (the JSON records them).
 * OMP_THREAD_LIMIT is the one that matters for CHOLMOD: its supernodal factorization asks OpenMP
 * for a fixed num_threads(4), which OMP_NUM_THREADS does not cap; on this shared 2-core machine
 * those threads made the factorization about twice as slow (10k tets: 0.12 to 0.15 s per Newton
 * iteration against 0.06 to 0.08 s with the limit).
 *
 * ROMKIT_BENCH_QUICK: 1k to 10k tets and the dhat row.
 * Writes bench/results/contact_scaling.{csv,json}. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench_cases.h"
#include "fom/fom.h"
#include "pipeline/pipeline.h"
#include "util/util.h"

#define GAP 2e-3         /* m between the boxes at the start */
#define DROP_SPEED 0.1   /* m/s downward: pairs within dhat in the first step, landing in the next */
#define YOUNG "5e5"      /* Pa, soft rubber: at 1e5 Pa and 0.3 m/s the landing step alone took 63 Newton
                          * iterations (194 s) at 105k tets */
#define DHAT 1.7e-3      /* m: 1e-3 of the scene's 1.73 m bounding-box diagonal, what the scene
                          * default would be, written out so the dhat row scales a known value */
#define WARMUP_MAX 8
#define MAX_STEPS 16

typedef struct {
    const char *name;
    int n;             /* cells [2n, n, 2n] per box */
    double dhat_scale; /* of DHAT */
    int steps;         /* timed steps */
    int quick;         /* also run under ROMKIT_BENCH_QUICK */
} contact_case;

static const contact_case CASES[] = {
    {"boxes_1k", 3, 1, 10, 1},  {"boxes_3k", 4, 1, 10, 1},  {"boxes_10k", 6, 1, 6, 1},
    {"boxes_25k", 8, 1, 4, 0},  {"boxes_48k", 10, 1, 3, 0}, {"boxes_105k", 13, 1, 2, 0},
    {"boxes_3k_dhat_x4", 4, 4, 10, 1},
};

#define MATERIAL "\"material\": {\"model\": \"neohookean\", \"young\": " YOUNG ", \"poisson\": 0.4, \"density\": 1000}"

static int build_scene(const contact_case *c, rk_scene *scene, rk_scene_sim *sim, rk_error *err)
{
    char text[2048];
    snprintf(text, sizeof text,
             "{\"objects\": ["
             "{\"mesh\": {\"box\": {\"size\": [1, 0.5, 1], \"cells\": [%d, %d, %d]}},"
             " " MATERIAL ", \"fixed\": [{\"box\": [[-1, -1, -1], [2, 0.001, 2]]}]},"
             "{\"mesh\": {\"box\": {\"size\": [0.8, 0.5, 0.8], \"cells\": [%d, %d, %d]}, \"translate\": [0.1, %.17g, 0.1]},"
             " " MATERIAL ", \"velocity\": [0, %.17g, 0]}],"
             " \"gravity\": [0, -9.81, 0], \"contact\": {\"dhat\": %.17g},"
             " \"time\": {\"step\": 0.01, \"duration\": 1}}",
             2 * c->n, c->n, 2 * c->n, 2 * c->n, c->n, 2 * c->n, 0.5 + GAP, -DROP_SPEED,
             DHAT * c->dhat_scale);
    if (rk_scene_parse(text, "bench_contact.json", scene, err)) return -1;
    if (rk_scene_build(scene, sim, err)) {
        rk_scene_free(scene);
        return -1;
    }
    return 0;
}

/* One case's numbers. */
typedef struct {
    int nv, nt, steps;
    double dhat, pairs_mean, min_distance, newton;
    long pairs_max, ccd_calls;
    double broad, ccd, barrier, factor, solve;
    double factor_s; /* CHOLMOD numeric factorization seconds per Newton iteration */
    bench_stat t;
} case_result;

static int fail(const char *name, const char *what, const rk_error *err)
{
    fprintf(stderr, "bench_contact: %s: %s%s%s\n", name, what, err ? ": " : "", err ? err->msg : "");
    return -1;
}

/* The state after a step: exactly no crossing (else the bench stops), and its smallest distance. */
static int check_state(const char *name, int step, rk_fom *fom, double *min_distance)
{
    rk_error err;
    int crossings;
    double d;
    if (rk_fom_contact_measure(fom, &crossings, &d, &err)) return fail(name, "contact measure", &err);
    if (crossings != 0) {
        fprintf(stderr, "bench_contact: %s: INTERSECTION: %d exact edge-triangle crossings after step %d\n", name,
                crossings, step);
        return -1;
    }
    *min_distance = fmin(*min_distance, d);
    return 0;
}

static int run_case(const contact_case *c, case_result *r)
{
    rk_error err;
    rk_scene scene;
    rk_scene_sim sim;
    if (build_scene(c, &scene, &sim, &err)) return fail(c->name, "scene", &err);
    rk_fom fom;
    int rc = -1;
    if (rk_fom_init(&fom, &sim.fem, &sim.options, &err)) {
        fail(c->name, "rk_fom_init", &err);
        goto out_scene;
    }
    const rk_contact_stats *cs = rk_fom_contact_stats(&fom);
    if (!cs) {
        fail(c->name, "the scene has no contact stage", NULL);
        goto out;
    }
    int warm = 0;
    do {
        long pairs0 = cs->pairs;
        if (rk_fom_step(&fom, &err)) {
            fail(c->name, "warm-up step", &err);
            goto out;
        }
        warm++;
        if (cs->pairs > pairs0) break;
    } while (warm < WARMUP_MAX);
    r->min_distance = INFINITY;
    if (check_state(c->name, warm, &fom, &r->min_distance)) goto out;
    rk_fom_stats f0 = fom.stats;
    rk_contact_stats c0 = *cs;
    double times[MAX_STEPS];
    for (int s = 0; s < c->steps; s++) {
        double t0 = rk_now();
        if (rk_fom_step(&fom, &err)) {
            fail(c->name, "step", &err);
            goto out;
        }
        times[s] = rk_now() - t0;
        if (check_state(c->name, warm + s + 1, &fom, &r->min_distance)) goto out;
    }
    double total = fom.stats.seconds_total - f0.seconds_total;
    long gathers = cs->gathers - c0.gathers, newton = fom.stats.newton_iterations - f0.newton_iterations;
    r->nv = sim.mesh.nv;
    r->nt = sim.mesh.nt;
    r->steps = c->steps;
    r->dhat = sim.options.contact.dhat;
    r->pairs_mean = gathers ? (double)(cs->pairs - c0.pairs) / gathers : 0;
    r->pairs_max = cs->max_pairs;
    r->ccd_calls = (cs->ccd_calls - c0.ccd_calls) / c->steps;
    r->newton = (double)newton / c->steps;
    r->broad = (cs->seconds_broad - c0.seconds_broad) / total;
    r->ccd = (cs->seconds_ccd - c0.seconds_ccd) / total;
    r->barrier = (cs->seconds_potential - c0.seconds_potential) / total;
    r->factor = (fom.stats.seconds_factor - f0.seconds_factor) / total;
    r->solve = (fom.stats.seconds_solve - f0.seconds_solve) / total;
    r->factor_s = newton > 0 ? (fom.stats.seconds_factor - f0.seconds_factor) / newton : NAN;
    r->t = bench_stat_of(times, c->steps);
    if (r->pairs_mean <= 0) {
        fail(c->name, "no contact pairs over the timed steps: the scene does not measure contact", NULL);
        goto out;
    }
    rc = 0;
out:
    rk_fom_free(&fom);
out_scene:
    rk_scene_sim_free(&sim);
    rk_scene_free(&scene);
    return rc;
}

int main(int argc, char **argv)
{
    bench_pin_one_thread(argv, "bench_contact");
    /* argv[1], the mesh folder of the other benches, is not used: these boxes are procedural */
    const char *out_dir = argc > 2 ? argv[2] : "bench/results";
    int quick = getenv("ROMKIT_BENCH_QUICK") != NULL;
    FILE *csv, *json;
    if (bench_open_results(out_dir, "contact_scaling",
                           "case,vertices,tets,dhat,steps,pairs_mean,pairs_max,s_per_step,s_per_step_min,"
                           "s_per_step_max,broad_share,ccd_share,barrier_share,factor_share,solve_share,"
                           "factor_s_per_newton,newton_per_step,ccd_calls_per_step,min_distance,intersections",
                           &csv, &json))
        return 1;
    printf("threads: OPENBLAS_NUM_THREADS=%s OMP_NUM_THREADS=%s OMP_THREAD_LIMIT=%s\n",
           getenv("OPENBLAS_NUM_THREADS"), getenv("OMP_NUM_THREADS"), getenv("OMP_THREAD_LIMIT"));
    printf("%-19s %7s %7s %8s %7s %7s %9s %19s %6s %6s %7s %6s %6s %7s %9s\n", "case", "verts", "tets", "dhat",
           "pairs", "max", "s/step", "(min..max)", "broad", "ccd", "barrier", "factor", "solve", "newton", "min dist");
    int first = 1;
    for (size_t k = 0; k < sizeof CASES / sizeof CASES[0]; k++) {
        const contact_case *c = &CASES[k];
        if (quick && !c->quick) continue;
        case_result r;
        if (run_case(c, &r)) return 1;
        printf("%-19s %7d %7d %8.2g %7.0f %7ld %9.4g %9.4g..%-9.4g %5.1f%% %5.1f%% %6.1f%% %5.1f%% %5.1f%% %7.1f %9.2g\n",
               c->name, r.nv, r.nt, r.dhat, r.pairs_mean, r.pairs_max, BENCH_STAT3(r.t), 100 * r.broad, 100 * r.ccd,
               100 * r.barrier, 100 * r.factor, 100 * r.solve, r.newton, r.min_distance);
        fflush(stdout);
        fprintf(csv, "%s,%d,%d,%.6g,%d,%.1f,%ld,%.6g,%.6g,%.6g,%.4f,%.4f,%.4f,%.4f,%.4f,%.6g,%.2f,%ld,%.6g,0\n", c->name,
                r.nv, r.nt, r.dhat, r.steps, r.pairs_mean, r.pairs_max, BENCH_STAT3(r.t), r.broad, r.ccd, r.barrier,
                r.factor, r.solve, r.factor_s, r.newton, r.ccd_calls, r.min_distance);
        fprintf(json,
                "%s  {\"case\": \"%s\", \"vertices\": %d, \"tets\": %d, \"dhat\": %.6g, \"steps\": %d,"
                " \"pairs_mean\": %.1f, \"pairs_max\": %ld, \"seconds_per_step\": %.6g,"
                " \"seconds_per_step_min\": %.6g, \"seconds_per_step_max\": %.6g, \"broad_share\": %.4f,"
                " \"ccd_share\": %.4f, \"barrier_share\": %.4f, \"factorization_share\": %.4f, \"solve_share\": %.4f,"
                " \"factorization_seconds_per_newton\": %.6g, \"newton_per_step\": %.2f, \"ccd_calls_per_step\": %ld, \"min_distance\": %.6g,"
                " \"intersections\": 0, \"openblas_threads\": \"%s\", \"omp_threads\": \"%s\","
                " \"omp_thread_limit\": \"%s\"}\n",
                first ? "" : ",", c->name, r.nv, r.nt, r.dhat, r.steps, r.pairs_mean, r.pairs_max, BENCH_STAT3(r.t),
                r.broad, r.ccd, r.barrier, r.factor, r.solve, r.factor_s, r.newton, r.ccd_calls, r.min_distance,
                getenv("OPENBLAS_NUM_THREADS"), getenv("OMP_NUM_THREADS"), getenv("OMP_THREAD_LIMIT"));
        first = 0;
    }
    fprintf(json, "]\n");
    fclose(csv);
    fclose(json);
    return 0;
}
