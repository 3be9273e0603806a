/* make bench, adaptive subspace part (issue 18): the adaptive-subspace paper's measurements on a
 * soft slab dropped onto a sphere.
 *
 * Scene: a neo-Hookean slab 0.4 x 0.2 x 0.1 m (nu 0.4, 1000 kg/m^3), rk_mesh_box cells [4n, 2n, n]
 * (48 n^3 tets), clamped at both ends (a trampoline: a free box balanced on a sphere is an
 * unstable equilibrium whose sliding direction kept full-order Newton from converging), GAP above
 * a fixed sphere of radius 5 cm under its middle, falling at DROP_SPEED under gravity; BDF2 (the
 * paper's integrator, Sec. 4) at h = 0.01 s, dhat 1 mm, Newton tolerance NEWTON_TOL for both
 * simulators (the full-order default, 1e-5 of the diagonal per second, takes up to ~200 Newton
 * iterations a step on this scene: the barrier against a sphere is concave sideways and projected
 * Newton creeps along it; docs/methods.md).
 * Candidates: 24 linear modes of the clamped slab (computed with the clamps held; skinning
 * eigenmodes are free-object modes, and zeroed at a clamp they make the elements beside it
 * stiff), the first 12 active from the start (the paper starts with 36 to 312 columns, Table 2).
 * Thresholds: eps_E = 1e-4 (the paper's), eps_d = 0.1, eps_G = EPS_FIXED unless swept.
 *
 *  thresholds  (Fig. 12) n = 6 (10k tets), E = 1e5: eps_G (nodal and modal together, then each
 *              alone with the other at EPS_FIXED) from 0.1 down to 1e-6; the final state's largest
 *              vertex distance from full order after STEPS steps (over the bounding-box diagonal),
 *              the full-space Newton step left at each step's answer (|d|_inf / h, the paper's
 *              measure, beside the tolerance),
 *              the enriched share and modes (mean over steps), s/step
 *  stiffness   (Fig. 14/16) n = 6, E = 1e5 ... 1e9, the slab as a free box (the clamped slab's
 *              start, falling between clamps, is an impulse whose size grows with E) with 8 skinning
 *              eigenmodes, 48 columns active from the start, eps_G 1e-3: enrichment, modes, PCG
 *              iterations per solve, and at the first Newton iteration of the contact step
 *              (PROBE_STEP) the same iterate's full-space system by block-Jacobi CG (iterations,
 *              seconds) and CHOLMOD
 *  speed       n = SIZES (24k to 162k tets), E = 1e5, EPS_FIXED: median seconds per step of full
 *              order (CHOLMOD) and adaptive over the same STEPS steps (with downdating and without),
 *              the final-state difference, and the linear solve three ways at PROBE_STEP (Table 3)
 *  downdate    (Fig. 11) n = 10, the same run (10 steps) with downdating on and off: seconds per step, enrichment
 *  mesh        (Fig. 9) the same scene at n = 6 and n = 12: the share of vertices enriched
 *  moving      (Fig. 11) downdating on and off where the contact moves: a stiff box sliding across
 *              a soft terrain (build_moving), 20 steps
 *
 * Timing: single steps of one run, median with min..max (bench_cases.h's convention; the spread
 * is over the steps of one run). One thread for everything (bench_pin_one_thread), so the ratios
 * compare the algorithms, not how each uses the 2 shared cores.
 * ROMKIT_BENCH_QUICK: n = 4 and 6 only. Writes bench/results/adaptive_{thresholds,stiffness,speed,
 * downdate,mesh,downdate_moving}.csv. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_cases.h"
#include "adaptive/adaptive.h"
#include "pipeline/pipeline.h"
#include "pipeline/method_adaptive_subspace.h"
#include "util/util.h"

#define GAP 1e-3
#define DROP_SPEED 0.5
#define STEPS 4
#define PROBE_STEP 2      /* 0-based: the step whose first Newton iteration is probed (in contact) */
#define EPS_FIXED 1e-3
#define NEWTON_TOL 1e-3   /* m/s on |d|_inf / h, both simulators (the paper's Table 2: 1e-4 to 1e-2) */
#define SWEEP_TOL 1e-4    /* the threshold sweep's: full order at 1e-3 is 3.6 mm from itself at 1e-5 on
                           * this scene (the sideways creep), at 1e-4 6e-7 m */

typedef struct {
    rk_scene scene;
    rk_scene_sim sim;
} built;

static int parse_and_build(built *b, const char *json, const char *name, rk_error *err)
{
    memset(b, 0, sizeof *b);
    if (rk_scene_parse(json, name, &b->scene, err)) return -1;
    return rk_scene_build(&b->scene, &b->sim, err);
}

/* The slab clamped at both ends, or (free) the same slab as a free box. */
static int build_scene(built *b, int n, double young, double tol, int free_box, const char *rom, rk_error *err)
{
    char json[4096];
    snprintf(json, sizeof json,
             "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [0.4, 0.2, 0.1], \"cells\": [%d, %d, %d]},"
             " \"translate\": [-0.2, -0.1, %g]},"
             " \"material\": {\"model\": \"neohookean\", \"young\": %g, \"poisson\": 0.4, \"density\": 1000},"
             " \"velocity\": [0, 0, -%g]%s}],"
             " \"gravity\": [0, 0, -9.81],"
             " \"obstacles\": [{\"sphere\": {\"center\": [0, 0, -0.05], \"radius\": 0.05}}],"
             " \"contact\": {\"dhat\": 1e-3},"
             " \"time\": {\"step\": 0.01, \"duration\": %g, \"integrator\": \"bdf2\"},"
             " \"newton\": {\"tolerance\": %g, \"max_iterations\": 1000},"
             " \"rom\": %s}",
             4 * n, 2 * n, n, GAP, young, DROP_SPEED,
             free_box ? "" : ", \"fixed\": [{\"box\": [[-1, -1, -1], [-0.199, 1, 1]]}, {\"box\": [[0.199, -1, -1], [1, 1, 1]]}]",
             0.01 * STEPS, tol, rom);
    return parse_and_build(b, json, "bench_adaptive.json", err);
}

static int build(built *b, int n, double young, double tol, const char *rom, rk_error *err)
{
    return build_scene(b, n, young, tol, 0, rom, err);
}

static void unbuild(built *b)
{
    rk_scene_sim_free(&b->sim);
    rk_scene_free(&b->scene);
}

typedef struct {
    double *x;                 /* final positions */
    bench_stat step;
    long newton;
} fom_result;

static int run_fom(built *b, fom_result *out, rk_error *err)
{
    rk_fom fom;
    if (rk_fom_init(&fom, &b->sim.fem, &b->sim.options, err)) return -1;
    double t[STEPS];
    for (int s = 0; s < STEPS; s++) {
        double t0 = rk_now();
        if (rk_fom_step(&fom, err)) {
            rk_fom_free(&fom);
            return -1;
        }
        t[s] = rk_now() - t0;
    }
    int n = 3 * b->sim.mesh.nv;
    out->x = malloc(sizeof(double) * (size_t)n);
    memcpy(out->x, fom.x, sizeof(double) * (size_t)n);
    out->step = bench_stat_of(t, STEPS);
    out->newton = fom.stats.newton_iterations;
    rk_fom_free(&fom);
    return 0;
}

typedef struct {
    bench_stat step;
    double difference;         /* largest vertex distance from full order / diagonal */
    double share, max_share, modes, pcg_per_solve, newton_per_step;
    rk_adaptive_probe probe;
    double seconds_total;
    double residual_mean, residual_max; /* the full-space Newton step left at each step's answer (m/s) */
} ad_result;

static int run_adaptive(built *b, const double *x_ref, int steps, int residual, ad_result *out, rk_error *err)
{
    rk_adaptive ad;
    if (rk_scene_adaptive_init(&b->scene, &b->sim, &b->scene.entries[0], NULL, 0, &ad, NULL, err)) return -1;
    ad.opt.residual = residual;
    ad.opt.residual_rounds = 0; /* the paper's oracle alone: the residual measured, not acted on */
    ad.opt.full_fraction = 1;   /* and no step handed to full order (the defaults' full_fraction) */
    double t[64];
    for (int s = 0; s < steps; s++) {
        ad.opt.probe = s == PROBE_STEP;
        double t0 = rk_now();
        if (rk_adaptive_step(&ad, err)) {
            rk_adaptive_free(&ad);
            return -1;
        }
        t[s] = rk_now() - t0;
    }
    int nv = b->sim.mesh.nv;
    double diag = rk_points_diagonal(b->sim.mesh.X, nv), worst = 0;
    for (int v = 0; x_ref && v < nv; v++) {
        double d = 0;
        for (int c = 0; c < 3; c++) d += (ad.fom.x[3 * v + c] - x_ref[3 * v + c]) * (ad.fom.x[3 * v + c] - x_ref[3 * v + c]);
        worst = fmax(worst, sqrt(d));
    }
    const rk_adaptive_stats *st = &ad.stats;
    out->step = bench_stat_of(t, steps);
    out->difference = x_ref ? worst / diag : NAN;
    out->share = st->sum_nodes / st->steps / nv;
    out->max_share = (double)st->max_nodes / nv;
    out->modes = st->sum_modes / st->steps;
    out->pcg_per_solve = st->solves ? (double)st->pcg_iterations / st->solves : 0;
    out->newton_per_step = (double)st->newton_iterations / st->steps;
    out->probe = st->probe;
    out->seconds_total = st->seconds_total;
    out->residual_mean = residual ? st->residual_sum / st->steps : NAN;
    out->residual_max = residual ? st->residual_max : NAN;
    rk_adaptive_free(&ad);
    return 0;
}

static char *rom_entry(char *buf, size_t size, double eps_nodal, double eps_modal, int downdate)
{
    snprintf(buf, size,
             "{\"method\": \"adaptive_subspace\", \"basis\": \"modes\", \"size\": 24, \"initial_size\": 12,"
             " \"eps_g_units\": \"paper\", \"residual\": false, \"accuracy\": 0, \"eps_g_nodal\": %g, \"eps_g_modal\": %g, \"downdate\": %s}",
             eps_nodal, eps_modal, downdate ? "true" : "false");
    return buf;
}

static FILE *open_csv(const char *dir, const char *name, const char *header)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "bench_adaptive: cannot write %s\n", path);
        exit(1);
    }
    fprintf(f, "%s\n", header);
    printf("\n%s\n%s\n", path, header);
    return f;
}

#define FAIL(what) do { fprintf(stderr, "bench_adaptive: %s: %s\n", what, err.msg); exit(1); } while (0)

static void thresholds(const char *dir, int n)
{
    rk_error err;
    char rom[512];
    built b;
    if (build(&b, n, 1e5, SWEEP_TOL, rom_entry(rom, sizeof rom, 1, 1, 1), &err)) FAIL("thresholds scene");
    fom_result F;
    if (run_fom(&b, &F, &err)) FAIL("thresholds full order");
    FILE *f = open_csv(dir, "adaptive_thresholds.csv",
                       "vary,eps_g,tets,difference,residual_mean,residual_max,newton_tol,enriched_share,enriched_share_max,modes,pcg_per_solve,"
                       "newton_per_step,s_per_step,s_per_step_min,s_per_step_max,fom_s_per_step");
    static const double eps[] = {0.1, 0.03, 0.01, 0.003, 0.001, 1e-4, 1e-6};
    static const char *vary[] = {"both", "nodal", "modal"};
    for (int v = 0; v < 3; v++)
        for (size_t k = 0; k < sizeof eps / sizeof *eps; k++) {
            built a;
            double en = v == 2 ? EPS_FIXED : eps[k], em = v == 1 ? EPS_FIXED : eps[k];
            if (build(&a, n, 1e5, SWEEP_TOL, rom_entry(rom, sizeof rom, en, em, 1), &err)) FAIL("thresholds scene");
            ad_result r;
            if (run_adaptive(&a, F.x, STEPS, 1, &r, &err)) FAIL("thresholds adaptive");
            char line[512];
            snprintf(line, sizeof line, "%s,%g,%d,%.4g,%.4g,%.4g,%g,%.4f,%.4f,%.1f,%.1f,%.1f,%.4g,%.4g,%.4g,%.4g", vary[v],
                     eps[k], a.sim.mesh.nt, r.difference, r.residual_mean, r.residual_max, SWEEP_TOL, r.share, r.max_share, r.modes, r.pcg_per_solve, r.newton_per_step,
                     r.step.median, r.step.min, r.step.max, F.step.median);
            fprintf(f, "%s\n", line);
            printf("%s\n", line);
            fflush(f);
            unbuild(&a);
        }
    fclose(f);
    free(F.x);
    unbuild(&b);
}

/* A free box's candidates: 8 skinning eigenmodes (108 columns), 4 weights' 48 active from the start. */
static const char *free_entry =
    "{\"method\": \"adaptive_subspace\", \"basis\": \"skinning\", \"size\": 8, \"initial_size\": 48,"
    " \"eps_g_units\": \"paper\", \"residual\": false, \"accuracy\": 0, \"eps_g_nodal\": 1e-3, \"eps_g_modal\": 1e-3}";

static void stiffness(const char *dir, int n)
{
    rk_error err;
    FILE *f = open_csv(dir, "adaptive_stiffness.csv",
                       "young,tets,difference,residual_mean,enriched_share,enriched_share_max,modes,pcg_per_solve,"
                       "probe_schur_iterations,probe_schur_s,probe_bjcg_iterations,probe_bjcg_s,probe_cholmod_s,"
                       "probe_enriched_dofs,s_per_step,fom_s_per_step");
    for (double E = 1e5; E <= 1e9 * 1.01; E *= 10) {
        built b;
        if (build_scene(&b, n, E, NEWTON_TOL, 1, free_entry, &err)) FAIL("stiffness scene");
        fom_result F;
        ad_result r;
        if (run_fom(&b, &F, &err)) FAIL("stiffness full order");
        if (run_adaptive(&b, F.x, STEPS, 1, &r, &err)) FAIL("stiffness adaptive");
        char line[512];
        snprintf(line, sizeof line, "%g,%d,%.4g,%.4g,%.4f,%.4f,%.1f,%.1f,%d,%.4g,%d,%.4g,%.4g,%d,%.4g,%.4g", E, b.sim.mesh.nt,
                 r.difference, r.residual_mean, r.share, r.max_share, r.modes, r.pcg_per_solve, r.probe.schur_iterations,
                 r.probe.schur_seconds, r.probe.bjcg_iterations, r.probe.bjcg_seconds, r.probe.cholmod_seconds,
                 r.probe.enriched_dofs, r.step.median, F.step.median);
        fprintf(f, "%s\n", line);
        printf("%s\n", line);
        fflush(f);
        free(F.x);
        unbuild(&b);
    }
    fclose(f);
}

static void speed(const char *dir, const int *sizes, int nsizes)
{
    rk_error err;
    char rom[512];
    FILE *f = open_csv(dir, "adaptive_speed.csv",
                       "tets,vertices,fom_s_per_step,fom_s_per_step_min,fom_s_per_step_max,fom_newton_per_step,"
                       "s_per_step,s_per_step_min,s_per_step_max,newton_per_step,speedup,difference,enriched_share,"
                       "modes,probe_schur_s,probe_schur_iterations,probe_cholmod_s,probe_bjcg_s,"
                       "probe_bjcg_iterations,probe_schur_nnz,probe_full_nnz,solve_speedup_cholmod,"
                       "solve_speedup_bjcg,no_downdate_s_per_step,no_downdate_newton_per_step,no_downdate_speedup,"
                       "no_downdate_difference");
    for (int k = 0; k < nsizes; k++) {
        built b;
        if (build(&b, sizes[k], 1e5, NEWTON_TOL, rom_entry(rom, sizeof rom, EPS_FIXED, EPS_FIXED, 1), &err)) FAIL("speed scene");
        fom_result F;
        ad_result r;
        if (run_fom(&b, &F, &err)) FAIL("speed full order");
        if (run_adaptive(&b, F.x, STEPS, 0, &r, &err)) FAIL("speed adaptive");
        built b2;
        ad_result r2;
        if (build(&b2, sizes[k], 1e5, NEWTON_TOL, rom_entry(rom, sizeof rom, EPS_FIXED, EPS_FIXED, 0), &err) ||
            run_adaptive(&b2, F.x, STEPS, 0, &r2, &err))
            FAIL("speed adaptive without downdating");
        unbuild(&b2);
        const rk_adaptive_probe *p = &r.probe;
        char line[1024];
        snprintf(line, sizeof line,
                 "%d,%d,%.4g,%.4g,%.4g,%.1f,%.4g,%.4g,%.4g,%.1f,%.2f,%.4g,%.4f,%.1f,%.4g,%d,%.4g,%.4g,%d,%ld,%ld,%.1f,%.1f,"
                 "%.4g,%.1f,%.2f,%.4g",
                 b.sim.mesh.nt, b.sim.mesh.nv, F.step.median, F.step.min, F.step.max, (double)F.newton / STEPS,
                 r.step.median, r.step.min, r.step.max, r.newton_per_step, F.step.median / r.step.median,
                 r.difference, r.share, r.modes, p->schur_seconds, p->schur_iterations, p->cholmod_seconds,
                 p->bjcg_seconds, p->bjcg_iterations, p->schur_nnz, p->full_nnz, p->cholmod_seconds / p->schur_seconds,
                 p->bjcg_seconds / p->schur_seconds, r2.step.median, r2.newton_per_step, F.step.median / r2.step.median,
                 r2.difference);
        fprintf(f, "%s\n", line);
        printf("%s\n", line);
        fflush(f);
        free(F.x);
        unbuild(&b);
    }
    fclose(f);
}

static void downdate(const char *dir, int n)
{
    rk_error err;
    char rom[512];
    FILE *f = open_csv(dir, "adaptive_downdate.csv",
                       "downdate,tets,s_per_step,s_per_step_min,s_per_step_max,seconds_total,enriched_share,modes,"
                       "pcg_per_solve");
    double total[2] = {0, 0};
    for (int on = 1; on >= 0; on--) {
        built b;
        if (build(&b, n, 1e5, NEWTON_TOL, rom_entry(rom, sizeof rom, EPS_FIXED, EPS_FIXED, on), &err)) FAIL("downdate scene");
        ad_result r;
        if (run_adaptive(&b, NULL, 10, 0, &r, &err)) FAIL("downdate adaptive");
        total[on] = r.seconds_total;
        char line[512];
        snprintf(line, sizeof line, "%d,%d,%.4g,%.4g,%.4g,%.4g,%.4f,%.1f,%.1f", on, b.sim.mesh.nt, r.step.median,
                 r.step.min, r.step.max, r.seconds_total, r.share, r.modes, r.pcg_per_solve);
        fprintf(f, "%s\n", line);
        printf("%s\n", line);
        unbuild(&b);
    }
    printf("downdating: %.2fx faster over the run\n", total[0] / total[1]);
    fclose(f);
}

/* Moving contact: a stiff box (E 1e8, 0.1 m, 3000 kg/m^3) sliding at 4 m/s across a soft terrain
 * (1.2 x 0.1 x 0.3 m, E 1e5, base fixed), BDF2, 20 steps: the contact front crosses the terrain, so
 * what enrichment it leaves behind is what downdating can drop (the paper's roller, Fig. 11). */
static int build_moving(built *b, int cells, int downdate, rk_error *err)
{
    char json[4096];
    snprintf(json, sizeof json,
             "{\"objects\": ["
             "{\"mesh\": {\"box\": {\"size\": [1.2, 0.1, 0.3], \"cells\": [%d, %d, %d]}, \"translate\": [-0.6, -0.1, -0.15]},"
             " \"material\": {\"model\": \"neohookean\", \"young\": 1e5, \"poisson\": 0.4, \"density\": 1000},"
             " \"fixed\": [{\"box\": [[-1, -1, -1], [1, -0.099, 1]]}]},"
             "{\"mesh\": {\"box\": {\"size\": [0.1, 0.1, 0.1], \"cells\": [3, 3, 3]}, \"translate\": [-0.5, 0.002, -0.05]},"
             " \"material\": {\"model\": \"neohookean\", \"young\": 1e8, \"poisson\": 0.4, \"density\": 3000},"
             " \"velocity\": [4, -0.3, 0]}],"
             " \"gravity\": [0, -9.81, 0], \"contact\": {\"dhat\": 1e-3},"
             " \"time\": {\"step\": 0.01, \"duration\": 0.2, \"integrator\": \"bdf2\"},"
             " \"newton\": {\"tolerance\": %g, \"max_iterations\": 1000},"
             " \"rom\": {\"method\": \"adaptive_subspace\", \"basis\": \"modes\", \"size\": 24, \"initial_size\": 12,"
             " \"eps_g_units\": \"paper\", \"residual\": false, \"accuracy\": 0, \"eps_g_nodal\": %g, \"eps_g_modal\": %g, \"downdate\": %s}}",
             4 * cells, cells / 3 > 0 ? cells / 3 : 1, cells, NEWTON_TOL, EPS_FIXED, EPS_FIXED, downdate ? "true" : "false");
    return parse_and_build(b, json, "bench_adaptive_moving.json", err);
}

static void moving(const char *dir, int cells)
{
    rk_error err;
    FILE *f = open_csv(dir, "adaptive_downdate_moving.csv",
                       "downdate,tets,s_per_step,s_per_step_min,s_per_step_max,seconds_total,enriched_share,"
                       "enriched_share_max,modes,pcg_per_solve,newton_per_step");
    double total[2] = {0, 0};
    for (int on = 1; on >= 0; on--) {
        built b;
        ad_result r;
        if (build_moving(&b, cells, on, &err) || run_adaptive(&b, NULL, 20, 0, &r, &err)) FAIL("moving contact");
        total[on] = r.seconds_total;
        char line[512];
        snprintf(line, sizeof line, "%d,%d,%.4g,%.4g,%.4g,%.4g,%.4f,%.4f,%.1f,%.1f,%.1f", on, b.sim.mesh.nt, r.step.median,
                 r.step.min, r.step.max, r.seconds_total, r.share, r.max_share, r.modes, r.pcg_per_solve,
                 r.newton_per_step);
        fprintf(f, "%s\n", line);
        printf("%s\n", line);
        unbuild(&b);
    }
    printf("downdating, moving contact: %.2fx faster over the run\n", total[0] / total[1]);
    fclose(f);
}

static void mesh(const char *dir, int n1, int n2)
{
    rk_error err;
    char rom[512];
    FILE *f = open_csv(dir, "adaptive_mesh.csv", "n,tets,vertices,enriched_share,enriched_share_max,modes");
    int ns[2] = {n1, n2};
    for (int k = 0; k < 2; k++) {
        built b;
        if (build(&b, ns[k], 1e5, NEWTON_TOL, rom_entry(rom, sizeof rom, EPS_FIXED, EPS_FIXED, 1), &err)) FAIL("mesh scene");
        ad_result r;
        if (run_adaptive(&b, NULL, STEPS, 0, &r, &err)) FAIL("mesh adaptive");
        char line[512];
        snprintf(line, sizeof line, "%d,%d,%d,%.4f,%.4f,%.1f", ns[k], b.sim.mesh.nt, b.sim.mesh.nv, r.share,
                 r.max_share, r.modes);
        fprintf(f, "%s\n", line);
        printf("%s\n", line);
        unbuild(&b);
    }
    fclose(f);
}

int main(int argc, char **argv)
{
    bench_pin_one_thread(argv, "bench_adaptive");
    const char *dir = argc > 2 ? argv[2] : "bench/results";
    rk_error err;
    if (rk_threads_init(&err)) FAIL("threads");
    rk_progress_set_quiet(1);
    int quick = getenv("ROMKIT_BENCH_QUICK") != NULL;
    const char *only = getenv("ROMKIT_BENCH_ONLY"); /* one part: thresholds, stiffness, speed, downdate, mesh, moving */
    static const int full_sizes[] = {8, 10, 12, 15}, quick_sizes[] = {4, 6};
    if (!only || !strcmp(only, "thresholds")) thresholds(dir, quick ? 4 : 6);
    if (!only || !strcmp(only, "stiffness")) stiffness(dir, quick ? 4 : 6);
    if (!only || !strcmp(only, "speed")) speed(dir, quick ? quick_sizes : full_sizes, quick ? 2 : 4);
    if (!only || !strcmp(only, "downdate")) downdate(dir, quick ? 6 : 10);
    if (!only || !strcmp(only, "mesh")) mesh(dir, quick ? 4 : 6, quick ? 6 : 12);
    if (!only || !strcmp(only, "moving")) moving(dir, quick ? 6 : 12);
    return 0;
}
