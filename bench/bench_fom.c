/* make bench, full-order part (issue 16): where a full-order step's time goes, against tet count,
 * thread count and CHOLMOD's ordering. Three tables:
 *
 * fom_scaling: every mesh of bench_cases.h plus box_440k (skipped under ROMKIT_BENCH_QUICK, as
 * everything from dinosaur_50k on): a soft neo-Hookean object, bottom 10% fixed, gravity, backward
 * Euler at h = 0.01 s, on the threads romkit picks (ROMKIT_THREADS, default the CPUs available);
 * one warm-up step, then case.steps (2 to 10) single steps of one run, each timed. s_per_step is
 * their median, _min and _max the fastest and slowest step; iteration_s the median (min, max) of
 * the timed steps' Newton iterations, factor_s the median of their numeric factorizations, and
 * iteration_per_factor the ratio of those two medians. Shares of the timed steps' time: numeric
 * factorization, solves, assembly (the Newton iterations' potential, gradient and matrix; hessian
 * is the element Hessians within it), the line search's evaluations, and the rest. fem_init_s is
 * the median of INIT_REPEATS runs of rk_fem_init (rest shapes, masses, the sparsity pattern and
 * slot map) on the same mesh, after the scene's own, spread over the repeats.
 *
 * fom_threads: the beam of examples/scenes/beam_bend.json (its own scene: 15,360 tets, E = 5 MPa)
 * and bunny_19k as above, at 1 thread, 2, 4 ... up to the CPUs available: the same columns, so the
 * threaded run can be held against one thread on the same machine.
 *
 * fom_orderings: CHOLMOD's numeric factorization of the Newton matrix at rest (mass / h^2 plus the
 * rest stiffness, the pattern every step factors) under each ordering CHOLMOD offers here (its
 * default: AMD, METIS when AMD fills in much; AMD; METIS; NESDIS; AMD|NESDIS, the sparser factor
 * of those two, what the simulator uses),
 * supernodal, on one thread: the analysis's seconds and flop count, and the median of ORDER_REPEATS
 * factorizations (min, max), on the beam, bunny_19k and box_100k (box_10k under QUICK).
 *
 * Writes bench/results/fom_{scaling,threads,orderings}.{csv,json}. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_cases.h"
#include "fom/fom.h"
#include "pipeline/pipeline.h"
#include "util/util.h"

#define INIT_REPEATS 5
#define ORDER_REPEATS 5
#define MAX_STEPS 16

/* rk_fem_init on the case's mesh and materials, INIT_REPEATS times. */
static int time_fem_init(const rk_scene_sim *sim, bench_stat *sec, rk_error *err)
{
    double t[INIT_REPEATS];
    for (int k = 0; k < INIT_REPEATS; k++) {
        rk_fem f;
        double t0 = rk_now();
        if (rk_fem_init(&f, &sim->mesh, sim->materials, err)) return -1;
        t[k] = rk_now() - t0;
        rk_fem_free(&f);
    }
    *sec = bench_stat_of(t, INIT_REPEATS);
    return 0;
}

/* What the timed steps of a run came to. */
typedef struct {
    int nv, nt, steps, threads;
    bench_stat step, iter, factor;
    double newton, ratio;
    double factor_share, solve_share, assembly_share, hessian_share, line_search_share, other_share;
} run_result;

/* Warm-up step, then `steps` timed single steps of s (initialised). */
static int time_steps(rk_fom *s, int steps, run_result *r, rk_error *err)
{
    if (rk_fom_step(s, err)) return -1;
    double times[MAX_STEPS];
    rk_fom_stats b = s->stats;
    long first = rk_fom_iterations(s, NULL, NULL);
    for (int k = 0; k < steps; k++) {
        double t0 = rk_now();
        if (rk_fom_step(s, err)) return -1;
        times[k] = rk_now() - t0;
    }
    const rk_fom_stats *a = &s->stats;
    const double *it, *fa;
    long n = rk_fom_iterations(s, &it, &fa) - first;
    double *iter = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1)), *fact = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
    if (!iter || !fact) {
        free(iter), free(fact);
        return rk_fail(err, "out of memory");
    }
    memcpy(iter, it + first, sizeof(double) * (size_t)n);
    memcpy(fact, fa + first, sizeof(double) * (size_t)n);
    r->steps = steps;
    r->threads = rk_threads();
    r->step = bench_stat_of(times, steps);
    r->iter = bench_stat_of(iter, (int)n);
    r->factor = bench_stat_of(fact, (int)n);
    free(iter), free(fact);
    r->ratio = r->iter.median / r->factor.median;
    r->newton = (double)(a->newton_iterations - b.newton_iterations) / steps;
    double total = a->seconds_total - b.seconds_total;
    r->factor_share = (a->seconds_factor - b.seconds_factor) / total;
    r->solve_share = (a->seconds_solve - b.seconds_solve) / total;
    r->assembly_share = (a->seconds_assemble - b.seconds_assemble) / total;
    r->hessian_share = (a->seconds_hessian - b.seconds_hessian) / total;
    r->line_search_share = (a->seconds_line_search - b.seconds_line_search) / total;
    r->other_share = 1 - r->factor_share - r->solve_share - r->assembly_share - r->line_search_share;
    return 0;
}

/* A bench case (bench_cases.h): its object with the lowest 10% (in y) fixed, timed. */
static int run_case(const bench_case *c, run_result *r, bench_stat *init, rk_error *err)
{
    rk_scene scene;
    rk_scene_sim sim;
    if (bench_scene(c, &scene, &sim, err)) return -1;
    int rc = init ? time_fem_init(&sim, init, err) : 0;
    double lo = INFINITY, hi = -INFINITY;
    for (int v = 0; v < sim.mesh.nv; v++) {
        lo = fmin(lo, sim.mesh.X[3 * v + 1]);
        hi = fmax(hi, sim.mesh.X[3 * v + 1]);
    }
    rk_prescribed fixed = {.kind = RK_MOTION_FIXED};
    fixed.verts = malloc(sizeof(int) * (size_t)sim.mesh.nv);
    if (!fixed.verts) rc = rk_fail(err, "out of memory");
    for (int v = 0; !rc && v < sim.mesh.nv; v++)
        if (sim.mesh.X[3 * v + 1] <= lo + 0.1 * (hi - lo)) fixed.verts[fixed.count++] = v;
    rk_fom_options opt = sim.options;
    opt.nprescribed = 1;
    opt.prescribed = &fixed;
    rk_fom fom;
    if (!rc && !(rc = rk_fom_init(&fom, &sim.fem, &opt, err))) {
        rc = time_steps(&fom, c->steps, r, err);
        rk_fom_free(&fom);
    }
    r->nv = sim.mesh.nv;
    r->nt = sim.mesh.nt;
    free(fixed.verts);
    rk_scene_sim_free(&sim);
    rk_scene_free(&scene);
    return rc;
}

/* A scene file as it stands (its own constraints and options), timed. */
static int run_scene(const char *path, int steps, run_result *r, rk_error *err)
{
    rk_scene scene;
    rk_scene_sim sim;
    if (rk_scene_load(path, &scene, err)) return -1;
    int rc = rk_scene_build(&scene, &sim, err);
    if (!rc) {
        rk_fom fom;
        if (!(rc = rk_fom_init(&fom, &sim.fem, &sim.options, err))) {
            rc = time_steps(&fom, steps, r, err);
            rk_fom_free(&fom);
        }
        r->nv = sim.mesh.nv;
        r->nt = sim.mesh.nt;
        rk_scene_sim_free(&sim);
    }
    rk_scene_free(&scene);
    return rc;
}

#define RUN_HEADER "s_per_step,s_per_step_min,s_per_step_max,newton_per_step,iteration_s,iteration_s_min,iteration_s_max," \
                   "factor_s,factor_s_min,factor_s_max,iteration_per_factor,factor_share,solve_share,assembly_share," \
                   "hessian_share,line_search_share,other_share,threads"

static void print_run(const char *name, const run_result *r)
{
    printf("%-14s %7d %7d %2d %9.4g %8.4g..%-8.4g %6.2f %9.4g %9.4g %6.2f %6.1f%% %5.1f%% %6.1f%% %6.1f%% %5.1f%% %5.1f%%",
           name, r->nv, r->nt, r->threads, BENCH_STAT3(r->step), r->newton, r->iter.median, r->factor.median, r->ratio,
           100 * r->factor_share, 100 * r->solve_share, 100 * r->assembly_share, 100 * r->hessian_share,
           100 * r->line_search_share, 100 * r->other_share);
}

static void csv_run(FILE *csv, const run_result *r)
{
    fprintf(csv, "%.6g,%.6g,%.6g,%.2f,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%d", BENCH_STAT3(r->step),
            r->newton, BENCH_STAT3(r->iter), BENCH_STAT3(r->factor), r->ratio, r->factor_share, r->solve_share,
            r->assembly_share, r->hessian_share, r->line_search_share, r->other_share, r->threads);
}

static void json_run(FILE *json, const run_result *r)
{
    fprintf(json,
            "\"seconds_per_step\": %.6g, \"seconds_per_step_min\": %.6g, \"seconds_per_step_max\": %.6g,"
            " \"newton_per_step\": %.2f, \"iteration_seconds\": %.6g, \"iteration_seconds_min\": %.6g,"
            " \"iteration_seconds_max\": %.6g, \"factorization_seconds\": %.6g, \"factorization_seconds_min\": %.6g,"
            " \"factorization_seconds_max\": %.6g, \"iteration_per_factorization\": %.4f,"
            " \"factorization_share\": %.4f, \"solve_share\": %.4f, \"assembly_share\": %.4f, \"hessian_share\": %.4f,"
            " \"line_search_share\": %.4f, \"other_share\": %.4f, \"threads\": %d",
            BENCH_STAT3(r->step), r->newton, BENCH_STAT3(r->iter), BENCH_STAT3(r->factor), r->ratio, r->factor_share,
            r->solve_share, r->assembly_share, r->hessian_share, r->line_search_share, r->other_share, r->threads);
}

static const char *RUN_COLUMNS = "%-14s %7s %7s %2s %9s %18s %6s %9s %9s %6s %7s %6s %7s %7s %6s %6s";

static void print_columns(void)
{
    printf(RUN_COLUMNS, "case", "verts", "tets", "th", "s/step", "(min..max)", "newton", "iter s", "factor s", "ratio",
           "factor", "solve", "assembl", "hessian", "lsrch", "other");
}

static int set_threads(int n, rk_error *err)
{
    char v[16];
    snprintf(v, sizeof v, "%d", n);
    setenv("ROMKIT_THREADS", v, 1);
    return rk_threads_init(err);
}

static int scaling(const char *data, const char *out_dir, int quick)
{
    bench_case cases[10];
    int ncases = bench_cases(data, cases);
    cases[ncases] = (bench_case){.name = "box_440k", .steps = 2}; /* 84 x 30 x 29 cells, 6 tets each */
    snprintf(cases[ncases].mesh_json, sizeof cases[ncases].mesh_json, "{\"box\": {\"size\": [2, 1, 1], \"cells\": [84, 30, 29]}}");
    ncases++;
    if (quick) ncases = 5;
    FILE *csv, *json;
    if (bench_open_results(out_dir, "fom_scaling", "case,vertices,tets,steps," RUN_HEADER ",fem_init_s,fem_init_s_min,fem_init_s_max",
                           &csv, &json))
        return 1;
    printf("full order against mesh size (%d threads)\n", rk_threads());
    print_columns();
    printf(" %10s\n", "fem_init s");
    for (int c = 0; c < ncases; c++) {
        rk_error err;
        run_result r;
        bench_stat init;
        if (run_case(&cases[c], &r, &init, &err)) {
            fprintf(stderr, "bench_fom: %s: %s\n", cases[c].name, err.msg);
            return 1;
        }
        print_run(cases[c].name, &r);
        printf(" %10.4g\n", init.median);
        fflush(stdout);
        fprintf(csv, "%s,%d,%d,%d,", cases[c].name, r.nv, r.nt, r.steps);
        csv_run(csv, &r);
        fprintf(csv, ",%.6g,%.6g,%.6g\n", BENCH_STAT3(init));
        fprintf(json, "%s  {\"case\": \"%s\", \"vertices\": %d, \"tets\": %d, \"steps\": %d, ", c ? "," : "", cases[c].name,
                r.nv, r.nt, r.steps);
        json_run(json, &r);
        fprintf(json, ", \"fem_init_seconds\": %.6g, \"fem_init_seconds_min\": %.6g, \"fem_init_seconds_max\": %.6g}\n",
                BENCH_STAT3(init));
    }
    fprintf(json, "]\n");
    fclose(csv);
    fclose(json);
    return 0;
}

static int threads(const char *data, const char *out_dir, int cpus)
{
    bench_case cases[9], bunny = {0};
    int ncases = bench_cases(data, cases);
    for (int c = 0; c < ncases; c++)
        if (strcmp(cases[c].name, "bunny_19k") == 0) bunny = cases[c];
    FILE *csv, *json;
    if (bench_open_results(out_dir, "fom_threads", "case,vertices,tets,steps," RUN_HEADER, &csv, &json)) return 1;
    printf("\nfull order against threads (the CPUs available: %d)\n", cpus);
    print_columns();
    printf("\n");
    int first = 1;
    for (int which = 0; which < 2; which++)
        for (int nt = 1; nt <= cpus; nt *= 2) {
            rk_error err;
            run_result r;
            const char *name = which ? "bunny_19k" : "beam_bend";
            if (set_threads(nt, &err) ||
                (which ? run_case(&bunny, &r, NULL, &err) : run_scene("examples/scenes/beam_bend.json", 10, &r, &err))) {
                fprintf(stderr, "bench_fom: %s on %d threads: %s\n", name, nt, err.msg);
                return 1;
            }
            print_run(name, &r);
            printf("\n");
            fflush(stdout);
            fprintf(csv, "%s,%d,%d,%d,", name, r.nv, r.nt, r.steps);
            csv_run(csv, &r);
            fprintf(csv, "\n");
            fprintf(json, "%s  {\"case\": \"%s\", \"vertices\": %d, \"tets\": %d, \"steps\": %d, ", first ? "" : ",", name, r.nv,
                    r.nt, r.steps);
            json_run(json, &r);
            fprintf(json, "}\n");
            first = 0;
        }
    fprintf(json, "]\n");
    fclose(csv);
    fclose(json);
    return 0;
}

/* The Newton matrix at rest of a built scene: M / h^2 + K0 on the fem pattern. */
static int rest_matrix(const rk_scene_sim *sim, rk_sparse *H, rk_error *err)
{
    if (rk_sparse_alloc_pattern(&sim->fem, H, err)) return -1;
    rk_fem_add_mass(&sim->fem, 0, 1.0 / (sim->options.h * sim->options.h), H);
    rk_fem_add_rest_stiffness(&sim->fem, 1.0, H);
    return 0;
}

static int orderings(const char *data, const char *out_dir, int quick)
{
    bench_case cases[9], pick[3];
    int ncases = bench_cases(data, cases), npick = 0;
    pick[npick] = (bench_case){.name = "beam_bend"};
    snprintf(pick[npick++].mesh_json, sizeof pick[0].mesh_json, "{\"box\": {\"size\": [5, 1, 1], \"cells\": [40, 8, 8]}}");
    for (int c = 0; c < ncases; c++)
        if (strcmp(cases[c].name, "bunny_19k") == 0 || strcmp(cases[c].name, quick ? "box_10k" : "box_100k") == 0)
            pick[npick++] = cases[c];
    static const struct { const char *name; int ordering, second; } ords[] = {
        {"default", -1, -1}, {"AMD", CHOLMOD_AMD, -1}, {"METIS", CHOLMOD_METIS, -1}, {"NESDIS", CHOLMOD_NESDIS, -1},
        {"AMD|NESDIS", CHOLMOD_AMD, CHOLMOD_NESDIS}};
    FILE *csv, *json;
    if (bench_open_results(out_dir, "fom_orderings", "case,dofs,ordering,chosen,analyze_s,flops,lnz,factor_s,factor_s_min,factor_s_max",
                           &csv, &json))
        return 1;
    rk_error err;
    int blas = rk_threads_blas(1);
    printf("\nCHOLMOD orderings (supernodal, one thread)\n%-10s %7s %-10s %-7s %9s %9s %9s %9s %18s\n", "case", "dofs", "ordering",
           "chosen", "analyze s", "flops", "nnz(L)", "factor s", "(min..max)");
    int first = 1;
    for (int c = 0; c < npick; c++) {
        rk_scene scene;
        rk_scene_sim sim;
        rk_sparse H;
        if (bench_scene(&pick[c], &scene, &sim, &err) || rest_matrix(&sim, &H, &err)) {
            fprintf(stderr, "bench_fom: %s: %s\n", pick[c].name, err.msg);
            return 1;
        }
        for (size_t o = 0; o < sizeof ords / sizeof ords[0]; o++) {
            cholmod_common cc;
            cholmod_start(&cc);
            cc.supernodal = CHOLMOD_SUPERNODAL;
            if (ords[o].ordering >= 0) {
                cc.nmethods = ords[o].second >= 0 ? 2 : 1;
                cc.method[0].ordering = ords[o].ordering;
                cc.method[1].ordering = ords[o].second;
                cc.postorder = 1;
            }
            cholmod_sparse A;
            rk_cholmod_sparse_view(&H, &A);
            double t0 = rk_now();
            cholmod_factor *L = cholmod_analyze(&A, &cc);
            double analyze = rk_now() - t0, t[ORDER_REPEATS];
            if (!L) {
                fprintf(stderr, "bench_fom: %s: CHOLMOD analysis failed\n", pick[c].name);
                return 1;
            }
            double fl = cc.fl, lnz = cc.lnz;
            for (int k = 0; k < ORDER_REPEATS; k++) {
                t0 = rk_now();
                cholmod_factorize(&A, L, &cc);
                t[k] = rk_now() - t0;
            }
            const char *chosen = L->ordering == CHOLMOD_AMD ? "AMD" : L->ordering == CHOLMOD_METIS ? "METIS"
                                 : L->ordering == CHOLMOD_NESDIS                                    ? "NESDIS"
                                                                                                    : "other";
            bench_stat f = bench_stat_of(t, ORDER_REPEATS);
            printf("%-10s %7d %-10s %-7s %9.4f %9.3g %9.3g %9.4g %8.4g..%-8.4g\n", pick[c].name, H.n, ords[o].name, chosen,
                   analyze, fl, lnz, BENCH_STAT3(f));
            fflush(stdout);
            fprintf(csv, "%s,%d,%s,%s,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n", pick[c].name, H.n, ords[o].name, chosen, analyze, fl,
                    lnz, BENCH_STAT3(f));
            fprintf(json,
                    "%s  {\"case\": \"%s\", \"dofs\": %d, \"ordering\": \"%s\", \"chosen\": \"%s\", \"analyze_seconds\": %.6g,"
                    " \"flops\": %.6g, \"lnz\": %.6g, \"factorization_seconds\": %.6g, \"factorization_seconds_min\": %.6g,"
                    " \"factorization_seconds_max\": %.6g}\n",
                    first ? "" : ",", pick[c].name, H.n, ords[o].name, chosen, analyze, fl, lnz, BENCH_STAT3(f));
            first = 0;
            cholmod_free_factor(&L, &cc);
            cholmod_finish(&cc);
        }
        rk_sparse_free(&H);
        rk_scene_sim_free(&sim);
        rk_scene_free(&scene);
    }
    rk_threads_blas(blas);
    fprintf(json, "]\n");
    fclose(csv);
    fclose(json);
    return 0;
}

int main(int argc, char **argv)
{
    const char *data = argc > 1 ? argv[1] : "tests/data/meshes";
    const char *out_dir = argc > 2 ? argv[2] : "bench/results";
    int quick = getenv("ROMKIT_BENCH_QUICK") != NULL;
    rk_error err;
    if (rk_threads_init(&err)) {
        fprintf(stderr, "bench_fom: %s\n", err.msg);
        return 1;
    }
    int cpus = rk_threads(), rc = scaling(data, out_dir, quick);
    if (!rc) rc = threads(data, out_dir, cpus);
    if (!rc) rc = orderings(data, out_dir, quick);
    return rc;
}
